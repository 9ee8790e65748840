//! Helpers shared by the command-line tests (`tests/cli.rs`, `tests/cli_faults.rs`,
//! `tests/trace_levels.rs`, `tests/diff_cli.rs`, `tests/fst_cli.rs`, `tests/regress.rs`): run the
//! `pmu50` binary from the project folder, its output as text, its exit code, a fresh temporary
//! folder per test, a file written in it.
#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

pub const BIN: &str = env!("CARGO_BIN_EXE_pmu50");

/// `pmu50 ARGS` run in the project folder (so `scenarios/...` paths work).
pub fn pmu50(args: &[&str]) -> Output {
    Command::new(BIN)
        .args(args)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .unwrap()
}

/// Standard output then standard error.
pub fn text(o: &Output) -> String {
    format!(
        "{}{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    )
}

/// An empty folder of this test binary and `tag` (whatever a previous run left is removed),
/// removed with what it holds when the test is done with it (dropped), unless the test failed:
/// then it stays for inspection and its path is printed.
pub fn tmp(tag: &str) -> TmpDir {
    let d = std::env::temp_dir().join(format!(
        "pmu50-{}-{tag}-{}",
        env!("CARGO_CRATE_NAME"),
        std::process::id()
    ));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    TmpDir(d)
}

/// A folder of [`tmp`]: a path (through `Deref`), removed when dropped.
pub struct TmpDir(PathBuf);

impl std::ops::Deref for TmpDir {
    type Target = Path;
    fn deref(&self) -> &Path {
        &self.0
    }
}

impl AsRef<Path> for TmpDir {
    fn as_ref(&self) -> &Path {
        &self.0
    }
}

impl Drop for TmpDir {
    fn drop(&mut self) {
        if std::thread::panicking() {
            eprintln!("the failed test's files are kept in {}", self.0.display());
        } else {
            let _ = std::fs::remove_dir_all(&self.0);
        }
    }
}

/// A path as the `&str` argument of a command line.
pub fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// Checks that `o` exited with `code`, that its output holds every string of `want` and no
/// panic message; its output.
pub fn expect(o: &Output, code: i32, want: &[&str]) -> String {
    let t = text(o);
    assert_eq!(o.status.code(), Some(code), "{t}");
    for w in want {
        assert!(t.contains(w), "output lacks `{w}`:\n{t}");
    }
    assert!(!t.contains("panicked"), "{t}");
    t
}

/// 50 ms with the key on all the time and the shaft turning fast: the most waveform a tick
/// writes (what the size estimates are bounded against).
pub const KEY_ON_FAST: &str = "duration = \"50 ms\"\n[motor]\nsegments = [ { kind = \"move\", duration = \"50 ms\", delta_deg = 2000.0 } ]\n[[events]]\nat = \"0 ms\"\nig = true\n";

/// Checks that `o` exited with `code` (the message shows its output).
pub fn expect_code(o: &Output, code: i32) {
    assert_eq!(o.status.code(), Some(code), "{}", text(o));
}

/// Standard output of `o`, after checking that it exited with `code` (the message shows both
/// streams).
pub fn exited(o: &Output, code: i32) -> String {
    let out = String::from_utf8_lossy(&o.stdout).into_owned();
    assert_eq!(
        o.status.code(),
        Some(code),
        "{out}{}",
        String::from_utf8_lossy(&o.stderr)
    );
    out
}

/// `bytes` written to `dir/name`; its path.
pub fn write(dir: &Path, name: &str, bytes: impl AsRef<[u8]>) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, bytes).unwrap();
    p
}
