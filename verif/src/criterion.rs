//! The sign-off's rows as types: what a row reads ([`Folder`], its inputs opened through
//! [`Folder::open`] with their provenance checked), what it gives ([`Row`], [`Figure`]) and the
//! thresholds ([`Thresholds`]). A new figure is a new type implementing [`Criterion`] in a file
//! of its own, registered with one line in `crate::signoff::criteria`.

use crate::error::RegressError;
use crate::provenance::Provenance;
use crate::summary::Summary;
use serde::Deserialize;
use serde_json::{Map, Value};
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
    /// Consecutive daily runs at 100 % on the same RTL (the soak row, from the history).
    pub soak_days: u64,
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
            soak_days: 7,
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
                     code_line, code_toggle, properties, seeds (percent, 0-100), undecided \
                     (a count) and soak_days (consecutive days)",
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

/// What a criterion reads: the folder, its regression summary, and the provenance every input
/// must agree with.
pub struct Folder<'a> {
    pub dir: &'a Path,
    pub summary: &'a Summary,
    /// The regression's provenance (from its sealed regress.json), or why there is none: the
    /// rows that need it are missing.
    pub reference: Result<&'a Provenance, String>,
    /// results.jsonl and coverage.json are those the run completed (their digests in
    /// regress.json match), or why not.
    pub complete: Result<(), String>,
    /// The history database, for the soak row (`--history`, `PMU50_HISTORY`).
    pub history: Option<&'a crate::history::Location>,
}

/// A file of evidence as a row gets it.
pub enum Input {
    /// Absent, or without provenance: why, and the command that makes it.
    Missing(String),
    /// Sealed, its digest checked, made on the regression's RTL and model: its content
    /// (without `provenance` and `digest`) and what made it.
    Sealed {
        content: Map<String, Value>,
        provenance: Box<Provenance>,
    },
}

/// Largest file of evidence a row reads (a formal or proofs file is some hundred kB).
const MAX_INPUT_BYTES: u64 = 256 << 20;

impl Folder<'_> {
    /// The sealed file `name` of the folder: [`Input::Missing`] when absent or without
    /// provenance (saying `remedy`); an error when edited (its digest), or made on another RTL,
    /// coverage model or (with `seeds`) seed range than the regression's, naming both values.
    pub fn open(&self, name: &str, remedy: &str, seeds: bool) -> Result<Input, RegressError> {
        let path = self.dir.join(name);
        let Some(f) = crate::folder::open_regular(&path, false)? else {
            return Ok(Input::Missing(format!("{name} missing: {remedy}")));
        };
        let mut text = String::new();
        std::io::Read::read_to_string(&mut std::io::Read::take(f, MAX_INPUT_BYTES + 1), &mut text)
            .map_err(|e| crate::error::file_err(&path, e))?;
        if text.len() as u64 > MAX_INPUT_BYTES {
            return Err(crate::error::file_err(
                &path,
                format!("larger than {MAX_INPUT_BYTES} bytes"),
            ));
        }
        let (content, provenance) = match crate::evidence::open_sealed(&path, &text, remedy) {
            Ok(x) => x,
            Err(crate::provenance::ProvenanceError::Missing { .. }) => {
                return Ok(Input::Missing(format!(
                    "{name} has no provenance (not written by the kit, or by a version before it): {remedy}"
                )))
            }
            Err(e) => return Err(RegressError::Usage(e.to_string())),
        };
        let reference = match &self.reference {
            Ok(r) => *r,
            Err(why) => return Ok(Input::Missing(why.clone())),
        };
        let theirs = if seeds {
            provenance.clone()
        } else {
            Provenance {
                seeds: None,
                ..provenance.clone()
            }
        };
        if seeds && provenance.seeds.is_none() {
            return Err(crate::error::file_err(
                &path,
                format!(
                    "field `provenance.seeds`: none; this file counts seeds, the regression's are {}",
                    seed_text(reference)
                ),
            ));
        }
        let d = crate::evidence::disagreements(reference, &theirs);
        if !d.is_empty() {
            return Err(crate::error::file_err(
                &path,
                format!(
                    "made on another RTL, model or seed range than the regression (regress.json) against this file: {}; every row of one sign-off is computed on one RTL",
                    d.join(", ")
                ),
            ));
        }
        Ok(Input::Sealed {
            content,
            provenance: Box::new(provenance),
        })
    }
}

fn seed_text(p: &Provenance) -> String {
    p.seeds
        .map(|s| format!("{}:{}", s.start, s.count))
        .unwrap_or_else(|| "none".into())
}

/// A sealed file's content as its type (a field that does not fit: an error naming it).
pub(crate) fn content_as<T: serde::de::DeserializeOwned>(
    dir: &Path,
    name: &str,
    content: Map<String, Value>,
) -> Result<T, RegressError> {
    serde_json::from_value(Value::Object(content))
        .map_err(|e| crate::error::file_err(&dir.join(name), e))
}

/// A sign-off figure.
pub trait Criterion {
    fn row(&self, f: &Folder, t: &Thresholds) -> Result<Row, RegressError>;
}

/// A share against a percentage; nothing to count (a total of 0) is missing, with `remedy`,
/// the command that makes what it counts.
pub(crate) fn share_row(
    name: &'static str,
    hit: u64,
    total: u64,
    min_pct: f64,
    detail: String,
    remedy: &str,
) -> Row {
    let threshold = format!("{} %", fmt_pct(min_pct));
    if total == 0 {
        return missing(
            name,
            threshold,
            format!("nothing to count (0 of 0): {detail}; {remedy}"),
        );
    }
    let pct = hit as f64 * 100.0 / total as f64;
    Row {
        name,
        figure: Figure::Share { hit, total },
        threshold,
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
        assert!(share_row("x", 10, 10, 100.0, String::new(), "make x").met);
        assert!(!share_row("x", 99_999, 100_000, 100.0, String::new(), "make x").met);
        assert!(share_row("x", 9, 10, 90.0, String::new(), "make x").met);
        assert!(!share_row("x", 8, 10, 90.0, String::new(), "make x").met);
    }

    #[test]
    fn nothing_to_count_is_missing_never_met() {
        let r = share_row(
            "properties proven",
            0,
            0,
            0.0,
            "formal.json".into(),
            "make formal",
        );
        assert!(!r.met);
        assert!(
            matches!(&r.figure, Figure::Missing(w) if w.contains("0 of 0") && w.contains("make formal"))
        );
    }
}
