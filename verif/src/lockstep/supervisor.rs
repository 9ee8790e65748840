//! The regression's side of a DUT worker: spawned, fed a seed, answered within the time limit,
//! killed with its process group when it hangs, restarted when it dies.

use super::children::*;
use super::protocol::*;
use pmu50_core::params::Params;
use std::io::{Read, Write};
use std::os::fd::AsRawFd;
use std::path::{Path, PathBuf};
use std::process::{Child, ChildStdin, ChildStdout, Command, Stdio};
use std::time::{Duration, Instant};

/// A running DUT worker.
pub struct Worker {
    pub(super) child: Child,
    pub(super) stdin: ChildStdin,
    pub(super) stdout: ChildStdout,
    pub(super) log: PathBuf,
    pub(super) buf: Vec<u8>,
    /// When the last seed was sent.
    pub(super) sent: Instant,
}

/// The `pmu50` executable that runs workers: `PMU50_EXE`, this one (under any name: a copy
/// renamed `pmu50-1.2` is still the command), or (when the caller is a test, bench or example
/// binary of target/<profile>/{deps,examples}/) the `pmu50` of the same target folder.
pub(super) fn worker_exe() -> Result<PathBuf, String> {
    if let Some(p) = std::env::var_os("PMU50_EXE") {
        return Ok(PathBuf::from(p));
    }
    let me = std::env::current_exe().map_err(|e| format!("cannot find this executable: {e}"))?;
    let in_target = me
        .parent()
        .and_then(|d| d.file_name())
        .is_some_and(|d| d == "deps" || d == "examples");
    if me.file_stem().is_some_and(|s| s == "pmu50") || !in_target {
        return Ok(me);
    }
    let beside = |up: usize, tail: &str| me.ancestors().nth(up).map(|d| d.join(tail));
    let p = [beside(2, "pmu50"), beside(3, "release/pmu50")]
        .into_iter()
        .flatten()
        .find(|p| p.is_file())
        .unwrap_or_else(|| PathBuf::from("pmu50"));
    if p.is_file() {
        Ok(p)
    } else {
        Err(format!(
            "the DUT worker needs the pmu50 executable: {} is missing (cargo build --release)",
            p.display()
        ))
    }
}

impl Worker {
    pub fn spawn(scratch: &Path) -> Result<Worker, String> {
        Worker::spawn_exe(&worker_exe()?, scratch)
    }

    /// A worker from this executable (`EXE dut-worker`), its stderr (the RTL's output) in a log
    /// of `scratch` opened for appending, so that it can be cut back while the worker writes.
    fn spawn_exe(exe: &Path, scratch: &Path) -> Result<Worker, String> {
        use std::os::unix::process::CommandExt;
        let (file, log) = tempfile::Builder::new()
            .prefix("dut-worker.")
            .suffix(".log")
            .tempfile_in(scratch)
            .map_err(|e| format!("a log for the DUT worker in {}: {e}", scratch.display()))?
            .keep()
            .map_err(|e| format!("a log for the DUT worker: {e}"))?;
        drop(file);
        let append = std::fs::OpenOptions::new()
            .append(true)
            .open(&log)
            .map_err(|e| format!("{}: {e}", log.display()))?;
        let mut child = Command::new(exe)
            .arg("dut-worker")
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::from(append))
            .process_group(0)
            .spawn()
            .map_err(|e| format!("cannot start the DUT worker: {e}"))?;
        register_child(child.id() as libc::pid_t);
        let (Some(stdin), Some(stdout)) = (child.stdin.take(), child.stdout.take()) else {
            let _ = child.kill();
            return Err("the DUT worker has no pipes".into());
        };
        Ok(Worker {
            child,
            stdin,
            stdout,
            log,
            buf: Vec::with_capacity(4096),
            sent: Instant::now(),
        })
    }

    /// Run one request. After [`Answer::TimedOut`] or [`Answer::Died`] the worker is gone: drop it.
    pub fn run(
        &mut self,
        kind: Request,
        lib: &Path,
        params: &Params,
        inputs: &[u32],
        timeout: Duration,
    ) -> Result<Answer, String> {
        self.send(kind, lib, params, inputs);
        self.receive(timeout)
    }

    /// A trace request ([`Request::Trace`]) of the edges `from..=to`.
    pub fn trace(
        &mut self,
        lib: &Path,
        params: &Params,
        inputs: &[u32],
        from: u64,
        to: u64,
        timeout: Duration,
    ) -> Result<Answer, String> {
        self.send_with(Request::Trace, lib, params, inputs, &[from, to]);
        self.receive(timeout)
    }

    /// A VCD request ([`Request::Vcd`]): the RTL's own waveform of ticks `from..=to` (a tick
    /// `ns_per_tick` ns long) written to `out`.
    #[allow(clippy::too_many_arguments)]
    pub fn vcd(
        &mut self,
        lib: &Path,
        params: &Params,
        inputs: &[u32],
        (from, to): (u64, u64),
        ns_per_tick: u64,
        out: &Path,
        timeout: Duration,
    ) -> Result<Answer, String> {
        let p = out.as_os_str().as_encoded_bytes();
        let mut t = Vec::with_capacity(4 + p.len());
        t.extend_from_slice(&(p.len() as u32).to_le_bytes());
        t.extend_from_slice(p);
        self.send_bytes(
            Request::Vcd,
            lib,
            params,
            inputs,
            &[from, to, ns_per_tick],
            &t,
        );
        self.receive(timeout)
    }

    /// Hand a request to the worker; [`Worker::receive`] takes its answer. The log of the
    /// previous request is emptied.
    pub fn send(&mut self, kind: Request, lib: &Path, params: &Params, inputs: &[u32]) {
        self.send_with(kind, lib, params, inputs, &[]);
    }

    /// A lockstep whose code coverage the worker writes to `out` before its reply.
    pub fn send_coverage(&mut self, lib: &Path, params: &Params, inputs: &[u32], out: &Path) {
        let p = out.as_os_str().as_encoded_bytes();
        let mut t = Vec::with_capacity(4 + p.len());
        t.extend_from_slice(&(p.len() as u32).to_le_bytes());
        t.extend_from_slice(p);
        self.send_bytes(Request::LockstepCoverage, lib, params, inputs, &[], &t);
    }

    fn send_with(
        &mut self,
        kind: Request,
        lib: &Path,
        params: &Params,
        inputs: &[u32],
        trailer: &[u64],
    ) {
        self.send_bytes(kind, lib, params, inputs, trailer, &[]);
    }

    fn send_bytes(
        &mut self,
        kind: Request,
        lib: &Path,
        params: &Params,
        inputs: &[u32],
        trailer: &[u64],
        bytes: &[u8],
    ) {
        let _ = std::fs::OpenOptions::new()
            .write(true)
            .open(&self.log)
            .and_then(|f| f.set_len(0));
        let path = lib.as_os_str().as_encoded_bytes();
        let mut req = Vec::with_capacity(4 + 1 + 4 + path.len() + 96 + 8 + 4 * inputs.len());
        req.extend_from_slice(MAGIC);
        req.push(kind as u8);
        req.extend_from_slice(&(path.len() as u32).to_le_bytes());
        req.extend_from_slice(path);
        for (_, v) in params.hdl_parameters() {
            req.extend_from_slice(&v.to_le_bytes());
        }
        req.extend_from_slice(&(inputs.len() as u64).to_le_bytes());
        for w in inputs {
            req.extend_from_slice(&w.to_le_bytes());
        }
        for t in trailer {
            req.extend_from_slice(&t.to_le_bytes());
        }
        req.extend_from_slice(bytes);
        self.sent = Instant::now();
        // The worker reads a whole request before it works on it, so this write ends unless it
        // died (EPIPE), which `receive` reports.
        let _ = self.stdin.write_all(&req).and_then(|()| self.stdin.flush());
    }

    /// Cut the log back to its last [`LOG_KEEP`] bytes once it passes [`LOG_LIMIT`]: an RTL
    /// that prints in a loop fills no disk.
    fn bound_log(&self) {
        if std::fs::metadata(&self.log).is_ok_and(|m| m.len() > LOG_LIMIT) {
            let keep = file_tail(&self.log, LOG_KEEP);
            if let Ok(f) = std::fs::OpenOptions::new().write(true).open(&self.log) {
                let _ = f.set_len(0);
                let _ = std::fs::OpenOptions::new()
                    .append(true)
                    .open(&self.log)
                    .and_then(|mut a| a.write_all(keep.as_bytes()));
            }
        }
    }

    /// The answer to the request [`Worker::send`] gave, within `timeout` from the send (an
    /// answer already written is taken even when the caller comes late).
    pub fn receive(&mut self, timeout: Duration) -> Result<Answer, String> {
        self.buf.clear();
        let fd = self.stdout.as_raw_fd();
        loop {
            if let Some(end) = self.buf.iter().position(|&b| b == b'\n') {
                let line = &self.buf[..end];
                return match serde_json::from_slice::<Reply>(line) {
                    Ok(r) => Ok(Answer::Reply(r)),
                    Err(e) => {
                        self.kill();
                        Err(format!(
                            "the DUT worker's reply is not one of the protocol: {e}"
                        ))
                    }
                };
            }
            if self.buf.len() > 64 << 20 {
                self.kill();
                return Err("the DUT worker's reply passed 64 MiB".into());
            }
            let left = timeout.saturating_sub(self.sent.elapsed());
            let mut pfd = libc::pollfd {
                fd,
                events: libc::POLLIN,
                revents: 0,
            };
            // wake at least every 200 ms to keep the RTL's log bounded
            let ms = if left.is_zero() {
                0
            } else {
                left.as_millis().clamp(1, 200) as i32
            };
            // SAFETY: one valid pollfd.
            let r = unsafe { libc::poll(&mut pfd, 1, ms) };
            if r < 0 {
                let e = std::io::Error::last_os_error();
                if e.kind() == std::io::ErrorKind::Interrupted {
                    continue;
                }
                self.kill();
                return Err(format!("waiting for the DUT worker: {e}"));
            }
            if r == 0 {
                self.bound_log();
                if left.is_zero() {
                    self.kill();
                    return Ok(Answer::TimedOut);
                }
                continue;
            }
            let mut chunk = [0u8; 65536];
            match self.stdout.read(&mut chunk) {
                Ok(0) => return Ok(Answer::Died(self.death())),
                Ok(n) => self.buf.extend_from_slice(&chunk[..n]),
                Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
                Err(e) => {
                    self.kill();
                    return Err(format!("reading the DUT worker: {e}"));
                }
            }
        }
    }

    fn kill(&mut self) {
        let g = self.child.id() as libc::pid_t;
        // SAFETY: kill(2) with the negated id of the group the child leads.
        unsafe { libc::kill(-g, libc::SIGKILL) };
        let _ = self.child.wait();
        unregister_child(g);
    }

    /// How the worker ended, with the last lines of its stderr.
    fn death(&mut self) -> String {
        use std::os::unix::process::ExitStatusExt;
        let how = match self.child.wait() {
            Ok(s) => match (s.code(), s.signal()) {
                (Some(c), _) => format!("the DUT ended its process (exit {c})"),
                (_, Some(sig)) => format!("the DUT crashed (signal {sig})"),
                _ => "the DUT ended its process".to_string(),
            },
            Err(e) => format!("the DUT worker ended ({e})"),
        };
        self.kill();
        let log = file_tail(&self.log, LOG_KEEP);
        let tail: Vec<&str> = log.lines().filter(|l| !l.trim().is_empty()).collect();
        let tail = tail[tail.len().saturating_sub(3)..].join(" | ");
        if tail.is_empty() {
            how
        } else {
            format!("{how}: {tail}")
        }
    }
}

impl Drop for Worker {
    fn drop(&mut self) {
        self.kill();
        let _ = std::fs::remove_file(&self.log);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A worker from a script just written: a test thread that forks meanwhile can hold the
    /// script open for writing a moment (ETXTBSY), so the start is tried again.
    fn spawn_fake(exe: &Path, dir: &Path) -> Worker {
        for _ in 0..200 {
            match Worker::spawn_exe(exe, dir) {
                Ok(w) => return w,
                Err(e) if e.contains("busy") => std::thread::sleep(Duration::from_millis(10)),
                Err(e) => panic!("{e}"),
            }
        }
        panic!("{} stays busy", exe.display())
    }

    fn fake_worker(dir: &Path, body: &str) -> PathBuf {
        use std::os::unix::fs::PermissionsExt;
        let p = dir.join("fake");
        let mut f = tempfile::NamedTempFile::new_in(dir).unwrap();
        f.write_all(format!("#!/bin/sh\n{body}\n").as_bytes())
            .unwrap();
        f.persist(&p).unwrap();
        std::fs::set_permissions(&p, std::fs::Permissions::from_mode(0o755)).unwrap();
        p
    }

    #[test]
    fn a_worker_that_hangs_is_killed_at_the_time_limit_with_its_group() {
        let dir = tempfile::tempdir().unwrap();
        // the worker leaves a child of its own behind, as a simulator under a script would
        let exe = fake_worker(
            dir.path(),
            "sleep 60 & echo $! > \"$(dirname \"$0\")/child.pid\"; exec sleep 60",
        );
        let mut w = spawn_fake(&exe, dir.path());
        let t = Instant::now();
        let a = w
            .run(
                Request::Lockstep,
                Path::new("/nonexistent.so"),
                &Params::default(),
                &[0; 100],
                Duration::from_millis(300),
            )
            .unwrap();
        assert!(matches!(a, Answer::TimedOut));
        assert!(t.elapsed() < Duration::from_secs(10));
        let pid: i32 = std::fs::read_to_string(dir.path().join("child.pid"))
            .unwrap()
            .trim()
            .parse()
            .unwrap();
        std::thread::sleep(Duration::from_millis(100));
        // SAFETY: signal 0 only asks whether the process exists.
        let alive = unsafe { libc::kill(pid, 0) } == 0
            && !std::fs::read_to_string(format!("/proc/{pid}/stat"))
                .unwrap_or_default()
                .contains(") Z ");
        assert!(!alive, "the worker's own child {pid} survived the kill");
    }

    #[test]
    fn an_rtl_that_prints_without_end_fills_no_disk() {
        let dir = tempfile::tempdir().unwrap();
        // 3 MiB every 50 ms on stderr (the RTL's $display, about 180 MiB in 3 s), never a reply
        let exe = fake_worker(
            dir.path(),
            "while :; do head -c 3145728 /dev/zero | tr '\\0' x >&2; sleep 0.05; done",
        );
        let mut w = spawn_fake(&exe, dir.path());
        let log = w.log.clone();
        let mut biggest = 0u64;
        w.send(
            Request::Lockstep,
            Path::new("/nonexistent.so"),
            &Params::default(),
            &[0; 10],
        );
        // the log is cut back while the worker writes, at every poll
        let a = w.receive(Duration::from_secs(3)).unwrap();
        assert!(matches!(a, Answer::TimedOut));
        biggest = biggest.max(std::fs::metadata(&log).map_or(0, |m| m.len()));
        assert!(
            biggest <= 32 << 20,
            "the log stays bounded: {biggest} bytes"
        );
        drop(w);
        assert!(!log.exists(), "a worker's log goes with it");
    }

    #[test]
    fn a_simulator_output_is_kept_to_its_last_bytes() {
        let big: Vec<u8> = (0..10_000_000u32).map(|i| b'a' + (i % 26) as u8).collect();
        let kept = file_tail_of(&big);
        assert_eq!(kept.len() as u64, LOG_KEEP);
        assert!(big.ends_with(kept.as_bytes()));
    }

    /// [`file_tail`] of bytes written to a file.
    fn file_tail_of(b: &[u8]) -> String {
        let d = tempfile::tempdir().unwrap();
        let p = d.path().join("log");
        std::fs::write(&p, b).unwrap();
        file_tail(&p, LOG_KEEP)
    }

    #[test]
    fn a_worker_that_ends_reports_how_with_its_last_words() {
        let dir = tempfile::tempdir().unwrap();
        let exe = fake_worker(
            dir.path(),
            "head -c 4 > /dev/null; echo '%Error: planted: the RTL gave up' >&2; exit 3",
        );
        let mut w = spawn_fake(&exe, dir.path());
        match w
            .run(
                Request::Lockstep,
                Path::new("/nonexistent.so"),
                &Params::default(),
                &[0; 100],
                Duration::from_secs(20),
            )
            .unwrap()
        {
            Answer::Died(how) => assert_eq!(
                how,
                "the DUT ended its process (exit 3): %Error: planted: the RTL gave up"
            ),
            _ => panic!("expected the worker's death"),
        }
    }
}
