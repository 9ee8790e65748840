//! The sign-off row of lint (`lint.json`, `pmu50 lint`): tool warnings not waived, at most 0.
//! Missing when the folder has no sealed lint report, or when a check could not run on the RTL
//! (the row names why). A row of [`ChecksRow`].

use crate::check_report::CheckReport;
use crate::lint::{FILE, FORMAT};
use crate::signoff_checks::ChecksRow;

/// Lint warnings not waived.
pub const LINT: ChecksRow = ChecksRow {
    name: "lint warnings not waived",
    file: FILE,
    format: FORMAT,
    remedy: "pmu50 lint --rtl LIST --waivers FILE --out DIR/lint.json",
    scope,
    finding: |w| format!("{}:{} {} {}", w.file, w.line, w.rule, w.message),
    waiver: |u| format!("{} {}:{}", u.waiver.rule, u.waiver.file, u.waiver.line),
};

/// `N warning(s) over F file(s) by TOOLS`.
fn scope(r: &CheckReport) -> Result<String, String> {
    Ok(format!(
        "{} warning(s){} by {}",
        r.checks.iter().map(|c| c.findings.len()).sum::<usize>(),
        r.over_files(),
        r.tools()
    ))
}
