//! Nothing is lost or half-written (README, "Outputs are never lost or half-written"): the real `pmu50` binary is interrupted
//! mid-run by SIGINT, SIGTERM and SIGKILL at random moments, and runs out of disk space; the
//! previous complete outputs must be byte-identical afterwards, and no temporary file may remain
//! (SIGKILL cannot be caught: there a stray temporary file is allowed, a damaged final file is
//! not).
//!
//! Disk full: a 1 MiB tmpfs mounted in a private mount namespace (`unshare -rm`, or `unshare -m`
//! as root). When neither works the test fails and says so: it never passes without having run.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant, SystemTime, UNIX_EPOCH};

const BIN: &str = env!("CARGO_BIN_EXE_pmu50");

fn tmp(tag: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("pmu50-int-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// A scenario named `victim`: short (the previous outputs) or long (the run that is interrupted;
/// mostly key off with the shaft turning, so the VCD grows steadily).
fn scenario(dir: &Path, file: &str, duration: &str) -> PathBuf {
    let p = dir.join(file);
    std::fs::write(
        &p,
        format!(
            "name = \"victim\"\nduration = \"{duration}\"\n[motor]\nstart_deg = 10.0\nsegments = [ {{ kind = \"move\", duration = \"{duration}\", delta_deg = 100000.0 }} ]\n\
             [[events]]\nat = \"0 ms\"\nig = true\n[[events]]\nat = \"5 ms\"\nig = false\n"
        ),
    )
    .unwrap();
    p
}

/// Every file in `d` but temporary files, with its bytes.
fn snapshot(d: &Path) -> BTreeMap<String, Vec<u8>> {
    std::fs::read_dir(d)
        .unwrap()
        .map(|e| e.unwrap())
        .filter(|e| {
            e.file_type().unwrap().is_file() && !e.file_name().to_string_lossy().ends_with(".tmp")
        })
        .map(|e| {
            (
                e.file_name().to_string_lossy().into_owned(),
                std::fs::read(e.path()).unwrap(),
            )
        })
        .collect()
}

fn temporaries(d: &Path) -> Vec<String> {
    std::fs::read_dir(d)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".tmp"))
        .collect()
}

/// Previous outputs of `victim` in `out`: a complete short run with `--log`.
fn previous_outputs(work: &Path, out: &Path) -> BTreeMap<String, Vec<u8>> {
    let short = scenario(work, "short.toml", "20 ms");
    let o = Command::new(BIN)
        .args([
            "run",
            short.to_str().unwrap(),
            "--log",
            "--out-dir",
            out.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let snap = snapshot(out);
    assert_eq!(
        snap.keys().collect::<Vec<_>>(),
        ["victim.gtkw", "victim.log", "victim.vcd"]
    );
    snap
}

/// Seeded xorshift for the random moments; the seed is printed on failure.
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0
    }
}

fn seed() -> u64 {
    SystemTime::now()
        .duration_since(UNIX_EPOCH)
        .map(|d| d.as_nanos() as u64)
        .unwrap_or(1)
        | 1
}

/// Start the long run and wait until it is writing (a temporary file exists), plus `extra`.
fn start_long(long: &Path, out: &Path, extra: Duration, ctx: &str) -> Child {
    let mut child = Command::new(BIN)
        .args([
            "run",
            long.to_str().unwrap(),
            "--log",
            "--out-dir",
            out.to_str().unwrap(),
        ])
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let t0 = Instant::now();
    let mine = format!(".{}.", child.id());
    while !temporaries(out).iter().any(|t| t.contains(&mine)) {
        assert!(
            t0.elapsed() < Duration::from_secs(30),
            "{ctx}: no temporary file appeared within 30 s"
        );
        assert!(
            child.try_wait().unwrap().is_none(),
            "{ctx}: the run ended before writing"
        );
        std::thread::sleep(Duration::from_millis(2));
    }
    std::thread::sleep(extra);
    assert!(
        child.try_wait().unwrap().is_none(),
        "{ctx}: the run finished before the signal: the scenario must be longer"
    );
    child
}

/// The shell's `kill` builtin (a fresh Debian has no /usr/bin/kill without procps).
fn kill(pid: u32, sig: &str) {
    let st = Command::new("sh")
        .args(["-c", &format!("kill -s {sig} {pid}")])
        .status()
        .unwrap();
    assert!(st.success(), "kill -s {sig} {pid} failed");
}

fn interrupt(sig: &str, want_code: Option<i32>, rounds: usize) {
    use std::os::unix::process::ExitStatusExt;
    let work = tmp(&format!("sig{sig}"));
    let out = work.join("out");
    std::fs::create_dir_all(&out).unwrap();
    let before = previous_outputs(&work, &out);
    let long = scenario(&work, "long.toml", "60 s");
    let s = seed();
    let mut rng = Rng(s);
    for round in 0..rounds {
        let delay = Duration::from_millis(rng.next() % 800);
        let ctx = format!("SIG{sig} round {round} seed {s} delay {delay:?}");
        let mut child = start_long(&long, &out, delay, &ctx);
        kill(child.id(), sig);
        let st = child.wait().unwrap();
        let mut stderr = String::new();
        if let Some(mut e) = child.stderr.take() {
            std::io::Read::read_to_string(&mut e, &mut stderr).unwrap();
        }
        match want_code {
            Some(c) => {
                assert_eq!(st.code(), Some(c), "{ctx}: exit status {st:?}\n{stderr}");
                assert!(!stderr.contains("panicked"), "{ctx}: {stderr}");
                assert_eq!(
                    temporaries(&out),
                    Vec::<String>::new(),
                    "{ctx}: temporary files left behind"
                );
            }
            None => {
                assert_eq!(st.signal(), Some(9), "{ctx}: {st:?}");
                // SIGKILL: stray temporary files are allowed (the run was writing when killed) ...
                assert!(
                    !temporaries(&out).is_empty(),
                    "{ctx}: a killed run leaves its temporary files"
                );
            }
        }
        let after = snapshot(&out);
        assert_eq!(
            after.keys().collect::<Vec<_>>(),
            before.keys().collect::<Vec<_>>(),
            "{ctx}"
        );
        for (k, v) in &before {
            assert!(
                after[k] == *v,
                "{ctx}: {k} changed ({} -> {} bytes)",
                v.len(),
                after[k].len()
            );
        }
    }
    if want_code.is_none() {
        // ... and the next run that writes the same outputs removes them.
        let short = work.join("short.toml");
        let o = Command::new(BIN)
            .args([
                "run",
                short.to_str().unwrap(),
                "--log",
                "--out-dir",
                out.to_str().unwrap(),
            ])
            .output()
            .unwrap();
        assert_eq!(
            o.status.code(),
            Some(0),
            "{}",
            String::from_utf8_lossy(&o.stderr)
        );
        assert_eq!(
            temporaries(&out),
            Vec::<String>::new(),
            "strays of killed runs are removed by the next run"
        );
    }
    std::fs::remove_dir_all(&work).ok();
}

#[test]
fn sigint_mid_run_keeps_previous_outputs_and_removes_temporaries() {
    interrupt("INT", Some(130), 3);
}

#[test]
fn sigterm_mid_run_keeps_previous_outputs_and_removes_temporaries() {
    interrupt("TERM", Some(143), 3);
}

#[test]
fn sigkill_mid_run_never_damages_a_final_file() {
    interrupt("KILL", None, 3);
}

/// The shell command run in a private mount namespace; `unshare -rm` first, then `unshare -m`.
fn in_private_mount_ns(script: &str) -> std::process::Output {
    let mut last = String::new();
    for args in [&["-rm"][..], &["-m"][..]] {
        match Command::new("unshare")
            .args(args)
            .args(["sh", "-c", script])
            .output()
        {
            Ok(o) if String::from_utf8_lossy(&o.stdout).contains("MOUNTED") => return o,
            Ok(o) => {
                last = format!(
                    "unshare {args:?}: {:?}\n{}{}",
                    o.status,
                    String::from_utf8_lossy(&o.stdout),
                    String::from_utf8_lossy(&o.stderr)
                )
            }
            Err(e) => last = format!("unshare {args:?}: {e}"),
        }
    }
    panic!(
        "the disk-full test needs a small tmpfs in a private mount namespace (util-linux `unshare -rm`, or `unshare -m` as root), \
         and could not make one here, so it did not run:\n{last}"
    );
}

#[test]
fn disk_full_keeps_previous_outputs_and_removes_temporaries() {
    let work = tmp("enospc");
    let prev = work.join("prev");
    let fs = work.join("fs");
    let after = work.join("after");
    for d in [&prev, &fs, &after] {
        std::fs::create_dir_all(d).unwrap();
    }
    let before = previous_outputs(&work, &prev);
    let long = scenario(&work, "long.toml", "2 s");
    let q = |p: &Path| format!("'{}'", p.display());
    let script = format!(
        "set -e; mount -t tmpfs -o size=1m tmpfs {fs}; echo MOUNTED; cp {prev}/* {fs}/; \
         set +e; {bin} run {long} --log --out-dir {fs} >/dev/null 2>{after}/stderr.txt; echo \"RC=$?\"; \
         df -k {fs} | tail -1; cp -a {fs}/. {after}/",
        fs = q(&fs),
        prev = q(&prev),
        bin = q(Path::new(BIN)),
        long = q(&long),
        after = q(&after),
    );
    let o = in_private_mount_ns(&script);
    let stdout = String::from_utf8_lossy(&o.stdout).into_owned();
    let stderr = std::fs::read_to_string(after.join("stderr.txt")).unwrap_or_default();
    assert!(
        stdout.contains("RC=2"),
        "the run must fail with exit 2 on a full disk:\n{stdout}\n{stderr}"
    );
    assert!(stderr.contains("No space left on device"), "{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    std::fs::remove_file(after.join("stderr.txt")).unwrap();
    assert_eq!(
        temporaries(&after),
        Vec::<String>::new(),
        "temporary files left on the full disk"
    );
    let got = snapshot(&after);
    assert_eq!(
        got.keys().collect::<Vec<_>>(),
        before.keys().collect::<Vec<_>>()
    );
    for (k, v) in &before {
        assert!(
            got[k] == *v,
            "{k} changed ({} -> {} bytes)",
            v.len(),
            got[k].len()
        );
    }
    std::fs::remove_dir_all(&work).ok();
}
