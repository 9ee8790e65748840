//! Grading (docs/verification.md, "Grading"): which seeds of a regression contribute which
//! coverage. `pmu50 grade DIR` ranks the seeds greedily, each by the bins it hits that no
//! earlier-ranked seed hits (ties to the smaller seed), until no seed adds a bin: the shortest
//! list this greedy set cover finds that keeps every bin the regression hit. `pmu50 regress
//! --seeds-from DIR/graded.json --out D` reruns only that list, each seed with the stimulus it
//! had in the regression (a directed seed's bias rebuilt from the seeds before its batch), and
//! compares the coverage.

use crate::error::{file_err, RegressError};
use crate::summary::{Source, Summary};
use pmu50_coverage::layout;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;
use std::time::Duration;

/// One ranked seed.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Ranked {
    pub seed: u64,
    /// Bins this seed hits that no earlier-ranked seed hits.
    pub adds: u64,
    /// Bins hit by the seeds ranked so far.
    pub covered: u64,
}

/// `graded.json`: the ranked list of a regression folder.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Graded {
    pub format: String,
    /// The regression folder graded.
    pub folder: String,
    /// Its seeds with a result, and the bins they hit together.
    pub seeds: u64,
    pub bins_hit: u64,
    /// The bins the seeds' stimuli can reach (the model's reachable bins).
    pub reachable: u64,
    pub ranked: Vec<Ranked>,
}

pub const FORMAT: &str = "pmu50-graded-1";
pub const FILE: &str = "graded.json";

/// Rank the seeds of `dir` (greedy set cover over the bins they hit).
pub fn grade(dir: &Path) -> Result<Graded, RegressError> {
    let spec = crate::summary::read_spec(dir)?;
    let s = Summary::build(spec.clone(), &[Source::of(dir, &spec)])?;
    let n = layout().bins.len();
    let mut sets: Vec<(u64, Vec<usize>)> = Vec::with_capacity(s.store.len());
    let mut reader = s.store.reader()?;
    let mut scratch = vec![0u64; n];
    for e in &s.store.entries {
        scratch.iter_mut().for_each(|h| *h = 0);
        reader
            .result(e)?
            .hits(&mut scratch)
            .map_err(RegressError::Usage)?;
        let bins: Vec<usize> = (0..n).filter(|&i| scratch[i] > 0).collect();
        if !bins.is_empty() {
            sets.push((e.seed, bins));
        }
    }
    drop(reader);
    let mut covered = vec![false; n];
    let mut ranked = Vec::new();
    let mut total = 0u64;
    loop {
        // the seed adding most (the smaller seed on a tie: sets are in seed order)
        let mut best: Option<(usize, u64)> = None;
        for (k, (_, bins)) in sets.iter().enumerate() {
            let adds = bins.iter().filter(|&&b| !covered[b]).count() as u64;
            if adds > best.map(|b| b.1).unwrap_or(0) {
                best = Some((k, adds));
            }
        }
        let Some((k, adds)) = best else { break };
        let (seed, bins) = sets.swap_remove(k);
        // keep seed order for the tie rule
        sets.sort_by_key(|(s, _)| *s);
        for b in bins {
            covered[b] = true;
        }
        total += adds;
        ranked.push(Ranked {
            seed,
            adds,
            covered: total,
        });
    }
    let (hit, reachable) = s.coverage.closure();
    debug_assert_eq!(hit as u64, total);
    Ok(Graded {
        format: FORMAT.into(),
        folder: dir.display().to_string(),
        seeds: s.seeds(),
        bins_hit: total,
        reachable: reachable as u64,
        ranked,
    })
}

impl Graded {
    /// Read a graded list (`pmu50 grade`'s `graded.json`).
    pub fn read(path: &Path) -> Result<Graded, RegressError> {
        let text = std::fs::read_to_string(path).map_err(|e| file_err(path, e))?;
        let g: Graded = serde_json::from_str(&text).map_err(|e| RegressError::Line {
            path: path.to_path_buf(),
            line: e.line() as u64,
            reason: e.to_string(),
        })?;
        if g.format != FORMAT {
            return Err(file_err(
                path,
                format!("field `format`: `{}`; valid is `{FORMAT}`", g.format),
            ));
        }
        Ok(g)
    }

    pub fn json(&self) -> String {
        serde_json::to_string_pretty(self).unwrap_or_default() + "\n"
    }

    /// The curve as text: rank, seed, bins added, bins covered.
    pub fn text(&self) -> String {
        let mut t = format!(
            "grade: {} of {} seeds keep the {} bins they hit ({} reachable)\n{:>5} {:>20} {:>6} {:>8}\n",
            self.ranked.len(),
            self.seeds,
            self.bins_hit,
            self.reachable,
            "rank",
            "seed",
            "adds",
            "covered"
        );
        for (i, r) in self.ranked.iter().enumerate() {
            t += &format!(
                "{:>5} {:>20} {:>6} {:>8}\n",
                i + 1,
                r.seed,
                r.adds,
                r.covered
            );
        }
        t
    }

    /// The curve as an SVG: bins covered against the seeds ranked.
    pub fn svg(&self) -> String {
        let (w, h, l, b) = (560.0, 260.0, 50.0, 36.0);
        let n = self.ranked.len().max(1) as f64;
        let top = self.reachable.max(1) as f64;
        let x = |i: f64| l + (w - l - 12.0) * i / n;
        let y = |c: f64| 10.0 + (h - b - 10.0) * (1.0 - c / top);
        let mut pts = vec![format!("{:.1},{:.1}", x(0.0), y(0.0))];
        for (i, r) in self.ranked.iter().enumerate() {
            pts.push(format!(
                "{:.1},{:.1}",
                x(i as f64 + 1.0),
                y(r.covered as f64)
            ));
        }
        format!(
            "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{w}\" height=\"{h}\" font-family=\"sans-serif\" font-size=\"11\">\n\
<rect width=\"{w}\" height=\"{h}\" fill=\"white\"/>\n\
<line x1=\"{l}\" y1=\"{y0:.1}\" x2=\"{xe:.1}\" y2=\"{y0:.1}\" stroke=\"#999\"/><line x1=\"{l}\" y1=\"10\" x2=\"{l}\" y2=\"{y0:.1}\" stroke=\"#999\"/>\n\
<line x1=\"{l}\" y1=\"{yt:.1}\" x2=\"{xe:.1}\" y2=\"{yt:.1}\" stroke=\"#ccc\" stroke-dasharray=\"4 3\"/>\n\
<text x=\"4\" y=\"{yt4:.1}\">{}</text><text x=\"4\" y=\"{y04:.1}\">0</text>\n\
<polyline fill=\"none\" stroke=\"#27c\" stroke-width=\"2\" points=\"{}\"/>\n\
<text x=\"{l}\" y=\"{yl:.1}\">graded seeds: {} of {} keep {} bins hit ({} reachable)</text>\n</svg>\n",
            self.reachable,
            pts.join(" "),
            self.ranked.len(),
            self.seeds,
            self.bins_hit,
            self.reachable,
            y0 = y(0.0),
            xe = w - 12.0,
            yt = y(top),
            yt4 = y(top) + 4.0,
            y04 = y(0.0) + 4.0,
            yl = h - 8.0,
        )
    }
}

/// `pmu50 grade DIR`: the ranked list into `DIR/graded.json` and `DIR/graded.svg`.
pub fn run(dir: &Path) -> Result<Graded, RegressError> {
    let g = grade(dir)?;
    let mut b = pmu50_testbench::atomic_file::Batch::new();
    b.add(pmu50_testbench::atomic_file::write_atomic(
        &dir.join(FILE),
        g.json().as_bytes(),
    )?);
    b.add(pmu50_testbench::atomic_file::write_atomic(
        &dir.join("graded.svg"),
        g.svg().as_bytes(),
    )?);
    b.commit()?;
    Ok(g)
}

/// What a rerun of a graded list found.
pub struct Rerun {
    pub seeds: u64,
    pub failed: u64,
    /// Bins the rerun hit, and the bins the graded regression hit.
    pub bins_hit: u64,
    pub original_hit: u64,
    /// Bins the regression hit that the rerun did not.
    pub lost: Vec<String>,
}

/// Rerun the seeds of a graded list on `d`, each with its regression's stimulus, into `out`
/// (`results.jsonl`, `coverage.json`).
pub fn rerun(
    list: &Path,
    out: &Path,
    d: &dyn crate::dut::Dut,
    jobs: usize,
    timeout: Duration,
    stop: &AtomicBool,
) -> Result<Rerun, RegressError> {
    let g = Graded::read(list)?;
    let dir = PathBuf::from(&g.folder);
    let spec = crate::summary::read_spec(&dir)?;
    let s = Summary::build(spec.clone(), &[Source::of(&dir, &spec)])?;
    let mut seeds: Vec<u64> = g.ranked.iter().map(|r| r.seed).collect();
    seeds.sort_unstable();
    // the batches of a directed regression, each with its bias
    let mut groups: Vec<(u64, Vec<u64>)> = Vec::new();
    for &seed in &seeds {
        let lo = if spec.directed {
            spec.start_seed + (seed - spec.start_seed) / crate::pool::BATCH * crate::pool::BATCH
        } else {
            0
        };
        match groups.last_mut() {
            Some((l, v)) if *l == lo => v.push(seed),
            _ => groups.push((lo, vec![seed])),
        }
    }
    let mut results = Vec::new();
    for (lo, todo) in groups {
        // as the regression drew it: its bias, and its pool of parameter sets (build modes)
        let before = if spec.directed {
            s.hits_before(lo)?
        } else {
            Vec::new()
        };
        let bias = spec.bias(&before);
        results.extend(crate::pool::run_pool(
            &spec,
            &todo,
            &bias,
            d,
            jobs,
            timeout,
            stop,
            |_| Ok(()),
        )?);
    }
    results.sort_by_key(|(r, _)| r.seed);
    let n = layout().bins.len();
    let mut hits = vec![0u64; n];
    let mut text = String::new();
    let mut failed = 0;
    for (r, h) in &results {
        for (t, x) in hits.iter_mut().zip(h) {
            *t = t.saturating_add(*x);
        }
        failed += u64::from(r.verdict != crate::spec::Verdict::Pass);
        text += &serde_json::to_string(r).map_err(|e| RegressError::Usage(e.to_string()))?;
        text.push('\n');
    }
    let runs = results
        .iter()
        .map(|(r, _)| pmu50_coverage::RunRecord {
            id: spec.run_id(r.seed),
            verdict: r.verdict.name().into(),
        })
        .collect();
    let cov = pmu50_coverage::CoverageFile::from_coverage(&hits, runs);
    pmu50_testbench::atomic_file::create_dir(out)?;
    let mut b = pmu50_testbench::atomic_file::Batch::new();
    b.add(pmu50_testbench::atomic_file::write_atomic(
        &out.join("results.jsonl"),
        text.as_bytes(),
    )?);
    b.add(pmu50_testbench::atomic_file::write_atomic(
        &out.join("coverage.json"),
        cov.to_text().as_bytes(),
    )?);
    b.commit()?;
    let lost: Vec<String> = s
        .coverage
        .bins
        .iter()
        .zip(&cov.bins)
        .filter(|(a, b)| a.hits > 0 && b.hits == 0)
        .map(|(a, _)| a.name.clone())
        .collect();
    Ok(Rerun {
        seeds: results.len() as u64,
        failed,
        bins_hit: cov.closure().0 as u64,
        original_hit: s.coverage.closure().0 as u64,
        lost,
    })
}
