//! The sign-off row of lint (`lint.json`, `pmu50 lint`): tool warnings not waived, at most 0.
//! Missing when the folder has no sealed lint report, or when a check could not run on the RTL
//! (the row names why).

use crate::error::RegressError;
use crate::lint::{LintReport, FILE, FORMAT};
use crate::signoff::{missing, Criterion, Figure, Folder, Row, Thresholds};

/// Lint warnings not waived.
pub struct Lint;

const NAME: &str = "lint warnings not waived";
const REMEDY: &str = "pmu50 lint --rtl LIST --waivers FILE --out DIR/lint.json";

impl Criterion for Lint {
    fn row(&self, f: &Folder, _t: &Thresholds) -> Result<Row, RegressError> {
        let Some(r) = read_sealed::<LintReport>(f.dir, FILE, REMEDY)? else {
            return Ok(missing(
                NAME,
                "<= 0".into(),
                format!("{FILE} missing: {REMEDY}"),
            ));
        };
        let r = match r {
            Ok(r) => r,
            Err(why) => return Ok(missing(NAME, "<= 0".into(), why)),
        };
        if r.format != FORMAT {
            return Err(RegressError::File {
                path: f.dir.join(FILE),
                reason: format!("field `format`: `{}`; valid is `{FORMAT}`", r.format),
            });
        }
        if let Some(c) = r.checks.iter().find(|c| !c.ran) {
            return Ok(missing(
                NAME,
                "<= 0".into(),
                format!("{FILE}: {} did not run: {}", c.tool, c.reason),
            ));
        }
        let n = r.unwaived.len() as u64;
        let mut detail = format!(
            "{FILE}: {} of {} ({} waived by {})",
            r.checks
                .iter()
                .map(|c| c.tool.as_str())
                .collect::<Vec<_>>()
                .join(" and "),
            r.checks.iter().map(|c| c.findings.len()).sum::<usize>(),
            r.waivers.iter().map(|u| u.waived).sum::<u64>(),
            if r.waivers_file.is_empty() {
                "no waivers file"
            } else {
                &r.waivers_file
            },
        );
        for w in r.unwaived.iter().take(5) {
            detail += &format!("; {}:{} {} {}", w.file, w.line, w.rule, w.message);
        }
        let stale: Vec<String> = r
            .waivers
            .iter()
            .filter_map(|u| {
                u.stale.as_ref().map(|s| {
                    format!(
                        "waiver {}:{} ({} {}:{}) {s}",
                        r.waivers_file, u.waiver.at, u.waiver.rule, u.waiver.file, u.waiver.line
                    )
                })
            })
            .collect();
        if !stale.is_empty() {
            detail += &format!("; {}", stale.join("; "));
        }
        Ok(Row {
            name: NAME,
            figure: Figure::Count(n),
            threshold: "<= 0".into(),
            met: n == 0 && stale.is_empty(),
            detail,
        })
    }
}

/// A sealed file of the folder: `None` absent, `Some(Err(why))` present but not evidence (no
/// provenance, edited, or of no RTL), `Some(Ok)` its content.
pub(crate) fn read_sealed<T: serde::de::DeserializeOwned>(
    dir: &std::path::Path,
    file: &str,
    remedy: &str,
) -> Result<Option<Result<T, String>>, RegressError> {
    let path = dir.join(file);
    let text = match std::fs::read_to_string(&path) {
        Ok(t) => t,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(None),
        Err(e) => {
            return Err(RegressError::File {
                path,
                reason: e.to_string(),
            })
        }
    };
    let (m, p) = match crate::provenance::open(&path, &text, remedy) {
        Ok(x) => x,
        Err(e) => return Ok(Some(Err(e.to_string()))),
    };
    if p.rtl.is_none() {
        return Ok(Some(Err(format!("{file}: made on no RTL"))));
    }
    serde_json::from_value(serde_json::Value::Object(m))
        .map(|v| Some(Ok(v)))
        .map_err(|e| RegressError::File {
            path,
            reason: e.to_string(),
        })
}
