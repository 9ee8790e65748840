//! Measuring: the clocks (process CPU time, `getrusage` of the children), one measurement
//! ([`Meas`]), the rounds of every harness and how they are interleaved, the in-process pass timed
//! in rounds, the external harness and the whole process timed, and how a rate or a size prints.
//! It knows what a stimulus is ([`crate::stim`]) and nothing of any peer.

use crate::stim::Stim;
use std::hint::black_box;
use std::path::Path;
use std::process::Command;
use std::time::Instant;

/// The process's CPU time so far in seconds (`CLOCK_PROCESS_CPUTIME_ID`: every thread).
pub fn cpu_now() -> f64 {
    let mut ts = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: clock_gettime writes one timespec through a valid pointer.
    unsafe { libc::clock_gettime(libc::CLOCK_PROCESS_CPUTIME_ID, &mut ts) };
    ts.tv_sec as f64 + ts.tv_nsec as f64 * 1e-9
}

/// (CPU seconds, peak resident KiB) of `who` (RUSAGE_SELF or RUSAGE_CHILDREN).
pub fn rusage(who: libc::c_int) -> (f64, i64) {
    // SAFETY: getrusage fills a zeroed rusage struct through a valid pointer.
    let mut u: libc::rusage = unsafe { std::mem::zeroed() };
    unsafe { libc::getrusage(who, &mut u) };
    let t = |v: libc::timeval| v.tv_sec as f64 + v.tv_usec as f64 * 1e-6;
    (t(u.ru_utime) + t(u.ru_stime), u.ru_maxrss)
}

/// One round of a harness: the ticks it replayed, the CPU seconds they took, the checksum of its
/// outputs (`None` where they are not folded: `pmu50 run`, and Icarus, which compares them with
/// the vector file) and the note of its row.
#[derive(Clone, Debug)]
pub struct Meas {
    pub ticks: u64,
    pub cpu: f64,
    pub checksum: Option<u64>,
    pub note: String,
}

impl Meas {
    pub fn rate(&self) -> f64 {
        self.ticks as f64 / self.cpu.max(1e-9)
    }
}

/// Rounds per measurement: every harness is timed in this many rounds and the fastest round
/// counts. On a shared machine the load only ever slows a round down, so the best round is the
/// one least disturbed; all harnesses are measured the same way, so their ratios stay fair.
const ROUNDS: u32 = 15;

/// [`ROUNDS`], or the `--rounds N` of the command line (1 for profiling under callgrind); a
/// value that is not a whole number of at least 1 ends the run with exit 2.
pub fn rounds() -> u32 {
    static R: std::sync::OnceLock<u32> = std::sync::OnceLock::new();
    *R.get_or_init(|| {
        let a: Vec<String> = std::env::args().collect();
        let Some(k) = a.iter().position(|x| x == "--rounds") else {
            return ROUNDS;
        };
        match a
            .get(k + 1)
            .and_then(|v| v.parse().ok())
            .filter(|&n: &u32| n > 0)
        {
            Some(n) => n,
            None => {
                eprintln!(
                    "compare: --rounds needs a whole number of at least 1, got {:?}",
                    a.get(k + 1)
                );
                std::process::exit(2);
            }
        }
    })
}

/// One round of one harness (a closure that times one round and returns its measurement).
pub type Round<'a> = Box<dyn FnMut() -> Result<Meas, String> + 'a>;

/// The rounds of the table's harnesses of one stimulus, run interleaved: round 1 of every
/// harness, then round 2 of every harness, and so on. A slow phase of the shared machine then
/// falls on the neighbouring rounds of all harnesses rather than on every round of one, which
/// kept the ratios of earlier runs from repeating; the fastest round of each harness counts.
pub fn interleaved(mut harnesses: Vec<Result<Round<'_>, String>>) -> Vec<Result<Meas, String>> {
    let mut best: Vec<Result<Option<Meas>, String>> = harnesses
        .iter()
        .map(|h| h.as_ref().map(|_| None).map_err(String::clone))
        .collect();
    for _ in 0..rounds() {
        for (h, b) in harnesses.iter_mut().zip(best.iter_mut()) {
            let (Ok(round), Ok(kept)) = (h, &mut *b) else {
                continue;
            };
            match round() {
                Ok(m) if kept.as_ref().is_none_or(|k| m.rate() > k.rate()) => *kept = Some(m),
                Ok(_) => {}
                Err(e) => *b = Err(e),
            }
        }
    }
    best.into_iter()
        .map(|b| b.and_then(|m| m.ok_or_else(|| "no round".to_string())))
        .collect()
}

/// A round of an in-process pass: the number of replays per round is chosen first so that
/// a round takes about `seconds / rounds` CPU seconds; each round checks the checksum.
pub fn pass_rounds<'a>(st: &'a Stim, seconds: f64, pass: fn(&Stim) -> u64) -> Round<'a> {
    let t0 = cpu_now();
    let h = black_box(pass(st));
    let one = (cpu_now() - t0).max(1e-6);
    let reps = ((seconds / f64::from(rounds()) / one).ceil() as u64).clamp(1, 1_000_000);
    Box::new(move || {
        let t0 = cpu_now();
        let mut last = 0;
        for _ in 0..reps {
            last = black_box(pass(black_box(st)));
        }
        let cpu = cpu_now() - t0;
        if last != h {
            return Err(format!(
                "{}: a replay from reset gave checksum {last:016x}, the first {h:016x}",
                st.name
            ));
        }
        Ok(Meas {
            ticks: reps * st.inputs.len() as u64,
            cpu,
            checksum: Some(last),
            note: String::new(),
        })
    })
}

/// One harness alone, for `--quick` and `--quick-traced`: its fastest round.
pub fn alone(round: Round<'_>) -> Meas {
    match interleaved(vec![Ok(round)]).pop() {
        Some(Ok(m)) => m,
        Some(Err(e)) => {
            eprintln!("compare: {e}");
            std::process::exit(1);
        }
        None => unreachable!("one harness gives one result"),
    }
}

/// Where a traced harness writes its waveform.
#[derive(Clone, Copy, PartialEq)]
pub enum Sink {
    /// a file in the bench directory (removed after the last round)
    File,
    /// `/dev/null`: the same writes, which the kernel throws away (no page cache): the
    /// tracer's own cost, without the disk's
    Null,
}

/// Run a harness binary that prints `ticks=N cpu_s=S checksum=H`.
pub fn external(bin: &Path, args: &[String]) -> Result<Meas, String> {
    let out = Command::new(bin)
        .args(args)
        .output()
        .map_err(|e| format!("{}: {e}", bin.display()))?;
    let text = String::from_utf8_lossy(&out.stdout).to_string();
    if !out.status.success() {
        return Err(format!(
            "{} failed: {}{}",
            bin.display(),
            text,
            String::from_utf8_lossy(&out.stderr)
        ));
    }
    let field = |k: &str| {
        text.split_whitespace()
            .find_map(|w| w.strip_prefix(k))
            .map(str::to_string)
            .ok_or_else(|| format!("{}: no `{k}` in `{text}`", bin.display()))
    };
    Ok(Meas {
        ticks: field("ticks=")?.parse().map_err(|e| format!("{e}"))?,
        cpu: field("cpu_s=")?.parse().map_err(|e| format!("{e}"))?,
        checksum: Some(u64::from_str_radix(&field("checksum=")?, 16).map_err(|e| format!("{e}"))?),
        note: String::new(),
    })
}

/// One whole process of the wall-time table: its wall time and CPU time (user + system, every
/// thread), in seconds, and what it printed.
#[derive(Clone, Debug)]
pub struct Proc {
    pub wall: f64,
    pub cpu: f64,
    pub stdout: String,
}

/// Run `cmd` to its end, timed.
pub fn timed(cmd: &mut Command) -> Result<Proc, String> {
    let (c0, _) = rusage(libc::RUSAGE_CHILDREN);
    let t0 = Instant::now();
    let o = cmd.output().map_err(|e| format!("{cmd:?}: {e}"))?;
    let wall = t0.elapsed().as_secs_f64();
    let (c1, _) = rusage(libc::RUSAGE_CHILDREN);
    if !o.status.success() {
        return Err(format!(
            "{cmd:?} failed: {}{}",
            String::from_utf8_lossy(&o.stdout),
            String::from_utf8_lossy(&o.stderr)
        ));
    }
    Ok(Proc {
        wall,
        cpu: c1 - c0,
        stdout: String::from_utf8_lossy(&o.stdout).into_owned(),
    })
}

/// [`timed`], but a process still running after `limit` seconds is killed (`Ok(None)`): a
/// Verilator model on two threads waits for its other thread by spinning, which on a machine
/// busy with other work can take minutes instead of milliseconds.
pub fn timed_within(cmd: &mut Command, limit: f64) -> Result<Option<Proc>, String> {
    use std::io::Read;
    let (c0, _) = rusage(libc::RUSAGE_CHILDREN);
    let t0 = Instant::now();
    let mut child = cmd
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::null())
        .spawn()
        .map_err(|e| format!("{cmd:?}: {e}"))?;
    let status = loop {
        if let Some(st) = child.try_wait().map_err(|e| format!("{cmd:?}: {e}"))? {
            break st;
        }
        if t0.elapsed().as_secs_f64() > limit {
            let _ = child.kill();
            let _ = child.wait();
            return Ok(None);
        }
        std::thread::sleep(std::time::Duration::from_micros(200));
    };
    let wall = t0.elapsed().as_secs_f64();
    let (c1, _) = rusage(libc::RUSAGE_CHILDREN);
    let mut stdout = String::new();
    if let Some(mut o) = child.stdout.take() {
        let _ = o.read_to_string(&mut stdout);
    }
    if !status.success() {
        return Err(format!("{cmd:?} failed: {stdout}"));
    }
    Ok(Some(Proc {
        wall,
        cpu: c1 - c0,
        stdout,
    }))
}

/// CPU nanoseconds per byte of writing 8 MiB into a new file of `dir` in 1 MiB writes (the
/// writers' buffer size), the best of fifteen: the page cache's cost, which every VCD harness
/// pays for its bytes.
pub fn page_cache_ns_per_byte(dir: &Path) -> std::io::Result<f64> {
    use std::io::Write;
    let path = dir.join("page_cache.bin");
    let chunk = vec![b'0'; 1 << 20];
    let mut best = f64::MAX;
    for _ in 0..15 {
        let mut f = std::fs::File::create(&path)?;
        let t0 = cpu_now();
        for _ in 0..8 {
            f.write_all(&chunk)?;
        }
        f.flush()?;
        drop(f);
        best = best.min(cpu_now() - t0);
        std::fs::remove_file(&path)?;
    }
    Ok(best * 1e9 / (8.0 * chunk.len() as f64))
}

pub fn fmt_bytes(b: u64) -> String {
    if b >= 1_000_000 {
        format!("{:.1} MB", b as f64 / 1e6)
    } else {
        format!("{:.0} kB", b as f64 / 1e3)
    }
}

pub fn fmt_rate(r: f64) -> String {
    if r >= 1e6 {
        format!("{:.1} M", r / 1e6)
    } else {
        format!("{:.0} k", r / 1e3)
    }
}
