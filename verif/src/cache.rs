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

// ------------------------------------------------------------------ bounds and leases ----
//
// The cache holds builds of RTL under test: `verilator/<rtl>/<key>/` (a library),
// `verilator/_runtime_<key>/` (the Verilator runtime and its precompiled header),
// `icarus/<rtl>/<key>.vvp` (with `<key>.deps`). Each build has a lock file beside it,
// `<key>.lock`: a run that uses the build holds it shared (a lease) for as long as it runs; a
// build is made, and evicted, under it held exclusively. Its modification time is the build's
// last use. A build is made in a temporary folder `.build-<key>-*` (`.runtime-<key>-*`,
// `.compile-<key>-*`) and renamed into place complete, so a build killed half-way leaves only
// that folder, which the next trim removes once no process holds its lock. An RTL's folder also
// has a lease, `.lease`, held shared by every run on that RTL, and `rtl.txt`, the file list it
// was made from. Beside the builds: the HDL kits the binaries carry, unpacked (`hdl-<key>/`,
// leased by each process that uses one through `hdl-<key>.lock`), and the compiler cache of the
// builds' C++ (`ccache/`, leased through `ccache.lock`; its own cap, `CCACHE_MAXSIZE`).

use std::fs::File;
use std::time::SystemTime;

/// The default cap of the cache (`PMU50_CACHE_MAX`): 1 GiB. A plain build of the twin is about
/// 0.25 MB and the Verilator runtime, built once and shared by every RTL, 57 MB, so 1 GiB holds
/// the runtimes and the pools of about a hundred edits before the least recently used builds go.
pub const DEFAULT_MAX: u64 = 1 << 30;

/// The cap: `PMU50_CACHE_MAX` in bytes, with an optional suffix K, M or G (powers of 1024), or
/// [`DEFAULT_MAX`].
pub fn cache_max() -> Result<u64, String> {
    match std::env::var("PMU50_CACHE_MAX") {
        Ok(v) if !v.trim().is_empty() => parse_size(v.trim()).ok_or_else(|| {
            format!("PMU50_CACHE_MAX={v}: not a size; valid is a number of bytes with an optional K, M or G (e.g. 500M)")
        }),
        _ => Ok(DEFAULT_MAX),
    }
}

/// `500M`, `2G`, `123456`.
pub fn parse_size(s: &str) -> Option<u64> {
    let (num, mul) = match s.char_indices().last()? {
        (i, 'K' | 'k') => (&s[..i], 1u64 << 10),
        (i, 'M' | 'm') => (&s[..i], 1 << 20),
        (i, 'G' | 'g') => (&s[..i], 1 << 30),
        _ => (s, 1),
    };
    num.trim().parse::<u64>().ok()?.checked_mul(mul)
}

/// Lock `path` (created if missing), shared or exclusive, waiting for it or not: `None` when
/// `wait` is false and another process holds an incompatible lock. The lock is on the file the
/// path names when it is taken (an eviction may remove the path meanwhile: then again).
pub fn lock(path: &Path, exclusive: bool, wait: bool) -> std::io::Result<Option<File>> {
    use std::os::unix::fs::MetadataExt;
    loop {
        if let Some(dir) = path.parent() {
            std::fs::create_dir_all(dir)?;
        }
        let f = std::fs::OpenOptions::new()
            .create(true)
            .truncate(false)
            .write(true)
            .open(path)?;
        let got = match (exclusive, wait) {
            (true, true) => f.lock().map(|_| true),
            (false, true) => f.lock_shared().map(|_| true),
            (true, false) => match f.try_lock() {
                Ok(()) => Ok(true),
                Err(std::fs::TryLockError::WouldBlock) => Ok(false),
                Err(std::fs::TryLockError::Error(e)) => Err(e),
            },
            (false, false) => match f.try_lock_shared() {
                Ok(()) => Ok(true),
                Err(std::fs::TryLockError::WouldBlock) => Ok(false),
                Err(std::fs::TryLockError::Error(e)) => Err(e),
            },
        }?;
        if !got {
            return Ok(None);
        }
        // the path still names the file locked (not removed by an eviction meanwhile)
        let same = match (f.metadata(), std::fs::metadata(path)) {
            (Ok(a), Ok(b)) => a.ino() == b.ino() && a.dev() == b.dev(),
            _ => false,
        };
        if same {
            return Ok(Some(f));
        }
    }
}

/// Mark a build used now (its lock file's modification time).
pub fn touch(lock: &File) {
    let _ = lock.set_modified(SystemTime::now());
}

/// A build's lock file: `<key>.lock` beside the build `dir/<key>` (or `<key>.vvp`).
pub fn lock_of(build: &Path) -> PathBuf {
    let stem = build
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    build.with_file_name(format!("{stem}.lock"))
}

/// Take a build's lease (shared, waiting for a build or an eviction in progress) and mark it
/// used.
pub fn lease(build: &Path) -> std::io::Result<File> {
    let f = lock(&lock_of(build), false, true)?.ok_or_else(|| std::io::Error::other("no lock"))?;
    touch(&f);
    Ok(f)
}

/// A build of the cache, leased for as long as the returned lock file is held: `ready` says
/// whether the build at `build` is there and complete (and gives what the caller takes of it);
/// when it is not, `make` makes it under the build's lock held exclusively, so that another
/// process making the same build meanwhile is waited for and its build taken, and a build is
/// made once. The lease is taken before the build is looked at, so no trim removes it between
/// the look and the use.
pub fn obtain<T>(
    build: &Path,
    mut ready: impl FnMut() -> Option<T>,
    mut make: impl FnMut() -> Result<(), String>,
) -> Result<(File, T), String> {
    let lock_path = lock_of(build);
    let io = |e: std::io::Error| format!("{}: {e}", lock_path.display());
    for _ in 0..3 {
        let held = lease(build).map_err(io)?;
        if let Some(t) = ready() {
            return Ok((held, t));
        }
        drop(held);
        let building = lock(&lock_path, true, true)
            .map_err(io)?
            .ok_or_else(|| format!("{}: not locked", lock_path.display()))?;
        if ready().is_none() {
            make()?;
        }
        // the newest build of the cache: the last a trim would take, before the lease is back
        touch(&building);
    }
    Err(format!(
        "{}: the build was removed by a trim of the cache each time it was made; the cap \
         (PMU50_CACHE_MAX={}) is too small for the builds in use",
        build.display(),
        cache_max().unwrap_or(DEFAULT_MAX)
    ))
}

/// One build of the cache, as trimming and `pmu50 cache` see it.
#[derive(Clone, Debug)]
pub struct Unit {
    /// `verilator`, `icarus`, `runtime`, `kit` (an unpacked HDL kit) or `ccache`.
    pub kind: &'static str,
    /// The RTL's folder (for a runtime, the folder of the runtimes).
    pub rtl: PathBuf,
    /// Its files and folders, removed together.
    pub paths: Vec<PathBuf>,
    pub lock: PathBuf,
    pub size: u64,
    pub last_use: SystemTime,
    /// A temporary folder left by a build that did not finish.
    pub orphan: bool,
}

/// The size of a file or a folder (recursively), symbolic links not followed.
pub fn size_of(p: &Path) -> u64 {
    let Ok(m) = std::fs::symlink_metadata(p) else {
        return 0;
    };
    if m.is_dir() {
        std::fs::read_dir(p)
            .map(|d| d.flatten().map(|e| size_of(&e.path())).sum())
            .unwrap_or(0)
    } else {
        m.len()
    }
}

fn mtime(p: &Path) -> SystemTime {
    std::fs::metadata(p)
        .and_then(|m| m.modified())
        .unwrap_or(SystemTime::UNIX_EPOCH)
}

fn names(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .map(|d| {
            d.flatten()
                .map(|e| e.file_name().to_string_lossy().into_owned())
                .collect()
        })
        .unwrap_or_default();
    v.sort();
    v
}

/// The key of a temporary build folder `.build-<key>-XXXX` (`.runtime-`, `.compile-`).
fn orphan_key(name: &str) -> Option<(&'static str, &str)> {
    for (prefix, lock_prefix) in [
        (".build-", ""),
        (".compile-", ""),
        (".runtime-", "_runtime_"),
    ] {
        if let Some(rest) = name.strip_prefix(prefix) {
            let key = rest.rsplit_once('-').map_or(rest, |(k, _)| k);
            return Some((lock_prefix, key));
        }
    }
    None
}

/// Every build in the cache folder `root`.
pub fn units(root: &Path) -> Vec<Unit> {
    let mut out = Vec::new();
    let unit = |kind, rtl: &Path, paths: Vec<PathBuf>, lock: PathBuf, orphan| {
        let size = paths.iter().map(|p| size_of(p)).sum::<u64>() + size_of(&lock);
        let last_use = if lock.exists() {
            mtime(&lock)
        } else {
            paths
                .iter()
                .map(|p| mtime(p))
                .max()
                .unwrap_or(SystemTime::UNIX_EPOCH)
        };
        Unit {
            kind,
            rtl: rtl.to_path_buf(),
            paths,
            lock,
            size,
            last_use,
            orphan,
        }
    };
    for n in names(root) {
        let p = root.join(&n);
        if !p.is_dir() {
            continue;
        }
        let kind = if n.starts_with("hdl-") {
            "kit"
        } else if n == "ccache" {
            "ccache"
        } else {
            continue;
        };
        out.push(unit(
            kind,
            &p,
            vec![p.clone()],
            root.join(format!("{n}.lock")),
            false,
        ));
    }
    let vdir = root.join("verilator");
    for n in names(&vdir) {
        let p = vdir.join(&n);
        if let Some(key) = n.strip_prefix("_runtime_") {
            if p.is_dir() {
                out.push(unit(
                    "runtime",
                    &vdir,
                    vec![p.clone()],
                    vdir.join(format!("_runtime_{key}.lock")),
                    false,
                ));
            }
        } else if let Some((lp, key)) = orphan_key(&n) {
            out.push(unit(
                "runtime",
                &vdir,
                vec![p.clone()],
                vdir.join(format!("{lp}{key}.lock")),
                true,
            ));
        } else if p.is_dir() {
            for b in names(&p) {
                let bp = p.join(&b);
                if !bp.is_dir() {
                    continue;
                }
                if let Some((_, key)) = orphan_key(&b) {
                    out.push(unit(
                        "verilator",
                        &p,
                        vec![bp.clone()],
                        p.join(format!("{key}.lock")),
                        true,
                    ));
                } else if !b.starts_with('.') {
                    out.push(unit(
                        "verilator",
                        &p,
                        vec![bp.clone()],
                        p.join(format!("{b}.lock")),
                        false,
                    ));
                }
            }
        }
    }
    let idir = root.join("icarus");
    for n in names(&idir) {
        let p = idir.join(&n);
        if !p.is_dir() {
            continue;
        }
        for b in names(&p) {
            let bp = p.join(&b);
            if let Some(key) = b.strip_suffix(".vvp") {
                out.push(unit(
                    "icarus",
                    &p,
                    vec![bp.clone(), p.join(format!("{key}.deps"))],
                    p.join(format!("{key}.lock")),
                    false,
                ));
            } else if let Some((_, key)) = orphan_key(&b).filter(|_| bp.is_dir()) {
                out.push(unit(
                    "icarus",
                    &p,
                    vec![bp.clone()],
                    p.join(format!("{key}.lock")),
                    true,
                ));
            }
        }
    }
    out
}

/// What a trim or a clean removed.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Trimmed {
    pub removed: usize,
    pub freed: u64,
    /// Builds kept because a running regression uses them (or builds them).
    pub in_use: usize,
    pub size_after: u64,
}

/// Remove the least recently used builds of the cache folder `root` until it holds at most
/// `cap` bytes (`None`: remove every build), never one that a running process holds the lease
/// or the build lock of; then the folders of RTLs left without a build, unless a run holds
/// their lease. Temporary folders of builds that did not finish go first.
pub fn trim(root: &Path, cap: Option<u64>) -> Trimmed {
    let mut size = size_of(root);
    let mut t = Trimmed::default();
    let mut all = units(root);
    all.sort_by_key(|u| (!u.orphan, u.last_use));
    for u in &all {
        if cap.is_some_and(|c| size <= c) && !u.orphan {
            break;
        }
        match lock(&u.lock, true, false) {
            Ok(Some(_held)) => {
                for p in &u.paths {
                    if p.is_dir() {
                        let _ = std::fs::remove_dir_all(p);
                    } else {
                        let _ = std::fs::remove_file(p);
                    }
                }
                let _ = std::fs::remove_file(&u.lock);
                t.removed += 1;
                t.freed += u.size;
                size = size.saturating_sub(u.size);
            }
            _ => t.in_use += 1,
        }
    }
    // RTL folders without a build left (elaborations, probes, the list's name)
    let left = units(root);
    for kind in ["verilator", "icarus"] {
        let dir = root.join(kind);
        for n in names(&dir) {
            let p = dir.join(&n);
            if !p.is_dir() || n.starts_with('_') || n.starts_with('.') {
                continue;
            }
            if left.iter().any(|u| u.rtl == p) {
                continue;
            }
            if cap.is_some_and(|c| size <= c) && !is_stale(&p) {
                continue;
            }
            if let Ok(Some(_held)) = lock(&p.join(".lease"), true, false) {
                let s = size_of(&p);
                if std::fs::remove_dir_all(&p).is_ok() {
                    size = size.saturating_sub(s);
                    t.freed += s;
                }
            }
        }
    }
    t.size_after = size_of(root);
    t
}

/// An RTL folder whose last use is more than a day old.
fn is_stale(p: &Path) -> bool {
    SystemTime::now()
        .duration_since(mtime(&p.join(".lease")))
        .is_ok_and(|d| d.as_secs() > 86_400)
}

/// The lease of a folder of the cache root that a process uses for as long as it runs (an
/// unpacked HDL kit, the compiler cache): `<folder>.lock` held shared, taken once per folder
/// and kept until the process ends, so that no `pmu50 cache clean` removes the folder under it.
pub fn lease_for_process(folder: &Path) {
    static HELD: std::sync::Mutex<Vec<(PathBuf, File)>> = std::sync::Mutex::new(Vec::new());
    let mut held = HELD.lock().unwrap_or_else(|e| e.into_inner());
    if held.iter().any(|(p, _)| p == folder) {
        return;
    }
    if let Ok(f) = lease(folder) {
        held.push((folder.to_path_buf(), f));
    }
}

/// Trim the cache to its cap after a build (errors are not a run's business: the cap is kept
/// at the next trim).
pub fn trim_to_cap() {
    if let Ok(cap) = cache_max() {
        let root = cache_dir();
        if size_of(&root) > cap {
            trim(&root, Some(cap));
        }
    }
}

/// The lease of an RTL's cache folder for a run (and the name of its file list, for
/// `pmu50 cache`).
pub fn rtl_lease(folder: &Path, list: &Path) -> std::io::Result<File> {
    let f = lock(&folder.join(".lease"), false, true)?
        .ok_or_else(|| std::io::Error::other("no lock"))?;
    touch(&f);
    let name = folder.join("rtl.txt");
    let text = format!("{}\n", list.display());
    if std::fs::read_to_string(&name).ok().as_deref() != Some(text.as_str()) {
        let tmp = folder.join(format!(".rtl.txt.{}", std::process::id()));
        std::fs::write(&tmp, &text)?;
        std::fs::rename(&tmp, &name)?;
    }
    Ok(f)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn build(root: &Path, rtl: &str, key: &str, bytes: usize, age_s: u64) -> PathBuf {
        let d = root.join("verilator").join(rtl).join(key);
        std::fs::create_dir_all(&d).unwrap();
        std::fs::write(d.join("libpmu50_dut.so"), vec![0u8; bytes]).unwrap();
        let l = lock(&lock_of(&d), false, true).unwrap().unwrap();
        l.set_modified(SystemTime::now() - std::time::Duration::from_secs(age_s))
            .unwrap();
        d
    }

    #[test]
    fn sizes_parse_with_their_suffix() {
        assert_eq!(parse_size("500M"), Some(500 << 20));
        assert_eq!(parse_size("2G"), Some(2 << 30));
        assert_eq!(parse_size("123"), Some(123));
        assert_eq!(parse_size("12k"), Some(12 << 10));
        assert_eq!(parse_size("lots"), None);
        assert_eq!(parse_size(""), None);
    }

    #[test]
    fn a_trim_removes_the_least_recently_used_builds_first_and_never_a_leased_one() {
        let t = tempfile::tempdir().unwrap();
        let root = t.path();
        let old = build(root, "a", "k1", 100_000, 300);
        let leased = build(root, "a", "k2", 100_000, 400);
        let mid = build(root, "b", "k3", 100_000, 200);
        let new = build(root, "b", "k4", 100_000, 100);
        let held = lease(&leased).unwrap();
        // a lease marks the build used now: age it again
        held.set_modified(SystemTime::now() - std::time::Duration::from_secs(400))
            .unwrap();
        let r = trim(root, Some(250_000));
        assert!(!old.exists(), "the oldest unleased build goes first");
        assert!(leased.exists(), "a leased build stays, however old");
        assert!(!mid.exists());
        assert!(
            new.exists(),
            "the cache is under its cap once the older ones are gone"
        );
        assert_eq!(r.removed, 2);
        assert!(r.size_after <= 250_000, "{r:?}");
        drop(held);
        let r = trim(root, None);
        assert!(!leased.exists() && !new.exists(), "{r:?}");
        assert!(!root.join("verilator/a").exists() && !root.join("verilator/b").exists());
    }

    #[test]
    fn a_build_killed_half_way_is_removed_once_its_lock_is_free() {
        let t = tempfile::tempdir().unwrap();
        let rtl = t.path().join("verilator/r");
        let tmp = rtl.join(".build-k9-abc123");
        std::fs::create_dir_all(tmp.join("obj")).unwrap();
        std::fs::write(tmp.join("obj/unity.o"), b"half").unwrap();
        // a build in progress holds the key's lock: kept
        let building = lock(&rtl.join("k9.lock"), true, true).unwrap().unwrap();
        let u = units(t.path());
        assert!(u.iter().any(|u| u.orphan), "{u:?}");
        trim(t.path(), Some(u64::MAX));
        assert!(tmp.exists());
        drop(building);
        // killed: its lock is free, and even under the cap the leftover goes
        trim(t.path(), Some(u64::MAX));
        assert!(!tmp.exists());
        // and nothing at the key's place looks complete
        assert!(!rtl.join("k9").exists());
    }

    #[test]
    fn a_lock_taken_on_a_removed_lock_file_is_taken_again_on_the_new_one() {
        let t = tempfile::tempdir().unwrap();
        let p = t.path().join("k.lock");
        let a = lock(&p, false, true).unwrap().unwrap();
        assert!(
            lock(&p, true, false).unwrap().is_none(),
            "shared blocks exclusive"
        );
        drop(a);
        let b = lock(&p, true, false).unwrap().unwrap();
        std::fs::remove_file(&p).unwrap();
        drop(b);
        let c = lock(&p, true, false).unwrap();
        assert!(c.is_some() && p.exists());
    }
}
