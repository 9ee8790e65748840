//! The code coverage of a regression folder (`<out>/code/`): one part per batch of seeds,
//! resumed, reconciled with `results.jsonl`, compacted and collected across folders.

use super::sums::*;
use super::waivers::*;
use crate::error::RegressError;
use std::collections::{BTreeSet, HashMap};
use std::path::{Path, PathBuf};

/// `<dir>/code`.
pub fn code_dir(dir: &Path) -> PathBuf {
    dir.join("code")
}

pub(super) fn parts_dir(dir: &Path) -> PathBuf {
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
    pmu50_testbench::atomic_file::create_dir(&pd)?;
    let text = total.dat(&format!(
        "seeds {}\npmu50 code coverage: the summed counts of these seeds",
        seeds_text(seeds)
    ));
    let path = pd.join(format!("{first}-{last}.dat"));
    let mut b = pmu50_testbench::atomic_file::Batch::new();
    b.add(pmu50_testbench::atomic_file::write_atomic(
        &path,
        text.as_bytes(),
    )?);
    b.commit()?;
    Ok(Some(path))
}

/// Parts a folder keeps while a run goes on: past this, they are summed into one.
pub(super) const MAX_PARTS: usize = 32;

/// The parts to count, largest first, none sharing a seed with one before it (a compaction an
/// interruption cut leaves the summed part beside the parts it sums).
pub(super) fn disjoint(mut parts: Vec<Part>) -> (Vec<Part>, Vec<Part>) {
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
    pmu50_testbench::atomic_file::create_dir(&pd)?;
    let mut b = pmu50_testbench::atomic_file::Batch::new();
    b.add(pmu50_testbench::atomic_file::write_atomic(
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
        let s = crate::folder::scan(&results, 0, range, &mut scratch, |_, _| {})?;
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
        let Some(f) = crate::folder::open_regular(&p, false)? else {
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
