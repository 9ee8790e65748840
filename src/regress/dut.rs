//! The design under test of `pmu50 regress --dut verilator|icarus [--rtl FILELIST]`: an RTL
//! with the contract interface of docs/signals.md, run on each seed's stimulus against the model.
//!
//! - `verilator`: the RTL as a Verilator library (hdl/tb/lockstep/dut_lib.cpp), one build per
//!   (SYNC_DEPTH, CNT_W), cached under `target/regress-dut/<hash of the RTL>/` (the twin: under
//!   hdl/build); a DUT worker steps it in lockstep with the core on the seed's stimulus held in
//!   memory ([`super::lockstep`]), compares every output and register after every edge and the
//!   internals before it, and reports the first divergence.
//! - `icarus`: the vector replay (hdl/tb/tb_vectors.v, method 1), which compares the outputs.
//!
//! Each run has the per-seed time limit: a DUT that hangs or crashes fails its seed with the
//! reason, and the regression goes on.

use super::check::{fig_path, Failure};
use super::lockstep::{Answer, InputRecorder, Worker};
use super::{DutKind, RunSpec};
use crate::scenario::Scenario;
use crate::sim::{self, Observer, SimError, SimOptions, TickView};
use crate::observers::vectors::VectorWriter;
use pmu50_core::drive_interval_changing_56b::{Fig17, Fig18};
use std::collections::HashMap;
use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::Mutex;
use std::time::{Duration, Instant};

/// The repository's hdl/ folder (scripts, benches), found next to the sources this binary was
/// built from, or in `PMU50_HDL_DIR`.
pub fn hdl_dir() -> PathBuf {
    std::env::var_os("PMU50_HDL_DIR").map(PathBuf::from).unwrap_or_else(|| Path::new(env!("CARGO_MANIFEST_DIR")).join("hdl"))
}

/// A seed's stimulus in a DUT worker ([`Dut::send`]), its verdict to take ([`Dut::receive`]).
pub struct InFlight(Worker);

pub struct Dut {
    kind: DutKind,
    filelist: PathBuf,
    build_dir: PathBuf,
    /// RTL libraries by (SYNC_DEPTH, CNT_W); a failed build is remembered with its reason.
    builds: Mutex<HashMap<(u8, u8), Result<PathBuf, String>>>,
    /// Idle DUT workers (`--dut verilator`): a job takes one, or starts one.
    workers: Mutex<Vec<Worker>>,
    scratch: tempfile::TempDir,
}

/// Check a file list: every entry names a readable file (relative to the list's folder).
pub fn check_filelist(list: &Path) -> Result<Vec<PathBuf>, String> {
    let text = std::fs::read_to_string(list).map_err(|e| format!("--rtl {}: {e}", list.display()))?;
    let dir = list.parent().filter(|p| !p.as_os_str().is_empty()).unwrap_or(Path::new("."));
    let mut files = Vec::new();
    for (n, line) in text.lines().enumerate() {
        let entry = line.split("//").next().unwrap_or("").split('#').next().unwrap_or("").trim();
        if entry.is_empty() {
            continue;
        }
        if entry.starts_with('+') || entry.starts_with('-') {
            return Err(format!("--rtl {}:{}: `{entry}`: a file list here holds Verilog file paths only (relative to the list's folder), no tool options", list.display(), n + 1));
        }
        let p = dir.join(entry);
        if !p.is_file() {
            return Err(format!("--rtl {}:{}: `{entry}` is not a readable file ({} does not exist)", list.display(), n + 1, p.display()));
        }
        files.push(p);
    }
    if files.is_empty() {
        return Err(format!("--rtl {}: the file list names no Verilog file", list.display()));
    }
    Ok(files)
}

impl Dut {
    pub fn prepare(spec: &RunSpec, _jobs: usize) -> Result<Dut, String> {
        let hdl = hdl_dir();
        let filelist = match &spec.rtl {
            Some(f) => PathBuf::from(f),
            None => hdl.join("pmu50.f"),
        };
        let files = check_filelist(&filelist)?;
        let filelist = filelist.canonicalize().map_err(|e| format!("--rtl {}: {e}", filelist.display()))?;
        let tool = match spec.dut {
            DutKind::Verilator => "verilator",
            DutKind::Icarus => "iverilog",
            DutKind::Model => return Err("the model is not an RTL DUT".into()),
        };
        if Command::new(tool).arg("--version").stdout(Stdio::null()).stderr(Stdio::null()).status().is_err() {
            return Err(format!("--dut {}: `{tool}` is not installed (Debian package {}; `make deps` installs it)", tool_name(&spec.dut), if tool == "iverilog" { "iverilog" } else { "verilator" }));
        }
        // The cache key: the RTL's paths and contents.
        let mut h: u64 = 0xcbf2_9ce4_8422_2325;
        for f in &files {
            let bytes = std::fs::read(f).map_err(|e| format!("{}: {e}", f.display()))?;
            for b in f.to_string_lossy().bytes().chain(bytes) {
                h = (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3);
            }
        }
        // The twin shares hdl/build with hdl/cosim.sh; another RTL gets a folder of its own.
        let build_dir = if spec.rtl.is_none() { hdl.join("build") } else { Path::new(env!("CARGO_MANIFEST_DIR")).join("target/regress-dut").join(format!("{h:016x}")) };
        std::fs::create_dir_all(&build_dir).map_err(|e| format!("{}: {e}", build_dir.display()))?;
        let scratch = tempfile::tempdir().map_err(|e| format!("a scratch folder for vector files: {e}"))?;
        Ok(Dut { kind: spec.dut.clone(), filelist, build_dir, builds: Mutex::new(HashMap::new()), workers: Mutex::new(Vec::new()), scratch })
    }

    /// The RTL library for (SYNC_DEPTH, CNT_W), built on first use. The lock is held while it
    /// builds, so jobs that need the same pair wait for one build.
    fn library(&self, sd: u8, w: u8) -> Result<PathBuf, String> {
        let mut builds = self.builds.lock().unwrap_or_else(|e| e.into_inner());
        if let Some(r) = builds.get(&(sd, w)) {
            return r.clone();
        }
        let out = Command::new("bash")
            .arg(hdl_dir().join("scripts/build_lockstep.sh"))
            .args(["none", &sd.to_string(), &w.to_string(), "lib"])
            .env("PMU50_FILELIST", &self.filelist)
            .env("PMU50_BUILD_DIR", &self.build_dir)
            .output()
            .map_err(|e| format!("cannot run build_lockstep.sh: {e}"));
        let r = out.and_then(|o| {
            if o.status.success() {
                Ok(self.build_dir.join(format!("lockstep/lib_none_{sd}_{w}/libpmu50_dut.so")))
            } else {
                let log = String::from_utf8_lossy(&o.stderr);
                Err(format!("Verilator build of {} (SYNC_DEPTH={sd}, CNT_W={w}) failed: {}", self.filelist.display(), log.lines().take(6).collect::<Vec<_>>().join(" | ")))
            }
        });
        builds.insert((sd, w), r.clone());
        r
    }

    /// A scratch vector file for `sc`, removed when dropped.
    pub fn vector_file(&self, sc: &Scenario) -> Result<tempfile::NamedTempFile, String> {
        tempfile::Builder::new().prefix(&format!("{}.", sc.name)).suffix(".vec").tempfile_in(self.scratch.path()).map_err(|e| format!("a scratch vector file in {}: {e}", self.scratch.path().display()))
    }

    /// Whether this DUT runs in lockstep from the recorded inputs ([`Dut::lockstep`]) rather
    /// than from a vector file ([`Dut::check_vectors`]).
    pub fn in_memory(&self) -> bool {
        self.kind == DutKind::Verilator
    }

    /// Run the DUT on a scenario's stimulus: `Ok(None)` equal, `Ok(Some)` the first divergence
    /// (or a hang or crash), `Err` a setup failure (the seed's verdict is then `error`).
    pub fn check(&self, sc: &Scenario, timeout: Duration) -> Result<Option<Failure>, String> {
        if self.in_memory() {
            let mut rec = InputRecorder::default();
            sim::run(sc, SimOptions::default(), &mut [&mut rec]).map_err(|e| e.to_string())?;
            return self.lockstep(sc, &rec.inputs, timeout);
        }
        let vec = self.vector_file(sc)?;
        let mut w = VectorWriter::new(std::io::BufWriter::new(vec.as_file()), sc).map_err(|e| e.to_string())?;
        sim::run(sc, SimOptions::default(), &mut [&mut w]).map_err(|e| e.to_string())?;
        use std::io::Write;
        w.into_inner().flush().map_err(|e| format!("{}: {e}", vec.path().display()))?;
        self.check_vectors(sc, vec.path(), timeout)
    }

    /// [`Dut::check`] on the inputs of every tick of `sc` (recorded by
    /// [`InputRecorder`]): the RTL library stepped by a DUT worker beside the core.
    pub fn lockstep(&self, sc: &Scenario, inputs: &[u32], timeout: Duration) -> Result<Option<Failure>, String> {
        let f = self.send(sc, inputs)?;
        self.receive(sc, f, timeout)
    }

    /// The first half of [`Dut::lockstep`]: the stimulus handed to an idle DUT worker (or a new
    /// one), which runs it while the caller goes on.
    pub fn send(&self, sc: &Scenario, inputs: &[u32]) -> Result<InFlight, String> {
        let lib = self.library(sc.params.sync_depth, sc.params.cnt_width)?;
        let idle = self.workers.lock().unwrap_or_else(|e| e.into_inner()).pop();
        let mut worker = match idle {
            Some(w) => w,
            None => Worker::spawn(self.scratch.path())?,
        };
        worker.send(&lib, &sc.params, inputs);
        Ok(InFlight(worker))
    }

    /// The second half of [`Dut::lockstep`]: the worker's verdict, within the time limit
    /// counted from [`Dut::send`].
    pub fn receive(&self, sc: &Scenario, flight: InFlight, timeout: Duration) -> Result<Option<Failure>, String> {
        let mut worker = flight.0;
        let text = match worker.receive(timeout)? {
            Answer::Reply(text) => {
                self.workers.lock().unwrap_or_else(|e| e.into_inner()).push(worker);
                text
            }
            Answer::TimedOut => return Ok(Some(dut_failure(sc, None, "dut", format!("the DUT did not finish within the per-seed time limit of {} s", timeout.as_secs_f64())))),
            Answer::Died(how) => return Ok(Some(dut_failure(sc, None, "dut", how))),
        };
        if text.starts_with("PASS") {
            return Ok(None);
        }
        if let Some(line) = text.lines().find(|l| l.starts_with("MISMATCH")) {
            return Ok(Some(parse_mismatch(sc, line, &text)));
        }
        Err(format!("the DUT's lockstep failed: {}", text.lines().filter(|l| !l.trim().is_empty()).take(4).collect::<Vec<_>>().join(" | ")))
    }

    /// [`Dut::check`] on a vector file of `sc` already written (`--dut icarus`).
    pub fn check_vectors(&self, sc: &Scenario, vec: &Path, timeout: Duration) -> Result<Option<Failure>, String> {
        let mut cmd = Command::new("bash");
        cmd.arg(hdl_dir().join("scripts/run_vectors.sh")).arg(vec).env("PMU50_FILELIST", &self.filelist).env("PMU50_BUILD_DIR", &self.build_dir);
        let res = run_limited(&mut cmd, timeout);
        let (code, text) = match res? {
            Limited::Done(code, text) => (code, text),
            Limited::TimedOut => return Ok(Some(dut_failure(sc, None, "dut", format!("the DUT did not finish within the per-seed time limit of {} s", timeout.as_secs_f64())))),
            Limited::Killed(sig) => return Ok(Some(dut_failure(sc, None, "dut", format!("the DUT crashed (signal {sig})")))),
        };
        if code == 0 {
            return Ok(None);
        }
        if let Some(line) = text.lines().find(|l| l.starts_with("MISMATCH")) {
            return Ok(Some(parse_mismatch(sc, line, &text)));
        }
        if code == 1 {
            return Ok(Some(dut_failure(sc, None, "dut", format!("the DUT reported a failure without a MISMATCH line: {}", text.lines().take(3).collect::<Vec<_>>().join(" | ")))));
        }
        Err(format!("the DUT's bench failed (exit {code}): {}", text.lines().filter(|l| !l.trim().is_empty()).take(4).collect::<Vec<_>>().join(" | ")))
    }
}

fn tool_name(k: &DutKind) -> &'static str {
    match k {
        DutKind::Model => "model",
        DutKind::Verilator => "verilator",
        DutKind::Icarus => "icarus",
    }
}

enum Limited {
    Done(i32, String),
    TimedOut,
    Killed(i32),
}

/// Run a command with a time limit, its stdout and stderr collected. The command runs in a
/// process group of its own, so that a hang is ended with everything it started (a simulator
/// under a script).
fn run_limited(cmd: &mut Command, timeout: Duration) -> Result<Limited, String> {
    use std::os::unix::process::CommandExt;
    let mut child = cmd.stdout(Stdio::piped()).stderr(Stdio::piped()).stdin(Stdio::null()).process_group(0).spawn().map_err(|e| format!("cannot start the DUT: {e}"))?;
    let group = child.id() as libc::pid_t;
    let mut out = child.stdout.take();
    let mut err = child.stderr.take();
    let reader = std::thread::spawn(move || {
        let mut s = String::new();
        if let Some(o) = out.as_mut() {
            let _ = o.read_to_string(&mut s);
        }
        if let Some(e) = err.as_mut() {
            let _ = e.read_to_string(&mut s);
        }
        s
    });
    let start = Instant::now();
    let status = loop {
        match child.try_wait() {
            Ok(Some(s)) => break s,
            Ok(None) if start.elapsed() > timeout => {
                // SAFETY: kill(2) with the negated id of the group the child leads.
                unsafe { libc::kill(-group, libc::SIGKILL) };
                let _ = child.wait();
                let _ = reader.join();
                return Ok(Limited::TimedOut);
            }
            Ok(None) => std::thread::sleep(Duration::from_millis(2)),
            Err(e) => return Err(format!("waiting for the DUT: {e}")),
        }
    };
    let text = reader.join().unwrap_or_default();
    use std::os::unix::process::ExitStatusExt;
    match (status.code(), status.signal()) {
        (Some(c), _) => Ok(Limited::Done(c, text)),
        (None, Some(sig)) => Ok(Limited::Killed(sig)),
        _ => Ok(Limited::Done(2, text)),
    }
}

/// `MISMATCH tick=<k> signal=<path> expected=<hex> got=<hex>`.
fn parse_mismatch(sc: &Scenario, line: &str, all: &str) -> Failure {
    let field = |k: &str| line.split_whitespace().find_map(|w| w.strip_prefix(k)).unwrap_or("?").to_string();
    let tick: u64 = field("tick=").parse().unwrap_or(0);
    let signal = field("signal=");
    // The block: of the first divergent register (the report lists a port before the register
    // that drives it), or the producer of a divergent internal signal.
    let block = all
        .lines()
        .filter(|l| l.starts_with("MISMATCH"))
        .filter_map(|l| l.split_whitespace().find_map(|w| w.strip_prefix("signal=")))
        .find_map(|sig| match sig.split_once('.') {
            Some(("internals", "fig17" | "fig18")) => Some("drive_interval"),
            Some(("internals", "kon" | "koff")) => Some("action_switching"),
            Some(("internals", "upd" | "first" | "chg_s" | "chg_c")) => Some("comparator_latch"),
            Some(("internals", "skip_clr")) => Some("register_file"),
            Some(("internals", _)) => None,
            Some((b, _)) => Some(b),
            None => None,
        })
        .unwrap_or("ports")
        .to_string();
    // internals are compared during cycle `tick`, the rest after edge `tick` (the end of cycle
    // `tick - 1`): the FIG. path of that cycle
    let cycle = if signal.starts_with("internals.") { Some(tick) } else { tick.checked_sub(1) };
    let mut f = dut_failure(sc, cycle, "dut", format!("the RTL diverges from the model: {line} ({} MISMATCH lines)", all.lines().filter(|l| l.starts_with("MISMATCH")).count()));
    f.tick = tick;
    f.signal = format!("pmu50.{signal}");
    f.expected = format!("0x{}", field("expected="));
    f.got = format!("0x{}", field("got="));
    f.block = block;
    f
}

fn dut_failure(sc: &Scenario, cycle: Option<u64>, kind: &str, detail: String) -> Failure {
    let fig = cycle.map_or_else(|| "-".to_string(), |c| fig_at(sc, c));
    Failure { kind: kind.into(), tick: cycle.map_or(0, |c| c + 1), signal: "dut".into(), expected: "-".into(), got: "-".into(), block: "-".into(), fig, detail }
}

/// The FIG. 17/18 path of bench cycle `cycle` (the edge at its end), from a run of the model.
pub fn fig_at(sc: &Scenario, cycle: u64) -> String {
    struct At(u64, Fig17, Fig18);
    impl Observer for At {
        fn tick(&mut self, v: &TickView<'_>) -> Result<(), SimError> {
            if v.tick == self.0 {
                self.1 = v.internals.fig17;
                self.2 = v.internals.fig18;
            }
            Ok(())
        }
    }
    let mut at = At(cycle, Fig17::Idle, Fig18::Idle);
    let mut short = sc.clone();
    short.ticks = short.ticks.min(cycle + 1);
    match sim::run(&short, SimOptions::default(), &mut [&mut at]) {
        Ok(_) => fig_path(at.1, at.2),
        Err(_) => "-".into(),
    }
}
