//! The sign-off rows of the kit's checks of an RTL ([`crate::check_report::CheckReport`]: lint,
//! X-propagation): findings not waived, at most 0. One row type, [`ChecksRow`]; each row is a
//! value of it (`signoff_lint::LINT`, `signoff_xprop::XPROP`) saying its file, format and what
//! its figure is over. Missing when the folder has no sealed report, when a check could not run
//! on the RTL (the row names why), or when the report counts over nothing.

use crate::check_report::CheckReport;
use crate::criterion::{content_as, missing, Criterion, Figure, Folder, Input, Row, Thresholds};
use crate::error::RegressError;
use crate::waiver::{Finding, SiteUse};

/// A row of a [`CheckReport`].
pub struct ChecksRow {
    pub name: &'static str,
    /// The report's name in the folder (`lint.json`).
    pub file: &'static str,
    /// Its format (`pmu50-lint-1`).
    pub format: &'static str,
    /// The command that writes it.
    pub remedy: &'static str,
    /// What the figure counts over (the detail's head, after the file's name), or why the report
    /// counts over nothing (the row is then missing).
    pub scope: fn(&CheckReport) -> Result<String, String>,
    /// A finding not waived, in the detail.
    pub finding: fn(&Finding) -> String,
    /// A waiver, where the detail says it is stale.
    pub waiver: fn(&SiteUse) -> String,
}

const THRESHOLD: &str = "<= 0";
/// Findings the detail lists.
const SHOWN: usize = 5;

impl Criterion for ChecksRow {
    fn row(&self, f: &Folder, _t: &Thresholds) -> Result<Row, RegressError> {
        let file = self.file;
        let r = match read_sealed::<CheckReport>(f, file, self.remedy)? {
            Ok(r) => r,
            Err(why) => return Ok(missing(self.name, THRESHOLD.into(), why)),
        };
        if r.format != self.format {
            return Err(RegressError::File {
                path: f.dir.join(file),
                reason: format!("field `format`: `{}`; valid is `{}`", r.format, self.format),
            });
        }
        if let Some(c) = r.checks.iter().find(|c| !c.ran) {
            return Ok(missing(
                self.name,
                THRESHOLD.into(),
                format!("{file}: {} did not run: {}", c.tool, c.reason),
            ));
        }
        let scope = match (self.scope)(&r) {
            Ok(s) => s,
            Err(why) => {
                return Ok(missing(
                    self.name,
                    THRESHOLD.into(),
                    format!("{file}: {why}"),
                ))
            }
        };
        let n = r.unwaived.len() as u64;
        let mut detail = format!(
            "{file}: {scope}; {} waived by {}",
            r.waived(),
            if r.waivers_file.is_empty() {
                "no waivers file"
            } else {
                &r.waivers_file
            },
        );
        // the findings at a place of the RTL (a register, a line) first: they name the cause,
        // the outputs it reaches follow
        let mut shown: Vec<&Finding> = r.unwaived.iter().collect();
        shown.sort_by_key(|w| w.file.is_empty());
        for w in shown.iter().take(SHOWN) {
            detail += &format!("; {}", (self.finding)(w));
        }
        if shown.len() > SHOWN {
            detail += &format!("; {} more in {file}", shown.len() - SHOWN);
        }
        let stale: Vec<String> = r
            .waivers
            .iter()
            .filter_map(|u| {
                u.stale.as_ref().map(|s| {
                    format!(
                        "waiver {}:{} ({}) {s}",
                        r.waivers_file,
                        u.waiver.at,
                        (self.waiver)(u)
                    )
                })
            })
            .collect();
        if !stale.is_empty() {
            detail += &format!("; {}", stale.join("; "));
        }
        Ok(Row {
            name: self.name,
            figure: Figure::Count(n),
            threshold: THRESHOLD.into(),
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
