//! The files of a regression folder read back (`--resume`, `merge`, `closure`): untrusted input,
//! checked as strictly as the command line.
//!
//! - `regress.json` ([`parse_spec`]): every field in its valid range (a seed range within 2^64
//!   and at most [`MAX_SEEDS`] seeds, a shard `I/N` with `I < N`, the options the command line
//!   allows together), at most [`MAX_SPEC_BYTES`].
//! - `results.jsonl` ([`scan`]): read line by line, each line at most [`MAX_LINE_BYTES`]; a
//!   complete line is a seed result of the folder's seed range, with a known verdict and a
//!   coverage of the model's reachable bins; a seed present twice is refused. A last line cut
//!   by an interruption (no newline) is dropped, and `--resume` truncates it before appending.
//! - Every file is a regular file: a FIFO, a device, a socket or a symbolic link in its place is
//!   refused before it is opened (and checked again on the open file), as `--out` refuses them.
//!
//! A regression keeps only an index of its results in memory ([`Entry`], 24 bytes a seed); the
//! results themselves stay in `results.jsonl` and are read back one at a time ([`Store`]).

use crate::check::Failure;
use crate::error::RegressError;
use crate::spec::RunSpec;
use crate::spec::SeedResult;
use pmu50_coverage::layout;
use std::fs::File;
use std::io::{BufRead, BufReader, Read};
use std::os::unix::fs::{FileExt, OpenOptionsExt};
use std::path::{Path, PathBuf};

/// Most seeds of one regression (`--iterations`), 10^7: about 7 hours of model seeds on 2 cores,
/// or a job array of shards. The memory of a regression grows by about 150 bytes a seed (the
/// index of its results and the run list of `coverage.json`), 1.5 GB at this limit.
pub const MAX_SEEDS: u64 = 10_000_000;
/// Longest line of `results.jsonl` (a seed's result with its sparse coverage is a few kB).
pub const MAX_LINE_BYTES: usize = 1 << 20;
/// Largest `regress.json` (a few hundred bytes).
pub const MAX_SPEC_BYTES: u64 = 64 << 10;

fn line_err(path: &Path, line: u64, reason: impl std::fmt::Display) -> RegressError {
    RegressError::Line {
        path: path.to_path_buf(),
        line,
        reason: reason.to_string(),
    }
}

fn file_err(path: &Path, reason: impl std::fmt::Display) -> RegressError {
    RegressError::File {
        path: path.to_path_buf(),
        reason: reason.to_string(),
    }
}

/// What is at `p` when it is not a regular file (not following a symbolic link).
fn not_regular(ft: std::fs::FileType) -> Option<&'static str> {
    use std::os::unix::fs::FileTypeExt;
    if ft.is_file() {
        None
    } else if ft.is_symlink() {
        Some("symbolic link")
    } else if ft.is_dir() {
        Some("folder")
    } else if ft.is_fifo() {
        Some("FIFO")
    } else if ft.is_char_device() {
        Some("character device")
    } else if ft.is_block_device() {
        Some("block device")
    } else if ft.is_socket() {
        Some("socket")
    } else {
        Some("special file")
    }
}

fn refuse(path: &Path, kind: &str) -> RegressError {
    file_err(path, format!("is a {kind}, not a regular file; the files of a regression folder are regular files (replace it with the file itself)"))
}

/// Open a file of a regression folder, for reading or (with `append`) writing: `Ok(None)` when
/// it does not exist; refused when it is anything but a regular file.
pub fn open_regular(path: &Path, write: bool) -> Result<Option<File>, RegressError> {
    match std::fs::symlink_metadata(path) {
        Ok(m) => {
            if let Some(kind) = not_regular(m.file_type()) {
                return Err(refuse(path, kind));
            }
        }
        Err(e) if e.kind() == std::io::ErrorKind::NotFound && !write => return Ok(None),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {}
        Err(e) => return Err(file_err(path, e)),
    }
    // No symlink is followed and no FIFO blocks the open, whatever replaced the file meanwhile.
    let mut o = std::fs::OpenOptions::new();
    o.custom_flags(libc::O_NOFOLLOW | libc::O_NONBLOCK);
    if write {
        o.append(true).create(true);
    } else {
        o.read(true);
    }
    let f = match o.open(path) {
        Ok(f) => f,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound && !write => return Ok(None),
        Err(e) if e.raw_os_error() == Some(libc::ELOOP) => {
            return Err(refuse(path, "symbolic link"))
        }
        Err(e) => return Err(file_err(path, e)),
    };
    let m = f.metadata().map_err(|e| file_err(path, e))?;
    if let Some(kind) = not_regular(m.file_type()) {
        return Err(refuse(path, kind));
    }
    Ok(Some(f))
}

/// Read `regress.json` of `dir`, checked ([`parse_spec`]).
pub fn read_spec(dir: &Path) -> Result<RunSpec, RegressError> {
    Ok(read_spec_file(dir)?.spec)
}

/// `regress.json` of `dir` with its evidence (when sealed; an edited byte is an error).
pub fn read_spec_file(dir: &Path) -> Result<crate::evidence::SpecFile, RegressError> {
    let p = dir.join("regress.json");
    let Some(f) = open_regular(&p, false)? else {
        return Err(file_err(
            &p,
            "No such file or directory (not a regression folder: it has no regress.json)",
        ));
    };
    let mut text = String::new();
    f.take(MAX_SPEC_BYTES + 1)
        .read_to_string(&mut text)
        .map_err(|e| file_err(&p, e))?;
    if text.len() as u64 > MAX_SPEC_BYTES {
        return Err(file_err(
            &p,
            format!("larger than {MAX_SPEC_BYTES} bytes: not the regress.json pmu50 writes"),
        ));
    }
    parse_spec_file(&text, &p)
}

/// Parse and check the text of a `regress.json` (`path` names it in errors).
pub fn parse_spec(text: &str, path: &Path) -> Result<RunSpec, RegressError> {
    Ok(parse_spec_file(text, path)?.spec)
}

/// Parse and check the text of a `regress.json`, sealed or plain, with its evidence.
pub fn parse_spec_file(text: &str, path: &Path) -> Result<crate::evidence::SpecFile, RegressError> {
    let sf = crate::evidence::parse_spec_file(text, path)?;
    let spec = &sf.spec;
    spec.validate().map_err(|reason| file_err(path, reason))?;
    let model = pmu50_coverage::model_id(layout());
    if spec.model != model {
        return Err(file_err(path, format!("field `model`: sampled with coverage model {}, this pmu50 has {model}: merge and resume with the same version", spec.model)));
    }
    Ok(sf)
}

impl RunSpec {
    /// Every field in the range the command line allows; the message names the field and what
    /// is valid.
    pub fn validate(&self) -> Result<(), String> {
        if self.iterations == 0 || self.iterations > MAX_SEEDS {
            return Err(format!(
                "field `iterations`: {} seeds; valid is 1 to {MAX_SEEDS}",
                self.iterations
            ));
        }
        if self.start_seed.checked_add(self.iterations).is_none() {
            return Err(format!("field `start_seed`: {} + {} seeds passes 2^64; valid is start_seed + iterations <= {}", self.start_seed, self.iterations, u64::MAX));
        }
        if let Some(s) = &self.shard {
            if s.count == 0 || s.index >= s.count {
                return Err(format!(
                    "field `shard`: {}/{}; valid is index/count with 0 <= index < count",
                    s.index, s.count
                ));
            }
            if self.directed {
                return Err("fields `shard` and `directed`: a directed regression is never sharded (each batch steers by the seeds before it)".into());
            }
        }
        let backend = crate::dut::of(&self.dut).map_err(|e| format!("field `dut`: {e}"))?;
        backend
            .check(self.rtl.is_some(), self.map.is_some(), self.code_coverage)
            .map_err(|e| e.as_field())?;
        for (n, v) in &self.fixed.values {
            let mut p = pmu50_core::Params::default();
            if let Err(e) = p.set_hdl_parameter(n, *v) {
                return Err(format!("field `fixed`: {e}"));
            }
        }
        if (self.param_sets == 0) != self.pool.is_empty() {
            return Err(format!("fields `param_sets` and `pool`: {} set(s) in the pool of a regression of `param_sets` {}; valid is a pool with `param_sets` above 0, none with 0", self.pool.len(), self.param_sets));
        }
        if let Some(d) = self.pins.sync_depth {
            if !(1..=4).contains(&d) {
                return Err(format!("field `pins.sync_depth`: {d}; valid is 1 to 4"));
            }
        }
        if let Some(w) = self.pins.cnt_width {
            if !(2..=16).contains(&w) {
                return Err(format!("field `pins.cnt_width`: {w}; valid is 2 to 16"));
            }
        }
        Ok(())
    }
}

pub use crate::spec::Verdict;

/// Where a seed's result is: which results file, at which byte, how long its line is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Entry {
    pub seed: u64,
    pub offset: u64,
    pub len: u32,
    pub file: u16,
    pub verdict: Verdict,
}

/// Check one line of a results file: a seed result of `range`, its verdict and failure
/// consistent, its coverage within the model's reachable bins (added to `hits`).
pub fn check_line(
    line: &[u8],
    range: &std::ops::Range<u64>,
    hits: &mut [u64],
) -> Result<SeedResult, String> {
    let r: SeedResult =
        serde_json::from_slice(line).map_err(|e| format!("not a seed result: {e}"))?;
    if !range.contains(&r.seed) {
        return Err(format!(
            "field `seed`: {} is outside the seeds of this folder ({}..={})",
            r.seed,
            range.start,
            range.end.wrapping_sub(1)
        ));
    }
    // (an unknown verdict is refused by the parser: `verdict` is one of pass, fail, error)
    let v = r.verdict;
    match (v, &r.failure) {
        (Verdict::Pass, Some(_)) => {
            return Err("field `failure`: a passing seed has no failure".into())
        }
        (Verdict::Fail | Verdict::Error, None) => {
            return Err(format!(
                "field `failure`: a seed with verdict {} says what failed",
                v.name()
            ))
        }
        _ => {}
    }
    r.hits(hits)?;
    Ok(r)
}

/// A results file read and checked: its index entries (in file order) and the length of its
/// complete lines (a torn last line lies beyond it).
pub struct Scanned {
    pub entries: Vec<Entry>,
    pub complete_len: u64,
}

/// Read a results file line by line; `each` is given every checked result with its entry.
/// A missing file holds no result.
pub fn scan(
    path: &Path,
    file: u16,
    range: &std::ops::Range<u64>,
    hits: &mut [u64],
    mut each: impl FnMut(&SeedResult, &Entry),
) -> Result<Scanned, RegressError> {
    let Some(f) = open_regular(path, false)? else {
        return Ok(Scanned {
            entries: Vec::new(),
            complete_len: 0,
        });
    };
    scan_reader(
        BufReader::with_capacity(1 << 16, f),
        path,
        file,
        range,
        hits,
        &mut each,
    )
}

/// [`scan`] of any reader (`path` names it in errors).
pub fn scan_reader(
    mut r: impl BufRead,
    path: &Path,
    file: u16,
    range: &std::ops::Range<u64>,
    hits: &mut [u64],
    each: &mut dyn FnMut(&SeedResult, &Entry),
) -> Result<Scanned, RegressError> {
    let mut entries = Vec::new();
    let mut line = Vec::new();
    let mut offset = 0u64;
    let mut n = 0u64;
    let mut scratch = vec![0u64; hits.len()];
    loop {
        line.clear();
        let complete = read_line(&mut r, &mut line).map_err(|e| match e {
            LineError::Io(e) => file_err(path, e),
            LineError::TooLong => line_err(
                path,
                n + 1,
                format!("longer than {MAX_LINE_BYTES} bytes: not a seed result"),
            ),
        })?;
        if !complete {
            // End of file; bytes after the last newline are a torn line, dropped.
            break;
        }
        n += 1;
        let start = offset;
        offset += line.len() as u64;
        let body = &line[..line.len() - 1];
        if body.iter().all(|b| b.is_ascii_whitespace()) {
            continue;
        }
        scratch.iter_mut().for_each(|h| *h = 0);
        let res = check_line(body, range, &mut scratch).map_err(|e| line_err(path, n, e))?;
        for (t, h) in hits.iter_mut().zip(&scratch) {
            *t = t
                .checked_add(*h)
                .ok_or_else(|| line_err(path, n, "field `cov`: the hits overflow 64 bits"))?;
        }
        let e = Entry {
            seed: res.seed,
            offset: start,
            len: line.len() as u32,
            file,
            verdict: res.verdict,
        };
        each(&res, &e);
        entries.push(e);
    }
    Ok(Scanned {
        entries,
        complete_len: offset,
    })
}

enum LineError {
    Io(std::io::Error),
    TooLong,
}

/// One line into `out` with its newline: `Ok(true)`; `Ok(false)` at the end of the input (what
/// is in `out` then has no newline). Never holds more than [`MAX_LINE_BYTES`].
fn read_line(r: &mut impl BufRead, out: &mut Vec<u8>) -> Result<bool, LineError> {
    loop {
        let buf = match r.fill_buf() {
            Ok(b) => b,
            Err(e) if e.kind() == std::io::ErrorKind::Interrupted => continue,
            Err(e) => return Err(LineError::Io(e)),
        };
        if buf.is_empty() {
            return Ok(false);
        }
        let (take, done) = match buf.iter().position(|&b| b == b'\n') {
            Some(i) => (i + 1, true),
            None => (buf.len(), false),
        };
        if out.len() + take > MAX_LINE_BYTES + 1 {
            return Err(LineError::TooLong);
        }
        out.extend_from_slice(&buf[..take]);
        r.consume(take);
        if done {
            return Ok(true);
        }
    }
}

/// Line number of the byte at `offset` of `path` (for messages).
pub fn line_of(path: &Path, offset: u64) -> u64 {
    let Ok(Some(f)) = open_regular(path, false) else {
        return 0;
    };
    let mut n = 1;
    let mut left = offset;
    let mut r = BufReader::new(f);
    while left > 0 {
        let Ok(buf) = r.fill_buf() else { break };
        if buf.is_empty() {
            break;
        }
        let k = (buf.len() as u64).min(left) as usize;
        n += buf[..k].iter().filter(|&&b| b == b'\n').count() as u64;
        r.consume(k);
        left -= k as u64;
    }
    n
}

/// The results of one regression in its results files: an index sorted by seed, each result
/// read back from its file when asked for.
pub struct Store {
    pub files: Vec<PathBuf>,
    /// Sorted by seed, each seed once.
    pub entries: Vec<Entry>,
}

impl Store {
    /// Sort the entries of `files`; a seed present twice is refused, naming both places.
    pub fn new(files: Vec<PathBuf>, mut entries: Vec<Entry>) -> Result<Store, RegressError> {
        entries.sort_by_key(|e| (e.seed, e.file, e.offset));
        if let Some(w) = entries.windows(2).find(|w| w[0].seed == w[1].seed) {
            let (a, b) = (w[0], w[1]);
            let (pa, pb) = (&files[a.file as usize], &files[b.file as usize]);
            return Err(RegressError::Usage(format!(
                "seed {} is in {} (line {}) and in {} (line {}): each seed is run and merged once",
                a.seed,
                pa.display(),
                line_of(pa, a.offset),
                pb.display(),
                line_of(pb, b.offset)
            )));
        }
        entries.shrink_to_fit();
        Ok(Store { files, entries })
    }

    pub fn len(&self) -> usize {
        self.entries.len()
    }

    pub fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }

    pub fn contains(&self, seed: u64) -> bool {
        self.entries.binary_search_by_key(&seed, |e| e.seed).is_ok()
    }

    /// A reader of the results in seed order.
    pub fn reader(&self) -> Result<StoreReader<'_>, RegressError> {
        Ok(StoreReader {
            store: self,
            files: (0..self.files.len()).map(|_| None).collect(),
            open: 0,
            buf: Vec::new(),
        })
    }
}

/// Results files a [`StoreReader`] keeps open at once (a merge of thousands of shard folders
/// stays far below the usual limit of 1024 open files).
const MAX_OPEN: usize = 64;

/// Reads results of a [`Store`] back, one at a time; each file is opened when first read.
pub struct StoreReader<'a> {
    store: &'a Store,
    files: Vec<Option<File>>,
    open: usize,
    buf: Vec<u8>,
}

impl StoreReader<'_> {
    /// The line of `e` (without its newline), as it is in its file.
    pub fn line(&mut self, e: &Entry) -> Result<&[u8], RegressError> {
        let k = e.file as usize;
        let path = &self.store.files[k];
        if self.files[k].is_none() {
            if self.open >= MAX_OPEN {
                self.files.iter_mut().for_each(|f| *f = None);
                self.open = 0;
            }
            let f = open_regular(path, false)?
                .ok_or_else(|| file_err(path, "disappeared while the regression read it"))?;
            self.files[k] = Some(f);
            self.open += 1;
        }
        let f = self.files[k]
            .as_ref()
            .ok_or_else(|| file_err(path, "disappeared while the regression read it"))?;
        self.buf.resize(e.len as usize, 0);
        f.read_exact_at(&mut self.buf, e.offset).map_err(|err| {
            file_err(path, format!("changed while the regression read it: {err}"))
        })?;
        if self.buf.last() != Some(&b'\n') {
            return Err(file_err(path, "changed while the regression read it"));
        }
        Ok(&self.buf[..self.buf.len() - 1])
    }

    /// The result of `e`.
    pub fn result(&mut self, e: &Entry) -> Result<SeedResult, RegressError> {
        let path = self.store.files[e.file as usize].clone();
        let line = self.line(e)?;
        let r: SeedResult = serde_json::from_slice(line).map_err(|err| {
            file_err(
                &path,
                format!("changed while the regression read it: {err}"),
            )
        })?;
        if r.seed != e.seed {
            return Err(file_err(&path, "changed while the regression read it"));
        }
        Ok(r)
    }
}

/// A failure signature's seeds: how many, the smallest and its failure, and which results file
/// holds it.
#[derive(Clone, Debug)]
pub struct Group {
    pub count: u64,
    pub smallest: u64,
    pub failure: Failure,
    pub file: u16,
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spec() -> RunSpec {
        let text = format!(
            "{{\"tool\": \"pmu50 0.1.0\", \"model\": \"{}\", \"start_seed\": 1, \"iterations\": 100, \"directed\": false, \"check_spec\": false, \"dut\": \"model\"}}",
            pmu50_coverage::model_id(layout())
        );
        parse_spec(&text, Path::new("regress.json")).unwrap()
    }

    #[test]
    fn bad_specs_name_the_field_and_what_is_valid() {
        let base = serde_json::to_value(spec()).unwrap();
        let cases: [(&str, serde_json::Value, &str); 7] = [
            (
                "shard",
                serde_json::json!({"index": 0, "count": 0}),
                "field `shard`: 0/0",
            ),
            (
                "shard",
                serde_json::json!({"index": 7, "count": 3}),
                "field `shard`: 7/3",
            ),
            (
                "iterations",
                serde_json::json!(0),
                "field `iterations`: 0 seeds; valid is 1 to",
            ),
            (
                "iterations",
                serde_json::json!(1_000_000_000_000u64),
                "field `iterations`",
            ),
            ("start_seed", serde_json::json!(u64::MAX - 5), "passes 2^64"),
            ("rtl", serde_json::json!("x.f"), "field `rtl`"),
            (
                "pins",
                serde_json::json!({"sync_depth": 9}),
                "field `pins.sync_depth`: 9",
            ),
        ];
        for (field, value, want) in cases {
            let mut v = base.clone();
            v[field] = value;
            let e = parse_spec(&v.to_string(), Path::new("d/regress.json"))
                .unwrap_err()
                .to_string();
            assert!(
                e.starts_with("d/regress.json: ") && e.contains(want),
                "{field}: {e}"
            );
        }
        let e = parse_spec("{\"tool\": 1", Path::new("d/regress.json"))
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("d/regress.json: line 1:"), "{e}");
    }

    fn line(seed: u64, verdict: &str) -> String {
        let failure = if verdict == "pass" {
            String::new()
        } else {
            ",\"failure\":{\"kind\":\"dut\",\"tick\":5,\"signal\":\"pmu50.diag\",\"expected\":\"0\",\"got\":\"1\",\"block\":\"-\",\"fig\":\"-\",\"detail\":\"d\"}".to_string()
        };
        format!("{{\"seed\":{seed},\"verdict\":\"{verdict}\",\"ticks\":1,\"evaluated\":1,\"readouts_checked\":0,\"wall_ms\":0.5{failure},\"where\":{{\"host\":\"h\"}},\"cov\":\"0:1\"}}\n")
    }

    fn scan_text(text: &str) -> Result<Scanned, RegressError> {
        let mut hits = vec![0u64; layout().bins.len()];
        scan_reader(
            text.as_bytes(),
            Path::new("r/results.jsonl"),
            0,
            &(1..101),
            &mut hits,
            &mut |_, _| {},
        )
    }

    #[test]
    fn a_torn_last_line_is_dropped_and_its_bytes_lie_past_the_complete_length() {
        let good = line(1, "pass") + &line(2, "fail");
        let s = scan_text(&format!("{good}{{\"seed\":3,\"fa")).unwrap();
        assert_eq!(s.entries.len(), 2);
        assert_eq!(s.complete_len, good.len() as u64);
    }

    #[test]
    fn bad_lines_name_the_line_and_the_field() {
        let cases = [
            (
                line(1, "pass") + &line(500, "pass"),
                "line 2: field `seed`: 500 is outside the seeds of this folder (1..=100)",
            ),
            (
                line(1, "maybe"),
                "line 1: not a seed result: field `verdict`: `maybe`; valid is pass, fail or error",
            ),
            (
                line(1, "pass").replace("\"cov\":\"0:1\"", "\"cov\":\"99999:1\""),
                "line 1: coverage bin 99999",
            ),
            (
                line(1, "fail").replace(",\"failure\":{", ",\"x\":{"),
                "line 1: not a seed result: unknown field `x`",
            ),
            (
                line(1, "pass") + &"x".repeat(MAX_LINE_BYTES + 10),
                "line 2: longer than",
            ),
        ];
        for (text, want) in cases {
            let e = scan_text(&text).err().expect(want).to_string();
            assert!(
                e.starts_with("r/results.jsonl: ") && e.contains(want),
                "{e}"
            );
        }
    }

    #[test]
    fn a_seed_present_twice_is_refused() {
        let s = scan_text(&(line(1, "pass") + &line(2, "pass") + &line(1, "pass"))).unwrap();
        let e = Store::new(vec![PathBuf::from("r/results.jsonl")], s.entries)
            .err()
            .unwrap()
            .to_string();
        assert!(e.contains("seed 1 is in r/results.jsonl"), "{e}");
    }

    #[test]
    fn special_files_are_refused_before_they_are_opened() {
        let d = tempfile::tempdir().unwrap();
        let fifo = d.path().join("results.jsonl");
        let c = std::ffi::CString::new(fifo.to_str().unwrap()).unwrap();
        assert_eq!(unsafe { libc::mkfifo(c.as_ptr(), 0o600) }, 0);
        for write in [false, true] {
            let e = open_regular(&fifo, write).err().unwrap().to_string();
            assert!(e.contains("is a FIFO, not a regular file"), "{e}");
        }
        let link = d.path().join("regress.json");
        std::os::unix::fs::symlink("/dev/null", &link).unwrap();
        assert!(open_regular(&link, true)
            .err()
            .unwrap()
            .to_string()
            .contains("symbolic link"));
        assert!(open_regular(Path::new("/dev/zero"), false)
            .err()
            .unwrap()
            .to_string()
            .contains("character device"));
        assert!(open_regular(&d.path().join("none"), false)
            .unwrap()
            .is_none());
    }
}
