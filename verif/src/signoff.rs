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
//! is absent is `missing` and misses its threshold (it says which command writes it); an input
//! that is present but unreadable is an error naming the file.

use crate::code_cov::figures::CodeSummary;
use crate::error::RegressError;
use crate::summary::Summary;
use serde::Deserialize;
use std::path::Path;

/// The thresholds, in percent (`undecided`: a count). Defaults: OpenTitan's V3.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Thresholds {
    pub functional: f64,
    pub unreachable_proven: f64,
    pub undecided: u64,
    pub code_line: f64,
    pub code_toggle: f64,
    pub properties: f64,
    pub seeds: f64,
}

impl Default for Thresholds {
    fn default() -> Thresholds {
        Thresholds {
            functional: 100.0,
            unreachable_proven: 100.0,
            undecided: 0,
            code_line: 100.0,
            code_toggle: 100.0,
            properties: 100.0,
            seeds: 100.0,
        }
    }
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct ThresholdFile {
    thresholds: Thresholds,
}

impl Thresholds {
    /// A TOML file with one table `[thresholds]` (any subset of the keys; percentages 0-100).
    pub fn read(path: &Path) -> Result<Thresholds, RegressError> {
        let text = std::fs::read_to_string(path).map_err(|e| RegressError::File {
            path: path.to_path_buf(),
            reason: e.to_string(),
        })?;
        Thresholds::parse(&text, path)
    }

    pub fn parse(text: &str, path: &Path) -> Result<Thresholds, RegressError> {
        let f: ThresholdFile = toml::from_str(text).map_err(|e| {
            let line = e
                .span()
                .map(|s| text[..s.start.min(text.len())].matches('\n').count() as u64 + 1)
                .unwrap_or(1);
            RegressError::Line {
                path: path.to_path_buf(),
                line,
                reason: format!(
                    "{}; valid: a table [thresholds] with functional, unreachable_proven, \
                     code_line, code_toggle, properties, seeds (percent, 0-100) and undecided \
                     (a count)",
                    e.message()
                ),
            }
        })?;
        let t = f.thresholds;
        for (k, v) in [
            ("functional", t.functional),
            ("unreachable_proven", t.unreachable_proven),
            ("code_line", t.code_line),
            ("code_toggle", t.code_toggle),
            ("properties", t.properties),
            ("seeds", t.seeds),
        ] {
            if !(0.0..=100.0).contains(&v) {
                let line = text
                    .lines()
                    .position(|l| l.trim_start().starts_with(k))
                    .map(|i| i as u64 + 1)
                    .unwrap_or(1);
                return Err(RegressError::Line {
                    path: path.to_path_buf(),
                    line,
                    reason: format!("`{k}` = {v}: a percentage, valid 0 to 100"),
                });
            }
        }
        Ok(t)
    }
}

/// One row's figure.
#[derive(Clone, Debug, PartialEq)]
pub enum Figure {
    /// `hit` of `total` (a share, against a percentage).
    Share { hit: u64, total: u64 },
    /// A count, against a maximum.
    Count(u64),
    /// The input is absent: what writes it.
    Missing(String),
}

/// One row of the table.
#[derive(Clone, Debug, PartialEq)]
pub struct Row {
    pub name: &'static str,
    pub figure: Figure,
    /// The threshold, printed (`100 %`, `<= 0`).
    pub threshold: String,
    pub met: bool,
    /// Where the figure comes from, and what is behind it.
    pub detail: String,
}

/// What a criterion reads: the folder and its regression summary.
pub struct Folder<'a> {
    pub dir: &'a Path,
    pub summary: &'a Summary,
}

/// A sign-off figure.
pub trait Criterion {
    fn row(&self, f: &Folder, t: &Thresholds) -> Result<Row, RegressError>;
}

pub(crate) fn share_row(
    name: &'static str,
    hit: u64,
    total: u64,
    min_pct: f64,
    detail: String,
) -> Row {
    let pct = if total == 0 {
        100.0
    } else {
        hit as f64 * 100.0 / total as f64
    };
    Row {
        name,
        figure: Figure::Share { hit, total },
        threshold: format!("{} %", fmt_pct(min_pct)),
        // compare on the counts where the threshold is 100 %: no rounding lets 99.999 pass
        met: if min_pct >= 100.0 {
            hit >= total
        } else {
            pct + 1e-9 >= min_pct
        },
        detail,
    }
}

pub(crate) fn missing(name: &'static str, threshold: String, what: String) -> Row {
    Row {
        name,
        figure: Figure::Missing(what.clone()),
        threshold,
        met: false,
        detail: what,
    }
}

pub(crate) fn fmt_pct(p: f64) -> String {
    if p.fract() == 0.0 {
        format!("{p:.0}")
    } else {
        format!("{p}")
    }
}

pub(crate) fn read_json<T: serde::de::DeserializeOwned>(
    path: &Path,
) -> Result<Option<T>, RegressError> {
    let text = match std::fs::read_to_string(path) {
        Ok(t) => t,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(None),
        Err(e) => {
            return Err(RegressError::File {
                path: path.to_path_buf(),
                reason: e.to_string(),
            })
        }
    };
    serde_json::from_str(&text)
        .map(Some)
        .map_err(|e| RegressError::Line {
            path: path.to_path_buf(),
            line: e.line() as u64,
            reason: e.to_string(),
        })
}

/// Reachable bins hit (`coverage.json`): the bins the model does not declare unreachable,
/// less those the coverage proofs prove unreachable.
pub struct Functional;
impl Criterion for Functional {
    fn row(&self, f: &Folder, t: &Thresholds) -> Result<Row, RegressError> {
        let c = &f.summary.coverage;
        let proofs = Proofs::read(f.dir)?;
        let proven: std::collections::BTreeSet<&str> = proofs
            .as_ref()
            .map(|p| {
                p.bins
                    .iter()
                    .filter(|b| b.status == BinStatus::ProvenUnreachable)
                    .map(|b| b.name.as_str())
                    .collect()
            })
            .unwrap_or_default();
        let reach: Vec<_> = c
            .bins
            .iter()
            .filter(|b| b.unreachable.is_none() && !proven.contains(b.name.as_str()))
            .collect();
        let hit = reach.iter().filter(|b| b.hits > 0).count() as u64;
        Ok(share_row(
            "functional coverage",
            hit,
            reach.len() as u64,
            t.functional,
            format!("coverage.json: reachable bins hit ({} runs)", c.runs.len()),
        ))
    }
}

/// A bin's reachability, as the coverage proofs decided it (`hdl/formal/coverage.py`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum BinStatus {
    /// `assert(!hit_<bin>)` proven unbounded on every parameter set it ran.
    ProvenUnreachable,
    /// Declared unreachable, but the proof found a trace that hits it.
    WrongDeclaration,
    /// `cover(hit_<bin>)` reached within the depth.
    Witnessed,
    /// Neither.
    Undecided,
}

#[derive(Clone, Debug, Deserialize)]
pub struct ProofBin {
    pub name: String,
    pub status: BinStatus,
    /// The model's reason, for a bin it declares unreachable.
    #[serde(default)]
    pub declared_unreachable: Option<String>,
    #[serde(default)]
    pub property: String,
    /// Proven on these parameter sets.
    #[serde(default)]
    pub sets: Vec<String>,
    /// Witnessed (or refuted) on this set, at this step.
    #[serde(default)]
    pub set: String,
    #[serde(default)]
    pub step: Option<u64>,
    /// Undecided: what was tried.
    #[serde(default)]
    pub tried: String,
    /// A witness or counterexample as a vector file.
    #[serde(default)]
    pub witness: Option<String>,
}

impl ProofBin {
    fn status_text(&self) -> &'static str {
        match self.status {
            BinStatus::ProvenUnreachable => "proven unreachable",
            BinStatus::WrongDeclaration => "WRONG DECLARATION",
            BinStatus::Witnessed => "witnessed",
            BinStatus::Undecided => "undecided",
        }
    }

    fn how(&self) -> String {
        let mut w = self.property.clone();
        if !self.sets.is_empty() {
            w += &format!(" on {}", self.sets.join(", "));
        } else if !self.set.is_empty() {
            w += &format!(" on {}", self.set);
        }
        if let Some(k) = self.step {
            w += &format!(" at step {k}");
        }
        if !self.tried.is_empty() {
            w += &format!("; tried: {}", self.tried);
        }
        if let Some(f) = &self.witness {
            w += &format!("; trace {f}");
        }
        w
    }
}

/// `coverage-proofs.json` (`make coverage-proofs`' coverage.json): each bin's reachability.
#[derive(Clone, Debug, Deserialize)]
pub struct Proofs {
    /// The coverage model the proofs are of (`pmu50-coverage/<bins>/<hash>`); hdl/formal/
    /// coverage.py always writes it.
    #[serde(default)]
    pub model_id: Option<String>,
    pub bins: Vec<ProofBin>,
    /// The code-coverage waivers' claims (`holds`) and their verdicts.
    #[serde(default)]
    pub waivers: Vec<ProofWaiver>,
}

/// A waiver's claim as the coverage proofs decided it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ClaimStatus {
    /// Proven on every parameter set.
    Proven,
    /// A trace from reset breaks it.
    Refuted,
    /// Neither.
    Undecided,
}

/// A waiver's claim and its verdict (hdl/formal/coverage.py `waivers`).
#[derive(Clone, Debug, Deserialize)]
pub struct ProofWaiver {
    pub file: String,
    /// `signal t[17:16]` or `line 40`, as the waiver's `what`.
    pub what: String,
    pub holds: String,
    pub status: ClaimStatus,
}

impl Proofs {
    pub const FILE: &'static str = "coverage-proofs.json";
    /// The folder's proofs; an error when they are of another coverage model than this
    /// pmu50's (proofs left from before the model changed would decide the wrong bins).
    pub fn read(dir: &Path) -> Result<Option<Proofs>, RegressError> {
        let path = dir.join(Proofs::FILE);
        let p: Option<Proofs> = read_json(&path)?;
        if let Some(id) = p.as_ref().and_then(|p| p.model_id.as_deref()) {
            let ours = pmu50_coverage::model_id(pmu50_coverage::layout());
            if id != ours {
                return Err(RegressError::File {
                    path,
                    reason: format!(
                        "model_id {id:?}: the proofs are of another coverage model than this \
                         pmu50's ({ours:?}); run `make coverage-proofs` again with this \
                         pmu50's monitor (pmu50 hdl coverage-monitor)"
                    ),
                });
            }
        }
        Ok(p)
    }
}

/// Bins declared unreachable that the proofs prove so.
pub struct UnreachableProven;
impl Criterion for UnreachableProven {
    fn row(&self, f: &Folder, t: &Thresholds) -> Result<Row, RegressError> {
        let Some(p) = Proofs::read(f.dir)? else {
            return Ok(missing(
                "bins proven unreachable",
                format!("{} %", fmt_pct(t.unreachable_proven)),
                format!("{} missing: make coverage-proofs", Proofs::FILE),
            ));
        };
        let declared = f
            .summary
            .coverage
            .bins
            .iter()
            .filter(|b| b.unreachable.is_some())
            .count() as u64;
        let proven = p
            .bins
            .iter()
            .filter(|b| {
                b.declared_unreachable.is_some() && b.status == BinStatus::ProvenUnreachable
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
            declared,
            t.unreachable_proven,
            format!(
                "{}: of the bins the model declares unreachable",
                Proofs::FILE
            ),
        );
        if !wrong.is_empty() {
            r.met = false;
            r.detail += &format!("; wrong declarations: {}", wrong.join(", "));
        }
        Ok(r)
    }
}

/// Bins neither proven unreachable nor hit or witnessed.
pub struct Undecided;
impl Criterion for Undecided {
    fn row(&self, f: &Folder, t: &Thresholds) -> Result<Row, RegressError> {
        let Some(p) = Proofs::read(f.dir)? else {
            return Ok(missing(
                "bins undecided",
                format!("<= {}", t.undecided),
                format!("{} missing: make coverage-proofs", Proofs::FILE),
            ));
        };
        let hit: std::collections::BTreeSet<&str> = f
            .summary
            .coverage
            .bins
            .iter()
            .filter(|b| b.hits > 0)
            .map(|b| b.name.as_str())
            .collect();
        let undecided: Vec<&str> = p
            .bins
            .iter()
            .filter(|b| b.status == BinStatus::Undecided && !hit.contains(b.name.as_str()))
            .map(|b| b.name.as_str())
            .collect();
        let n = undecided.len() as u64;
        let mut detail = format!("{}: neither proven nor witnessed, nor hit", Proofs::FILE);
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
    /// The summary of a folder (`None` when it has none); another format is refused.
    pub fn read(dir: &Path) -> Result<Option<CodeSummary>, RegressError> {
        let path = dir.join(CodeSummary::FILE);
        let c: Option<CodeSummary> = read_json(&path)?;
        if let Some(c) = &c {
            if c.format != crate::code_cov::figures::SUMMARY_FORMAT {
                return Err(RegressError::File {
                    path,
                    reason: format!(
                        "field `format`: `{}`; valid is `{}`",
                        c.format,
                        crate::code_cov::figures::SUMMARY_FORMAT
                    ),
                });
            }
        }
        Ok(c)
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
        let Some(c) = CodeSummary::read(f.dir)? else {
            return Ok(missing(
                name,
                format!("{} %", fmt_pct(min)),
                format!(
                    "{} missing: pmu50 regress --dut verilator --code-coverage",
                    CodeSummary::FILE
                ),
            ));
        };
        let fig = if self.toggle { &c.toggle } else { &c.line };
        // the waivers of this row's kind, each shown to hold (crate::signoff_waivers)
        let kind = if self.toggle { "signal " } else { "line" };
        let proofs = Proofs::read(f.dir)?.map(|p| p.waivers);
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
}

/// Properties of the formal kit proven (every parameter set it ran).
pub struct Properties;
impl Criterion for Properties {
    fn row(&self, f: &Folder, t: &Thresholds) -> Result<Row, RegressError> {
        let Some(r) = read_json::<FormalResults>(&f.dir.join(FormalResults::FILE))? else {
            return Ok(missing(
                "properties proven",
                format!("{} %", fmt_pct(t.properties)),
                format!(
                    "{} missing: hdl/formal/run.py --json DIR/{}",
                    FormalResults::FILE,
                    FormalResults::FILE
                ),
            ));
        };
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
        ))
    }
}

/// Seeds of the regression passing.
pub struct Seeds;
impl Criterion for Seeds {
    fn row(&self, f: &Folder, t: &Thresholds) -> Result<Row, RegressError> {
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
        );
        if s.missing_count() > 0 || s.seeds() == 0 {
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
        Box::new(crate::signoff_lint::Lint),
        Box::new(crate::signoff_xprop::XProp),
        Box::new(Properties),
        Box::new(Seeds),
    ]
}

/// The sign-off table of a folder.
#[derive(Clone, Debug, PartialEq)]
pub struct SignOff {
    pub rows: Vec<Row>,
    /// Every bin's reachability (when the folder has the coverage proofs): HTML.
    pub reachability: Option<String>,
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
    pub fn evaluate(dir: &Path, s: &Summary, t: &Thresholds) -> Result<SignOff, RegressError> {
        let f = Folder { dir, summary: s };
        let rows = criteria()
            .iter()
            .map(|c| c.row(&f, t))
            .collect::<Result<_, _>>()?;
        let reachability = Proofs::read(dir)?.map(|p| reachability_html(&p, s));
        Ok(SignOff { rows, reachability })
    }

    pub fn met(&self) -> bool {
        self.rows.iter().all(|r| r.met)
    }

    /// The table as text (stdout of `pmu50 signoff`).
    pub fn text(&self) -> String {
        let mut s = format!(
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
        let mut h = String::from(
            "<h2>Sign-off</h2>\n<table><tr><th>figure</th><th>value</th><th>threshold</th><th></th><th>from</th></tr>\n",
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
            "format": "pmu50-signoff", "version": 1, "met": self.met(), "rows": rows
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

/// `pmu50 signoff DIR`: the table of a regression folder, printed, written as `signoff.json`
/// and at the top of `report.html` (rewritten).
pub fn run(dir: &Path, thresholds: Option<&Path>) -> Result<SignOff, RegressError> {
    let t = match thresholds {
        Some(p) => Thresholds::read(p)?,
        None => Thresholds::default(),
    };
    let spec = crate::summary::read_spec(dir)?;
    let mut s = Summary::build(spec.clone(), &[crate::summary::Source::of(dir, &spec)])?;
    // The folder's coverage.json is the whole coverage: a merge adds coverage files (formal
    // witnesses replayed through the RTL) to what the seeds of results.jsonl hit.
    let cov_path = dir.join("coverage.json");
    if cov_path.is_file() {
        let c = pmu50_coverage::CoverageFile::read(&cov_path).map_err(|e| RegressError::File {
            path: cov_path.clone(),
            reason: e.to_string(),
        })?;
        // it holds at least the seeds' hits (else it is stale, and the seeds' count stands)
        if c.bins.len() == s.coverage.bins.len()
            && c.bins
                .iter()
                .zip(&s.coverage.bins)
                .all(|(a, b)| a.hits >= b.hits)
        {
            s.coverage = c;
        }
    }
    let so = SignOff::evaluate(dir, &s, &t)?;
    let repros = s.repro_folders(dir)?;
    let mut b = pmu50_testbench::atomic_file::Batch::new();
    b.add(pmu50_testbench::atomic_file::write_atomic(
        &dir.join("signoff.json"),
        so.json().as_bytes(),
    )?);
    // each bin's decision into coverage.json and the UCIS export
    if let Some(p) = Proofs::read(dir)? {
        let by_name: std::collections::BTreeMap<&str, &ProofBin> =
            p.bins.iter().map(|b| (b.name.as_str(), b)).collect();
        for r in &mut s.coverage.bins {
            r.proof = by_name
                .get(r.name.as_str())
                .map(|b| format!("{}: {}", b.status_text(), b.how()));
        }
        b.add(pmu50_testbench::atomic_file::write_atomic(
            &dir.join("coverage.json"),
            s.coverage.to_text().as_bytes(),
        )?);
        let mut x = String::new();
        pmu50_coverage::write_ucis_xml(&s.coverage, &mut x).map_err(|_| RegressError::File {
            path: dir.join("coverage.ucis.xml"),
            reason: "formatting failed".into(),
        })?;
        b.add(pmu50_testbench::atomic_file::write_atomic(
            &dir.join("coverage.ucis.xml"),
            x.as_bytes(),
        )?);
    }
    b.add(pmu50_testbench::atomic_file::write_atomic(
        &dir.join("report.html"),
        crate::report::html(&s, None, &repros, Some(&so.html())).as_bytes(),
    )?);
    b.commit()?;
    Ok(so)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn thresholds_default_to_v3_and_a_file_sets_a_subset() {
        assert_eq!(Thresholds::default().functional, 100.0);
        let t = Thresholds::parse(
            "[thresholds]\nfunctional = 90\ncode_toggle = 90.5\n",
            Path::new("t.toml"),
        )
        .unwrap();
        assert_eq!(t.functional, 90.0);
        assert_eq!(t.code_toggle, 90.5);
        assert_eq!(t.code_line, 100.0);
    }

    #[test]
    fn a_bad_threshold_file_names_file_line_and_what_is_valid() {
        let e = Thresholds::parse("[thresholds]\nfunctional = 120\n", Path::new("t.toml"))
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("t.toml: line 2") && e.contains("valid 0 to 100"),
            "{e}"
        );
        let e = Thresholds::parse("[thresholds]\nfunctionl = 90\n", Path::new("t.toml"))
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("t.toml: line 2") && e.contains("functionl") && e.contains("valid:"),
            "{e}"
        );
    }

    #[test]
    fn a_share_at_100_percent_compares_counts() {
        assert!(share_row("x", 10, 10, 100.0, String::new()).met);
        assert!(!share_row("x", 99_999, 100_000, 100.0, String::new()).met);
        assert!(share_row("x", 9, 10, 90.0, String::new()).met);
        assert!(!share_row("x", 8, 10, 90.0, String::new()).met);
    }
}
