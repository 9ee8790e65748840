//! The build cache of RTL under test: where builds go ([`cache_dir`]), their keys ([`fnv`]) and
//! the record of the files a build read, with a hash of each ([`write_record`],
//! [`files_unchanged`]), so that a build whose inputs changed is made again.

use std::path::{Path, PathBuf};

/// Where builds of RTL under test go: `PMU50_CACHE_DIR`, or `$XDG_CACHE_HOME/pmu50`, or
/// `~/.cache/pmu50`, or `pmu50-cache` in the temporary folder.
pub fn cache_dir() -> PathBuf {
    let env = |k: &str| {
        std::env::var_os(k)
            .filter(|v| !v.is_empty())
            .map(PathBuf::from)
    };
    env("PMU50_CACHE_DIR")
        .or_else(|| env("XDG_CACHE_HOME").map(|p| p.join("pmu50")))
        .or_else(|| env("HOME").map(|p| p.join(".cache/pmu50")))
        .unwrap_or_else(|| std::env::temp_dir().join("pmu50-cache"))
}

/// A stable 64-bit hash (FNV-1a) for cache keys.
pub fn fnv(parts: &[&[u8]]) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for p in parts {
        for &b in p.iter().chain(&[0xffu8]) {
            h = (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3);
        }
    }
    h
}

/// Write a record of files and their hashes (a build's or an elaboration's inputs).
pub fn write_record(record: &Path, files: &[PathBuf]) {
    let mut files: Vec<&PathBuf> = files.iter().filter(|f| f.is_file()).collect();
    files.sort();
    files.dedup();
    let text: String = files
        .iter()
        .map(|f| {
            format!(
                "{:016x} {}\n",
                std::fs::read(f).map(|b| fnv(&[&b])).unwrap_or(0),
                f.display()
            )
        })
        .collect();
    let tmp = record.with_extension("tmp");
    if std::fs::write(&tmp, text).is_ok() {
        let _ = std::fs::rename(&tmp, record);
    }
}

/// Whether every file of a record still has its hash (an empty or missing record: no).
pub fn files_unchanged(record: &Path) -> bool {
    let Ok(text) = std::fs::read_to_string(record) else {
        return false;
    };
    !text.is_empty()
        && text.lines().all(|l| match l.split_once(' ') {
            Some((h, p)) => std::fs::read(p)
                .map(|b| format!("{:016x}", fnv(&[&b])) == h)
                .unwrap_or(false),
            None => false,
        })
}
