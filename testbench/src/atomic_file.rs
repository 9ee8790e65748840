//! Atomic output files: nothing the CLI writes is ever lost or left half-written.
//!
//! Every output (`.vcd`, `.gtkw`, `.log`, vectors, random scenarios) is written to a temporary
//! file `.<name>.<pid>.<random>.tmp` in the folder of its final path, and renamed into place only when
//! the whole run succeeded ([`Batch::commit`]). rename(2) replaces whatever is at the final path,
//! a symlink included: the link itself is replaced, its target is never written.
//!
//! Durability: before the renames every file's data is flushed to the disk (`fdatasync`), so
//! that after a crash of the operating system or a power loss the final path holds the old file
//! or the complete new one, on any file system. `PMU50_SYNC=0` in the environment
//! ([`SYNC_VAR`]) leaves out that flush (the renames stay): an interrupted run still leaves the
//! previous files as they were, but a crash of the system within seconds of the run can leave
//! a new file empty or incomplete where the file system does not order a replacing rename
//! after the file's data (ext4's default `auto_da_alloc` does). A run on a disk shared with
//! other writers then waits for no journal commit: 2-40 ms of wall time for `pmu50 run --trace
//! all` on a busy machine (docs/performance.md).
//!
//! Interruptions:
//! - an error (disk full, a refused write) drops the temporary files, the previous outputs stay;
//! - SIGINT/SIGTERM ([`install_signal_cleanup`]): a thread removes every live temporary file and
//!   exits 130/143; a batch being renamed into place finishes first (it holds the registry
//!   lock), so the files of one run are either all old or all new;
//! - SIGKILL cannot be caught: at most a stray `.*.tmp` file is left, never a damaged final file;
//!   the next run writing the same output removes it (its process is gone).
//!
//! Paths that are not files: an output path that exists and is a character or block device, a
//! FIFO or a socket (or a symlink to one, such as `/proc/self/fd/1`) is refused with
//! [`OutputError::NotRegular`] and left as it was, checked when the output is staged and again
//! just before the rename. A folder is refused ([`OutputError::IsDir`]); a symlink to a regular
//! file or to a folder is replaced by the new file (its target is left alone). `-` is standard
//! output where a command offers it ([`Sink`]).

use std::fs::Permissions;
use std::io::{self, Write};
use std::os::unix::fs::PermissionsExt;
use std::path::{Path, PathBuf};
use std::sync::{Mutex, MutexGuard};

/// Temporary files alive in this process, removed by the signal thread.
static LIVE: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

fn live() -> MutexGuard<'static, Vec<PathBuf>> {
    LIVE.lock().unwrap_or_else(|p| p.into_inner())
}

/// Cleanups that owners of other resources (child processes, scratch folders) add with
/// [`on_signal`]; the signal thread runs them, in the order added, before it removes the
/// temporary files.
static ON_SIGNAL: Mutex<Vec<fn()>> = Mutex::new(Vec::new());

/// Run `cleanup` when SIGINT or SIGTERM ends the process ([`install_signal_cleanup`]). Adding
/// the same function twice runs it once.
pub fn on_signal(cleanup: fn()) {
    let mut v = ON_SIGNAL.lock().unwrap_or_else(|p| p.into_inner());
    if !v.iter().any(|f| std::ptr::fn_addr_eq(*f, cleanup)) {
        v.push(cleanup);
    }
}

/// The cleanups added so far (a copy: a cleanup may take its time without holding the lock).
fn signal_cleanups() -> Vec<fn()> {
    ON_SIGNAL.lock().unwrap_or_else(|p| p.into_inner()).clone()
}

/// Errors writing output files.
#[derive(Debug, thiserror::Error)]
pub enum OutputError {
    #[error("{}: cannot create the output folder: {source}", path.display())]
    Folder {
        path: PathBuf,
        #[source]
        source: io::Error,
    },
    #[error("{}: cannot create a temporary file beside it: {source}", path.display())]
    Create {
        path: PathBuf,
        #[source]
        source: io::Error,
    },
    #[error("{}: cannot write (the previous file is left as it was): {source}", path.display())]
    Write {
        path: PathBuf,
        #[source]
        source: io::Error,
    },
    #[error("{}: cannot rename the complete file into place: {source}", path.display())]
    Rename {
        path: PathBuf,
        #[source]
        source: io::Error,
    },
    #[error("{}: is a directory; an output file cannot replace it", path.display())]
    IsDir { path: PathBuf },
    #[error("{}: is a {kind}, not a regular file; an output file never replaces it (give the path of a file{})", path.display(), if *stdout_ok { ", or - for standard output" } else { "" })]
    NotRegular {
        path: PathBuf,
        kind: &'static str,
        stdout_ok: bool,
    },
    #[error("{}: cannot remove the stale file: {source}", path.display())]
    Remove {
        path: PathBuf,
        #[source]
        source: io::Error,
    },
}

/// The environment variable that says whether output files are flushed to the disk before they
/// are renamed into place: `1` (unset: the default) or `0` (see the module documentation).
pub const SYNC_VAR: &str = "PMU50_SYNC";

/// Whether output files are flushed to the disk before the rename ([`SYNC_VAR`]); an error
/// message for a value other than `0` or `1`. Read once per process: every file of a run is
/// written the same way.
pub fn sync_to_disk() -> Result<bool, String> {
    static ONCE: std::sync::OnceLock<Result<bool, String>> = std::sync::OnceLock::new();
    ONCE.get_or_init(read_sync_var).clone()
}

fn read_sync_var() -> Result<bool, String> {
    match std::env::var(SYNC_VAR) {
        Ok(v) if v == "0" => Ok(false),
        Ok(v) if v == "1" => Ok(true),
        Ok(v) => Err(format!("{SYNC_VAR}={v:?}: use 1 (flush output files to the disk before renaming them into place, the default) or 0 (rename without the flush)")),
        Err(std::env::VarError::NotPresent) => Ok(true),
        Err(std::env::VarError::NotUnicode(v)) => Err(format!("{SYNC_VAR}={v:?}: use 1 or 0")),
    }
}

/// Bytes written since the last write-back was started before the next one is
/// ([`AtomicFile`]'s writes).
const WRITE_BEHIND: u64 = 256 << 10;

/// An output file being written: a temporary file beside `dest`.
///
/// Its data goes to the disk while the run goes on: every [`WRITE_BEHIND`] bytes written, the
/// write-back of those bytes is started without waiting for it (`sync_file_range` with
/// `SYNC_FILE_RANGE_WRITE`, Linux), so the `fdatasync` before the rename ([`Batch::commit`])
/// finds little left to write. This changes nothing in what is durable when: the rename still
/// waits for the whole file's `fdatasync`.
#[derive(Debug)]
pub struct AtomicFile {
    file: Option<tempfile::NamedTempFile>,
    dest: PathBuf,
    tmp: PathBuf,
    /// Bytes written through [`Write`].
    written: u64,
    /// Bytes whose write-back was started.
    started: u64,
    /// Whether the file is flushed before the rename ([`sync_to_disk`]), so its write-back is
    /// started on the way.
    behind: bool,
}

impl AtomicFile {
    /// Stage a new `dest`: a temporary file beside it (its folder must exist), renamed over
    /// `dest` only when its batch commits.
    pub fn stage(dest: &Path) -> Result<AtomicFile, OutputError> {
        if is_real_dir(dest) {
            return Err(OutputError::IsDir {
                path: dest.to_path_buf(),
            });
        }
        refuse_special(dest)?;
        let dir = match dest.parent() {
            Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
            _ => PathBuf::from("."),
        };
        let base = dest
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default();
        remove_strays(&dir, &base);
        let mut reg = live();
        // 0o666 less the umask, like File::create; the registry lock is held while the file is
        // created so that a signal cannot slip between creation and registration.
        let file = tempfile::Builder::new()
            .prefix(&format!(".{base}.{}.", std::process::id()))
            .suffix(".tmp")
            .permissions(Permissions::from_mode(0o666))
            .tempfile_in(&dir)
            .map_err(|source| OutputError::Create {
                path: dest.to_path_buf(),
                source,
            })?;
        let tmp = file.path().to_path_buf();
        reg.push(tmp.clone());
        Ok(AtomicFile {
            file: Some(file),
            dest: dest.to_path_buf(),
            tmp,
            written: 0,
            started: 0,
            behind: sync_to_disk().unwrap_or(true),
        })
    }

    /// The final path.
    pub fn dest(&self) -> &Path {
        &self.dest
    }

    /// The temporary path (for tests and messages).
    pub fn temp_path(&self) -> &Path {
        &self.tmp
    }

    fn inner(&mut self) -> io::Result<&mut tempfile::NamedTempFile> {
        self.file
            .as_mut()
            .ok_or_else(|| io::Error::other("output file already committed"))
    }

    /// Note `n` more bytes written; start the write-back of what was written since the last
    /// start once that is [`WRITE_BEHIND`] bytes or more.
    fn wrote(&mut self, n: usize) {
        self.written += n as u64;
        if self.behind && self.written - self.started >= WRITE_BEHIND {
            self.start_write_back();
        }
    }

    /// Start writing the bytes written since the last start to the disk, without waiting.
    /// Advisory: a file system that refuses it (or another OS) writes them at the `fdatasync`
    /// before the rename, which reports any error.
    fn start_write_back(&mut self) {
        if self.written == self.started {
            return;
        }
        #[cfg(target_os = "linux")]
        if let Some(f) = &self.file {
            use std::os::unix::io::AsRawFd;
            let (from, len) = (self.started, self.written - self.started);
            // SAFETY: sync_file_range only reads its arguments; the descriptor is open (owned
            // by `f`), and a failure is harmless (see above).
            unsafe {
                libc::sync_file_range(
                    f.as_file().as_raw_fd(),
                    from as libc::off64_t,
                    len as libc::off64_t,
                    libc::SYNC_FILE_RANGE_WRITE,
                );
            }
        }
        self.started = self.written;
    }

    /// Flush the file's data to the disk (`fdatasync`).
    fn sync(&self) -> Result<(), OutputError> {
        let file = self.file.as_ref().ok_or_else(|| OutputError::Write {
            path: self.dest.clone(),
            source: io::Error::other("output file already committed"),
        })?;
        file.as_file()
            .sync_data()
            .map_err(|source| OutputError::Write {
                path: self.dest.clone(),
                source,
            })
    }

    /// Rename into place (after [`AtomicFile::sync`]); the caller holds the registry lock (so
    /// this never locks it: on every path the temporary file is taken out before `self` is
    /// dropped).
    fn rename_into_place(mut self, reg: &mut Vec<PathBuf>) -> Result<(), OutputError> {
        let dest = self.dest.clone();
        reg.retain(|p| p != &self.tmp);
        // On an error the temporary file is dropped (deleted) on return.
        let file = self.file.take().ok_or_else(|| OutputError::Write {
            path: dest.clone(),
            source: io::Error::other("output file already committed"),
        })?;
        if is_real_dir(&dest) {
            return Err(OutputError::IsDir { path: dest });
        }
        // The path may have become a device or a FIFO while the run wrote.
        refuse_special(&dest)?;
        file.persist(&dest)
            .map(|_| ())
            .map_err(|e| OutputError::Rename {
                path: dest,
                source: e.error,
            })
    }

    /// Delete the temporary file; the caller holds the registry lock.
    fn discard(mut self, reg: &mut Vec<PathBuf>) {
        reg.retain(|p| p != &self.tmp);
        self.file = None;
    }
}

impl Write for AtomicFile {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        let n = self.inner()?.write(buf)?;
        self.wrote(n);
        Ok(n)
    }
    fn write_all(&mut self, buf: &[u8]) -> io::Result<()> {
        self.inner()?.write_all(buf)?;
        self.wrote(buf.len());
        Ok(())
    }
    fn flush(&mut self) -> io::Result<()> {
        self.inner()?.flush()
    }
}

impl Drop for AtomicFile {
    fn drop(&mut self) {
        if self.file.is_some() {
            let mut reg = live();
            // NamedTempFile removes the file when dropped.
            self.file = None;
            reg.retain(|p| p != &self.tmp);
        }
    }
}

/// What `p` is (following symlinks) when it exists and is a device, a FIFO or a socket.
pub fn special_kind(p: &Path) -> Option<&'static str> {
    use std::os::unix::fs::FileTypeExt;
    let ft = std::fs::metadata(p).ok()?.file_type();
    if ft.is_char_device() {
        Some("character device")
    } else if ft.is_block_device() {
        Some("block device")
    } else if ft.is_fifo() {
        Some("FIFO")
    } else if ft.is_socket() {
        Some("socket")
    } else {
        None
    }
}

/// [`OutputError::NotRegular`] when `dest` exists and is a device, a FIFO or a socket.
fn refuse_special(dest: &Path) -> Result<(), OutputError> {
    match special_kind(dest) {
        Some(kind) => Err(OutputError::NotRegular {
            path: dest.to_path_buf(),
            kind,
            stdout_ok: false,
        }),
        None => Ok(()),
    }
}

/// True when `a` and `b` exist and are the same file (device and inode; through symlinks and
/// hard links).
pub fn same_file(a: &Path, b: &Path) -> bool {
    use std::os::unix::fs::MetadataExt;
    match (std::fs::metadata(a), std::fs::metadata(b)) {
        (Ok(x), Ok(y)) => x.dev() == y.dev() && x.ino() == y.ino(),
        _ => false,
    }
}

/// Where a command with `-o FILE` writes: a staged [`AtomicFile`], or standard output for `-`
/// (streamed as it is produced; nothing to rename).
pub enum Sink {
    File(AtomicFile),
    Stdout(io::Stdout),
}

impl Sink {
    /// `-` is standard output; any other path is staged (refused when it is a folder, a device,
    /// a FIFO or a socket; the message then mentions `-`).
    pub fn open(dest: &Path) -> Result<Sink, OutputError> {
        if dest.as_os_str() == "-" {
            return Ok(Sink::Stdout(io::stdout()));
        }
        AtomicFile::stage(dest)
            .map(Sink::File)
            .map_err(|e| match e {
                OutputError::NotRegular { path, kind, .. } => OutputError::NotRegular {
                    path,
                    kind,
                    stdout_ok: true,
                },
                e => e,
            })
    }

    /// Add the file to `batch` (renamed into place when it commits); standard output is flushed.
    pub fn finish(self, batch: &mut Batch) -> Result<(), OutputError> {
        match self {
            Sink::File(f) => {
                batch.add(f);
                Ok(())
            }
            Sink::Stdout(mut o) => o.flush().map_err(|source| OutputError::Write {
                path: PathBuf::from("-"),
                source,
            }),
        }
    }
}

impl Write for Sink {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        match self {
            Sink::File(f) => f.write(buf),
            Sink::Stdout(o) => o.write(buf),
        }
    }
    fn write_all(&mut self, buf: &[u8]) -> io::Result<()> {
        match self {
            Sink::File(f) => f.write_all(buf),
            Sink::Stdout(o) => o.write_all(buf),
        }
    }
    fn flush(&mut self) -> io::Result<()> {
        match self {
            Sink::File(f) => f.flush(),
            Sink::Stdout(o) => o.flush(),
        }
    }
}

/// A folder (not a symlink to one: rename replaces a symlink whatever it points at).
fn is_real_dir(p: &Path) -> bool {
    std::fs::symlink_metadata(p).is_ok_and(|m| m.file_type().is_dir())
}

/// Remove temporary files `.<base>.<pid>.*.tmp` in `dir` left by a process that no longer runs
/// (a run killed by SIGKILL): the next run that writes the same output cleans up after it.
fn remove_strays(dir: &Path, base: &str) {
    let Ok(rd) = std::fs::read_dir(dir) else {
        return;
    };
    let prefix = format!(".{base}.");
    for e in rd.flatten() {
        let name = e.file_name().to_string_lossy().into_owned();
        let Some(rest) = name
            .strip_prefix(&prefix)
            .filter(|_| name.ends_with(".tmp"))
        else {
            continue;
        };
        let Some(pid) = rest.split('.').next().and_then(|p| p.parse::<u32>().ok()) else {
            continue;
        };
        if pid != std::process::id()
            && !Path::new(&format!("/proc/{pid}")).exists()
            && e.file_type().is_ok_and(|t| t.is_file())
        {
            let _ = std::fs::remove_file(e.path());
        }
    }
}

/// Write a whole small file atomically (e.g. a `.gtkw` or a random scenario).
pub fn write_atomic(dest: &Path, bytes: &[u8]) -> Result<AtomicFile, OutputError> {
    let mut f = AtomicFile::stage(dest)?;
    f.write_all(bytes).map_err(|source| OutputError::Write {
        path: dest.to_path_buf(),
        source,
    })?;
    Ok(f)
}

/// The files of one run, renamed into place together, in the order they were added (the
/// `.gtkw` last), and stale files to remove at the same moment.
#[derive(Debug, Default)]
pub struct Batch {
    files: Vec<AtomicFile>,
    last: Option<AtomicFile>,
    stale: Vec<PathBuf>,
}

impl Batch {
    pub fn new() -> Batch {
        Batch::default()
    }

    pub fn add(&mut self, f: AtomicFile) {
        self.files.push(f);
    }

    /// The file renamed last (the `.gtkw`, so that it never points at a file not yet in place).
    pub fn set_last(&mut self, f: AtomicFile) {
        self.last = Some(f);
    }

    /// Remove `path` when the batch is committed (when it exists).
    pub fn remove_stale(&mut self, path: PathBuf) {
        self.stale.push(path);
    }

    /// Final paths of the files in this batch.
    pub fn paths(&self) -> Vec<PathBuf> {
        self.files
            .iter()
            .chain(&self.last)
            .map(|f| f.dest.clone())
            .collect()
    }

    /// Rename every file into place. A signal arriving meanwhile waits until all are renamed.
    pub fn commit(self) -> Result<(), OutputError> {
        let mut reg = live();
        let Batch { files, last, stale } = self;
        // Every file's remaining bytes on their way to the disk at once, then every file's
        // `fdatasync` (the later ones mostly find their data written and their metadata in the
        // journal commit of the first); nothing is renamed before all are on the disk. (An
        // `fdatasync` on a thread of each measured no faster on a busy machine: the threads
        // waited for a core.)
        let mut all: Vec<AtomicFile> = files.into_iter().chain(last).collect();
        // A bad value was refused when the command started (`pmu50`'s main); here it syncs.
        let sync = sync_to_disk().unwrap_or(true);
        if sync {
            for f in all.iter_mut() {
                f.start_write_back();
            }
        }
        if let Err(e) = if sync { sync_all(&all) } else { Ok(()) } {
            for f in all {
                f.discard(&mut reg);
            }
            return Err(e);
        }
        let mut result = Ok(());
        for f in all {
            if result.is_ok() {
                result = f.rename_into_place(&mut reg);
            } else {
                // A file failed: the ones after it (the `.gtkw` among them) stay as they were.
                f.discard(&mut reg);
            }
        }
        result?;
        for p in stale {
            match std::fs::remove_file(&p) {
                Ok(()) => {}
                Err(e) if e.kind() == io::ErrorKind::NotFound => {}
                Err(source) => return Err(OutputError::Remove { path: p, source }),
            }
        }
        Ok(())
    }
}

/// `fdatasync` every file, in order; the first error.
fn sync_all(files: &[AtomicFile]) -> Result<(), OutputError> {
    files.iter().try_for_each(AtomicFile::sync)
}

/// Create `dir` (and parents) for outputs.
pub fn create_dir(dir: &Path) -> Result<(), OutputError> {
    std::fs::create_dir_all(dir).map_err(|source| OutputError::Folder {
        path: dir.to_path_buf(),
        source,
    })
}

/// Remove every live temporary file (signal thread; also usable before an emergency exit).
pub fn remove_temporaries() {
    let mut reg = live();
    for p in reg.drain(..) {
        let _ = std::fs::remove_file(&p);
    }
    // Keep the lock until the process exits so that no new temporary file appears.
    std::mem::forget(reg);
}

/// On SIGINT or SIGTERM: run the cleanups of [`on_signal`], remove the temporary files and exit 130 or 143 (128 + signal number).
pub fn install_signal_cleanup() -> Result<(), io::Error> {
    use signal_hook::consts::{SIGINT, SIGTERM};
    let mut signals = signal_hook::iterator::Signals::new([SIGINT, SIGTERM])?;
    std::thread::Builder::new()
        .name("signal-cleanup".into())
        .spawn(move || {
            if let Some(sig) = signals.forever().next() {
                for cleanup in signal_cleanups() {
                    cleanup();
                }
                remove_temporaries();
                std::process::exit(128 + sig);
            }
        })?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dir(tag: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("pmu50-atomic-{tag}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).unwrap();
        d
    }

    fn names(d: &Path) -> Vec<String> {
        let mut v: Vec<String> = std::fs::read_dir(d)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        v.sort();
        v
    }

    #[test]
    fn nothing_appears_until_commit_and_drop_leaves_the_old_file() {
        let d = dir("drop");
        let p = d.join("a.vcd");
        std::fs::write(&p, "old").unwrap();
        {
            let mut f = AtomicFile::stage(&p).unwrap();
            f.write_all(b"new, half").unwrap();
            assert_eq!(std::fs::read_to_string(&p).unwrap(), "old");
            assert_eq!(names(&d).len(), 2, "the temporary file is beside it");
        }
        assert_eq!(names(&d), ["a.vcd"]);
        assert_eq!(std::fs::read_to_string(&p).unwrap(), "old");
        // Other tests of this process may hold temporary files of their own at this moment.
        assert!(
            !live().iter().any(|t| t.starts_with(&d)),
            "no temporary file of this folder stays registered"
        );
        std::fs::remove_dir_all(&d).ok();
    }

    #[test]
    fn commit_replaces_a_symlink_and_leaves_its_target_alone() {
        let d = dir("link");
        let target = d.join("precious.txt");
        std::fs::write(&target, "keep me").unwrap();
        let p = d.join("a.gtkw");
        std::os::unix::fs::symlink(&target, &p).unwrap();
        let mut b = Batch::new();
        b.add(write_atomic(&p, b"save file").unwrap());
        b.remove_stale(d.join("a.log"));
        b.commit().unwrap();
        assert_eq!(std::fs::read_to_string(&target).unwrap(), "keep me");
        assert!(!std::fs::symlink_metadata(&p)
            .unwrap()
            .file_type()
            .is_symlink());
        assert_eq!(std::fs::read_to_string(&p).unwrap(), "save file");
        assert_eq!(names(&d), ["a.gtkw", "precious.txt"]);
        // A symlink to a folder is replaced as well; the folder stays.
        let folder = d.join("folder");
        std::fs::create_dir(&folder).unwrap();
        std::os::unix::fs::symlink(&folder, d.join("b.vcd")).unwrap();
        let mut b = Batch::new();
        b.add(write_atomic(&d.join("b.vcd"), b"vcd").unwrap());
        b.commit().unwrap();
        assert_eq!(std::fs::read_to_string(d.join("b.vcd")).unwrap(), "vcd");
        assert!(folder.is_dir());
        std::fs::remove_dir_all(&d).ok();
    }

    #[test]
    fn a_directory_at_the_output_path_is_an_error() {
        let d = dir("isdir");
        std::fs::create_dir(d.join("a.vcd")).unwrap();
        assert!(matches!(
            AtomicFile::stage(&d.join("a.vcd")),
            Err(OutputError::IsDir { .. })
        ));
        std::fs::remove_dir_all(&d).ok();
    }

    #[test]
    fn a_failed_rename_discards_the_rest_of_the_batch() {
        let d = dir("fail");
        std::fs::write(d.join("b.gtkw"), "old save file").unwrap();
        let mut b = Batch::new();
        b.add(write_atomic(&d.join("a.vcd"), b"vcd").unwrap());
        b.set_last(write_atomic(&d.join("b.gtkw"), b"new save file").unwrap());
        std::fs::create_dir(d.join("a.vcd")).unwrap();
        assert!(matches!(b.commit(), Err(OutputError::IsDir { .. })));
        assert_eq!(names(&d), ["a.vcd", "b.gtkw"]);
        assert_eq!(
            std::fs::read_to_string(d.join("b.gtkw")).unwrap(),
            "old save file"
        );
        std::fs::remove_dir_all(&d).ok();
    }

    #[test]
    fn strays_of_dead_processes_are_removed_and_live_ones_kept() {
        let d = dir("strays");
        // pid 0x7fff_fff0 does not run; our own pid does.
        let dead = d.join(".a.vcd.2147483632.XyZ123.tmp");
        let alive = d.join(format!(".a.vcd.{}.AbC456.tmp", std::process::id()));
        let other = d.join(".b.vcd.2147483632.XyZ123.tmp");
        for p in [&dead, &alive, &other] {
            std::fs::write(p, "partial").unwrap();
        }
        let f = AtomicFile::stage(&d.join("a.vcd")).unwrap();
        assert!(!dead.exists(), "the dead run's temporary file is removed");
        assert!(
            alive.exists() && other.exists(),
            "a live process's and another output's are kept"
        );
        drop(f);
        std::fs::remove_dir_all(&d).ok();
    }

    #[test]
    fn write_behind_starts_on_the_way_and_keeps_every_byte() {
        let d = dir("behind");
        let p = d.join("a.vcd");
        std::fs::write(&p, "old").unwrap();
        let mut f = AtomicFile::stage(&p).unwrap();
        let mut want = Vec::new();
        let mut k = 0u32;
        while want.len() < 3 * WRITE_BEHIND as usize + 17 {
            // uneven pieces, through write_all and write
            let piece: Vec<u8> = (0..(k * 7919) % 70_001).map(|i| (i ^ k) as u8).collect();
            if k.is_multiple_of(2) {
                f.write_all(&piece).unwrap();
                want.extend_from_slice(&piece);
            } else {
                let n = f.write(&piece).unwrap();
                want.extend_from_slice(&piece[..n]);
            }
            assert_eq!(f.written, want.len() as u64);
            assert!(f.written - f.started < WRITE_BEHIND, "write-back started");
            k += 1;
        }
        assert!(f.started > 0 && f.started < f.written);
        assert_eq!(std::fs::read_to_string(&p).unwrap(), "old");
        let mut b = Batch::new();
        b.add(f);
        b.commit().unwrap();
        assert_eq!(std::fs::read(&p).unwrap(), want);
        std::fs::remove_dir_all(&d).ok();
    }

    #[test]
    fn stale_files_are_removed_on_commit() {
        let d = dir("stale");
        std::fs::write(d.join("a.log"), "old log").unwrap();
        let mut b = Batch::new();
        b.add(write_atomic(&d.join("a.vcd"), b"vcd").unwrap());
        b.remove_stale(d.join("a.log"));
        assert!(d.join("a.log").exists());
        b.commit().unwrap();
        assert_eq!(names(&d), ["a.vcd"]);
        std::fs::remove_dir_all(&d).ok();
    }
}
