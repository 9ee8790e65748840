//! Sign-off view: one table of a regression folder's closure figures, each against its
//! threshold, as OpenTitan's V1-V3 checklists put them (default: V3, every figure at 100 %).
//!
//! | row                | from (in the regression folder)          | figure                         |
//! |--------------------|------------------------------------------|--------------------------------|
//! | functional         | `coverage.json`                          | reachable bins hit             |
//! | unreachable proven | `coverage-proofs.json` (`make signoff`)  | declared-unreachable bins proven |
//! | undecided          | `coverage-proofs.json`                   | bins neither proven nor hit/witnessed (at most) |
//! | code line          | `code/summary.json` (`--code-coverage`)  | RTL lines hit, after waivers   |
//! | code toggle        | `code/summary.json`                      | RTL bits toggled, after waivers |
//! | properties         | `formal.json` (`hdl/formal/run.py --json`) | kit properties proven          |
//! | seeds              | `results.jsonl`                          | seeds passing                  |
//!
//! With the proofs, each bin's decision also goes into `coverage.json` and `coverage.ucis.xml`
//! (the bin's `proof`), and the report lists every bin's reachability.
//!
//! Each row is a [`Criterion`]: a new figure is a new type, not a new branch. A row whose input
//! is absent, or has no provenance, is `missing` and misses its threshold (it says which command
//! writes it); so is a row with nothing to count (0 of 0). An input that is present but
//! unreadable, edited after it was written (its digest), or made on another RTL, coverage model
//! or seed range than the regression's, is an error naming the file and both values (exit 2);
//! so is a regression that ran no RTL. Every input is read through [`Folder::open`]
//! (crate::evidence, crate::provenance).

use crate::code_cov::figures::CodeSummary;
use crate::criterion::{
    content_as, fmt_pct, missing, share_row, Criterion, Figure, Folder, Input, Row, Thresholds,
};
use crate::error::RegressError;
use crate::proofs::{BinStatus, ProofBin, Proofs};
use crate::provenance::RtlId;
use crate::summary::Summary;
use serde::Deserialize;
use std::collections::BTreeSet;
use std::path::Path;

/// What writes a regression folder's results and coverage.
const REGRESS: &str = "pmu50 regress --dut verilator [--rtl LIST] --code-coverage (make signoff)";

/// Reachable bins hit (`coverage.json`): the bins the model does not declare unreachable,
/// less those the coverage proofs prove unreachable.
pub struct Functional;
impl Criterion for Functional {
    fn row(&self, f: &Folder, t: &Thresholds) -> Result<Row, RegressError> {
        let th = format!("{} %", fmt_pct(t.functional));
        let name = "functional coverage";
        if let Err(why) = f.reference.as_ref().and(f.complete.as_ref()) {
            return Ok(missing(name, th, why.clone()));
        }
        // every coverage file merged into the folder carries the provenance of this RTL
        let ev = f.summary.evidence.as_ref();
        for c in ev.map(|e| e.coverage_inputs.as_slice()).unwrap_or_default() {
            if c.provenance.is_none() {
                return Ok(missing(
                    name,
                    th,
                    format!(
                        "coverage.json counts {}, which has no provenance: replay the witness with pmu50 lockstep --coverage and merge again",
                        c.file
                    ),
                ));
            }
        }
        let c = &f.summary.coverage;
        let proven: BTreeSet<String> = match Proofs::read(f)? {
            Ok(p) => p
                .bins
                .iter()
                .filter(|b| b.status == BinStatus::ProvenUnreachable)
                .map(|b| b.name.clone())
                .collect(),
            Err(_) => BTreeSet::new(),
        };
        let reach: Vec<_> = c
            .bins
            .iter()
            .filter(|b| b.unreachable.is_none() && !proven.contains(&b.name))
            .collect();
        let hit = reach.iter().filter(|b| b.hits > 0).count() as u64;
        Ok(share_row(
            name,
            hit,
            reach.len() as u64,
            t.functional,
            format!("coverage.json: reachable bins hit ({} runs)", c.runs.len()),
            REGRESS,
        ))
    }
}

/// Bins declared unreachable that the proofs prove so (each bin once).
pub struct UnreachableProven;
impl Criterion for UnreachableProven {
    fn row(&self, f: &Folder, t: &Thresholds) -> Result<Row, RegressError> {
        let p = match Proofs::read(f)? {
            Ok(p) => p,
            Err(why) => {
                return Ok(missing(
                    "bins proven unreachable",
                    format!("{} %", fmt_pct(t.unreachable_proven)),
                    why,
                ))
            }
        };
        let declared: BTreeSet<&str> = pmu50_coverage::layout()
            .bins
            .iter()
            .filter(|b| b.unreachable.is_some())
            .map(|b| b.name.as_str())
            .collect();
        let proven = p
            .bins
            .iter()
            .filter(|b| {
                declared.contains(b.name.as_str()) && b.status == BinStatus::ProvenUnreachable
            })
            .count() as u64;
        let wrong: Vec<&str> = p
            .bins
            .iter()
            .filter(|b| b.status == BinStatus::WrongDeclaration)
            .map(|b| b.name.as_str())
            .collect();
        let mut r = share_row(
            "bins proven unreachable",
            proven,
            declared.len() as u64,
            t.unreachable_proven,
            format!(
                "{}: of the bins the model declares unreachable",
                Proofs::FILE
            ),
            Proofs::REMEDY,
        );
        if !wrong.is_empty() {
            r.met = false;
            r.detail += &format!("; wrong declarations: {}", wrong.join(", "));
        }
        Ok(r)
    }
}

/// Bins decided by nothing: the model's declared bins less the distinct bins the proofs prove
/// unreachable or witness, and those the regression hit.
pub struct Undecided;
impl Criterion for Undecided {
    fn row(&self, f: &Folder, t: &Thresholds) -> Result<Row, RegressError> {
        let p = match Proofs::read(f)? {
            Ok(p) => p,
            Err(why) => {
                return Ok(missing(
                    "bins undecided",
                    format!("<= {}", t.undecided),
                    why,
                ))
            }
        };
        let mut decided: BTreeSet<&str> = p
            .bins
            .iter()
            .filter(|b| {
                matches!(
                    b.status,
                    BinStatus::ProvenUnreachable | BinStatus::Witnessed
                )
            })
            .map(|b| b.name.as_str())
            .collect();
        // the regression's hits count only when its results are the completed, sealed ones
        if f.reference.is_ok() && f.complete.is_ok() {
            decided.extend(
                f.summary
                    .coverage
                    .bins
                    .iter()
                    .filter(|b| b.hits > 0)
                    .map(|b| b.name.as_str()),
            );
        }
        let undecided: Vec<&str> = pmu50_coverage::layout()
            .bins
            .iter()
            .map(|b| b.name.as_str())
            .filter(|n| !decided.contains(n))
            .collect();
        let n = undecided.len() as u64;
        let mut detail = format!(
            "{}: of the model's {} bins, neither proven unreachable nor witnessed, nor hit",
            Proofs::FILE,
            pmu50_coverage::layout().bins.len()
        );
        if !undecided.is_empty() {
            let shown: Vec<&str> = undecided.iter().take(8).copied().collect();
            detail += &format!(": {}{}", shown.join(", "), if n > 8 { ", ..." } else { "" });
        }
        Ok(Row {
            name: "bins undecided",
            figure: Figure::Count(n),
            threshold: format!("<= {}", t.undecided),
            met: n <= t.undecided,
            detail,
        })
    }
}

/// `code/summary.json`, read with the type that writes it.
impl CodeSummary {
    pub const FILE: &'static str = "code/summary.json";
    pub const REMEDY: &'static str = "pmu50 regress --dut verilator --code-coverage";
    /// The folder's summary (`Err`: why it is missing): sealed, of the regression's RTL, model
    /// and seeds; another format is refused.
    pub fn read(f: &Folder) -> Result<Result<CodeSummary, String>, RegressError> {
        let content = match f.open(CodeSummary::FILE, CodeSummary::REMEDY, true)? {
            Input::Missing(why) => return Ok(Err(why)),
            Input::Sealed { content, .. } => content,
        };
        let c: CodeSummary = content_as(f.dir, CodeSummary::FILE, content)?;
        if c.format != crate::code_cov::figures::SUMMARY_FORMAT {
            return Err(crate::error::file_err(
                &f.dir.join(CodeSummary::FILE),
                format!(
                    "field `format`: `{}`; valid is `{}`",
                    c.format,
                    crate::code_cov::figures::SUMMARY_FORMAT
                ),
            ));
        }
        Ok(Ok(c))
    }
}

/// Line or toggle coverage of the RTL under test.
pub struct Code {
    pub toggle: bool,
}
impl Criterion for Code {
    fn row(&self, f: &Folder, t: &Thresholds) -> Result<Row, RegressError> {
        let (name, min) = if self.toggle {
            ("code toggle coverage", t.code_toggle)
        } else {
            ("code line coverage", t.code_line)
        };
        let c = match CodeSummary::read(f)? {
            Ok(c) => c,
            Err(why) => return Ok(missing(name, format!("{} %", fmt_pct(min)), why)),
        };
        let fig = if self.toggle { &c.toggle } else { &c.line };
        // the waivers of this row's kind, each shown to hold (crate::signoff_waivers)
        let kind = if self.toggle { "signal " } else { "line" };
        let proofs = Proofs::read(f)?.ok().map(|p| p.waivers);
        let unproven = crate::signoff_waivers::problems(&c, kind, proofs.as_deref());
        let claimed = c
            .waivers
            .iter()
            .filter(|w| w.what.starts_with(kind) && w.holds.is_some())
            .count();
        let mut r = share_row(
            name,
            fig.hit,
            fig.total,
            min,
            format!(
                "{}: after {} waivers (code/waivers.toml){}",
                CodeSummary::FILE,
                c.waivers.len(),
                if claimed > 0 {
                    format!(
                        ", {} of their {claimed} claims proven",
                        claimed.saturating_sub(unproven.len())
                    )
                } else {
                    String::new()
                }
            ),
            CodeSummary::REMEDY,
        );
        if !unproven.is_empty() {
            // a waiver whose claim does not hold excludes points it should not
            r.met = false;
            r.detail += &format!("; waivers not shown to hold: {}", unproven.join("; "));
        }
        if c.seeds_unaccounted > 0 {
            r.met = false;
            r.detail += &format!(
                "; {} seeds have a result but no code coverage",
                c.seeds_unaccounted
            );
        }
        Ok(r)
    }
}

#[derive(Clone, Debug, Deserialize)]
pub struct FormalProperty {
    pub name: String,
    pub set: String,
    pub verdict: String,
    #[serde(default)]
    pub how: String,
}

/// `formal.json`: the property kit's verdicts (`hdl/formal/run.py --json`).
#[derive(Clone, Debug, Deserialize)]
pub struct FormalResults {
    pub properties: Vec<FormalProperty>,
}

impl FormalResults {
    pub const FILE: &'static str = "formal.json";
    pub const REMEDY: &'static str =
        "hdl/formal/run.py --rtl LIST --json DIR/formal.json (make signoff)";
}

/// Properties of the formal kit proven (every parameter set it ran).
pub struct Properties;
impl Criterion for Properties {
    fn row(&self, f: &Folder, t: &Thresholds) -> Result<Row, RegressError> {
        let th = format!("{} %", fmt_pct(t.properties));
        let r: FormalResults = match f.open(FormalResults::FILE, FormalResults::REMEDY, false)? {
            Input::Missing(why) => return Ok(missing("properties proven", th, why)),
            Input::Sealed { content, .. } => content_as(f.dir, FormalResults::FILE, content)?,
        };
        // a property proven twice on one set counts once
        let mut seen = BTreeSet::new();
        for p in &r.properties {
            if !seen.insert((p.name.as_str(), p.set.as_str())) {
                return Err(crate::error::file_err(
                    &f.dir.join(FormalResults::FILE),
                    format!(
                        "property `{}` on set `{}` is listed twice: each is decided once",
                        p.name, p.set
                    ),
                ));
            }
        }
        let proven = r
            .properties
            .iter()
            .filter(|p| p.verdict == "proven")
            .count() as u64;
        let other: Vec<String> = r
            .properties
            .iter()
            .filter(|p| p.verdict != "proven")
            .map(|p| format!("{} ({}, {})", p.name, p.set, p.verdict))
            .collect();
        let mut sets: Vec<&str> = r.properties.iter().map(|p| p.set.as_str()).collect();
        sets.sort();
        sets.dedup();
        let mut detail = format!(
            "{}: unbounded proofs, parameter sets {}",
            FormalResults::FILE,
            sets.join(", ")
        );
        if !other.is_empty() {
            detail += &format!("; not proven: {}", other.join(", "));
        }
        Ok(share_row(
            "properties proven",
            proven,
            r.properties.len() as u64,
            t.properties,
            detail,
            FormalResults::REMEDY,
        ))
    }
}

/// Seeds of the regression passing.
pub struct Seeds;
impl Criterion for Seeds {
    fn row(&self, f: &Folder, t: &Thresholds) -> Result<Row, RegressError> {
        let th = format!("{} %", fmt_pct(t.seeds));
        if let Err(why) = f.reference.as_ref().and(f.complete.as_ref()) {
            return Ok(missing("seeds passing", th, why.clone()));
        }
        let s = f.summary;
        let mut r = share_row(
            "seeds passing",
            s.pass,
            s.seeds(),
            t.seeds,
            format!(
                "results.jsonl: {} fail, {} error{}",
                s.fail,
                s.error,
                if s.missing_count() > 0 {
                    format!(", {} missing", s.missing_count())
                } else {
                    String::new()
                }
            ),
            REGRESS,
        );
        if s.missing_count() > 0 {
            r.met = false;
        }
        Ok(r)
    }
}

/// Every criterion, in the table's order.
pub fn criteria() -> Vec<Box<dyn Criterion>> {
    vec![
        Box::new(Functional),
        Box::new(UnreachableProven),
        Box::new(Undecided),
        Box::new(Code { toggle: false }),
        Box::new(Code { toggle: true }),
        Box::new(crate::signoff_expr::Expression),
        Box::new(crate::signoff_lint::LINT),
        Box::new(crate::signoff_xprop::XPROP),
        Box::new(Properties),
        Box::new(Seeds),
        Box::new(crate::signoff_soak::Soak),
    ]
}

/// The sign-off table of a folder.
#[derive(Clone, Debug, PartialEq)]
pub struct SignOff {
    pub rows: Vec<Row>,
    /// Every bin's reachability (when the folder has the coverage proofs): HTML.
    pub reachability: Option<String>,
    /// The RTL every row was computed on (the regression's; every input agrees with it).
    pub rtl: Option<RtlId>,
}

/// Every bin as the proofs and the regression decided it: status, how, hits.
fn reachability_html(p: &Proofs, s: &Summary) -> String {
    use pmu50_testbench::plot::svg::esc;
    let hits: std::collections::BTreeMap<&str, u64> = s
        .coverage
        .bins
        .iter()
        .map(|b| (b.name.as_str(), b.hits))
        .collect();
    let mut counts = std::collections::BTreeMap::new();
    for b in &p.bins {
        *counts.entry(b.status_text()).or_insert(0u64) += 1;
    }
    let mut h = format!(
        "<details><summary>Reachability of every bin, by the coverage proofs: {}</summary>\n\
<table><tr><th>bin</th><th>status</th><th>how</th><th>hits in this regression</th></tr>\n",
        counts
            .iter()
            .map(|(k, v)| format!("{v} {k}"))
            .collect::<Vec<_>>()
            .join(", ")
    );
    for b in &p.bins {
        let n = hits.get(b.name.as_str()).copied();
        h += &format!(
            "<tr><td><code>{}</code></td><td class=\"{}\">{}</td><td>{}</td><td>{}</td></tr>\n",
            esc(&b.name),
            match b.status {
                BinStatus::WrongDeclaration => "bad",
                BinStatus::Undecided if n.unwrap_or(0) == 0 => "bad",
                _ => "ok",
            },
            b.status_text(),
            esc(&b.how()),
            n.map(|n| n.to_string()).unwrap_or_else(|| "-".into())
        );
    }
    h + "</table></details>\n"
}

impl SignOff {
    /// The table of the folder `dir` whose regression is `s` (its evidence: `s.evidence`),
    /// whose results and coverage are complete or not (`complete`). A regression that ran no
    /// RTL is refused.
    pub fn evaluate(
        dir: &Path,
        s: &Summary,
        t: &Thresholds,
        complete: Result<(), String>,
        history: Option<&crate::history::Location>,
    ) -> Result<SignOff, RegressError> {
        let reference = match &s.evidence {
            None => Err(format!(
                "{} has no provenance (a folder of a version before it): run the regression again ({REGRESS})",
                dir.join("regress.json").display()
            )),
            Some(e) => {
                if e.provenance.rtl.is_none() || !crate::dut::of(&s.spec.dut).is_ok_and(|b| b.caps.rtl) {
                    return Err(RegressError::Usage(format!(
                        "{}: the regression ran no RTL (dut = {}): a sign-off is of an RTL; run {REGRESS}",
                        dir.join("regress.json").display(),
                        s.spec.dut.name()
                    )));
                }
                Ok(&e.provenance)
            }
        };
        let f = Folder {
            dir,
            summary: s,
            reference,
            complete,
            history,
        };
        let rows = criteria()
            .iter()
            .map(|c| c.row(&f, t))
            .collect::<Result<_, _>>()?;
        let reachability = Proofs::read(&f)?.ok().map(|p| reachability_html(&p, s));
        Ok(SignOff {
            rows,
            reachability,
            rtl: f.reference.ok().and_then(|p| p.rtl.clone()),
        })
    }

    pub fn met(&self) -> bool {
        self.rows.iter().all(|r| r.met)
    }

    /// Which RTL the rows were computed on.
    pub fn rtl_line(&self) -> String {
        match &self.rtl {
            Some(r) => format!(
                "every row computed on the RTL {} ({}); inputs of another RTL, model or seed range are refused",
                r.list, r.hash
            ),
            None => "the regression has no provenance: the rows that need its RTL are missing".into(),
        }
    }

    /// The table as text (stdout of `pmu50 signoff`).
    pub fn text(&self) -> String {
        let mut s = format!("{}\n", self.rtl_line());
        s += &format!(
            "{:<26} {:>22} {:>10}  {:<6} {}\n",
            "sign-off", "figure", "threshold", "", "from"
        );
        for r in &self.rows {
            s += &format!(
                "{:<26} {:>22} {:>10}  {:<6} {}\n",
                r.name,
                figure_text(&r.figure),
                r.threshold,
                if r.met { "met" } else { "MISSED" },
                r.detail
            );
        }
        let missed = self.rows.iter().filter(|r| !r.met).count();
        s += &if missed == 0 {
            "signoff: every threshold met\n".to_string()
        } else {
            format!(
                "signoff: {missed} of {} thresholds missed\n",
                self.rows.len()
            )
        };
        s
    }

    /// The table as HTML (the top of report.html).
    pub fn html(&self) -> String {
        use pmu50_testbench::plot::svg::esc;
        let mut h = format!(
            "<h2>Sign-off</h2>\n<p>{}</p>\n<table><tr><th>figure</th><th>value</th><th>threshold</th><th></th><th>from</th></tr>\n",
            esc(&self.rtl_line())
        );
        for r in &self.rows {
            h += &format!(
                "<tr><td>{}</td><td>{}</td><td>{}</td><td class=\"{}\">{}</td><td>{}</td></tr>\n",
                esc(r.name),
                esc(&figure_text(&r.figure)),
                esc(&r.threshold),
                if r.met { "ok" } else { "bad" },
                if r.met { "met" } else { "missed" },
                esc(&r.detail)
            );
        }
        h += "</table>\n";
        if let Some(r) = &self.reachability {
            h += r;
        }
        h
    }

    /// `signoff.json`: the rows, for dashboards.
    pub fn json(&self) -> String {
        let rows: Vec<serde_json::Value> = self
            .rows
            .iter()
            .map(|r| {
                let (hit, total, count, missing) = match &r.figure {
                    Figure::Share { hit, total } => (Some(*hit), Some(*total), None, None),
                    Figure::Count(n) => (None, None, Some(*n), None),
                    Figure::Missing(w) => (None, None, None, Some(w.clone())),
                };
                serde_json::json!({
                    "name": r.name, "hit": hit, "total": total, "count": count,
                    "missing": missing, "threshold": r.threshold, "met": r.met,
                    "detail": r.detail,
                })
            })
            .collect();
        serde_json::to_string_pretty(&serde_json::json!({
            "format": "pmu50-signoff", "version": 1, "met": self.met(), "rows": rows,
            "rtl": self.rtl,
        }))
        .expect("JSON values serialise")
            + "\n"
    }
}

fn figure_text(f: &Figure) -> String {
    match f {
        Figure::Share { hit, total } => {
            let p = if *total == 0 {
                100.0
            } else {
                *hit as f64 * 100.0 / *total as f64
            };
            format!("{hit}/{total} ({p:.1} %)")
        }
        Figure::Count(n) => n.to_string(),
        Figure::Missing(_) => "missing".into(),
    }
}

/// Whether `results.jsonl` and `coverage.json` of `dir` are those its run completed: `Ok` when
/// their digests match those sealed into regress.json, `Err(why)` when the run has not
/// completed (no digests yet); an error (exit 2) when a file was edited.
fn check_files(
    dir: &Path,
    sf: &crate::evidence::SpecFile,
) -> Result<Result<(), String>, RegressError> {
    if sf.evidence.is_none() {
        return Ok(Err("regress.json has no provenance".into()));
    }
    for name in ["results.jsonl", "coverage.json"] {
        let path = dir.join(name);
        let Some(want) = sf.files.get(name) else {
            return Ok(Err(format!(
                "{name}: the regression did not complete (regress.json holds no digest of it): pmu50 regress --resume {}",
                dir.display()
            )));
        };
        if crate::folder::open_regular(&path, false)?.is_none() {
            return Err(crate::error::file_err(
                &path,
                "missing, though regress.json holds its digest",
            ));
        }
        let got = crate::evidence::file_digest(&path)?;
        if &got != want {
            return Err(crate::error::file_err(
                &path,
                format!(
                    "the digest does not match the one sealed into regress.json: the file was edited after the run wrote it (recorded {want}, computed {got})"
                ),
            ));
        }
    }
    Ok(Ok(()))
}

/// `pmu50 signoff DIR`: the table of a regression folder, printed, written as `signoff.json`,
/// `signoff.txt` (the table as printed) and at the top of `report.html` (rewritten). `history`: the database the soak row reads.
pub fn run(
    dir: &Path,
    thresholds: Option<&Path>,
    history: Option<&crate::history::Location>,
) -> Result<(SignOff, Summary), RegressError> {
    let t = match thresholds {
        Some(p) => Thresholds::read(p)?,
        None => Thresholds::default(),
    };
    let sf = crate::folder::read_spec_file(dir)?;
    let complete = check_files(dir, &sf)?;
    let spec = sf.spec.clone();
    let mut s = Summary::build(spec.clone(), &[crate::summary::Source::of(dir, &spec)])?;
    s.evidence = sf.evidence.clone();
    // The folder's coverage.json is the whole coverage: a merge adds coverage files (formal
    // witnesses replayed through the RTL) to what the seeds of results.jsonl hit. Sealed by
    // regress.json's digest, it holds at least the seeds' hits.
    let cov_path = dir.join("coverage.json");
    if complete.is_ok() {
        let c = pmu50_coverage::CoverageFile::read(&cov_path).map_err(|e| RegressError::File {
            path: cov_path.clone(),
            reason: e.to_string(),
        })?;
        if let Some((a, b)) = c
            .bins
            .iter()
            .zip(&s.coverage.bins)
            .find(|(a, b)| a.hits < b.hits)
        {
            return Err(crate::error::file_err(
                &cov_path,
                format!(
                    "bin {}: {} hits, fewer than the {} of the seeds of results.jsonl: not the coverage of this regression",
                    a.name, a.hits, b.hits
                ),
            ));
        }
        s.coverage = c;
    }
    let so = SignOff::evaluate(dir, &s, &t, complete.clone(), history)?;
    let repros = s.repro_folders(dir)?;
    let mut b = pmu50_testbench::atomic_file::Batch::new();
    b.add(pmu50_testbench::atomic_file::write_atomic(
        &dir.join("signoff.json"),
        so.json().as_bytes(),
    )?);
    // the table as printed: the docs quote it (tests/doc_figures.rs)
    b.add(pmu50_testbench::atomic_file::write_atomic(
        &dir.join("signoff.txt"),
        so.text().as_bytes(),
    )?);
    // each bin's decision into coverage.json and the UCIS export (coverage.json's new digest
    // sealed into regress.json)
    let proofs = {
        let f = Folder {
            dir,
            summary: &s,
            reference: s
                .evidence
                .as_ref()
                .map(|e| &e.provenance)
                .ok_or_else(String::new),
            complete: complete.clone(),
            history,
        };
        Proofs::read(&f)?.ok()
    };
    if let (Some(p), Ok(())) = (proofs, &complete) {
        let by_name: std::collections::BTreeMap<&str, &ProofBin> =
            p.bins.iter().map(|b| (b.name.as_str(), b)).collect();
        for r in &mut s.coverage.bins {
            r.proof = by_name
                .get(r.name.as_str())
                .map(|b| format!("{}: {}", b.status_text(), b.how()));
        }
        let text = s.coverage.to_text();
        let cov = pmu50_testbench::atomic_file::write_atomic(&cov_path, text.as_bytes())?;
        let mut files = sf.files.clone();
        files.insert(
            "coverage.json".into(),
            format!("sha256:{}", crate::digest::sha256_hex(text.as_bytes())),
        );
        b.add(cov);
        let mut x = String::new();
        pmu50_coverage::write_ucis_xml(&s.coverage, &mut x).map_err(|_| RegressError::File {
            path: dir.join("coverage.ucis.xml"),
            reason: "formatting failed".into(),
        })?;
        b.add(pmu50_testbench::atomic_file::write_atomic(
            &dir.join("coverage.ucis.xml"),
            x.as_bytes(),
        )?);
        let spec_text = crate::evidence::spec_text(&sf.spec, sf.evidence.as_ref(), &files)?;
        b.set_last(pmu50_testbench::atomic_file::write_atomic(
            &dir.join("regress.json"),
            spec_text.as_bytes(),
        )?);
    }
    b.add(pmu50_testbench::atomic_file::write_atomic(
        &dir.join("report.html"),
        crate::report::html(&s, None, &repros, Some(&so.html())).as_bytes(),
    )?);
    b.commit()?;
    Ok((so, s))
}

impl SignOff {
    /// The history's record of this sign-off of the folder `dir` (`s`: its summary).
    pub fn record(&self, s: &Summary, dir: &Path) -> crate::history::Record {
        let mut r = crate::history::record_of(s, "signoff", dir);
        r.rows = self
            .rows
            .iter()
            .map(|row| crate::history::RowRecord {
                name: row.name.to_string(),
                figure: figure_text(&row.figure),
                met: row.met,
                detail: row.detail.clone(),
            })
            .collect();
        r.signoff_met = Some(self.met());
        r
    }
}
