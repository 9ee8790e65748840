//! The sign-off row of X-propagation (`xprop.json`, `pmu50 xprop`): X findings not waived (an
//! output X or Z after reset in the 4-state simulation, a flip-flop without reset), at most 0.
//! Missing when the folder has no sealed report, or when a check could not run on the RTL (the
//! row names why: an RTL Icarus or yosys cannot read has no X evidence).

use crate::criterion::{missing, Criterion, Figure, Folder, Row, Thresholds};
use crate::error::RegressError;
use crate::signoff_lint::read_sealed;
use crate::xprop::{XReport, FILE, FORMAT};

pub struct XProp;

const NAME: &str = "X-propagation findings";
const REMEDY: &str = "pmu50 xprop --rtl LIST --out DIR/xprop.json";

impl Criterion for XProp {
    fn row(&self, f: &Folder, _t: &Thresholds) -> Result<Row, RegressError> {
        let r = match read_sealed::<XReport>(f, FILE, REMEDY)? {
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
        if r.seeds == 0 {
            return Ok(missing(
                NAME,
                "<= 0".into(),
                format!("{FILE}: 0 seeds simulated"),
            ));
        }
        let n = r.unwaived.len() as u64;
        let mut detail = format!(
            "{FILE}: {} seed(s) in 4 states, every flip-flop's reset; {} waived",
            r.seeds,
            r.waivers.iter().map(|u| u.waived).sum::<u64>()
        );
        for w in r.unwaived.iter().take(5) {
            detail += &format!("; {}", w.message);
        }
        let stale: Vec<String> = r
            .waivers
            .iter()
            .filter_map(|u| {
                u.stale.as_ref().map(|s| {
                    format!(
                        "waiver {}:{} ({}) {s}",
                        r.waivers_file, u.waiver.at, u.waiver.signal
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
