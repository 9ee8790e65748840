//! `pmu50 merge --out DIR IN...`: regression folders (shards of one regression, or resumed
//! parts) and coverage files (from cocotb, a DPI bench, another regression) merged into one
//! folder with the same files as a one-process run: the same results, coverage and verdicts.
//!
//! Refused, before anything is written: folders of different regressions (seed range or
//! options), a shard given twice, a seed present in two folders, a coverage run id counted
//! twice, a corrupt or foreign file. Missing seeds are listed (and written to `missing.txt`);
//! `pmu50 regress --resume DIR` runs only those.

use super::{read_results, read_spec, RegressError, RunSpec, SeedResult, Summary};
use pmu50_coverage::{merge as merge_cov, CoverageFile};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// What was merged.
pub struct Merged {
    pub summary: Summary,
    pub folders: usize,
    pub coverage_files: usize,
}

pub fn merge(inputs: &[PathBuf], out: &Path) -> Result<Merged, RegressError> {
    if inputs.is_empty() {
        return Err(RegressError::Usage("merge needs at least one input: regression folders (with regress.json) or coverage.json files".into()));
    }
    let out_canon = out.canonicalize().ok();
    let mut spec: Option<(RunSpec, PathBuf)> = None;
    let mut seeds: BTreeMap<u64, PathBuf> = BTreeMap::new();
    let mut shards: BTreeMap<u64, PathBuf> = BTreeMap::new();
    let mut results: Vec<SeedResult> = Vec::new();
    let mut extra: Vec<(String, CoverageFile)> = Vec::new();
    let mut folders = 0;
    for p in inputs {
        if out_canon.is_some() && p.canonicalize().ok() == out_canon {
            return Err(RegressError::Usage(format!("{}: the output folder is also an input; merge into a new folder", p.display())));
        }
        let meta = std::fs::metadata(p).map_err(|e| RegressError::File { path: p.clone(), reason: e.to_string() })?;
        if meta.is_file() {
            let cf = CoverageFile::read(p).map_err(|e| RegressError::Usage(e.to_string()))?;
            extra.push((p.display().to_string(), cf));
            continue;
        }
        folders += 1;
        let s = read_spec(p)?;
        match &spec {
            None => spec = Some((s.clone(), p.clone())),
            Some((first, fp)) if !first.same_regression(&s) => {
                return Err(RegressError::Usage(format!(
                    "{} and {} are parts of different regressions (seed range {}+{} {} against {}+{} {}): merge the shards of one regression",
                    fp.display(),
                    p.display(),
                    first.start_seed,
                    first.iterations,
                    describe(first),
                    s.start_seed,
                    s.iterations,
                    describe(&s)
                )));
            }
            _ => {}
        }
        if let Some(sh) = &s.shard {
            if let Some(other) = shards.insert(sh.index, p.clone()) {
                return Err(RegressError::Usage(format!("shard {}/{} is given twice: {} and {}", sh.index, sh.count, other.display(), p.display())));
            }
        }
        for r in read_results(&p.join("results.jsonl"))? {
            if let Some(other) = seeds.insert(r.seed, p.clone()) {
                return Err(RegressError::Usage(format!("seed {} is in {} and in {}: each seed may be merged once", r.seed, other.display(), p.display())));
            }
            results.push(r);
        }
    }
    let summary = match spec {
        Some((s, _)) => {
            let whole = RunSpec { shard: None, ..s };
            let mut sum = Summary::build(whole, results)?;
            if !extra.is_empty() {
                let mut files: Vec<(&str, &CoverageFile)> = vec![("the regression folders", &sum.coverage)];
                files.extend(extra.iter().map(|(n, f)| (n.as_str(), f)));
                sum.coverage = merge_cov(files).map_err(|e| RegressError::Usage(e.to_string()))?;
            }
            sum
        }
        None => {
            // Coverage files only.
            let cov = merge_cov(extra.iter().map(|(n, f)| (n.as_str(), f))).map_err(|e| RegressError::Usage(e.to_string()))?;
            let spec = RunSpec {
                tool: format!("pmu50 {}", env!("CARGO_PKG_VERSION")),
                model: cov.model.clone(),
                start_seed: 0,
                iterations: 0,
                directed: false,
                check_spec: false,
                dut: super::DutKind::Model,
                rtl: None,
                map: None,
                fixed: Default::default(),
                pins: super::gen::Pins::default(),
                shard: None,
            };
            let mut sum = Summary::build(spec, Vec::new())?;
            sum.coverage = cov;
            sum
        }
    };
    crate::atomic_file::create_dir(out)?;
    summary.write(out, None)?;
    Ok(Merged { summary, folders, coverage_files: extra.len() })
}

fn describe(s: &RunSpec) -> String {
    let mut d = format!("dut {:?}", s.dut).to_lowercase();
    if s.directed {
        d.push_str(", directed");
    }
    if s.check_spec {
        d.push_str(", check-spec");
    }
    if let Some(r) = &s.rtl {
        d.push_str(&format!(", rtl {r}"));
    }
    d
}
