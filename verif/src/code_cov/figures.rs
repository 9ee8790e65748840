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
    #[serde(default)]
    pub expr: Count,
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
    /// Its kind (`UNR`, `NON_RTL`, `UNSUPPORTED`, `EXTERNAL`, `LOW_RISK`) and reviewer.
    #[serde(default)]
    pub kind: String,
    #[serde(default)]
    pub reviewer: String,
    /// Its claim (`holds`), proven by the coverage proofs.
    #[serde(default)]
    pub holds: Option<String>,
    /// The source lines it covers (`12-14,40`) and their checksum now.
    #[serde(default)]
    pub lines: String,
    #[serde(default)]
    pub checksum: String,
    /// Why it does not apply (stale: its lines changed since its review; or no checksum): its
    /// points count as not waived.
    #[serde(default)]
    pub stale: Option<String>,
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
    /// Expression terms (Verilator's `--coverage-expr`, `v_expr`: one row of an expression's
    /// truth table, continuous `assign`s included): seen at least once. A build without
    /// expression coverage has none (`expr_measured` false).
    #[serde(default)]
    pub expr: Count,
    /// Whether the builds measured expression coverage (a Verilator with `--coverage-expr` on
    /// continuous assignments: the coverage builds' Verilator, docs/verification.md).
    #[serde(default)]
    pub expr_measured: bool,
    pub files: Vec<FileFigures>,
    pub waivers: Vec<WaiverUse>,
    /// The waivers file the figures apply: `code/waivers.toml` of the folder (a copy of the
    /// file given to the run), empty when the run had none.
    pub waivers_file: String,
}

impl CodeSummary {
    /// The per-file table as Markdown (`code/summary.md`), as docs/verification.md quotes the
    /// twin's figures (section 9; checked against a run by tests/doc_figures.rs): line, toggle
    /// and expression points covered of those counted, and those waived; `-` where a file has
    /// no point of a kind.
    pub fn markdown(&self) -> String {
        fn cell(c: &Count, bold: bool) -> String {
            if c.total == 0 {
                return "-".into();
            }
            let pct = if c.pct.fract() == 0.0 {
                format!("{:.0} %", c.pct)
            } else {
                format!("{:.2} %", c.pct)
            };
            if bold {
                format!("**{}/{} ({pct})**", c.hit, c.total)
            } else {
                format!("{}/{}", c.hit, c.total)
            }
        }
        let expr = |c: &Count, bold: bool| {
            if self.expr_measured {
                cell(c, bold)
            } else {
                "not measured".to_string()
            }
        };
        let mut t = String::from(
            "| file | line | toggle | toggle waived | expression | expression waived |\n|---|---:|---:|---:|---:|---:|\n",
        );
        for f in &self.files {
            t.push_str(&format!(
                "| {} | {} | {} | {} | {} | {} |\n",
                f.file,
                cell(&f.line, false),
                cell(&f.toggle, false),
                f.toggle.waived,
                expr(&f.expr, false),
                f.expr.waived
            ));
        }
        t.push_str(&format!(
            "| **all** | {} | {} | **{}** | {} | **{}** |\n",
            cell(&self.line, true),
            cell(&self.toggle, true),
            self.toggle.waived,
            expr(&self.expr, true),
            self.expr.waived
        ));
        t
    }
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
        // the file each waiver is in, as the points name it, and its source now
        let point_files: std::collections::BTreeSet<String> = c
            .total
            .counts
            .keys()
            .map(|k| Point::parse(k).file)
            .filter(|f| !f.is_empty())
            .collect();
        let review = |w: &Waiver| -> (String, String, Option<String>) {
            let found = point_files.iter().find(|f| file_matches(f, &w.file));
            let source = found.and_then(|f| {
                let p = Path::new(f);
                let p = match &base {
                    Some(b) if p.is_relative() => b.join(p),
                    _ => p.to_path_buf(),
                };
                std::fs::read_to_string(p).ok()
            });
            match source {
                None => (
                    String::new(),
                    String::new(),
                    Some(format!(
                        "stale: its file {} is not a file of the run's RTL that can be read",
                        w.file
                    )),
                ),
                Some(src) => {
                    let lines = w.lines(&src);
                    let now = crate::waiver::checksum(&src, &lines);
                    let stale = crate::waiver::current(&w.review, &src, &lines)
                        .err()
                        .map(|e| {
                            format!(
                                "{e}; lines {} of {}",
                                crate::waiver::ranges(&lines),
                                found.map_or("", |f| f.as_str())
                            )
                        });
                    (crate::waiver::ranges(&lines), now, stale)
                }
            }
        };
        let reviews: Vec<(String, String, Option<String>)> =
            waivers.list.iter().map(review).collect();
        let mut uses: Vec<WaiverUse> = waivers
            .list
            .iter()
            .zip(&reviews)
            .map(|(w, (lines, checksum, stale))| WaiverUse {
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
                kind: w.review.kind.name().to_string(),
                reviewer: w.review.reviewer.clone(),
                holds: w.holds.clone(),
                lines: lines.clone(),
                checksum: checksum.clone(),
                stale: stale.clone(),
            })
            .collect();
        let (mut line, mut toggle, mut expr) =
            (Count::default(), Count::default(), Count::default());
        for (k, &n) in &c.total.counts {
            let p = Point::parse(k);
            if p.kind == Kind::Other {
                continue;
            }
            // a stale waiver does not apply: its points count
            let matching = waivers.list.iter().position(|w| w.covers(&p));
            let covered = p.covered(n);
            if let Some(i) = matching {
                uses[i].points += 1;
                uses[i].covered += u64::from(covered);
            }
            let by = matching.filter(|&i| reviews[i].2.is_none());
            let f = files.entry(p.file.clone()).or_insert_with(|| FileFigures {
                file: p.file.clone(),
                ..Default::default()
            });
            match p.kind {
                Kind::Toggle => {
                    f.toggle.add(covered, by.is_some());
                    toggle.add(covered, by.is_some());
                }
                Kind::Expr => {
                    f.expr.add(covered, by.is_some());
                    expr.add(covered, by.is_some());
                }
                _ => {
                    f.line.add(covered, by.is_some());
                    line.add(covered, by.is_some());
                }
            }
            points.entry(p.file.clone()).or_default().push((p, n, by));
        }
        line.finish();
        toggle.finish();
        expr.finish();
        let expr_measured = c
            .total
            .counts
            .keys()
            .any(|k| k.contains("\u{1}page\u{2}v_expr"));
        let files: Vec<FileFigures> = files
            .into_values()
            .map(|mut f| {
                f.line.finish();
                f.toggle.finish();
                f.expr.finish();
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
                expr,
                expr_measured,
                files,
                waivers: uses,
                waivers_file: waivers.origin.clone(),
            },
            points,
            base,
        }
    }

    /// coverage.dat, lcov.info, summary.json and summary.md of `dir/code/`, added to `batch`; the summary
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
        batch.add(write_atomic(
            &cd.join("summary.md"),
            self.summary.markdown().as_bytes(),
        )?);
        Ok(())
    }

    /// The lines printed on stderr: the figures, and each waiver with what it excluded.
    pub fn text(&self) -> String {
        let s = &self.summary;
        let mut t = format!(
            "code coverage: line {}/{} ({:.2} %), toggle {}/{} ({:.2} %), {} over {} seed(s); {} line, {} toggle and {} expression point(s) waived by {} waiver(s) of {}\n",
            s.line.hit,
            s.line.total,
            s.line.pct,
            s.toggle.hit,
            s.toggle.total,
            s.toggle.pct,
            if s.expr_measured {
                format!("expression {}/{} ({:.2} %)", s.expr.hit, s.expr.total, s.expr.pct)
            } else {
                "expression not measured (a Verilator without --coverage-expr on continuous assignments)".to_string()
            },
            s.seeds,
            s.line.waived,
            s.toggle.waived,
            s.expr.waived,
            s.waivers.len(),
            if s.waivers_file.is_empty() { "(none)" } else { &s.waivers_file },
        );
        for w in &s.waivers {
            if let Some(st) = &w.stale {
                t.push_str(&format!(
                    "  waiver {}:{} ({} {}) does not apply, {st}\n",
                    s.waivers_file, w.at, w.file, w.what
                ));
                continue;
            }
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
