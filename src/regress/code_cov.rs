//! Code coverage of the RTL under test: `pmu50 regress --dut verilator --code-coverage`.
//!
//! The RTL is built with Verilator's line and toggle coverage (`--coverage-line
//! --coverage-toggle`, a build cached apart from the plain one). Each seed's RTL run counts in
//! its own DUT handle; the worker writes the counts of the run as a Verilator `coverage.dat`
//! and the regression reads them back ([`read_counts`]), so the code coverage of a seed is known
//! exactly, whatever worker ran it. A seed whose RTL run ended without a verdict (a hang, a
//! crash) and a seed the model failed before the RTL ran count nothing.
//!
//! Folder layout (`<out>/code/`):
//! - `parts/<first>-<last>.dat`: the summed counts of the seeds of one batch of
//!   `results.jsonl`, written before the batch's results, with the seeds it holds on its second
//!   line (`# seeds 1-32,40`). A Verilator coverage.dat (`verilator_coverage` reads it).
//!   `--resume` keeps the parts whose seeds all have a result, removes those none of whose seeds
//!   has one, and cuts the results of a batch an interruption tore ([`reconcile`]); `pmu50
//!   merge` sums the parts of its folders. So the code coverage of a folder is that of exactly
//!   the seeds of its results, however often it was interrupted, sharded or merged.
//! - `coverage.dat`: every point of every build the seeds used, with its summed count, sorted by
//!   key, file paths relative to the file list's folder (one regression run in one process and
//!   the same regression run in shards and merged give the same bytes).
//! - `lcov.info`: the same as LCOV tracefile data ([`Total::lcov`]).
//! - `waivers.toml`: the waivers applied ([`Waivers`]); `summary.json`: the figures after the
//!   waivers ([`CodeSummary`], format `pmu50-code-coverage-1`).
//!
//! What counts: a line point (a block, or an `if`/`else`/`case` branch: Verilator's `v_line`
//! and `v_branch`) is hit when it ran at least once; a toggle point (one bit of a signal) is
//! toggled when it rose and fell within one seed's run. Verilator counts a bit's changes; the
//! count a seed adds to a toggle point is its changes halved (rounded down: the rise-and-fall
//! pairs from reset on), so that two seeds that each only raise a bit do not add up to a
//! toggle. In the folder's files a toggle point's count is that number of pairs.

use super::RegressError;
use serde::{Deserialize, Serialize};
use std::collections::{BTreeMap, BTreeSet, HashMap};
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex, OnceLock};

/// Version of `summary.json`.
pub const SUMMARY_FORMAT: &str = "pmu50-code-coverage-1";
/// The first line of a Verilator coverage file.
const DAT_HEADER: &str = "# SystemC::Coverage-3";
/// The changes Verilator counts for one rise-and-fall of a bit (a toggle point's count in the
/// folder is a seed's changes divided by this, summed over the seeds).
pub const TOGGLE_CHANGES: u64 = 2;

// ------------------------------------------------------------------------------------------
// points

/// The point keys of this process, each numbered once: a seed's counts are (number, count).
struct Interner {
    ids: HashMap<Arc<str>, u32>,
    keys: Vec<Arc<str>>,
}

fn interner() -> &'static Mutex<Interner> {
    static I: OnceLock<Mutex<Interner>> = OnceLock::new();
    I.get_or_init(|| {
        Mutex::new(Interner {
            ids: HashMap::new(),
            keys: Vec::new(),
        })
    })
}

fn intern(key: &str) -> u32 {
    let mut i = interner().lock().unwrap_or_else(|e| e.into_inner());
    if let Some(&id) = i.ids.get(key) {
        return id;
    }
    let k: Arc<str> = Arc::from(key);
    let id = i.keys.len() as u32;
    i.keys.push(k.clone());
    i.ids.insert(k, id);
    id
}

fn key_of(id: u32) -> Arc<str> {
    let i = interner().lock().unwrap_or_else(|e| e.into_inner());
    i.keys
        .get(id as usize)
        .cloned()
        .unwrap_or_else(|| Arc::from(""))
}

/// The code coverage of one seed's RTL run: its nonzero counts and every point of its build.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SeedCode {
    /// (point, count), count > 0.
    pub counts: Vec<(u32, u64)>,
    /// Every point of the library the seed ran on, hit or not.
    pub points: Arc<Vec<u32>>,
}

/// The folder the RTL's paths are made relative to in point keys (the file list's folder), set
/// once by the regression.
static BASE: OnceLock<PathBuf> = OnceLock::new();

/// Make the file paths of the points this process reads relative to `dir` (the file list's
/// folder), so that the keys of one RTL are the same on every machine.
pub fn set_base(dir: &Path) {
    let _ = BASE.set(dir.to_path_buf());
}

/// A key as the folder keeps it: its `f` field relative to the base folder, and its `page`
/// without the suffix Verilator gives a module per parameter set (`updown_counter_58cd__C10`,
/// `register_file__pi1`), so that a source line's point is one point whatever the parameters
/// of the build that counted it.
pub fn normalise(key: &str) -> String {
    key.split('\u{1}')
        .map(|field| {
            if let Some(f) = field.strip_prefix("f\u{2}") {
                if let Some(rel) = BASE.get().and_then(|b| Path::new(f).strip_prefix(b).ok()) {
                    return format!("f\u{2}{}", rel.display());
                }
            } else if let Some(page) = field.strip_prefix("page\u{2}") {
                return format!("page\u{2}{}", strip_param_suffix(page));
            }
            field.to_string()
        })
        .collect::<Vec<_>>()
        .join("\u{1}")
}

/// `v_line/m__C10` and `v_line/m__pi3` are `v_line/m`.
fn strip_param_suffix(page: &str) -> &str {
    if let Some(i) = page.rfind("__") {
        let tail = &page[i + 2..];
        let param = tail
            .strip_prefix("pi")
            .filter(|t| !t.is_empty() && t.chars().all(|c| c.is_ascii_digit()))
            .is_some()
            || tail
                .strip_prefix('C')
                .filter(|t| !t.is_empty() && t.chars().all(|c| c.is_ascii_alphanumeric()))
                .is_some();
        if param {
            return &page[..i];
        }
    }
    page
}

/// One line of a coverage.dat: `C '<key>' <count>`.
fn dat_line(line: &str) -> Option<(&str, u64)> {
    let rest = line.strip_prefix("C '")?;
    let end = rest.rfind('\'')?;
    let count = rest[end + 1..].trim().parse().ok()?;
    Some((&rest[..end], count))
}

/// The counts of a Verilator coverage.dat a worker wrote: (point, count) for every point.
pub fn read_counts(path: &Path) -> Result<Vec<(u32, u64)>, String> {
    let text = std::fs::read_to_string(path).map_err(|e| {
        format!(
            "the code coverage of the RTL's run ({}): {e}",
            path.display()
        )
    })?;
    let mut v = Vec::new();
    for (n, l) in text.lines().enumerate() {
        if l.is_empty() || l.starts_with('#') {
            continue;
        }
        let (k, c) = dat_line(l).ok_or_else(|| {
            format!(
                "{}:{}: not a line of a Verilator coverage file",
                path.display(),
                n + 1
            )
        })?;
        // a toggle point: rise-and-fall pairs, not changes
        let c = if k.contains("\u{1}page\u{2}v_toggle/") {
            c / TOGGLE_CHANGES
        } else {
            c
        };
        v.push((intern(&normalise(k)), c));
    }
    Ok(v)
}

/// The kind of a point (its `page`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Kind {
    /// A block (`v_line`).
    Line,
    /// An `if`/`else`/`case` branch (`v_branch`).
    Branch,
    /// One bit of a signal (`v_toggle`).
    Toggle,
    /// Anything else (user coverage): counted in coverage.dat, not in the figures.
    Other,
}

/// A name as the RTL spells it: Verilator writes a character other than a letter, a digit or
/// `_` of a name as `__0` and two hex digits (a netlist's `\\drive_interval.si` is
/// `drive_interval__02esi`).
pub fn demangle(name: &str) -> String {
    let b = name.as_bytes();
    let mut out = String::with_capacity(name.len());
    let mut i = 0;
    while i < b.len() {
        if b[i..].starts_with(b"__0") && i + 5 <= b.len() {
            if let Ok(c) = u8::from_str_radix(&name[i + 3..i + 5], 16) {
                if c.is_ascii_graphic() {
                    out.push(char::from(c));
                    i += 5;
                    continue;
                }
            }
        }
        out.push(char::from(b[i]));
        i += 1;
    }
    out
}

/// A point's key, read.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Point {
    pub file: String,
    pub line: u32,
    pub kind: Kind,
    /// The block kind (`block`, `if`, `else`, `case`) or the signal and bit (`cnt[3]`).
    pub comment: String,
    /// The instance.
    pub hier: String,
    /// The source lines of a block (`S`), as ranges; the point's line when absent.
    pub lines: Vec<(u32, u32)>,
}

impl Point {
    pub fn parse(key: &str) -> Point {
        let mut p = Point {
            file: String::new(),
            line: 0,
            kind: Kind::Other,
            comment: String::new(),
            hier: String::new(),
            lines: Vec::new(),
        };
        for field in key.split('\u{1}') {
            let Some((name, value)) = field.split_once('\u{2}') else {
                continue;
            };
            match name {
                "f" => p.file = value.to_string(),
                "l" => p.line = value.parse().unwrap_or(0),
                "page" => {
                    p.kind = if value.starts_with("v_line/") {
                        Kind::Line
                    } else if value.starts_with("v_branch/") {
                        Kind::Branch
                    } else if value.starts_with("v_toggle/") {
                        Kind::Toggle
                    } else {
                        Kind::Other
                    }
                }
                "o" => p.comment = value.to_string(),
                "h" => p.hier = value.to_string(),
                "S" => {
                    p.lines = value
                        .split(',')
                        .filter_map(|r| match r.split_once('-') {
                            Some((a, b)) => Some((a.parse().ok()?, b.parse().ok()?)),
                            None => r.parse().ok().map(|a| (a, a)),
                        })
                        .collect()
                }
                _ => {}
            }
        }
        if p.lines.is_empty() && p.line > 0 {
            p.lines.push((p.line, p.line));
        }
        p
    }

    /// A line or branch point.
    pub fn is_line(&self) -> bool {
        matches!(self.kind, Kind::Line | Kind::Branch)
    }

    /// Whether `count` covers this point (a toggle point's count is rise-and-fall pairs).
    pub fn covered(&self, count: u64) -> bool {
        count > 0
    }

    /// A toggle point's signal and bit: `cnt[3]` is (`cnt`, Some(3)).
    pub fn signal(&self) -> (&str, Option<u32>) {
        let c = self.comment.as_str();
        if let Some(open) = c.rfind('[') {
            if let Some(bit) = c[open + 1..].strip_suffix(']').and_then(|b| b.parse().ok()) {
                return (&c[..open], Some(bit));
            }
        }
        (c, None)
    }
}

// ------------------------------------------------------------------------------------------
// sums

/// Counts by point key, sorted: a part, or the total of a folder.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Total {
    pub counts: BTreeMap<String, u64>,
}

impl Total {
    /// Add a seed's counts (and its build's points, at zero where not hit).
    pub fn add_seed(&mut self, s: &SeedCode) {
        for &p in s.points.iter() {
            self.counts.entry(key_of(p).to_string()).or_insert(0);
        }
        for &(p, n) in &s.counts {
            let c = self.counts.entry(key_of(p).to_string()).or_insert(0);
            *c = c.saturating_add(n);
        }
    }

    pub fn add(&mut self, o: &Total) {
        for (k, n) in &o.counts {
            let c = self.counts.entry(k.clone()).or_insert(0);
            *c = c.saturating_add(*n);
        }
    }

    /// As a Verilator coverage.dat, with `note` lines (`# ...`) after the header.
    pub fn dat(&self, note: &str) -> String {
        let mut s = String::with_capacity(self.counts.len() * 160);
        s.push_str(DAT_HEADER);
        s.push('\n');
        for l in note.lines() {
            s.push_str("# ");
            s.push_str(l);
            s.push('\n');
        }
        for (k, n) in &self.counts {
            s.push_str("C '");
            s.push_str(k);
            s.push_str("' ");
            s.push_str(&n.to_string());
            s.push('\n');
        }
        s
    }

    /// Read a coverage.dat (a part): its counts and its `# ` note lines.
    pub fn read(path: &Path) -> Result<(Total, Vec<String>), RegressError> {
        let f = super::folder::open_regular(path, false)?.ok_or_else(|| RegressError::File {
            path: path.to_path_buf(),
            reason: "No such file".into(),
        })?;
        let mut text = String::new();
        std::io::Read::read_to_string(&mut std::io::Read::take(f, 1 << 30), &mut text).map_err(
            |e| RegressError::File {
                path: path.to_path_buf(),
                reason: e.to_string(),
            },
        )?;
        let mut t = Total::default();
        let mut notes = Vec::new();
        for (n, l) in text.lines().enumerate() {
            if l == DAT_HEADER || l.is_empty() {
                continue;
            }
            if let Some(note) = l.strip_prefix("# ") {
                notes.push(note.to_string());
                continue;
            }
            let (k, c) = dat_line(l).ok_or_else(|| RegressError::Line {
                path: path.to_path_buf(),
                line: n as u64 + 1,
                reason: "not a line of a Verilator coverage file (C '<key>' <count>)".into(),
            })?;
            let e = t.counts.entry(k.to_string()).or_insert(0);
            *e = e.saturating_add(c);
        }
        Ok((t, notes))
    }

    /// LCOV tracefile data: per file, `DA:<line>,<count>` for each source line of a block or
    /// branch (the largest count of the points holding the line), `BRDA:<line>,0,<n>,<count>`
    /// for each branch and `BRDA:<line>,1,<n>,<count>` for each toggle bit (block 1: toggles,
    /// `<count>` the bit's rise-and-fall pairs), with the LF/LH/BRF/BRH totals. Waivers are not
    /// applied.
    pub fn lcov(&self) -> String {
        struct F {
            da: BTreeMap<u32, u64>,
            br: Vec<(u32, u8, u64)>,
        }
        let mut files: BTreeMap<String, F> = BTreeMap::new();
        for (k, &n) in &self.counts {
            let p = Point::parse(k);
            if p.kind == Kind::Other || p.file.is_empty() {
                continue;
            }
            let f = files.entry(p.file.clone()).or_insert(F {
                da: BTreeMap::new(),
                br: Vec::new(),
            });
            match p.kind {
                Kind::Line | Kind::Branch => {
                    for &(a, b) in &p.lines {
                        for l in a..=b.min(a.saturating_add(100_000)) {
                            let e = f.da.entry(l).or_insert(0);
                            *e = (*e).max(n);
                        }
                    }
                    if p.kind == Kind::Branch {
                        f.br.push((p.line, 0, n));
                    }
                }
                Kind::Toggle => f.br.push((p.line, 1, n)),
                Kind::Other => {}
            }
        }
        let mut s = String::from("TN:pmu50\n");
        for (name, mut f) in files {
            s.push_str(&format!("SF:{name}\n"));
            f.br.sort_by_key(|b| (b.0, b.1));
            let mut seq: BTreeMap<(u32, u8), u32> = BTreeMap::new();
            for (l, block, n) in &f.br {
                let i = seq.entry((*l, *block)).or_insert(0);
                s.push_str(&format!("BRDA:{l},{block},{i},{n}\n"));
                *i += 1;
            }
            s.push_str(&format!(
                "BRF:{}\nBRH:{}\n",
                f.br.len(),
                f.br.iter().filter(|b| b.2 > 0).count()
            ));
            for (l, n) in &f.da {
                s.push_str(&format!("DA:{l},{n}\n"));
            }
            s.push_str(&format!(
                "LF:{}\nLH:{}\nend_of_record\n",
                f.da.len(),
                f.da.values().filter(|n| **n > 0).count()
            ));
        }
        s
    }
}

/// Seeds as ranges: `1-32,40`.
pub fn seeds_text(seeds: &[u64]) -> String {
    let mut v: Vec<u64> = seeds.to_vec();
    v.sort_unstable();
    v.dedup();
    let mut out: Vec<String> = Vec::new();
    let mut i = 0;
    while i < v.len() {
        let mut j = i;
        while j + 1 < v.len() && v[j + 1] == v[j] + 1 {
            j += 1;
        }
        out.push(if i == j {
            v[i].to_string()
        } else {
            format!("{}-{}", v[i], v[j])
        });
        i = j + 1;
    }
    out.join(",")
}

fn parse_seeds(text: &str) -> Option<Vec<u64>> {
    let mut v = Vec::new();
    for r in text.split(',').filter(|r| !r.is_empty()) {
        match r.split_once('-') {
            Some((a, b)) => {
                let (a, b): (u64, u64) = (a.parse().ok()?, b.parse().ok()?);
                if b < a || b - a > super::folder::MAX_SEEDS {
                    return None;
                }
                v.extend(a..=b);
            }
            None => v.push(r.parse().ok()?),
        }
    }
    Some(v)
}

// ------------------------------------------------------------------------------------------
// the folder

/// `<dir>/code`.
pub fn code_dir(dir: &Path) -> PathBuf {
    dir.join("code")
}

fn parts_dir(dir: &Path) -> PathBuf {
    code_dir(dir).join("parts")
}

/// A part of a folder: its file, its seeds and its counts.
pub struct Part {
    pub path: PathBuf,
    pub seeds: Vec<u64>,
    pub total: Total,
}

/// The parts of `dir` (none when it has no `code/parts`).
pub fn read_parts(dir: &Path) -> Result<Vec<Part>, RegressError> {
    let pd = parts_dir(dir);
    let rd = match std::fs::read_dir(&pd) {
        Ok(rd) => rd,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(Vec::new()),
        Err(e) => {
            return Err(RegressError::File {
                path: pd,
                reason: e.to_string(),
            })
        }
    };
    let mut names: Vec<PathBuf> = rd
        .filter_map(|e| e.ok())
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|x| x == "dat"))
        .collect();
    names.sort();
    let mut parts = Vec::new();
    for path in names {
        let (total, notes) = Total::read(&path)?;
        let seeds = notes
            .iter()
            .find_map(|n| n.strip_prefix("seeds "))
            .and_then(parse_seeds)
            .ok_or_else(|| RegressError::Line {
                path: path.clone(),
                line: 2,
                reason: "a part of the code coverage names its seeds on its second line (`# seeds 1-32,40`)".into(),
            })?;
        parts.push(Part { path, seeds, total });
    }
    Ok(parts)
}

/// Write the part of a batch of seeds (before their results), atomically: its path.
pub fn write_part(
    dir: &Path,
    seeds: &[u64],
    total: &Total,
) -> Result<Option<PathBuf>, RegressError> {
    let (Some(first), Some(last)) = (seeds.iter().min(), seeds.iter().max()) else {
        return Ok(None);
    };
    let pd = parts_dir(dir);
    crate::atomic_file::create_dir(&pd)?;
    let text = total.dat(&format!(
        "seeds {}\npmu50 code coverage: the summed counts of these seeds",
        seeds_text(seeds)
    ));
    let path = pd.join(format!("{first}-{last}.dat"));
    let mut b = crate::atomic_file::Batch::new();
    b.add(crate::atomic_file::write_atomic(&path, text.as_bytes())?);
    b.commit()?;
    Ok(Some(path))
}

/// Parts a folder keeps while a run goes on: past this, they are summed into one.
const MAX_PARTS: usize = 32;

/// The parts to count, largest first, none sharing a seed with one before it (a compaction an
/// interruption cut leaves the summed part beside the parts it sums).
fn disjoint(mut parts: Vec<Part>) -> (Vec<Part>, Vec<Part>) {
    parts.sort_by(|a, b| b.seeds.len().cmp(&a.seeds.len()).then(a.path.cmp(&b.path)));
    let mut seen = BTreeSet::new();
    let (mut keep, mut drop) = (Vec::new(), Vec::new());
    for p in parts {
        if p.seeds.iter().any(|s| seen.contains(s)) {
            drop.push(p);
        } else {
            seen.extend(p.seeds.iter().copied());
            keep.push(p);
        }
    }
    (keep, drop)
}

/// Sum the parts of `dir` into one, when there are more than [`MAX_PARTS`] (or, with `all`,
/// more than one). Called after a batch's results are written: every part's seeds have one.
pub fn compact(dir: &Path, all: bool) -> Result<(), RegressError> {
    let parts = read_parts(dir)?;
    if parts.len() <= 1 || (!all && parts.len() <= MAX_PARTS) {
        return Ok(());
    }
    let (keep, drop) = disjoint(parts);
    let mut total = Total::default();
    let mut seeds = Vec::new();
    for p in &keep {
        total.add(&p.total);
        seeds.extend(p.seeds.iter().copied());
    }
    let written = write_part(dir, &seeds, &total)?;
    for p in keep.iter().chain(&drop) {
        if Some(&p.path) != written.as_ref() {
            std::fs::remove_file(&p.path).map_err(|e| RegressError::File {
                path: p.path.clone(),
                reason: e.to_string(),
            })?;
        }
    }
    Ok(())
}

/// Remove `dir/code/` (a new run without code coverage).
pub fn remove(dir: &Path) -> Result<(), RegressError> {
    let cd = code_dir(dir);
    match std::fs::symlink_metadata(&cd) {
        Ok(m) if m.is_dir() => std::fs::remove_dir_all(&cd).map_err(|e| RegressError::File {
            path: cd,
            reason: format!("cannot remove the code coverage of an earlier run: {e}"),
        }),
        _ => Ok(()),
    }
}

/// Start the code coverage of a new run in `dir`: the parts of an earlier run removed, the
/// waivers written.
pub fn start(dir: &Path, waivers: &Waivers) -> Result<(), RegressError> {
    let pd = parts_dir(dir);
    match std::fs::remove_dir_all(&pd) {
        Ok(()) => {}
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {}
        Err(e) => {
            return Err(RegressError::File {
                path: pd,
                reason: e.to_string(),
            })
        }
    }
    crate::atomic_file::create_dir(&pd)?;
    let mut b = crate::atomic_file::Batch::new();
    b.add(crate::atomic_file::write_atomic(
        &code_dir(dir).join("waivers.toml"),
        waivers.text.as_bytes(),
    )?);
    b.commit()?;
    Ok(())
}

/// Before `--resume` of `dir`: each part whose seeds all have a result stays, one none of whose
/// seeds has a result is removed (its seeds run again), and the results of a part an
/// interruption tore (some of its seeds have a result, written after the part) are cut from
/// the end of `results.jsonl`, so that they run again too.
pub fn reconcile(dir: &Path, range: &std::ops::Range<u64>) -> Result<(), RegressError> {
    let results = dir.join("results.jsonl");
    for _ in 0..2 {
        let mut scratch = vec![0u64; pmu50_coverage::layout().bins.len()];
        let s = super::folder::scan(&results, 0, range, &mut scratch, |_, _| {})?;
        let done: HashMap<u64, u64> = s.entries.iter().map(|e| (e.seed, e.offset)).collect();
        let mut cut: Option<u64> = None;
        for p in read_parts(dir)? {
            let have: Vec<u64> = p
                .seeds
                .iter()
                .filter_map(|s| done.get(s).copied())
                .collect();
            if have.len() == p.seeds.len() {
                continue;
            }
            if have.is_empty() {
                std::fs::remove_file(&p.path).map_err(|e| RegressError::File {
                    path: p.path.clone(),
                    reason: e.to_string(),
                })?;
                continue;
            }
            // a torn batch: its results are the last lines of the file
            let from = have.iter().copied().min().unwrap_or(0);
            let tail_ok = s
                .entries
                .iter()
                .filter(|e| e.offset >= from)
                .all(|e| p.seeds.contains(&e.seed));
            if !tail_ok {
                return Err(RegressError::File { path: p.path.clone(), reason: "some of its seeds have results in results.jsonl and some do not, and those that do are not its last lines: the folder's code coverage and results disagree; run the regression again into a new folder".into() });
            }
            std::fs::remove_file(&p.path).map_err(|e| RegressError::File {
                path: p.path.clone(),
                reason: e.to_string(),
            })?;
            cut = Some(cut.map_or(from, |c: u64| c.min(from)));
        }
        match cut {
            None => return Ok(()),
            Some(at) => {
                let f = std::fs::OpenOptions::new()
                    .write(true)
                    .open(&results)
                    .map_err(|e| RegressError::File {
                        path: results.clone(),
                        reason: e.to_string(),
                    })?;
                f.set_len(at).map_err(|e| RegressError::File {
                    path: results.clone(),
                    reason: e.to_string(),
                })?;
            }
        }
    }
    Ok(())
}

/// The code coverage of regression folders: the parts whose seeds all have a result in their
/// folder, summed.
#[derive(Clone, Debug, Default)]
pub struct Collected {
    pub total: Total,
    /// Seeds counted (in a part).
    pub seeds: u64,
    /// Seeds with a result but in no part counted (a folder interrupted and not resumed).
    pub unaccounted: u64,
}

/// Sum the parts of each folder (`dirs`, each with the seeds of its results).
pub fn collect(dirs: &[(PathBuf, BTreeSet<u64>)]) -> Result<Collected, RegressError> {
    let mut c = Collected::default();
    for (dir, have) in dirs {
        let mut counted = BTreeSet::new();
        let (keep, _) = disjoint(read_parts(dir)?);
        for p in keep {
            if p.seeds.iter().all(|s| have.contains(s)) {
                c.total.add(&p.total);
                counted.extend(p.seeds.iter().copied());
            }
        }
        c.seeds += counted.len() as u64;
        c.unaccounted += have.iter().filter(|s| !counted.contains(s)).count() as u64;
    }
    Ok(c)
}

/// The waivers of `dirs`' code coverage: the same text in each (`code/waivers.toml`), or an
/// error naming two that differ. None when no folder has one.
pub fn folder_waivers(dirs: &[PathBuf]) -> Result<Option<Waivers>, RegressError> {
    let mut found: Option<(PathBuf, String)> = None;
    for d in dirs {
        let p = code_dir(d).join("waivers.toml");
        let Some(f) = super::folder::open_regular(&p, false)? else {
            continue;
        };
        let mut text = String::new();
        std::io::Read::read_to_string(&mut std::io::Read::take(f, 16 << 20), &mut text).map_err(
            |e| RegressError::File {
                path: p.clone(),
                reason: e.to_string(),
            },
        )?;
        match &found {
            Some((q, t)) if *t != text => {
                return Err(RegressError::Usage(format!(
                    "{} and {} differ: the code coverage of one regression has one set of waivers",
                    q.display(),
                    p.display()
                )))
            }
            Some(_) => {}
            None => found = Some((p, text)),
        }
    }
    match found {
        None => Ok(None),
        Some((p, text)) => Waivers::parse(&text, &p, None)
            .map(|mut w| {
                // the folder's copy, whatever the folder's path
                w.origin = "code/waivers.toml".into();
                Some(w)
            })
            .map_err(|e| RegressError::Usage(e.to_string())),
    }
}

// ------------------------------------------------------------------------------------------
// waivers

/// A waivers file that is not valid: where, which field, what is valid.
#[derive(Debug, thiserror::Error)]
pub enum WaiverError {
    #[error("{}: {reason}", path.display())]
    File { path: PathBuf, reason: String },
    #[error("{}:{line}: field `{field}`: {reason}", path.display())]
    Field {
        path: PathBuf,
        line: usize,
        field: &'static str,
        reason: String,
    },
}

/// What a waiver excludes.
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Target {
    /// The line and branch points starting on these lines (first, last).
    Lines(u32, u32),
    /// The toggle points of a signal, all its bits or bits `lo..=hi`.
    Signal {
        name: String,
        bits: Option<(u32, u32)>,
    },
}

/// One waiver.
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
pub struct Waiver {
    /// The RTL file: its path as the file list names it, or a trailing part of it.
    pub file: String,
    pub target: Target,
    pub reason: String,
    /// The claim behind the reason as a Verilog expression over the file's module (`holds`):
    /// an invariant of every reachable state after reset, which `make coverage-proofs` proves
    /// on the twin (hdl/formal/coverage.py). `$past(x)` names the value one edge before.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub holds: Option<String>,
    /// Its line in the waivers file.
    pub at: usize,
}

impl Waiver {
    /// The target as written: `40`, `40-45`, `cnt`, `cnt[15:4]`.
    pub fn what(&self) -> String {
        match &self.target {
            Target::Lines(a, b) if a == b => format!("line {a}"),
            Target::Lines(a, b) => format!("lines {a}-{b}"),
            Target::Signal { name, bits: None } => format!("signal {name}"),
            Target::Signal {
                name,
                bits: Some((lo, hi)),
            } if lo == hi => format!("signal {name}[{lo}]"),
            Target::Signal {
                name,
                bits: Some((lo, hi)),
            } => format!("signal {name}[{hi}:{lo}]"),
        }
    }

    /// Whether this waiver excludes point `p`.
    pub fn covers(&self, p: &Point) -> bool {
        if !file_matches(&p.file, &self.file) {
            return false;
        }
        match &self.target {
            Target::Lines(a, b) => p.is_line() && (*a..=*b).contains(&p.line),
            Target::Signal { name, bits } => {
                if p.kind != Kind::Toggle {
                    return false;
                }
                let (sig, bit) = p.signal();
                (sig == name || demangle(sig) == *name)
                    && match (bits, bit) {
                        (None, _) => true,
                        (Some((lo, hi)), Some(b)) => (*lo..=*hi).contains(&b),
                        (Some(_), None) => false,
                    }
            }
        }
    }
}

/// Whether `path` is `file` or ends with it on a folder boundary.
fn file_matches(path: &str, file: &str) -> bool {
    path == file || path.ends_with(&format!("/{file}"))
}

/// The waivers of a run: `hdl/coverage-waivers.toml` for the twin, `--waivers FILE` for any RTL.
#[derive(Clone, Debug, Default)]
pub struct Waivers {
    pub list: Vec<Waiver>,
    /// The file's text (kept in the folder as `code/waivers.toml`).
    pub text: String,
    /// Where it was read from.
    pub origin: String,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawFile {
    #[serde(default)]
    waiver: Vec<toml::Spanned<RawWaiver>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawWaiver {
    file: Option<toml::Spanned<String>>,
    line: Option<toml::Spanned<toml::Value>>,
    signal: Option<toml::Spanned<String>>,
    reason: Option<toml::Spanned<String>>,
    holds: Option<toml::Spanned<String>>,
}

/// The line (from 1) of byte `at` of `text`.
fn line_at(text: &str, at: usize) -> usize {
    text.as_bytes()[..at.min(text.len())]
        .iter()
        .filter(|b| **b == b'\n')
        .count()
        + 1
}

/// `name`, `name[3]` or `name[15:4]`.
fn parse_signal(s: &str) -> Option<(String, Option<(u32, u32)>)> {
    let ident = |n: &str| {
        !n.is_empty()
            && n.chars()
                .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '$' || c == '.')
            && !n.starts_with(|c: char| c.is_ascii_digit())
    };
    match s.split_once('[') {
        None => ident(s).then(|| (s.to_string(), None)),
        Some((n, rest)) => {
            let inner = rest.strip_suffix(']')?;
            let bits = match inner.split_once(':') {
                Some((hi, lo)) => {
                    let (hi, lo): (u32, u32) = (hi.trim().parse().ok()?, lo.trim().parse().ok()?);
                    (lo.min(hi), lo.max(hi))
                }
                None => {
                    let b: u32 = inner.trim().parse().ok()?;
                    (b, b)
                }
            };
            ident(n).then(|| (n.to_string(), Some(bits)))
        }
    }
}

impl Waivers {
    /// Read and check a waivers file. With `rtl` (the file list's files), each waiver's file
    /// must name exactly one of them, its lines must be in that file and its signal must appear
    /// in it.
    pub fn read(path: &Path, rtl: Option<&[PathBuf]>) -> Result<Waivers, WaiverError> {
        let text = std::fs::read_to_string(path).map_err(|e| WaiverError::File {
            path: path.to_path_buf(),
            reason: e.to_string(),
        })?;
        Waivers::parse(&text, path, rtl)
    }

    pub fn parse(text: &str, path: &Path, rtl: Option<&[PathBuf]>) -> Result<Waivers, WaiverError> {
        let raw: RawFile = toml::from_str(text).map_err(|e| match e.span() {
            Some(s) => WaiverError::Field {
                path: path.to_path_buf(),
                line: line_at(text, s.start),
                field: "waiver",
                reason: e.message().to_string(),
            },
            None => WaiverError::File {
                path: path.to_path_buf(),
                reason: e.message().to_string(),
            },
        })?;
        let mut list = Vec::new();
        for w in raw.waiver {
            let at = line_at(text, w.span().start);
            let w = w.into_inner();
            let field_err = |line: usize, field: &'static str, reason: String| WaiverError::Field {
                path: path.to_path_buf(),
                line,
                field,
                reason,
            };
            let file = w
                .file
                .ok_or_else(|| field_err(at, "file", "missing: the RTL file the waiver is in (its path as the file list names it, or the end of it)".into()))?;
            let file_line = line_at(text, file.span().start);
            let file = file.into_inner();
            if file.trim().is_empty() {
                return Err(field_err(
                    file_line,
                    "file",
                    "empty: name the RTL file".into(),
                ));
            }
            let reason = w.reason.ok_or_else(|| {
                field_err(
                    at,
                    "reason",
                    "missing: every waiver says why the point cannot or need not be covered".into(),
                )
            })?;
            let reason_line = line_at(text, reason.span().start);
            let reason = reason.into_inner();
            if reason.trim().len() < 10 {
                return Err(field_err(reason_line, "reason", format!("`{reason}` is too short: say why the point cannot or need not be covered (at least 10 characters)")));
            }
            let target_line;
            let target = match (w.line, w.signal) {
                (Some(_), Some(s)) => {
                    return Err(field_err(
                        line_at(text, s.span().start),
                        "signal",
                        "a waiver has either `line` or `signal`, not both".into(),
                    ))
                }
                (None, None) => {
                    return Err(field_err(at, "line", "missing: give `line` (a line, 42, or a range, \"40-45\") or `signal` (a toggled signal, \"cnt\" or \"cnt[15:4]\")".into()))
                }
                (Some(l), None) => {
                    let ll = line_at(text, l.span().start);
                    target_line = ll;
                    let bad = || {
                        field_err(
                            ll,
                            "line",
                            format!("{}: valid is a line number (42) or a range (\"40-45\") from 1", l.get_ref()),
                        )
                    };
                    let (a, b) = match l.get_ref() {
                        toml::Value::Integer(n) if *n >= 1 && *n <= i64::from(u32::MAX) => {
                            (*n as u32, *n as u32)
                        }
                        toml::Value::String(s) => {
                            let (a, b) = s.split_once('-').unwrap_or((s, s));
                            let a: u32 = a.trim().parse().map_err(|_| bad())?;
                            let b: u32 = b.trim().parse().map_err(|_| bad())?;
                            if a == 0 || b < a {
                                return Err(bad());
                            }
                            (a, b)
                        }
                        _ => return Err(bad()),
                    };
                    Target::Lines(a, b)
                }
                (None, Some(s)) => {
                    let sl = line_at(text, s.span().start);
                    target_line = sl;
                    let (name, bits) = parse_signal(s.get_ref()).ok_or_else(|| {
                        field_err(
                            sl,
                            "signal",
                            format!(
                                "`{}`: valid is a signal name, with a bit (\"cnt[3]\") or bits (\"cnt[15:4]\")",
                                s.get_ref()
                            ),
                        )
                    })?;
                    Target::Signal { name, bits }
                }
            };
            if let Some(files) = rtl {
                let matching: Vec<&PathBuf> = files
                    .iter()
                    .filter(|f| file_matches(&f.display().to_string(), &file))
                    .collect();
                let src = match matching.as_slice() {
                    [one] => *one,
                    [] => {
                        return Err(field_err(
                            file_line,
                            "file",
                            format!(
                                "`{file}` is none of the RTL's files ({})",
                                files
                                    .iter()
                                    .filter_map(|f| f.file_name())
                                    .map(|n| n.to_string_lossy().into_owned())
                                    .collect::<Vec<_>>()
                                    .join(", ")
                            ),
                        ))
                    }
                    many => {
                        return Err(field_err(
                            file_line,
                            "file",
                            format!(
                                "`{file}` names {} of the RTL's files ({}): give more of its path",
                                many.len(),
                                many.iter()
                                    .map(|f| f.display().to_string())
                                    .collect::<Vec<_>>()
                                    .join(", ")
                            ),
                        ))
                    }
                };
                let source = std::fs::read_to_string(src).unwrap_or_default();
                match &target {
                    Target::Lines(_, b) => {
                        let n = source.lines().count() as u32;
                        if *b > n {
                            return Err(field_err(
                                target_line,
                                "line",
                                format!(
                                    "line {b} is past the end of {} ({n} lines)",
                                    src.display()
                                ),
                            ));
                        }
                    }
                    Target::Signal { name, .. } => {
                        // a name, or a netlist's escaped one (`\\drive_interval.si `)
                        let word = |t: &str| {
                            t.split(|c: char| !(c.is_ascii_alphanumeric() || "_$.\\".contains(c)))
                                .any(|w| w == name || w.trim_start_matches(['\\', '.']) == name)
                        };
                        if !word(&source) {
                            return Err(field_err(
                                target_line,
                                "signal",
                                format!("`{name}` does not appear in {}", src.display()),
                            ));
                        }
                    }
                }
            }
            let holds = match w.holds {
                Some(h) if h.get_ref().trim().is_empty() => {
                    return Err(field_err(
                        line_at(text, h.span().start),
                        "holds",
                        "empty: give the claim as a Verilog expression over the file's module (\"t[17:16] == 2'b00\"), or leave the field out".into(),
                    ))
                }
                Some(h) => Some(h.into_inner().trim().to_string()),
                None => None,
            };
            list.push(Waiver {
                file,
                target,
                reason: reason.trim().to_string(),
                holds,
                at,
            });
        }
        Ok(Waivers {
            list,
            text: text.to_string(),
            origin: path.display().to_string(),
        })
    }
}

// ------------------------------------------------------------------------------------------
// the figures

/// Hit and total of one measure.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Count {
    pub hit: u64,
    pub total: u64,
    /// Points excluded by a waiver (not in `total`).
    pub waived: u64,
    /// 100 · hit / total (100 when total is 0).
    pub pct: f64,
}

impl Count {
    fn add(&mut self, covered: bool, waived: bool) {
        if waived {
            self.waived += 1;
        } else {
            self.total += 1;
            self.hit += u64::from(covered);
        }
    }
    fn finish(&mut self) {
        self.pct = if self.total == 0 {
            100.0
        } else {
            (1e4 * self.hit as f64 / self.total as f64).floor() / 100.0
        };
    }
}

/// The figures of one RTL file.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct FileFigures {
    pub file: String,
    pub line: Count,
    pub toggle: Count,
}

/// A waiver and what it excluded.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct WaiverUse {
    pub file: String,
    pub what: String,
    pub reason: String,
    /// Its line in the waivers file.
    pub at: usize,
    /// Points it excluded.
    pub points: u64,
    /// Of those, points the seeds covered all the same (a toggle waived as constant that
    /// toggled: the waiver's reason is wrong).
    pub covered: u64,
}

/// `code/summary.json`: the code coverage of a folder after its waivers.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CodeSummary {
    /// [`SUMMARY_FORMAT`].
    pub format: String,
    /// Seeds whose RTL runs are counted (all the seeds with a result, but for those the model
    /// failed before the RTL ran or whose RTL run hung or crashed, which count zero).
    pub seeds: u64,
    /// Seeds with a result whose code coverage is not counted (a folder interrupted and not
    /// resumed): 0 for a complete folder.
    pub seeds_unaccounted: u64,
    /// Line and branch points (Verilator's `v_line`, `v_branch`): hit at least once.
    pub line: Count,
    /// Toggle points (one bit of a signal): rose and fell within one seed's run.
    pub toggle: Count,
    pub files: Vec<FileFigures>,
    pub waivers: Vec<WaiverUse>,
    /// The waivers file the figures apply: `code/waivers.toml` of the folder (a copy of the
    /// file given to the run), empty when the run had none.
    pub waivers_file: String,
}

/// A folder's code coverage, ready to write and to render.
#[derive(Clone, Debug)]
pub struct CodeReport {
    pub total: Total,
    pub summary: CodeSummary,
    /// Per file (display name): per point, (point, count, waived by).
    pub points: BTreeMap<String, Vec<(Point, u64, Option<usize>)>>,
    /// Where the RTL's files are (to show their source), the folder their paths are relative to.
    pub base: Option<PathBuf>,
}

impl CodeReport {
    pub fn build(c: &Collected, waivers: &Waivers, base: Option<PathBuf>) -> CodeReport {
        let mut files: BTreeMap<String, FileFigures> = BTreeMap::new();
        let mut points: BTreeMap<String, Vec<(Point, u64, Option<usize>)>> = BTreeMap::new();
        let mut uses: Vec<WaiverUse> = waivers
            .list
            .iter()
            .map(|w| WaiverUse {
                file: w.file.clone(),
                what: w.what(),
                reason: match &w.holds {
                    Some(h) => format!(
                        "{} (the claim `{h}` is proven by make coverage-proofs)",
                        w.reason
                    ),
                    None => w.reason.clone(),
                },
                at: w.at,
                points: 0,
                covered: 0,
            })
            .collect();
        let (mut line, mut toggle) = (Count::default(), Count::default());
        for (k, &n) in &c.total.counts {
            let p = Point::parse(k);
            if p.kind == Kind::Other {
                continue;
            }
            let by = waivers.list.iter().position(|w| w.covers(&p));
            let covered = p.covered(n);
            if let Some(i) = by {
                uses[i].points += 1;
                uses[i].covered += u64::from(covered);
            }
            let f = files.entry(p.file.clone()).or_insert_with(|| FileFigures {
                file: p.file.clone(),
                ..Default::default()
            });
            if p.kind == Kind::Toggle {
                f.toggle.add(covered, by.is_some());
                toggle.add(covered, by.is_some());
            } else {
                f.line.add(covered, by.is_some());
                line.add(covered, by.is_some());
            }
            points.entry(p.file.clone()).or_default().push((p, n, by));
        }
        line.finish();
        toggle.finish();
        let files: Vec<FileFigures> = files
            .into_values()
            .map(|mut f| {
                f.line.finish();
                f.toggle.finish();
                f
            })
            .collect();
        CodeReport {
            total: c.total.clone(),
            summary: CodeSummary {
                format: SUMMARY_FORMAT.into(),
                seeds: c.seeds,
                seeds_unaccounted: c.unaccounted,
                line,
                toggle,
                files,
                waivers: uses,
                waivers_file: waivers.origin.clone(),
            },
            points,
            base,
        }
    }

    /// coverage.dat, lcov.info and summary.json of `dir/code/`, added to `batch`.
    pub fn write(
        &self,
        dir: &Path,
        batch: &mut crate::atomic_file::Batch,
    ) -> Result<(), RegressError> {
        use crate::atomic_file::write_atomic;
        let cd = code_dir(dir);
        crate::atomic_file::create_dir(&cd)?;
        batch.add(write_atomic(
            &cd.join("coverage.dat"),
            self.total
                .dat("pmu50 code coverage of the RTL under test")
                .as_bytes(),
        )?);
        batch.add(write_atomic(
            &cd.join("lcov.info"),
            self.total.lcov().as_bytes(),
        )?);
        let json = serde_json::to_string_pretty(&self.summary)
            .map_err(|e| RegressError::Usage(e.to_string()))?
            + "\n";
        batch.add(write_atomic(&cd.join("summary.json"), json.as_bytes())?);
        Ok(())
    }

    /// The lines printed on stderr: the figures, and each waiver with what it excluded.
    pub fn text(&self) -> String {
        let s = &self.summary;
        let mut t = format!(
            "code coverage: line {}/{} ({:.2} %), toggle {}/{} ({:.2} %) over {} seed(s); {} line and {} toggle point(s) waived by {} waiver(s) of {}\n",
            s.line.hit,
            s.line.total,
            s.line.pct,
            s.toggle.hit,
            s.toggle.total,
            s.toggle.pct,
            s.seeds,
            s.line.waived,
            s.toggle.waived,
            s.waivers.len(),
            if s.waivers_file.is_empty() { "(none)" } else { &s.waivers_file },
        );
        for w in &s.waivers {
            t.push_str(&format!(
                "  waived {} {}: {} point(s){}: {}\n",
                w.file,
                w.what,
                w.points,
                if w.covered > 0 {
                    format!(
                        ", {} of them covered all the same (check the reason)",
                        w.covered
                    )
                } else if w.points == 0 {
                    " (matches nothing)".to_string()
                } else {
                    String::new()
                },
                w.reason
            ));
        }
        if s.seeds_unaccounted > 0 {
            t.push_str(&format!("  {} seed(s) with a result have no code coverage counted (an interrupted folder): run --resume on it\n", s.seeds_unaccounted));
        }
        t
    }
}

// ------------------------------------------------------------------------------------------
// report.html

/// Source lines shown in full per file; a longer file (a netlist) shows the lines around its
/// misses only.
const FULL_SOURCE_LINES: usize = 1500;
/// Misses listed per file.
const MISSES_SHOWN: usize = 200;

/// The "Code coverage" section of report.html: the figures per file, the waivers, and per file
/// (folded) the source with the hit count of each line, the never-hit lines marked, and the
/// bits that did not toggle.
pub fn render_html(r: &CodeReport) -> String {
    use crate::plot::svg::esc;
    use std::fmt::Write;
    let s = &r.summary;
    let mut h = format!("<style>{CSS}</style>\n");
    let _ = write!(
        h,
        "<h2 id=\"code\">Code coverage of the RTL</h2>\n<p>Verilator line coverage (blocks and branches: hit at least once) and toggle coverage (each bit: rose and fell within one seed's run) over {} seed(s), after {} waiver(s) ({}). Files: <code>code/coverage.dat</code>, <code>code/lcov.info</code>, <code>code/summary.json</code>.</p>\n",
        s.seeds,
        s.waivers.len(),
        esc(if s.waivers_file.is_empty() { "none" } else { &s.waivers_file })
    );
    if s.seeds_unaccounted > 0 {
        let _ = writeln!(h, "<p class=\"cc-bad\">{} seed(s) with a result have no code coverage counted: the folder was interrupted; run <code>pmu50 regress --resume</code> on it.</p>", s.seeds_unaccounted);
    }
    let cell = |c: &Count| {
        let cls = if c.hit == c.total { "cc-ok" } else { "cc-bad" };
        format!(
            "<td class=\"{cls}\">{}/{}</td><td class=\"{cls}\">{:.2} %</td><td>{}</td>",
            c.hit, c.total, c.pct, c.waived
        )
    };
    h.push_str("<table><tr><th>file</th><th>line</th><th>%</th><th>waived</th><th>toggle</th><th>%</th><th>waived</th></tr>\n");
    for f in &s.files {
        let _ = writeln!(
            h,
            "<tr><td><a href=\"#code-{}\">{}</a></td>{}{}</tr>",
            esc(&anchor(&f.file)),
            esc(&f.file),
            cell(&f.line),
            cell(&f.toggle)
        );
    }
    let _ = writeln!(
        h,
        "<tr><th>all</th>{}{}</tr></table>",
        cell(&s.line),
        cell(&s.toggle)
    );
    if !s.waivers.is_empty() {
        h.push_str("<h3>Waivers</h3>\n<table><tr><th>file</th><th>what</th><th>points</th><th>reason</th></tr>\n");
        for w in &s.waivers {
            let note = if w.covered > 0 {
                format!(
                    " <span class=\"cc-bad\">({} covered all the same: check the reason)</span>",
                    w.covered
                )
            } else if w.points == 0 {
                " <span class=\"cc-bad\">(matches nothing)</span>".to_string()
            } else {
                String::new()
            };
            let _ = writeln!(
                h,
                "<tr><td>{}</td><td>{}</td><td>{}{note}</td><td>{}</td></tr>",
                esc(&w.file),
                esc(&w.what),
                w.points,
                esc(&w.reason)
            );
        }
        h.push_str("</table>\n");
    }
    for (file, pts) in &r.points {
        let fig = s.files.iter().find(|f| &f.file == file);
        let missed_l = fig.map_or(0, |f| f.line.total - f.line.hit);
        let missed_t = fig.map_or(0, |f| f.toggle.total - f.toggle.hit);
        let _ = writeln!(
            h,
            "<details id=\"code-{}\"{}><summary><code>{}</code>: {} line point(s) and {} bit(s) not covered</summary>",
            esc(&anchor(file)),
            if missed_l + missed_t > 0 { " open" } else { "" },
            esc(file),
            missed_l,
            missed_t
        );
        // the bits that did not toggle
        // by instance and signal, the bits as ranges: `cnt[15:12] (pmu50.u_cnt)`
        let mut by_signal: BTreeMap<(String, String), Vec<Option<u32>>> = BTreeMap::new();
        for (p, _, _) in pts
            .iter()
            .filter(|(p, n, by)| p.kind == Kind::Toggle && by.is_none() && !p.covered(*n))
        {
            let (sig, bit) = p.signal();
            by_signal
                .entry((p.hier.clone(), demangle(sig)))
                .or_default()
                .push(bit);
        }
        let bits: usize = by_signal.values().map(Vec::len).sum();
        let mut untoggled: Vec<String> = Vec::new();
        for ((hier, sig), mut v) in by_signal {
            v.sort_unstable_by(|a, b| b.cmp(a));
            let mut i = 0;
            while i < v.len() {
                let mut j = i;
                while let (Some(Some(a)), Some(Some(b))) = (v.get(j), v.get(j + 1)) {
                    if *a != b + 1 {
                        break;
                    }
                    j += 1;
                }
                untoggled.push(match (v[i], v[j]) {
                    (Some(hi), Some(lo)) if hi != lo => format!("{sig}[{hi}:{lo}] ({hier})"),
                    (Some(b), _) => format!("{sig}[{b}] ({hier})"),
                    (None, _) => format!("{sig} ({hier})"),
                });
                i = j + 1;
            }
        }
        if !untoggled.is_empty() {
            let _ = write!(h, "<p>Bits not toggled ({bits}): ");
            let shown: Vec<String> = untoggled
                .iter()
                .take(MISSES_SHOWN)
                .map(|u| format!("<code>{}</code>", esc(u)))
                .collect();
            h.push_str(&shown.join(", "));
            if untoggled.len() > MISSES_SHOWN {
                let _ = write!(h, " and {} more", untoggled.len() - MISSES_SHOWN);
            }
            h.push_str("</p>\n");
        }
        h.push_str(&source_html(r, file, pts));
        h.push_str("</details>\n");
    }
    h
}

fn anchor(file: &str) -> String {
    file.chars()
        .map(|c| if c.is_ascii_alphanumeric() { c } else { '-' })
        .collect()
}

/// The source of `file` with, per line, the largest count of its line and branch points, the
/// lines of a point never hit marked (`miss`), the waived ones greyed.
fn source_html(r: &CodeReport, file: &str, pts: &[(Point, u64, Option<usize>)]) -> String {
    use crate::plot::svg::esc;
    // per line: (largest count, a point missed, all waived)
    let mut at: BTreeMap<u32, (u64, bool, bool)> = BTreeMap::new();
    for (p, n, by) in pts.iter().filter(|(p, _, _)| p.is_line()) {
        for &(a, b) in &p.lines {
            for l in a..=b.min(a.saturating_add(100_000)) {
                let e = at.entry(l).or_insert((0, false, true));
                e.0 = e.0.max(*n);
                if by.is_none() {
                    e.2 = false;
                }
            }
        }
        if by.is_none() && !p.covered(*n) {
            at.entry(p.line).or_insert((0, false, false)).1 = true;
        }
    }
    let text = r
        .base
        .as_ref()
        .map(|b| b.join(file))
        .or_else(|| Some(PathBuf::from(file)))
        .and_then(|p| std::fs::read_to_string(p).ok());
    let Some(text) = text else {
        return "<p>(the source is not available here)</p>\n".into();
    };
    let lines: Vec<&str> = text.lines().collect();
    let show: Box<dyn Fn(usize) -> bool> = if lines.len() <= FULL_SOURCE_LINES {
        Box::new(|_| true)
    } else {
        let misses: BTreeSet<usize> = at
            .iter()
            .filter(|(_, v)| v.1)
            .map(|(l, _)| *l as usize)
            .take(MISSES_SHOWN)
            .collect();
        Box::new(move |l| misses.range(l.saturating_sub(2)..=l + 2).next().is_some())
    };
    let mut h = String::from("<pre class=\"src\">");
    let mut gap = false;
    for (i, l) in lines.iter().enumerate() {
        let n = i as u32 + 1;
        if !show(i + 1) {
            if !gap {
                h.push_str("<span class=\"gap\">      ...</span>\n");
                gap = true;
            }
            continue;
        }
        gap = false;
        let (count, cls) = match at.get(&n) {
            Some(&(_, true, _)) => (" miss".to_string(), "miss"),
            Some(&(_, _, true)) => ("waived".to_string(), "waived"),
            Some(&(c, false, false)) => (format!("{c:>6}"), "hit"),
            None => (String::new(), "none"),
        };
        let _ = std::fmt::Write::write_fmt(
            &mut h,
            format_args!(
                "<span class=\"{cls}\">{n:>5} {count:>6}  {}</span>\n",
                esc(l)
            ),
        );
    }
    h.push_str("</pre>\n");
    h
}

/// The style of the section (added to report.html's).
pub const CSS: &str = "pre.src{font-size:12px;line-height:1.25;overflow-x:auto;background:#fafafa;padding:4px}pre.src span{display:inline-block;width:100%}pre.src .miss{background:#f4a6a6}pre.src .hit{background:#e5f5e0}pre.src .waived{background:#e0e0e0;color:#555}pre.src .gap{color:#888}.cc-ok{background:#e5f5e0}.cc-bad{background:#fbe3a0}";

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_point_is_one_whatever_the_parameters_of_its_build() {
        assert_eq!(
            strip_param_suffix("v_line/updown_counter_58cd__C10"),
            "v_line/updown_counter_58cd"
        );
        assert_eq!(
            strip_param_suffix("v_line/register_file__pi1"),
            "v_line/register_file"
        );
        assert_eq!(strip_param_suffix("v_toggle/pmu50"), "v_toggle/pmu50");
        assert_eq!(strip_param_suffix("v_toggle/my__mod"), "v_toggle/my__mod");
    }

    #[test]
    fn netlist_names_read_as_written() {
        assert_eq!(
            demangle("drive_interval__02esi_max"),
            "drive_interval.si_max"
        );
        assert_eq!(demangle("plain_name"), "plain_name");
        assert_eq!(demangle("a__0"), "a__0");
    }

    #[test]
    fn seeds_round_trip_as_ranges() {
        let s = [5, 1, 2, 3, 9, 10, 7];
        assert_eq!(seeds_text(&s), "1-3,5,7,9-10");
        assert_eq!(
            parse_seeds("1-3,5,7,9-10").unwrap(),
            vec![1, 2, 3, 5, 7, 9, 10]
        );
        assert!(parse_seeds("3-1").is_none());
    }

    #[test]
    fn a_key_is_read_into_its_point() {
        let k = "\u{1}f\u{2}rtl/a.v\u{1}l\u{2}33\u{1}n\u{2}9\u{1}page\u{2}v_branch/a\u{1}o\u{2}if\u{1}S\u{2}33-36,40\u{1}h\u{2}pmu50.u";
        let p = Point::parse(k);
        assert_eq!(p.file, "rtl/a.v");
        assert_eq!(p.line, 33);
        assert_eq!(p.kind, Kind::Branch);
        assert_eq!(p.lines, vec![(33, 36), (40, 40)]);
        let t = Point::parse(
            "\u{1}f\u{2}rtl/a.v\u{1}l\u{2}3\u{1}page\u{2}v_toggle/a\u{1}o\u{2}cnt[12]\u{1}h\u{2}x",
        );
        assert_eq!(t.signal(), ("cnt", Some(12)));
        assert!(!t.covered(0) && t.covered(1));
    }

    #[test]
    fn waivers_are_checked_with_file_line_and_field() {
        let p = Path::new("w.toml");
        let ok = "[[waiver]]\nfile = \"rtl/a.v\"\nsignal = \"cnt[15:4]\"\nreason = \"unused high bits of CNT_W\"\n\n[[waiver]]\nfile = \"a.v\"\nline = \"3-4\"\nreason = \"defensive default of a full case\"\n";
        let w = Waivers::parse(ok, p, None).unwrap();
        assert_eq!(w.list.len(), 2);
        assert_eq!(w.list[1].at, 6);
        let t = Point::parse("\u{1}f\u{2}hdl/rtl/a.v\u{1}l\u{2}3\u{1}page\u{2}v_toggle/a\u{1}o\u{2}cnt[12]\u{1}h\u{2}x");
        assert!(w.list[0].covers(&t));
        let low = Point::parse("\u{1}f\u{2}hdl/rtl/a.v\u{1}l\u{2}3\u{1}page\u{2}v_toggle/a\u{1}o\u{2}cnt[3]\u{1}h\u{2}x");
        assert!(!w.list[0].covers(&low));
        let cases = [
            (
                "[[waiver]]\nfile = \"a.v\"\nline = 0\nreason = \"a good long reason\"\n",
                "w.toml:3: field `line`",
            ),
            (
                "[[waiver]]\nfile = \"a.v\"\nline = 3\nreason = \"short\"\n",
                "w.toml:4: field `reason`",
            ),
            (
                "[[waiver]]\nfile = \"a.v\"\nreason = \"a good long reason\"\n",
                "w.toml:1: field `line`",
            ),
            (
                "[[waiver]]\nfile = \"a.v\"\nsignal = \"3x\"\nreason = \"a good long reason\"\n",
                "w.toml:3: field `signal`",
            ),
            (
                "[[waiver]]\nfile = \"a.v\"\nline = 3\nwhy = 1\nreason = \"a good long reason\"\n",
                "w.toml:",
            ),
        ];
        for (text, want) in cases {
            let e = Waivers::parse(text, p, None).unwrap_err().to_string();
            assert!(e.starts_with(want), "{e} should start with {want}");
        }
    }

    #[test]
    fn lcov_has_lines_branches_and_toggles() {
        let mut t = Total::default();
        t.counts.insert("\u{1}f\u{2}a.v\u{1}l\u{2}3\u{1}page\u{2}v_line/a\u{1}o\u{2}block\u{1}S\u{2}3-4\u{1}h\u{2}x".into(), 5);
        t.counts.insert("\u{1}f\u{2}a.v\u{1}l\u{2}6\u{1}page\u{2}v_branch/a\u{1}o\u{2}if\u{1}S\u{2}6\u{1}h\u{2}x".into(), 0);
        t.counts.insert(
            "\u{1}f\u{2}a.v\u{1}l\u{2}1\u{1}page\u{2}v_toggle/a\u{1}o\u{2}q\u{1}h\u{2}x".into(),
            2,
        );
        let l = t.lcov();
        assert!(l.contains("SF:a.v\n"));
        assert!(l.contains("DA:3,5\nDA:4,5\nDA:6,0\n"));
        assert!(l.contains("BRDA:1,1,0,2\nBRDA:6,0,0,0\nBRF:2\nBRH:1\n"));
        assert!(l.contains("LF:3\nLH:2\nend_of_record"));
    }
}
