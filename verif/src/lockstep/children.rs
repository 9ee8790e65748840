//! The child processes and scratch folders of a regression, ended and removed when a signal
//! interrupts it (the cleanup is added to `pmu50_testbench::atomic_file::on_signal`).

use std::io::Read;
use std::path::{Path, PathBuf};
use std::time::Duration;

/// Most bytes of a worker's log (the RTL's `$display` output) kept on disk and read back.
pub const LOG_KEEP: u64 = 64 * 1024;
/// A worker's log is cut back to its last [`LOG_KEEP`] bytes when it passes this size.
pub(super) const LOG_LIMIT: u64 = 4 << 20;

/// The process groups of the running DUT workers and simulators, ended by the signal handler
/// of an interrupted regression ([`kill_children`]).
pub(super) static CHILDREN: std::sync::Mutex<Vec<libc::pid_t>> = std::sync::Mutex::new(Vec::new());

/// Register a child process group (its leader's id) to be killed on an interrupt.
pub fn register_child(pgid: libc::pid_t) {
    pmu50_testbench::atomic_file::on_signal(cleanup_on_signal);
    CHILDREN
        .lock()
        .unwrap_or_else(|e| e.into_inner())
        .push(pgid);
}

/// Forget a child process group that has ended.
pub fn unregister_child(pgid: libc::pid_t) {
    CHILDREN
        .lock()
        .unwrap_or_else(|e| e.into_inner())
        .retain(|&p| p != pgid);
}

/// Kill every registered child process group (on SIGINT or SIGTERM, before the exit).
pub fn kill_children() {
    // try_lock: a signal can arrive while a job thread holds the lock for a moment
    for _ in 0..100 {
        if let Ok(c) = CHILDREN.try_lock() {
            for &g in c.iter() {
                // SAFETY: kill(2) with the negated id of a group a child leads.
                unsafe { libc::kill(-g, libc::SIGKILL) };
            }
            return;
        }
        std::thread::sleep(Duration::from_millis(1));
    }
}

/// The scratch folders of the running regression (vector files, worker logs), removed by
/// [`cleanup_on_signal`].
pub(super) static SCRATCH: std::sync::Mutex<Vec<PathBuf>> = std::sync::Mutex::new(Vec::new());

/// Register a scratch folder to be removed on an interrupt.
pub fn register_scratch(p: &Path) {
    pmu50_testbench::atomic_file::on_signal(cleanup_on_signal);
    SCRATCH
        .lock()
        .unwrap_or_else(|e| e.into_inner())
        .push(p.to_path_buf());
}

pub fn unregister_scratch(p: &Path) {
    SCRATCH
        .lock()
        .unwrap_or_else(|e| e.into_inner())
        .retain(|q| q != p);
}

/// On SIGINT or SIGTERM (added to `pmu50_testbench::atomic_file::on_signal` by the first
/// registration): kill every DUT worker and simulator with its
/// process group, and remove the scratch folders. An interrupted regression leaves neither.
pub fn cleanup_on_signal() {
    kill_children();
    for _ in 0..100 {
        if let Ok(s) = SCRATCH.try_lock() {
            for p in s.iter() {
                let _ = std::fs::remove_dir_all(p);
            }
            return;
        }
        std::thread::sleep(Duration::from_millis(1));
    }
}

/// The last `keep` bytes of a file, as text.
pub fn file_tail(path: &Path, keep: u64) -> String {
    use std::io::Seek;
    let Ok(mut f) = std::fs::File::open(path) else {
        return String::new();
    };
    let len = f.metadata().map_or(0, |m| m.len());
    let from = len.saturating_sub(keep);
    if f.seek(std::io::SeekFrom::Start(from)).is_err() {
        return String::new();
    }
    let mut b = Vec::new();
    let _ = f.take(keep).read_to_end(&mut b);
    String::from_utf8_lossy(&b).into_owned()
}
