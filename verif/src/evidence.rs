//! The chain of evidence of a regression folder (docs/verification.md, "Sign-off"): what made
//! each file, which RTL it was computed on, and the digests that catch an edited byte.
//!
//! - `regress.json` is sealed ([`crate::provenance::seal`]): beside the run's options it holds
//!   the [`Provenance`] of the run (tool and git commit, coverage model, the RTL's file list and
//!   content hash, the DUT, the seed range, the simulators' versions), the [`Record`] of the run
//!   (its command line and the SHA-256 of every RTL file read), the coverage files merged into
//!   the folder with their own provenance ([`CoverageInput`]), and `files`: the SHA-256 of
//!   `results.jsonl` and `coverage.json` as the run completed them. An appended file cannot
//!   carry its own digest while it grows; the run writes both files and then the digests, in
//!   one commit (regress.json renamed last), so a folder interrupted mid-run has none, and an
//!   edited line or bin is seen.
//! - `code/summary.json` is sealed with the run's provenance.
//! - A coverage file of a single run (`pmu50 lockstep --coverage`) is sealed inline; `pmu50
//!   merge` records its provenance in the merged folder's regress.json.
//! - The scripts (formal kit, coverage proofs) seal their JSON with `pmu50 seal`.

use crate::error::{file_err, RegressError};
use crate::filelist::FileList;
use crate::provenance::{self, Provenance, RtlId, Seeds};
use crate::spec::RunSpec;
use serde::{Deserialize, Serialize};
use serde_json::{Map, Value};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// One RTL file as the run read it.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RtlFile {
    /// Its path relative to the file list's folder (absolute when outside it).
    pub file: String,
    /// `sha256:` and the digest of its bytes.
    pub sha256: String,
}

/// What a failure needs to be reproduced: the command line and every RTL file's digest.
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Record {
    /// The command line that started the run (`pmu50 regress ...`).
    pub command: Vec<String>,
    /// Every file of the RTL (sources, libraries, included files), in path order.
    pub rtl_files: Vec<RtlFile>,
}

/// A coverage file merged into a folder, with what made it (`None`: it had no provenance).
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CoverageInput {
    /// As named on the merge's command line.
    pub file: String,
    pub sha256: String,
    pub provenance: Option<Provenance>,
}

/// The evidence of a regression folder besides its options: sealed into its `regress.json`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct RunEvidence {
    pub provenance: Provenance,
    pub record: Record,
    pub coverage_inputs: Vec<CoverageInput>,
}

/// A regression folder's `regress.json` read back: the options and, when sealed, the evidence
/// and the digests of its completed files.
#[derive(Clone, Debug)]
pub struct SpecFile {
    pub spec: RunSpec,
    pub evidence: Option<RunEvidence>,
    /// `results.jsonl`, `coverage.json`: `sha256:...` of each as the run completed it.
    pub files: BTreeMap<String, String>,
}

/// The keys of a sealed regress.json that are not [`RunSpec`]'s.
const EVIDENCE_KEYS: [&str; 4] = ["provenance", "record", "files", "coverage_inputs"];

/// The file list of the RTL a run of `spec` is on (the twin's when `--rtl` is absent), or
/// `None` for a DUT that runs no RTL.
pub fn rtl_list(spec: &RunSpec) -> Option<PathBuf> {
    let caps = crate::dut::of(&spec.dut).ok()?.caps;
    if !caps.rtl {
        return None;
    }
    Some(match &spec.rtl {
        Some(r) => PathBuf::from(r),
        None => crate::hdl_kit::hdl_dir().join("pmu50.f"),
    })
}

/// The RTL `list` names: its id (list and content hash) and every file's digest.
pub fn rtl_of(list: &Path) -> Result<(RtlId, Vec<RtlFile>), RegressError> {
    let fl = FileList::read(list).map_err(|e| RegressError::Usage(e.to_string()))?;
    let hash = fl
        .content_hash()
        .map_err(|e| RegressError::Usage(e.to_string()))?;
    let base = fl.list.parent().unwrap_or(Path::new("/")).to_path_buf();
    let mut files = Vec::new();
    for f in fl.content_files() {
        let bytes = std::fs::read(&f).map_err(|e| file_err(&f, e))?;
        files.push(RtlFile {
            file: f
                .strip_prefix(&base)
                .map(|r| r.display().to_string())
                .unwrap_or_else(|_| f.display().to_string()),
            sha256: format!("sha256:{}", crate::digest::sha256_hex(&bytes)),
        });
    }
    Ok((
        RtlId {
            list: list.display().to_string(),
            hash,
        },
        files,
    ))
}

/// The seed range of a run (the whole regression's, whatever the shard).
pub fn seeds_of(spec: &RunSpec) -> Seeds {
    Seeds {
        start: spec.start_seed,
        count: spec.iterations,
    }
}

/// The evidence of a new run of `spec`, made by `made_by`, started by `command`.
pub fn for_run(
    spec: &RunSpec,
    made_by: &str,
    command: Vec<String>,
) -> Result<RunEvidence, RegressError> {
    let (rtl, rtl_files) = match rtl_list(spec) {
        Some(l) => {
            let (id, files) = rtl_of(&l)?;
            (Some(id), files)
        }
        None => (None, Vec::new()),
    };
    Ok(RunEvidence {
        provenance: Provenance::now(made_by, rtl, spec.dut.name(), Some(seeds_of(spec))),
        record: Record { command, rtl_files },
        coverage_inputs: Vec::new(),
    })
}

/// The command line of this process, for the [`Record`].
pub fn command_line() -> Vec<String> {
    std::env::args().collect()
}

/// The text of `regress.json`: the options, sealed with the evidence and the digests of the
/// completed files when there is evidence (a plain JSON object otherwise).
pub fn spec_text(
    spec: &RunSpec,
    ev: Option<&RunEvidence>,
    files: &BTreeMap<String, String>,
) -> Result<String, RegressError> {
    let v = serde_json::to_value(spec).map_err(|e| RegressError::Usage(e.to_string()))?;
    let Some(ev) = ev else {
        return serde_json::to_string_pretty(&v)
            .map(|t| t + "\n")
            .map_err(|e| RegressError::Usage(e.to_string()));
    };
    let Value::Object(mut m) = v else {
        return Err(RegressError::Usage("a run spec is a JSON object".into()));
    };
    m.insert("record".into(), to_value(&ev.record));
    m.insert("files".into(), to_value(files));
    m.insert("coverage_inputs".into(), to_value(&ev.coverage_inputs));
    Ok(provenance::seal(m, &ev.provenance))
}

/// A value as JSON (every type here serialises).
fn to_value<T: Serialize>(x: &T) -> Value {
    serde_json::to_value(x).unwrap_or(Value::Null)
}

/// Parse a `regress.json`: sealed (its digest checked: an edited byte is an error) or plain (a
/// folder of a version before provenance, or of a run without: no evidence).
pub fn parse_spec_file(text: &str, path: &Path) -> Result<SpecFile, RegressError> {
    let v: Value = serde_json::from_str(text).map_err(|e| RegressError::Line {
        path: path.to_path_buf(),
        line: e.line() as u64,
        reason: e.to_string(),
    })?;
    let sealed = v.get("digest").is_some() || v.get("provenance").is_some();
    if !sealed {
        let spec: RunSpec = serde_json::from_value(v).map_err(|e| file_err(path, e))?;
        return Ok(SpecFile {
            spec,
            evidence: None,
            files: BTreeMap::new(),
        });
    }
    let (mut m, p) = provenance::open(path, text, "pmu50 regress")
        .map_err(|e| RegressError::Usage(e.to_string()))?;
    let mut take = |k: &str| m.remove(k).unwrap_or(Value::Null);
    let _ = take("provenance");
    let record: Record = field(path, "record", take("record"))?.unwrap_or_default();
    let files: BTreeMap<String, String> = field(path, "files", take("files"))?.unwrap_or_default();
    let coverage_inputs: Vec<CoverageInput> =
        field(path, "coverage_inputs", take("coverage_inputs"))?.unwrap_or_default();
    debug_assert!(EVIDENCE_KEYS.iter().all(|k| !m.contains_key(*k)));
    let spec: RunSpec = serde_json::from_value(Value::Object(m)).map_err(|e| file_err(path, e))?;
    Ok(SpecFile {
        spec,
        evidence: Some(RunEvidence {
            provenance: p,
            record,
            coverage_inputs,
        }),
        files,
    })
}

fn field<T: serde::de::DeserializeOwned>(
    path: &Path,
    name: &str,
    v: Value,
) -> Result<Option<T>, RegressError> {
    if v.is_null() {
        return Ok(None);
    }
    serde_json::from_value(v)
        .map(Some)
        .map_err(|e| file_err(path, format!("field `{name}`: {e}")))
}

/// `sha256:` and the SHA-256 of a file's bytes, read in pieces.
pub fn file_digest(path: &Path) -> Result<String, RegressError> {
    use sha2::{Digest, Sha256};
    use std::io::Read;
    let mut f = std::fs::File::open(path).map_err(|e| file_err(path, e))?;
    let mut h = Sha256::new();
    let mut buf = vec![0u8; 1 << 16];
    loop {
        let n = f.read(&mut buf).map_err(|e| file_err(path, e))?;
        if n == 0 {
            break;
        }
        h.update(&buf[..n]);
    }
    let mut s = String::from("sha256:");
    for b in h.finalize() {
        s.push_str(&format!("{b:02x}"));
    }
    Ok(s)
}

/// A coverage file given to `pmu50 merge`: sealed inline (`pmu50 lockstep --coverage`; the
/// digest checked) or plain (a cocotb or DPI bench's; no provenance).
pub fn read_coverage_input(
    path: &Path,
) -> Result<(pmu50_coverage::CoverageFile, CoverageInput), RegressError> {
    let name = path.display().to_string();
    let meta = std::fs::metadata(path).map_err(|e| file_err(path, e))?;
    if !meta.is_file() || meta.len() > 1 << 30 {
        return Err(file_err(
            path,
            "not a regular file of a coverage file's size",
        ));
    }
    let text = std::fs::read_to_string(path).map_err(|e| file_err(path, e))?;
    let sha256 = format!("sha256:{}", crate::digest::sha256_hex(text.as_bytes()));
    let head: Value = serde_json::from_str(&text).unwrap_or(Value::Null);
    let sealed = head.get("digest").is_some() || head.get("provenance").is_some();
    let (cf, p) = if sealed {
        let (mut m, p) = provenance::open(path, &text, "pmu50 lockstep --coverage")
            .map_err(|e| RegressError::Usage(e.to_string()))?;
        m.remove("provenance");
        let plain = serde_json::to_string(&Value::Object(m)).unwrap_or_default();
        let cf = pmu50_coverage::CoverageFile::parse(&plain, &name)
            .map_err(|e| RegressError::Usage(e.to_string()))?;
        (cf, Some(p))
    } else {
        let cf = pmu50_coverage::CoverageFile::parse(&text, &name)
            .map_err(|e| RegressError::Usage(e.to_string()))?;
        (cf, None)
    };
    Ok((
        cf,
        CoverageInput {
            file: name,
            sha256,
            provenance: p,
        },
    ))
}

/// A coverage file of one run, sealed (`pmu50 lockstep --coverage`).
pub fn sealed_coverage(c: &pmu50_coverage::CoverageFile, p: &Provenance) -> String {
    let v: Value = serde_json::from_str(&c.to_text()).unwrap_or(Value::Null);
    match v {
        Value::Object(m) => provenance::seal(m, p),
        _ => c.to_text(),
    }
}

/// The two provenances' values that disagree on what evidence of one sign-off must share:
/// the RTL (content hash), the coverage model and, where both have one, the seed range. Each
/// as `field: A against B`.
pub fn disagreements(a: &Provenance, b: &Provenance) -> Vec<String> {
    let mut d = Vec::new();
    let rtl = |p: &Provenance| {
        p.rtl
            .as_ref()
            .map(|r| format!("{} ({})", r.hash, r.list))
            .unwrap_or_else(|| "no RTL".into())
    };
    if a.rtl.as_ref().map(|r| &r.hash) != b.rtl.as_ref().map(|r| &r.hash) {
        d.push(format!("rtl {} against {}", rtl(a), rtl(b)));
    }
    if a.model_id != b.model_id {
        d.push(format!("model_id {} against {}", a.model_id, b.model_id));
    }
    if let (Some(x), Some(y)) = (a.seeds, b.seeds) {
        if x != y {
            d.push(format!(
                "seeds {}:{} against {}:{}",
                x.start, x.count, y.start, y.count
            ));
        }
    }
    d
}

/// `text` (a sealed JSON object) opened, its provenance removed: the content and what made it.
pub fn open_sealed(
    path: &Path,
    text: &str,
    remedy: &str,
) -> Result<(Map<String, Value>, Provenance), provenance::ProvenanceError> {
    let (mut m, p) = provenance::open(path, text, remedy)?;
    m.remove("provenance");
    Ok((m, p))
}

/// The files that differ between two readings of an RTL, for a message: `` (changed: a.v,
/// added: b.v)`` or nothing.
pub fn changed_files(was: &[RtlFile], now: &[RtlFile]) -> String {
    let old: BTreeMap<&str, &str> = was
        .iter()
        .map(|f| (f.file.as_str(), f.sha256.as_str()))
        .collect();
    let new: BTreeMap<&str, &str> = now
        .iter()
        .map(|f| (f.file.as_str(), f.sha256.as_str()))
        .collect();
    let mut parts = Vec::new();
    let changed: Vec<&str> = new
        .iter()
        .filter(|(k, v)| old.get(*k).is_some_and(|o| o != *v))
        .map(|(k, _)| *k)
        .collect();
    let added: Vec<&str> = new
        .keys()
        .filter(|k| !old.contains_key(*k))
        .copied()
        .collect();
    let removed: Vec<&str> = old
        .keys()
        .filter(|k| !new.contains_key(*k))
        .copied()
        .collect();
    for (what, v) in [("changed", changed), ("added", added), ("removed", removed)] {
        if !v.is_empty() {
            parts.push(format!("{what}: {}", v.join(", ")));
        }
    }
    if parts.is_empty() {
        String::new()
    } else {
        format!(" ({})", parts.join("; "))
    }
}

/// For `pmu50 regress --repro DIR/failures/<sig>/repro.toml`: what the regression of `DIR`
/// recorded of its RTL against the RTL the repro runs on now: `Some` line to print when a file
/// changed (or the regression ran another RTL), `None` when the same or unknown.
pub fn repro_rtl_note(repro: &Path, spec: &RunSpec) -> Result<Option<String>, RegressError> {
    let Some(dir) = repro.parent().and_then(Path::parent).and_then(Path::parent) else {
        return Ok(None);
    };
    let dir = if dir.as_os_str().is_empty() {
        Path::new(".")
    } else {
        dir
    };
    if !dir.join("regress.json").is_file() {
        return Ok(None);
    }
    let spec_path = dir.join("regress.json");
    let Ok(text) = std::fs::read_to_string(&spec_path) else {
        return Ok(None);
    };
    let Ok(sf) = parse_spec_file(&text, &spec_path) else {
        return Ok(None);
    };
    let (Some(ev), Some(list)) = (sf.evidence, rtl_list(spec)) else {
        return Ok(None);
    };
    let Some(was) = &ev.provenance.rtl else {
        return Ok(None);
    };
    let (now, files) = rtl_of(&list)?;
    if now.hash == was.hash {
        return Ok(Some(format!(
            "the RTL is the one the failure was found on ({})",
            now.hash
        )));
    }
    Ok(Some(format!(
        "the RTL changed since the failure was found: {} recorded {} ({}), it is now {} ({}){}",
        dir.join("regress.json").display(),
        was.hash,
        was.list,
        now.hash,
        now.list,
        changed_files(&ev.record.rtl_files, &files)
    )))
}
