//! The soak row: N consecutive daily regressions at 100 % on the RTL of the sign-off (OpenTitan's
//! V3 "nightly regression at 100 % for a week"), read from the history (crate::history).

use crate::criterion::{missing, Criterion, Figure, Folder, Row, Thresholds};
use crate::error::RegressError;

pub struct Soak;

impl Criterion for Soak {
    fn row(&self, f: &Folder, t: &Thresholds) -> Result<Row, RegressError> {
        let name = "soak (daily runs at 100 %)";
        let th = format!(">= {} days", t.soak_days);
        let reference = match &f.reference {
            Ok(r) => *r,
            Err(why) => return Ok(missing(name, th, why.clone())),
        };
        let Some(hash) = reference.rtl.as_ref().map(|r| r.hash.as_str()) else {
            return Ok(missing(name, th, "the regression ran no RTL".into()));
        };
        let Some(loc) = f.history else {
            return Ok(missing(
                name,
                th,
                "no history: pmu50 regress --history FILE (or PMU50_HISTORY) every night".into(),
            ));
        };
        let runs = loc
            .open()
            .and_then(|mut db| crate::history::query::runs(db.as_mut()))
            .map_err(|e| RegressError::Usage(e.to_string()))?;
        let (days, last) = crate::history::query::soak(&runs, hash);
        Ok(Row {
            name,
            figure: Figure::Count(days),
            threshold: th,
            met: days >= t.soak_days,
            detail: format!(
                "history {}: consecutive days with every regression of this RTL at 100 %{}",
                loc.text(),
                last.map(|d| format!(", up to {d}")).unwrap_or_default()
            ),
        })
    }
}
