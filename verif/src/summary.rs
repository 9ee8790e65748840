//! What a regression folder holds, summed ([`Summary`]): read back from `regress.json` and the
//! results files (written by `crate::publish`).

use crate::curve::pct;
use crate::error::{file_err, RegressError};
use crate::spec::RunSpec;
use crate::{code_cov, folder};
use pmu50_coverage::{layout, CoverageFile, RunRecord};
use std::path::Path;
use std::path::PathBuf;

/// Read regress.json of `dir`, checked as strictly as the command line ([`folder::parse_spec`]).
pub fn read_spec(dir: &Path) -> Result<RunSpec, RegressError> {
    folder::read_spec(dir)
}

/// A results file summed into a [`Summary`], and the seeds it may hold (its folder's range).
#[derive(Clone, Debug)]
pub struct Source {
    pub results: PathBuf,
    pub range: std::ops::Range<u64>,
}

impl Source {
    /// The results file of the regression folder `dir` of `spec`.
    pub fn of(dir: &Path, spec: &RunSpec) -> Source {
        Source {
            results: dir.join("results.jsonl"),
            range: spec.seeds(),
        }
    }
}

/// What a regression folder holds, summed: the counts, the coverage and the failures by
/// signature in memory; the results themselves stay in their files ([`folder::Store`]).
pub struct Summary {
    pub spec: RunSpec,
    pub store: folder::Store,
    pub pass: u64,
    pub fail: u64,
    pub error: u64,
    /// Failing seeds by signature.
    pub groups: std::collections::BTreeMap<String, folder::Group>,
    pub coverage: CoverageFile,
    /// Seeds of the range with no result, as ranges.
    pub missing: Vec<std::ops::Range<u64>>,
    /// The closure curve: (seeds, % of the bins scenario stimuli reach), where it changes.
    pub curve: Vec<(u64, f64)>,
    /// The RTL's code coverage (`spec.code_coverage`), from the folders' `code/parts/`.
    pub code: Option<code_cov::CodeReport>,
    /// What made the folder (sealed into its regress.json when written); `None` for a folder
    /// without provenance.
    pub evidence: Option<crate::evidence::RunEvidence>,
}

impl Summary {
    /// Read and check every results file of `sources`, in one pass each, and sum them.
    pub fn build(spec: RunSpec, sources: &[Source]) -> Result<Summary, RegressError> {
        if sources.len() > usize::from(u16::MAX) {
            return Err(RegressError::Usage(format!(
                "{} results files: at most {} merge at once",
                sources.len(),
                u16::MAX
            )));
        }
        let mut hits = vec![0u64; layout().bins.len()];
        let (mut pass, mut fail, mut error) = (0u64, 0u64, 0u64);
        let mut groups: std::collections::BTreeMap<String, folder::Group> =
            std::collections::BTreeMap::new();
        let mut entries = Vec::new();
        for (k, s) in sources.iter().enumerate() {
            let scanned = folder::scan(&s.results, k as u16, &s.range, &mut hits, |r, e| {
                match e.verdict {
                    folder::Verdict::Pass => pass += 1,
                    folder::Verdict::Fail => fail += 1,
                    folder::Verdict::Error => error += 1,
                }
                if let Some(f) = &r.failure {
                    let g = groups
                        .entry(f.signature())
                        .or_insert_with(|| folder::Group {
                            count: 0,
                            smallest: r.seed,
                            failure: f.clone(),
                            file: e.file,
                        });
                    g.count += 1;
                    if r.seed < g.smallest {
                        g.smallest = r.seed;
                        g.failure = f.clone();
                        g.file = e.file;
                    }
                }
            })?;
            entries.extend(scanned.entries);
        }
        let store =
            folder::Store::new(sources.iter().map(|s| s.results.clone()).collect(), entries)?;
        let runs = store
            .entries
            .iter()
            .map(|e| RunRecord {
                id: spec.run_id(e.seed),
                verdict: e.verdict.name().into(),
            })
            .collect();
        let mut missing = Vec::new();
        let range = spec.seeds();
        let mut next = range.start;
        for e in &store.entries {
            if e.seed > next {
                missing.push(next..e.seed);
            }
            next = e.seed + 1;
        }
        if next < range.end {
            missing.push(next..range.end);
        }
        let mut curve = crate::curve::Curve::new();
        let mut reader = store.reader()?;
        let mut scratch = vec![0u64; hits.len()];
        for e in &store.entries {
            scratch.iter_mut().for_each(|h| *h = 0);
            reader
                .result(e)?
                .hits(&mut scratch)
                .map_err(RegressError::Usage)?;
            curve.push(&scratch);
        }
        drop(reader);
        let code = if spec.code_coverage {
            let dirs: Vec<(PathBuf, std::collections::BTreeSet<u64>)> = sources
                .iter()
                .enumerate()
                .map(|(k, s)| {
                    (
                        s.results.parent().unwrap_or(Path::new(".")).to_path_buf(),
                        store
                            .entries
                            .iter()
                            .filter(|e| usize::from(e.file) == k)
                            .map(|e| e.seed)
                            .collect(),
                    )
                })
                .collect();
            let collected = code_cov::collect(&dirs)?;
            let folders: Vec<PathBuf> = dirs.iter().map(|(d, _)| d.clone()).collect();
            let waivers = code_cov::folder_waivers(&folders)?.unwrap_or_default();
            let base = match &spec.rtl {
                Some(r) => Path::new(r).parent().map(Path::to_path_buf),
                None => Some(crate::hdl_kit::hdl_dir()),
            };
            Some(code_cov::CodeReport::build(&collected, &waivers, base))
        } else {
            None
        };
        Ok(Summary {
            code,
            evidence: None,
            coverage: CoverageFile::from_coverage(&hits, runs),
            spec,
            store,
            pass,
            fail,
            error,
            groups,
            missing,
            curve: curve.finish(),
        })
    }

    /// Seeds with a result.
    pub fn seeds(&self) -> u64 {
        self.store.len() as u64
    }

    /// Seeds that did not pass.
    pub fn failed(&self) -> u64 {
        self.fail + self.error
    }

    /// Seeds of the range with no result.
    pub fn missing_count(&self) -> u64 {
        self.missing.iter().map(|r| r.end - r.start).sum()
    }

    /// The coverage of the seeds before `seed` (a directed batch's bias), read back in order.
    pub fn hits_before(&self, seed: u64) -> Result<Vec<u64>, RegressError> {
        let mut before = vec![0u64; layout().bins.len()];
        let mut reader = self.store.reader()?;
        for e in self.store.entries.iter().take_while(|e| e.seed < seed) {
            reader
                .result(e)?
                .hits(&mut before)
                .map_err(RegressError::Usage)?;
        }
        Ok(before)
    }

    /// The signatures whose repro folder `dir/failures/<signature>/` holds a repro; the folders
    /// of signatures no seed fails with are removed (a rerun into the same folder).
    pub fn repro_folders(
        &self,
        dir: &Path,
    ) -> Result<std::collections::BTreeMap<String, Option<String>>, RegressError> {
        let mut have = std::collections::BTreeMap::new();
        let failures = dir.join("failures");
        match std::fs::symlink_metadata(&failures) {
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(have),
            Err(e) => return Err(file_err(&failures, e)),
            Ok(m) if !m.is_dir() => {
                return Err(file_err(
                    &failures,
                    "is not a folder; the repros of a regression go into the folder failures/",
                ))
            }
            Ok(_) => {}
        }
        let rd = std::fs::read_dir(&failures).map_err(|e| file_err(&failures, e))?;
        for d in rd {
            let d = d.map_err(|e| file_err(&failures, e))?;
            let name = d.file_name().to_string_lossy().into_owned();
            let path = d.path();
            if self.groups.contains_key(&name) {
                if std::fs::symlink_metadata(path.join("repro.toml")).is_ok_and(|m| m.is_file()) {
                    // the picture, when it is a regular file of a sane size
                    let svg = path.join("divergence.svg");
                    let pic = std::fs::symlink_metadata(&svg)
                        .ok()
                        .filter(|m| m.is_file() && m.len() < 4 << 20)
                        .and_then(|_| std::fs::read_to_string(&svg).ok())
                        .and_then(|t| t.find("<svg").map(|i| t[i..].to_string()));
                    have.insert(name, pic);
                }
            } else if std::fs::symlink_metadata(&path).is_ok_and(|m| m.is_dir()) {
                // A signature of an earlier run into this folder: no seed fails with it now.
                std::fs::remove_dir_all(&path).map_err(|e| {
                    file_err(&path, format!("cannot remove the stale repro folder: {e}"))
                })?;
            }
        }
        Ok(have)
    }

    /// The summary printed on stdout.
    pub fn text(&self) -> String {
        let (hit, reachable) = self.coverage.closure();
        let scen = scenario_closure(&self.coverage);
        let mut s = format!(
            "regress: {} seeds, {} pass, {} fail, {} error; coverage {hit}/{reachable} bins ({:.1} %), {}/{} of those scenario stimuli can reach ({:.1} %)\n",
            self.seeds(),
            self.pass,
            self.fail,
            self.error,
            pct(hit, reachable),
            scen.0,
            scen.1,
            pct(scen.0, scen.1),
        );
        if let Some(first) = self.missing.first() {
            s.push_str(&format!(
                "missing seeds: {} (first {}); run them with --resume\n",
                self.missing_count(),
                first.start
            ));
        }
        for (sig, g) in &self.groups {
            s.push_str(&format!(
                "  fail {sig}: {} seed(s), smallest {}\n",
                g.count, g.smallest
            ));
        }
        s
    }
}

/// Bins that scenario stimuli can reach (not unreachable, not port-level only): hit and total.
pub fn scenario_closure(c: &CoverageFile) -> (usize, usize) {
    let l = layout();
    let mut hit = 0;
    let mut total = 0;
    for (b, info) in c.bins.iter().zip(&l.bins) {
        if info.unreachable.is_none() && !info.port_only {
            total += 1;
            hit += usize::from(b.hits > 0);
        }
    }
    (hit, total)
}
