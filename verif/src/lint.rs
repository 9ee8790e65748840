//! `pmu50 lint --rtl LIST [--waivers FILE] --out FILE.json`: the RTL's tool warnings, each waived
//! with a reviewed reason or counted. Two checks, each its own function:
//! - [`verilator_lint`]: Verilator `--lint-only -Wall` with the file list's options (those of the
//!   regression's builds), top `pmu50`; every `%Warning-RULE: file:line:` is a finding;
//! - [`yosys_check`]: yosys's `check` after `hierarchy -top pmu50; proc` on the RTL as Debian's
//!   yosys 0.23 reads it (`read_verilog -sv`); an RTL it cannot read (SystemVerilog beyond it:
//!   package imports in module headers, typed parameters) is reported as not checked, with the
//!   reason, not as clean.
//!
//! The output is sealed with its provenance ([`crate::provenance`]); the sign-off row
//! (`signoff_lint`) reads it.

use crate::filelist::FileList;
use crate::waiver::{Finding, SiteUse, SiteWaivers};
use serde::{Deserialize, Serialize};
use std::path::Path;
use std::process::Command;

/// Version of the lint report.
pub const FORMAT: &str = "pmu50-lint-1";
/// Its name in a sign-off folder.
pub const FILE: &str = "lint.json";

/// One check's outcome.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct CheckRun {
    /// `verilator -Wall --lint-only`, `yosys check`.
    pub tool: String,
    /// Whether it ran on the RTL; when not, why (`reason`).
    pub ran: bool,
    #[serde(default)]
    pub reason: String,
    pub findings: Vec<Finding>,
}

/// The lint report (`lint.json`, sealed).
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct LintReport {
    pub format: String,
    pub checks: Vec<CheckRun>,
    /// The findings no applying waiver waives.
    pub unwaived: Vec<Finding>,
    pub waivers: Vec<SiteUse>,
    /// The waivers file, as given (empty: none).
    pub waivers_file: String,
}

impl LintReport {
    /// Whether every check ran, and every finding is waived.
    pub fn clean(&self) -> bool {
        self.checks.iter().all(|c| c.ran) && self.unwaived.is_empty()
    }
}

/// `%Warning-RULE: file:line:col: message` lines of Verilator's output.
pub fn parse_verilator(log: &str) -> Vec<Finding> {
    let mut out = Vec::new();
    for l in log.lines() {
        let Some(rest) = l.strip_prefix("%Warning-") else {
            continue;
        };
        let Some((rule, rest)) = rest.split_once(": ") else {
            continue;
        };
        let mut parts = rest.splitn(4, ':');
        let (file, line) = (parts.next().unwrap_or(""), parts.next().unwrap_or(""));
        let Ok(line) = line.trim().parse::<u32>() else {
            out.push(Finding {
                rule: rule.to_string(),
                file: String::new(),
                line: 0,
                signal: String::new(),
                message: rest.trim().to_string(),
            });
            continue;
        };
        let _col = parts.next();
        let message = parts.next().unwrap_or("").trim().to_string();
        let signal = message
            .split('\'')
            .nth(1)
            .map(|s| s.to_string())
            .unwrap_or_default();
        out.push(Finding {
            rule: rule.to_string(),
            file: file.to_string(),
            line,
            signal,
            message,
        });
    }
    out
}

/// Verilator `-Wall --lint-only` of the RTL (its file list's options, top `pmu50`). `Err`: the
/// RTL does not lint (an `%Error`), with Verilator's words.
pub fn verilator_lint(list: &FileList) -> Result<CheckRun, String> {
    let out = Command::new("verilator")
        .args([
            "--lint-only",
            "-Wall",
            "--no-timing",
            "--top-module",
            "pmu50",
        ])
        .args(list.verilator_args())
        .args(&list.files)
        .output()
        .map_err(|e| format!("cannot run verilator (Debian package verilator): {e}"))?;
    let log = String::from_utf8_lossy(&out.stderr).into_owned();
    // warnings end with `%Error: Exiting due to N warning(s)`; any other error is the RTL's
    if let Some(e) = log
        .lines()
        .find(|l| l.starts_with("%Error") && !l.contains("Exiting due to"))
    {
        return Err(format!("verilator --lint-only: {e}"));
    }
    Ok(CheckRun {
        tool: "verilator -Wall --lint-only".into(),
        ran: true,
        reason: String::new(),
        findings: parse_verilator(&log),
    })
}

/// yosys's `check` (hierarchy -top pmu50; proc) of the RTL as Debian's yosys reads it. An RTL it
/// cannot read is not checked: `ran` false with yosys's error.
pub fn yosys_check(list: &FileList, work: &Path) -> Result<CheckRun, String> {
    let read = list.yosys_read("-nooverwrite");
    let log = work.join("yosys-check.log");
    let out = Command::new("yosys")
        .arg("-q")
        .arg("-l")
        .arg(&log)
        .arg("-p")
        .arg(format!("{read}; hierarchy -top pmu50; proc; check"))
        .output()
        .map_err(|e| format!("cannot run yosys (Debian package yosys): {e}"))?;
    let text =
        std::fs::read_to_string(&log).unwrap_or_default() + &String::from_utf8_lossy(&out.stderr);
    let _ = std::fs::remove_file(&log);
    if !out.status.success() {
        let err = text
            .lines()
            .find(|l| l.contains("ERROR"))
            .unwrap_or("yosys failed")
            .trim()
            .to_string();
        return Ok(CheckRun {
            tool: "yosys check".into(),
            ran: false,
            reason: format!(
                "yosys 0.23 cannot read this RTL ({err}): not checked; a SystemVerilog front end lowering it first is the formal kit's (hdl/formal/pmu50_formal)"
            ),
            findings: Vec::new(),
        });
    }
    let findings = text
        .lines()
        .filter_map(|l| l.trim().strip_prefix("Warning: "))
        .map(|m| {
            // `... at file.v:12.3-12.9` where yosys gives a source
            let (file, line) = m
                .rsplit_once(' ')
                .and_then(|(_, loc)| loc.split_once(':'))
                .and_then(|(f, l)| {
                    let n: u32 = l.split('.').next()?.parse().ok()?;
                    Some((f.to_string(), n))
                })
                .unwrap_or_default();
            Finding {
                rule: "yosys-check".into(),
                file,
                line,
                signal: String::new(),
                message: m.to_string(),
            }
        })
        .collect::<std::collections::BTreeSet<_>>()
        .into_iter()
        .collect();
    Ok(CheckRun {
        tool: "yosys check".into(),
        ran: true,
        reason: String::new(),
        findings,
    })
}

impl PartialOrd for Finding {
    fn partial_cmp(&self, o: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(o))
    }
}
impl Ord for Finding {
    fn cmp(&self, o: &Self) -> std::cmp::Ordering {
        (
            &self.file,
            self.line,
            &self.rule,
            &self.signal,
            &self.message,
        )
            .cmp(&(&o.file, o.line, &o.rule, &o.signal, &o.message))
    }
}

/// Both checks of `list`, with `waivers` applied.
pub fn run(list: &FileList, waivers: Option<&SiteWaivers>) -> Result<LintReport, String> {
    let work = tempfile::tempdir().map_err(|e| format!("a scratch folder: {e}"))?;
    let checks = vec![verilator_lint(list)?, yosys_check(list, work.path())?];
    let all: Vec<Finding> = checks.iter().flat_map(|c| c.findings.clone()).collect();
    let (unwaived, uses) = match waivers {
        Some(w) => w.apply(&all, &list.files),
        None => (all, Vec::new()),
    };
    Ok(LintReport {
        format: FORMAT.into(),
        checks,
        unwaived,
        waivers: uses,
        waivers_file: waivers.map(|w| w.path.clone()).unwrap_or_default(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn verilator_warnings_are_read_with_their_place() {
        let log = "%Warning-UNUSEDSIGNAL: /r/a.v:12:15: Signal is not used: 'spare'\n                                    : ... In instance pmu50\n%Warning-WIDTHEXPAND: b.sv:3:7: Operator ASSIGN expects 8 bits\n%Error: Exiting due to 2 warning(s)\n";
        let f = parse_verilator(log);
        assert_eq!(f.len(), 2);
        assert_eq!(
            (
                f[0].rule.as_str(),
                f[0].file.as_str(),
                f[0].line,
                f[0].signal.as_str()
            ),
            ("UNUSEDSIGNAL", "/r/a.v", 12, "spare")
        );
        assert_eq!((f[1].file.as_str(), f[1].line), ("b.sv", 3));
    }
}
