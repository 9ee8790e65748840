//! The figures of a folder's code coverage after the waivers: `summary.json` and the report's
//! data.

use super::parts::*;
use super::points::*;
use super::sums::*;
use super::waivers::*;
use crate::error::RegressError;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// Version of `summary.json`.
pub const SUMMARY_FORMAT: &str = "pmu50-code-coverage-1";

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

    /// coverage.dat, lcov.info and summary.json of `dir/code/`, added to `batch`; the summary
    /// sealed with `prov` (crate::provenance) when given.
    pub fn write(
        &self,
        dir: &Path,
        batch: &mut pmu50_testbench::atomic_file::Batch,
        prov: Option<&crate::provenance::Provenance>,
    ) -> Result<(), RegressError> {
        use pmu50_testbench::atomic_file::write_atomic;
        let cd = code_dir(dir);
        pmu50_testbench::atomic_file::create_dir(&cd)?;
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
        let json = match (prov, serde_json::to_value(&self.summary)) {
            (Some(p), Ok(serde_json::Value::Object(m))) => crate::provenance::seal(m, p),
            _ => {
                serde_json::to_string_pretty(&self.summary)
                    .map_err(|e| RegressError::Usage(e.to_string()))?
                    + "\n"
            }
        };
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
