//! The sign-off row of X-propagation (`xprop.json`, `pmu50 xprop`): X findings not waived (an
//! output X or Z after reset in the 4-state simulation, a flip-flop without reset), at most 0.
//! Missing when the folder has no sealed report, when a check could not run on the RTL (the row
//! names why: an RTL no reader gives Icarus or yosys has no X evidence), or when it simulated no
//! seed. A row of [`ChecksRow`].

use crate::check_report::CheckReport;
use crate::signoff_checks::ChecksRow;
use crate::xprop::{FILE, FORMAT};

/// X-propagation findings not waived.
pub const XPROP: ChecksRow = ChecksRow {
    name: "X-propagation findings",
    file: FILE,
    format: FORMAT,
    remedy: "pmu50 xprop --rtl LIST --out DIR/xprop.json",
    scope,
    finding: |w| w.message.clone(),
    waiver: |u| u.waiver.signal.clone(),
};

/// `N seed(s) in 4 states and every flip-flop's reset over F file(s)`, and the reader.
fn scope(r: &CheckReport) -> Result<String, String> {
    match r.seeds {
        None | Some(0) => Err("0 seeds simulated".into()),
        Some(n) => Ok(format!(
            "{n} seed(s) in 4 states and every flip-flop's reset{}{}",
            r.over_files(),
            r.read_by()
        )),
    }
}
