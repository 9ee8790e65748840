//! `coverage.json`, the merge format: every bin of the model with its hits, and the runs counted
//! in them.
//!
//! ```json
//! {"format": "pmu50-coverage", "version": 1, "model": "pmu50-coverage/1234/…",
//!  "bins": [{"name": "fig17.path.s6_shorten", "kind": "point", "hits": 12, "cite": "…"}, …],
//!  "runs": [{"id": "random/42", "verdict": "pass"}, …]}
//! ```
//!
//! A merge adds the hits bin by bin and unites the runs: it is commutative and associative
//! (sums and a set union kept sorted by id), and it refuses a run id counted twice, a file of
//! another model or format, and a corrupt file, before anything is written.

use crate::model::{model_id, Kind};
use crate::sample::{layout, Coverage};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::Path;

pub const FORMAT: &str = "pmu50-coverage";
pub const VERSION: u32 = 1;

#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BinRecord {
    pub name: String,
    pub kind: Kind,
    pub hits: u64,
    pub cite: String,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub unreachable: Option<String>,
    /// How the coverage proofs decided the bin (`pmu50 signoff` writes it): `proven
    /// unreachable: <property> on <sets>`, `witnessed: ...`, `undecided: ...`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub proof: Option<String>,
}

/// One run counted in the hits: its id (unique across every merged file) and its verdict.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RunRecord {
    pub id: String,
    pub verdict: String,
}

#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CoverageFile {
    pub format: String,
    pub version: u32,
    pub model: String,
    pub bins: Vec<BinRecord>,
    pub runs: Vec<RunRecord>,
}

#[derive(Debug, thiserror::Error, PartialEq, Eq)]
pub enum DbError {
    #[error("{file}: not a coverage file: {detail}")]
    Corrupt { file: String, detail: String },
    #[error("{file}: format \"{found}\" version {version} is not {FORMAT} version {VERSION}")]
    Foreign {
        file: String,
        found: String,
        version: u32,
    },
    #[error("{file}: sampled with coverage model {found}, this tool's model is {expected}: merge files of the same pmu50 version")]
    OtherModel {
        file: String,
        found: String,
        expected: String,
    },
    #[error("{file}: bin {index} is \"{found}\" where the model has \"{expected}\"")]
    BinMismatch {
        file: String,
        index: usize,
        found: String,
        expected: String,
    },
    #[error("run \"{id}\" is counted twice ({first} and {second}): each run may be merged once")]
    DuplicateRun {
        id: String,
        first: String,
        second: String,
    },
    #[error("{file}: hits of bin \"{bin}\" overflow 64 bits")]
    Overflow { file: String, bin: String },
    #[error("{file}: bin \"{bin}\" is declared unreachable ({why}) but has {hits} hits: not a file this model's sampler wrote")]
    UnreachableHit {
        file: String,
        bin: String,
        why: String,
        hits: u64,
    },
    #[error("{file}: {hits} hits counted in no run (\"runs\": []); a coverage file names the runs it counts, so that a merge counts each run once")]
    NoRuns { file: String, hits: u64 },
    #[error("{file}: {reason}")]
    Io { file: String, reason: String },
    #[error("{file}: the output is also input {input}, which the merge would replace; write to another file")]
    OutputIsInput { file: String, input: String },
}

impl CoverageFile {
    /// The file of one set of counters and the runs counted in them.
    pub fn from_coverage(hits: &[u64], runs: Vec<RunRecord>) -> CoverageFile {
        let l = layout();
        let bins = l
            .bins
            .iter()
            .zip(hits)
            .map(|(b, &h)| BinRecord {
                name: b.name.clone(),
                kind: b.kind,
                hits: h,
                cite: b.cite.to_string(),
                unreachable: b.unreachable.map(str::to_string),
                proof: None,
            })
            .collect();
        let mut runs = runs;
        runs.sort_by(|a, b| a.id.cmp(&b.id));
        CoverageFile {
            format: FORMAT.into(),
            version: VERSION,
            model: model_id(l),
            bins,
            runs,
        }
    }

    /// An empty file of this model (the identity of [`merge`]).
    pub fn empty() -> CoverageFile {
        CoverageFile::from_coverage(&vec![0; layout().bins.len()], Vec::new())
    }

    pub fn hits(&self) -> Vec<u64> {
        self.bins.iter().map(|b| b.hits).collect()
    }

    /// Parse and check a file's text (`file` names it in errors). Parsed straight into the
    /// typed file (a 50 MB file of a million runs takes about its size in memory, not 30 times).
    pub fn parse(text: &str, file: &str) -> Result<CoverageFile, DbError> {
        #[derive(Deserialize)]
        struct Header {
            #[serde(default)]
            format: Option<serde_json::Value>,
            #[serde(default)]
            version: Option<serde_json::Value>,
        }
        let corrupt = |e: serde_json::Error| DbError::Corrupt {
            file: file.into(),
            detail: format!("line {}, column {}: {e}", e.line(), e.column()),
        };
        let h: Header = serde_json::from_str(text).map_err(corrupt)?;
        let format = h
            .format
            .as_ref()
            .and_then(|f| f.as_str())
            .unwrap_or("")
            .to_string();
        let version = h.version.as_ref().and_then(|v| v.as_u64()).unwrap_or(0);
        if format != FORMAT || version != u64::from(VERSION) {
            return Err(DbError::Foreign {
                file: file.into(),
                found: format,
                version: version.min(u64::from(u32::MAX)) as u32,
            });
        }
        let f: CoverageFile = serde_json::from_str(text).map_err(corrupt)?;
        f.check(file)?;
        Ok(f)
    }

    /// The model, bins and runs are this tool's and consistent.
    pub fn check(&self, file: &str) -> Result<(), DbError> {
        let l = layout();
        let expected = model_id(l);
        if self.model != expected {
            return Err(DbError::OtherModel {
                file: file.into(),
                found: self.model.clone(),
                expected,
            });
        }
        if self.bins.len() != l.bins.len() {
            return Err(DbError::Corrupt {
                file: file.into(),
                detail: format!("{} bins, the model has {}", self.bins.len(), l.bins.len()),
            });
        }
        for (index, (b, m)) in self.bins.iter().zip(&l.bins).enumerate() {
            if b.name != m.name || b.kind != m.kind {
                return Err(DbError::BinMismatch {
                    file: file.into(),
                    index,
                    found: b.name.clone(),
                    expected: m.name.clone(),
                });
            }
        }
        for (b, m) in self.bins.iter().zip(&l.bins) {
            if let (Some(why), true) = (m.unreachable, b.hits > 0) {
                return Err(DbError::UnreachableHit {
                    file: file.into(),
                    bin: b.name.clone(),
                    why: why.to_string(),
                    hits: b.hits,
                });
            }
        }
        let total = self.bins.iter().fold(0u64, |t, b| t.saturating_add(b.hits));
        if self.runs.is_empty() && total > 0 {
            return Err(DbError::NoRuns {
                file: file.into(),
                hits: total,
            });
        }
        let mut seen: BTreeMap<&str, ()> = BTreeMap::new();
        for r in &self.runs {
            if seen.insert(&r.id, ()).is_some() {
                return Err(DbError::DuplicateRun {
                    id: r.id.clone(),
                    first: file.into(),
                    second: file.into(),
                });
            }
        }
        Ok(())
    }

    pub fn read(path: &Path) -> Result<CoverageFile, DbError> {
        let file = path.display().to_string();
        let meta = std::fs::metadata(path).map_err(|e| DbError::Io {
            file: file.clone(),
            reason: e.to_string(),
        })?;
        if !meta.is_file() {
            return Err(DbError::Io {
                file,
                reason: "not a regular file".into(),
            });
        }
        const LIMIT: u64 = 1 << 30;
        if meta.len() > LIMIT {
            return Err(DbError::Corrupt {
                file,
                detail: format!(
                    "{} bytes, more than a coverage file of this model can be ({LIMIT})",
                    meta.len()
                ),
            });
        }
        let text = std::fs::read_to_string(path).map_err(|e| DbError::Io {
            file: file.clone(),
            reason: e.to_string(),
        })?;
        CoverageFile::parse(&text, &file)
    }

    /// The text written to `coverage.json` (one bin per line, deterministic).
    pub fn to_text(&self) -> String {
        let mut s = String::with_capacity(self.bins.len() * 160 + self.runs.len() * 48);
        let _ = self.write_text(&mut s);
        s
    }

    /// [`CoverageFile::to_text`] into `w`, a line at a time.
    pub fn write_text(&self, w: &mut dyn std::fmt::Write) -> std::fmt::Result {
        writeln!(
            w,
            "{{\"format\": {}, \"version\": {}, \"model\": {},\n \"bins\": [",
            json(&self.format),
            self.version,
            json(&self.model)
        )?;
        for (k, b) in self.bins.iter().enumerate() {
            let sep = if k + 1 == self.bins.len() { "" } else { "," };
            writeln!(
                w,
                "  {}{sep}",
                serde_json::to_string(b).expect("a bin record serialises")
            )?;
        }
        writeln!(w, " ],\n \"runs\": [")?;
        for (k, r) in self.runs.iter().enumerate() {
            let sep = if k + 1 == self.runs.len() { "" } else { "," };
            writeln!(
                w,
                "  {}{sep}",
                serde_json::to_string(r).expect("a run record serialises")
            )?;
        }
        writeln!(w, " ]}}")
    }

    /// Bins hit at least once, and bins that can be hit.
    pub fn closure(&self) -> (usize, usize) {
        let reachable = self.bins.iter().filter(|b| b.unreachable.is_none()).count();
        let hit = self
            .bins
            .iter()
            .filter(|b| b.unreachable.is_none() && b.hits > 0)
            .count();
        (hit, reachable)
    }
}

fn json(s: &str) -> String {
    serde_json::to_string(s).expect("a string serialises")
}

/// Merge files (each with the name used in errors): the hits added bin by bin, the runs united.
/// Nothing is returned unless every file is consistent and no run is counted twice.
pub fn merge<'a>(
    files: impl IntoIterator<Item = (&'a str, &'a CoverageFile)>,
) -> Result<CoverageFile, DbError> {
    let l = layout();
    let mut hits = vec![0u64; l.bins.len()];
    let mut runs: BTreeMap<&str, (&RunRecord, &str)> = BTreeMap::new();
    for (name, f) in files {
        f.check(name)?;
        for (k, b) in f.bins.iter().enumerate() {
            hits[k] = hits[k]
                .checked_add(b.hits)
                .ok_or_else(|| DbError::Overflow {
                    file: name.into(),
                    bin: b.name.clone(),
                })?;
        }
        for r in &f.runs {
            if let Some((_, first)) = runs.get(r.id.as_str()) {
                return Err(DbError::DuplicateRun {
                    id: r.id.clone(),
                    first: first.to_string(),
                    second: name.into(),
                });
            }
            runs.insert(&r.id, (r, name));
        }
    }
    Ok(CoverageFile::from_coverage(
        &hits,
        runs.into_values().map(|(r, _)| r.clone()).collect(),
    ))
}

/// Write `text` to `path` through a temporary file beside it, renamed into place when complete.
/// A path that is (or links to) a device, a FIFO, a socket or a folder is refused and left as it
/// is: the rename would replace the node itself (as root, `/dev/null`). A symbolic link to a
/// regular file is replaced by the file; its target is left alone.
pub fn write_file(path: &Path, text: &str) -> Result<(), DbError> {
    use std::io::Write;
    let file = path.display().to_string();
    let refuse = |kind: &str| {
        DbError::Io { file: file.clone(), reason: format!("is a {kind}, not a regular file; a coverage file never replaces it (give the path of a file)") }
    };
    let check = || -> Result<(), DbError> {
        match std::fs::metadata(path) {
            Ok(m) => match special_kind(&m) {
                Some(kind) => Err(refuse(kind)),
                None => Ok(()),
            },
            Err(_) => Ok(()),
        }
    };
    check()?;
    let name = path.file_name().ok_or_else(|| DbError::Io {
        file: file.clone(),
        reason: "not a file name".into(),
    })?;
    let io = |e: std::io::Error| DbError::Io {
        file: file.clone(),
        reason: e.to_string(),
    };
    let mut tmp = None;
    for k in 0..100u32 {
        let mut tmp_name = std::ffi::OsString::from(".");
        tmp_name.push(name);
        tmp_name.push(format!(".{}.{k}.tmp", std::process::id()));
        let p = path.with_file_name(tmp_name);
        match std::fs::OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(&p)
        {
            Ok(f) => {
                tmp = Some((p, f));
                break;
            }
            Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => continue,
            Err(e) => return Err(io(e)),
        }
    }
    let (tmp, mut f) = tmp.ok_or_else(|| DbError::Io {
        file: file.clone(),
        reason: "no free temporary name beside it".into(),
    })?;
    let done = f
        .write_all(text.as_bytes())
        .and_then(|_| f.sync_data())
        .map_err(io)
        .and_then(|_| check())
        .and_then(|_| std::fs::rename(&tmp, path).map_err(io));
    if done.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    done
}

/// What `m` is when it is a folder, a device, a FIFO or a socket.
fn special_kind(m: &std::fs::Metadata) -> Option<&'static str> {
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        let ft = m.file_type();
        if ft.is_char_device() {
            return Some("character device");
        } else if ft.is_block_device() {
            return Some("block device");
        } else if ft.is_fifo() {
            return Some("FIFO");
        } else if ft.is_socket() {
            return Some("socket");
        }
    }
    if m.is_dir() {
        Some("folder")
    } else {
        None
    }
}

/// Merge the files `paths` into `out` (written with [`write_file`]): refused when `out` is one
/// of the inputs (the same file, through any link), before anything is read.
pub fn merge_files(paths: &[&Path], out: &Path) -> Result<CoverageFile, DbError> {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        if let Ok(o) = std::fs::metadata(out) {
            for p in paths {
                if std::fs::metadata(p).is_ok_and(|m| m.dev() == o.dev() && m.ino() == o.ino()) {
                    return Err(DbError::OutputIsInput {
                        file: out.display().to_string(),
                        input: p.display().to_string(),
                    });
                }
            }
        }
    }
    let files: Vec<(String, CoverageFile)> = paths
        .iter()
        .map(|p| Ok((p.display().to_string(), CoverageFile::read(p)?)))
        .collect::<Result<_, DbError>>()?;
    let merged = merge(files.iter().map(|(n, f)| (n.as_str(), f)))?;
    write_file(out, &merged.to_text())?;
    Ok(merged)
}

/// The file of one coverage run.
pub fn of_run(c: &Coverage, id: &str, verdict: &str) -> CoverageFile {
    CoverageFile::from_coverage(
        c.hits(),
        vec![RunRecord {
            id: id.into(),
            verdict: verdict.into(),
        }],
    )
}
