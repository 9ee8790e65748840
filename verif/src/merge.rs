//! `pmu50 merge --out DIR IN...`: regression folders (shards of one regression, resumed parts,
//! or regressions of adjacent seed ranges) and coverage files (from cocotb, a DPI bench, another
//! regression) merged into one folder with the same files as a one-process run: the same
//! results, coverage, verdicts and repro folders.
//!
//! Folders of the same DUT and options whose seed ranges differ merge into one regression over
//! the union of their ranges (seeds 1-2000 today, 2001-4000 tomorrow), when the ranges neither
//! overlap nor leave a gap, and the regression is not directed (a directed seed depends on the
//! seeds before it in its own range).
//!
//! Refused, before anything is written: folders of different regressions (naming the field that
//! differs), overlapping ranges or a gap between them, a shard given twice, a seed present in two
//! folders, a coverage run id counted twice, a corrupt or foreign file; an output folder that is
//! an input or holds one; an output folder holding a regression already, unless `--force`.
//! Missing seeds are listed (and written to `missing.txt`); `pmu50 regress --resume DIR` runs
//! only those.

use crate::error::RegressError;
use crate::evidence::{CoverageInput, RunEvidence};
use crate::folder;
use crate::folder::read_spec_file;
use crate::provenance::Provenance;
use crate::spec::RunSpec;
use crate::summary::Source;
use crate::summary::Summary;
use crate::triage;
use pmu50_coverage::{merge as merge_cov, CoverageFile};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// What was merged.
pub struct Merged {
    pub summary: Summary,
    pub folders: usize,
    pub coverage_files: usize,
}

/// The fields of two runs that differ (other than the seed range and the shard), each as
/// `field: A against B`.
pub fn differences(a: &RunSpec, b: &RunSpec) -> Vec<String> {
    let mut d = Vec::new();
    let mut cmp = |field: &str, x: String, y: String| {
        if x != y {
            d.push(format!("{field} {x} against {y}"));
        }
    };
    cmp("tool", a.tool.clone(), b.tool.clone());
    cmp("model", a.model.clone(), b.model.clone());
    cmp("directed", a.directed.to_string(), b.directed.to_string());
    cmp(
        "check_spec",
        a.check_spec.to_string(),
        b.check_spec.to_string(),
    );
    cmp(
        "dut",
        format!("{:?}", a.dut).to_lowercase(),
        format!("{:?}", b.dut).to_lowercase(),
    );
    cmp(
        "rtl",
        a.rtl.clone().unwrap_or_else(|| "(none)".into()),
        b.rtl.clone().unwrap_or_else(|| "(none)".into()),
    );
    cmp(
        "map",
        a.map.clone().unwrap_or_else(|| "(none)".into()),
        b.map.clone().unwrap_or_else(|| "(none)".into()),
    );
    let fixed = |f: &crate::rtl::Fixed| {
        if f.is_empty() {
            "(nothing)".to_string()
        } else {
            f.text()
        }
    };
    cmp("fixed", fixed(&a.fixed), fixed(&b.fixed));
    cmp(
        "code_coverage",
        a.code_coverage.to_string(),
        b.code_coverage.to_string(),
    );
    cmp(
        "param_sets",
        a.param_sets.to_string(),
        b.param_sets.to_string(),
    );
    let pin = |p: Option<u8>| p.map_or_else(|| "(drawn per seed)".to_string(), |v| v.to_string());
    cmp(
        "pins.sync_depth",
        pin(a.pins.sync_depth),
        pin(b.pins.sync_depth),
    );
    cmp(
        "pins.cnt_width",
        pin(a.pins.cnt_width),
        pin(b.pins.cnt_width),
    );
    if (a.start_seed, a.iterations) == (b.start_seed, b.iterations) && a.pool != b.pool {
        // parts of one seed range draw from one pool
        d.push("pool (the parameter sets differ)".to_string());
    }
    d
}

/// The regression the folders `specs` (each with its path) are parts of: their common options
/// over the union of their seed ranges. Pure: the merge's plan, checked before any file is read.
pub fn plan(specs: &[(PathBuf, RunSpec)]) -> Result<RunSpec, RegressError> {
    let Some((p0, first)) = specs.first() else {
        return Err(RegressError::Usage("no regression folder to merge".into()));
    };
    for (p, s) in &specs[1..] {
        let d = differences(first, s);
        if !d.is_empty() {
            return Err(RegressError::Usage(format!("{} and {} are parts of different regressions ({}): merge folders of one DUT and the same options", p0.display(), p.display(), d.join(", "))));
        }
    }
    // The seed ranges, each with the first folder of it; shards by range.
    let mut ranges: BTreeMap<(u64, u64), &Path> = BTreeMap::new();
    let mut shards: BTreeMap<(u64, u64, u64), &Path> = BTreeMap::new();
    for (p, s) in specs {
        let whole = (s.start_seed, s.start_seed + s.iterations);
        ranges.entry(whole).or_insert(p);
        if let Some(sh) = &s.shard {
            if let Some(other) = shards.insert((whole.0, whole.1, sh.index), p) {
                return Err(RegressError::Usage(format!(
                    "shard {}/{} is given twice: {} and {}",
                    sh.index,
                    sh.count,
                    other.display(),
                    p.display()
                )));
            }
        }
    }
    let whole: Vec<((u64, u64), &Path)> = ranges.into_iter().collect();
    if whole.len() > 1 && first.directed {
        return Err(RegressError::Usage(format!(
            "{} and {} are directed regressions of different seed ranges ({}..={} and {}..={}): a directed seed steers by the seeds before it in its own range, so only the shards and resumed parts of one directed regression merge",
            whole[0].1.display(),
            whole[1].1.display(),
            whole[0].0 .0,
            whole[0].0 .1 - 1,
            whole[1].0 .0,
            whole[1].0 .1 - 1
        )));
    }
    for w in whole.windows(2) {
        let (((a0, a1), pa), ((b0, b1), pb)) = (w[0], w[1]);
        if b0 < a1 {
            return Err(RegressError::Usage(format!(
                "{} (seeds {a0}..={}) and {} (seeds {b0}..={}) overlap in seeds {b0}..={}: merge regressions of disjoint seed ranges",
                pa.display(),
                a1 - 1,
                pb.display(),
                b1 - 1,
                a1.min(b1) - 1
            )));
        }
        if b0 > a1 {
            return Err(RegressError::Usage(format!(
                "seeds {a1}..={} lie between {} (seeds {a0}..={}) and {} (seeds {b0}..={}) and are in neither: run them (pmu50 regress --start-seed {a1} --iterations {}) and merge the three",
                b0 - 1,
                pa.display(),
                a1 - 1,
                pb.display(),
                b1 - 1,
                b0 - a1
            )));
        }
    }
    let (start, end) = (whole[0].0 .0, whole[whole.len() - 1].0 .1);
    // Adjacent seed ranges each drew from their own pool: the merged record lists them all.
    let mut pool = first.pool.clone();
    for (_, s) in specs {
        for set in &s.pool {
            if !pool.contains(set) {
                pool.push(*set);
            }
        }
    }
    let merged = RunSpec {
        start_seed: start,
        iterations: end - start,
        shard: None,
        pool,
        ..first.clone()
    };
    merged.validate().map_err(|e| {
        RegressError::Usage(format!(
            "the union of the seed ranges {start}..={}: {e}",
            end - 1
        ))
    })?;
    Ok(merged)
}

/// Refuse an output folder that is an input or holds an input file (which the merge could
/// replace), and (without `force`) one that holds a regression already.
fn check_output(inputs: &[PathBuf], out: &Path, force: bool) -> Result<(), RegressError> {
    let Ok(out_canon) = out.canonicalize() else {
        return Ok(());
    };
    for p in inputs {
        let Ok(c) = p.canonicalize() else { continue };
        if c == out_canon {
            return Err(RegressError::Usage(format!(
                "{}: the output folder is also an input; merge into a new folder",
                p.display()
            )));
        }
        // A file in the output folder (its coverage.json) may be one the merge replaces; a
        // folder in it (shards kept below the merged folder) is not, unless under failures/.
        if c.starts_with(&out_canon) && (!c.is_dir() || c.starts_with(out_canon.join("failures"))) {
            return Err(RegressError::Usage(format!("{}: this input is inside the output folder {}, whose files the merge replaces; merge into a new folder", p.display(), out.display())));
        }
    }
    if !force && std::fs::symlink_metadata(out.join("regress.json")).is_ok() {
        return Err(RegressError::Usage(format!("{}: holds a regression already (regress.json); merge into a new folder, or give --force to replace its files", out.display())));
    }
    Ok(())
}

pub fn merge(inputs: &[PathBuf], out: &Path, force: bool) -> Result<Merged, RegressError> {
    if inputs.is_empty() {
        return Err(RegressError::Usage("merge needs at least one input: regression folders (with regress.json) or coverage.json files".into()));
    }
    check_output(inputs, out, force)?;
    let mut specs: Vec<(PathBuf, RunSpec)> = Vec::new();
    let mut evidence: Vec<(PathBuf, Option<RunEvidence>)> = Vec::new();
    let mut extra: Vec<(String, CoverageFile)> = Vec::new();
    let mut extra_inputs: Vec<CoverageInput> = Vec::new();
    for p in inputs {
        let meta = std::fs::metadata(p).map_err(|e| RegressError::File {
            path: p.clone(),
            reason: e.to_string(),
        })?;
        if meta.is_dir() {
            let sf = read_spec_file(p)?;
            specs.push((p.clone(), sf.spec));
            evidence.push((p.clone(), sf.evidence));
        } else {
            let (cf, input) = crate::evidence::read_coverage_input(p)?;
            extra.push((p.display().to_string(), cf));
            extra_inputs.push(input);
        }
    }
    let summary = if specs.is_empty() {
        // Coverage files only.
        let cov = merge_cov(extra.iter().map(|(n, f)| (n.as_str(), f)))
            .map_err(|e| RegressError::Usage(e.to_string()))?;
        let spec = RunSpec {
            tool: format!("pmu50 {}", env!("CARGO_PKG_VERSION")),
            model: cov.model.clone(),
            start_seed: 0,
            iterations: 0,
            directed: false,
            check_spec: false,
            dut: crate::spec::DutKind::model(),
            rtl: None,
            map: None,
            fixed: Default::default(),
            pins: crate::gen::Pins::default(),
            shard: None,
            code_coverage: false,
            param_sets: 0,
            pool: Vec::new(),
        };
        let mut sum = Summary::build(spec, &[])?;
        sum.coverage = cov;
        sum
    } else {
        let whole = plan(&specs)?;
        let sources: Vec<Source> = specs.iter().map(|(p, s)| Source::of(p, s)).collect();
        let mut sum = Summary::build(whole.clone(), &sources)?;
        sum.evidence = merged_evidence(&whole, &evidence, extra_inputs)?;
        if !extra.is_empty() {
            let mut files: Vec<(&str, &CoverageFile)> =
                vec![("the regression folders", &sum.coverage)];
            files.extend(extra.iter().map(|(n, f)| (n.as_str(), f)));
            sum.coverage = merge_cov(files).map_err(|e| RegressError::Usage(e.to_string()))?;
        }
        sum
    };
    if let Some(code) = &summary.code {
        if code.summary.seeds_unaccounted > 0 {
            return Err(RegressError::Usage(format!("{} seed(s) of the input folders have a result but no code coverage counted (a folder interrupted and not resumed): run pmu50 regress --resume on each such input, then merge", code.summary.seeds_unaccounted)));
        }
    }
    pmu50_testbench::atomic_file::create_dir(out)?;
    let folders: Vec<&Path> = specs.iter().map(|(p, _)| p.as_path()).collect();
    copy_repros(&summary, &folders, out)?;
    if let Some(code) = &summary.code {
        // the merged folder's code coverage as one part of all its counted seeds, and the
        // waivers of its inputs: it merges and resumes as a folder of one run does
        let seeds: Vec<u64> = summary.store.entries.iter().map(|e| e.seed).collect();
        let waivers = crate::code_cov::folder_waivers(
            &folders.iter().map(|p| p.to_path_buf()).collect::<Vec<_>>(),
        )?
        .unwrap_or_default();
        crate::code_cov::start(out, &waivers)?;
        crate::code_cov::write_part(out, &seeds, &code.total)?;
    }
    crate::publish::write(&summary, out, None)?;
    Ok(Merged {
        summary,
        folders: specs.len(),
        coverage_files: extra.len(),
    })
}

/// The files of a repro folder, copied as they are but for `command.txt` and the command at
/// the end of `failure.txt`, which name the repro's new path.
const REPRO_FILES: [&str; 5] = [
    "repro.toml",
    "repro.vcd",
    "repro.gtkw",
    "failure.txt",
    "divergence.svg",
];

/// For each signature, the repro folder of its smallest seed, from the input folder holding
/// that seed, into `out/failures/<signature>/` (when that input has one).
fn copy_repros(s: &Summary, folders: &[&Path], out: &Path) -> Result<(), RegressError> {
    use pmu50_testbench::atomic_file::{write_atomic, AtomicFile, Batch, OutputError};
    for (sig, g) in &s.groups {
        let Some(input) = folders.get(usize::from(g.file)) else {
            continue;
        };
        let from = input.join("failures").join(sig);
        if !std::fs::symlink_metadata(from.join("repro.toml")).is_ok_and(|m| m.is_file()) {
            continue;
        }
        let to = out.join("failures").join(sig);
        pmu50_testbench::atomic_file::create_dir(&to)?;
        let repro = to.join("repro.toml");
        let cmd = triage::command(&s.spec, &repro);
        let mut batch = Batch::new();
        for name in REPRO_FILES {
            let src = from.join(name);
            let Some(mut f) = folder::open_regular(&src, false)? else {
                continue;
            };
            let dest = to.join(name);
            if name == "failure.txt" {
                let mut text = String::new();
                std::io::Read::read_to_string(&mut std::io::Read::take(&mut f, 1 << 20), &mut text)
                    .map_err(|e| RegressError::File {
                        path: src.clone(),
                        reason: e.to_string(),
                    })?;
                let head = text.split("\nreproduce:\n").next().unwrap_or_default();
                batch.add(write_atomic(
                    &dest,
                    format!("{head}\nreproduce:\n  {cmd}\n").as_bytes(),
                )?);
            } else {
                let mut a = AtomicFile::stage(&dest)?;
                std::io::copy(&mut f, &mut a).map_err(|source| OutputError::Write {
                    path: dest.clone(),
                    source,
                })?;
                if name == "repro.gtkw" {
                    batch.set_last(a);
                } else {
                    batch.add(a);
                }
            }
        }
        batch.add(write_atomic(
            &to.join("command.txt"),
            format!("{cmd}\n").as_bytes(),
        )?);
        batch.commit()?;
    }
    Ok(())
}

/// The evidence of a merged folder: the inputs' common RTL and coverage model (refused when two
/// disagree, naming both), the merged seed range, and every coverage file merged with its own
/// provenance. `None` when an input folder has none: a merge never makes provenance up.
fn merged_evidence(
    whole: &RunSpec,
    inputs: &[(PathBuf, Option<RunEvidence>)],
    extra: Vec<CoverageInput>,
) -> Result<Option<RunEvidence>, RegressError> {
    let mut first: Option<(&Path, &RunEvidence)> = None;
    let mut coverage_inputs = Vec::new();
    for (p, ev) in inputs {
        let Some(ev) = ev else { return Ok(None) };
        match first {
            None => first = Some((p, ev)),
            Some((p0, e0)) => {
                let d = crate::evidence::disagreements(
                    &Provenance {
                        seeds: None,
                        ..e0.provenance.clone()
                    },
                    &ev.provenance,
                );
                if !d.is_empty() {
                    return Err(RegressError::Usage(format!(
                        "{} and {} were run on different RTLs or models ({}): merge folders of one RTL",
                        p0.display(),
                        p.display(),
                        d.join(", ")
                    )));
                }
            }
        }
        coverage_inputs.extend(ev.coverage_inputs.iter().cloned());
    }
    let Some((p0, e0)) = first else {
        return Ok(None);
    };
    for c in &extra {
        if let Some(cp) = &c.provenance {
            let d = crate::evidence::disagreements(
                &Provenance {
                    seeds: None,
                    ..e0.provenance.clone()
                },
                cp,
            );
            if !d.is_empty() {
                return Err(RegressError::Usage(format!(
                    "{} and {} are of different RTLs or models ({}): merge coverage of the RTL the regression ran",
                    p0.display(),
                    c.file,
                    d.join(", ")
                )));
            }
        }
    }
    coverage_inputs.extend(extra);
    let mut provenance = Provenance::now(
        "pmu50 merge",
        e0.provenance.rtl.clone(),
        &e0.provenance.dut,
        Some(crate::evidence::seeds_of(whole)),
    );
    provenance.tools = e0.provenance.tools.clone();
    Ok(Some(RunEvidence {
        provenance,
        record: crate::evidence::Record {
            command: crate::evidence::command_line(),
            rtl_files: e0.record.rtl_files.clone(),
        },
        coverage_inputs,
    }))
}
