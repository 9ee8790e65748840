//! The report of the kit's checks of an RTL (`pmu50 lint`: lint.json, `pmu50 xprop`: xprop.json):
//! the checks run, each with its tool, the reader the tool read the RTL through
//! ([`crate::rtl_reader`]) and its findings; the findings no waiver waives; each waiver's use.
//! One type for both reports, sealed with its provenance ([`crate::provenance`]); one sign-off
//! row type reads them (`signoff_checks`).

use crate::filelist::FileList;
use crate::waiver::{Finding, SiteUse, SiteWaivers};
use serde::{Deserialize, Serialize};

/// One check's outcome.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct CheckRun {
    /// `verilator -Wall --lint-only`, `yosys check`.
    pub tool: String,
    /// How the tool read the RTL (`rtl_reader`): its own reader, or slang's lowering.
    #[serde(default)]
    pub reader: String,
    /// Whether it ran on the RTL; when not, why (`reason`).
    pub ran: bool,
    #[serde(default)]
    pub reason: String,
    pub findings: Vec<Finding>,
}

impl CheckRun {
    /// A check that ran, with its findings.
    pub fn ran(tool: &str, reader: String, findings: Vec<Finding>) -> CheckRun {
        CheckRun {
            tool: tool.into(),
            reader,
            ran: true,
            reason: String::new(),
            findings,
        }
    }

    /// A check that could not run on the RTL, and why.
    pub fn not_run(tool: &str, reader: String, reason: String) -> CheckRun {
        CheckRun {
            tool: tool.into(),
            reader,
            ran: false,
            reason,
            findings: Vec::new(),
        }
    }
}

/// A report of checks (lint.json, xprop.json; sealed).
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct CheckReport {
    /// `pmu50-lint-1`, `pmu50-xprop-1`.
    pub format: String,
    /// Regression seeds simulated (1..=seeds), for the checks that simulate.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub seeds: Option<u64>,
    /// Source files of the RTL checked (its file list's).
    #[serde(default)]
    pub files: u64,
    pub checks: Vec<CheckRun>,
    /// The findings no applying waiver waives.
    pub unwaived: Vec<Finding>,
    pub waivers: Vec<SiteUse>,
    /// The waivers file, as given (empty: none).
    pub waivers_file: String,
}

impl CheckReport {
    /// The report of `checks` of `list`, with `waivers` applied.
    pub fn new(
        format: &str,
        list: &FileList,
        seeds: Option<u64>,
        checks: Vec<CheckRun>,
        waivers: Option<&SiteWaivers>,
    ) -> CheckReport {
        let all: Vec<Finding> = checks.iter().flat_map(|c| c.findings.clone()).collect();
        let (unwaived, uses) = match waivers {
            Some(w) => w.apply(&all, &list.files),
            None => (all, Vec::new()),
        };
        CheckReport {
            format: format.into(),
            seeds,
            files: list.files.len() as u64,
            checks,
            unwaived,
            waivers: uses,
            waivers_file: waivers.map(|w| w.path.clone()).unwrap_or_default(),
        }
    }

    /// Whether every check ran, and every finding is waived.
    pub fn clean(&self) -> bool {
        self.checks.iter().all(|c| c.ran) && self.unwaived.is_empty()
    }

    /// ` over N file(s)`; empty for a report that does not count them (made before the count).
    pub fn over_files(&self) -> String {
        match self.files {
            0 => String::new(),
            n => format!(" over {n} file(s)"),
        }
    }

    /// Findings waived.
    pub fn waived(&self) -> u64 {
        self.waivers.iter().map(|u| u.waived).sum()
    }

    /// The checks, each as its tool and, when a reader other than the tool's own read the RTL,
    /// which ([`crate::rtl_reader::read_by`]), joined by "and".
    pub fn tools(&self) -> String {
        self.checks
            .iter()
            .map(|c| format!("{}{}", c.tool, crate::rtl_reader::read_by(&c.reader)))
            .collect::<Vec<_>>()
            .join(" and ")
    }

    /// ` (the RTL read by READER)` when every check's RTL was read by one reader other than the
    /// tool's own; the readers per check otherwise ([`CheckReport::tools`] style); empty when the
    /// tools read it themselves.
    pub fn read_by(&self) -> String {
        let mut readers: Vec<&str> = self.checks.iter().map(|c| c.reader.as_str()).collect();
        readers.dedup();
        match readers.as_slice() {
            [one] => crate::rtl_reader::read_by(one),
            _ if readers
                .iter()
                .all(|r| crate::rtl_reader::read_by(r).is_empty()) =>
            {
                String::new()
            }
            _ => format!(" ({})", self.tools()),
        }
    }
}
