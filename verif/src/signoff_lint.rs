//! The sign-off row of lint (`lint.json`, `pmu50 lint`): tool warnings not waived, at most 0.
//! Missing when the folder has no sealed lint report, or when a check could not run on the RTL
//! (the row names why).

use crate::criterion::{content_as, missing, Criterion, Figure, Folder, Input, Row, Thresholds};
use crate::error::RegressError;
use crate::lint::{LintReport, FILE, FORMAT};

/// Lint warnings not waived.
pub struct Lint;

const NAME: &str = "lint warnings not waived";
const REMEDY: &str = "pmu50 lint --rtl LIST --waivers FILE --out DIR/lint.json";

impl Criterion for Lint {
    fn row(&self, f: &Folder, _t: &Thresholds) -> Result<Row, RegressError> {
        let r = match read_sealed::<LintReport>(f, FILE, REMEDY)? {
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

/// A sealed report of the folder as its type (`Err`: why it is missing): checked by
/// [`Folder::open`] to be made on the regression's RTL and model, and made on an RTL at all.
pub(crate) fn read_sealed<T: serde::de::DeserializeOwned>(
    f: &Folder,
    file: &str,
    remedy: &str,
) -> Result<Result<T, String>, RegressError> {
    match f.open(file, remedy, false)? {
        Input::Missing(why) => Ok(Err(why)),
        Input::Sealed {
            content,
            provenance,
        } => {
            if provenance.rtl.is_none() {
                return Ok(Err(format!("{file}: made on no RTL")));
            }
            content_as(f.dir, file, content).map(Ok)
        }
    }
}
