//! `pmu50 lint --rtl LIST [--waivers FILE] --out FILE.json`: the RTL's tool warnings, each waived
//! with a reviewed reason or counted. Two checks, each its own function:
//! - [`verilator_lint`]: Verilator `--lint-only -Wall` with the file list's options (those of the
//!   regression's builds), top `pmu50`; every `%Warning-RULE: file:line:` is a finding. Verilator
//!   reads SystemVerilog itself;
//! - [`yosys_check`]: yosys's `check` after `hierarchy -top pmu50; proc` on the RTL as Debian's
//!   yosys 0.23 gets it from [`crate::rtl_reader`]: a Verilog RTL read by yosys itself, an RTL
//!   with SystemVerilog files lowered by slang first (findings at the RTL's files and lines,
//!   from slang's `src` attributes); an RTL no reader gives is reported as not checked, with the
//!   reason, never as clean.
//!
//! The report ([`CheckReport`]) is sealed with its provenance ([`crate::provenance`]); the
//! sign-off row (`signoff_lint`) reads it.

use crate::check_report::{CheckReport, CheckRun};
use crate::filelist::FileList;
use crate::rtl_reader::{readers, RtlReader};
use crate::waiver::{Finding, SiteWaivers};
use std::path::Path;
use std::process::Command;

/// Version of the lint report.
pub const FORMAT: &str = "pmu50-lint-1";
/// Its name in a sign-off folder.
pub const FILE: &str = "lint.json";

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
    Ok(CheckRun::ran(
        "verilator -Wall --lint-only",
        crate::rtl_reader::NATIVE.into(),
        parse_verilator(&log),
    ))
}

const YOSYS_CHECK: &str = "yosys check";

/// yosys's `check` (hierarchy -top pmu50; proc) of the RTL as Debian's yosys gets it from the
/// first reader that gives it ([`crate::rtl_reader::readers`]). An RTL none gives is not
/// checked: `ran` false with every reader's reason.
pub fn yosys_check(list: &FileList, work: &Path) -> Result<CheckRun, String> {
    let mut why = Vec::new();
    for r in readers(list) {
        match check_with(list, r.as_ref(), work)? {
            Ok(findings) => return Ok(CheckRun::ran(YOSYS_CHECK, r.name(), findings)),
            Err(e) => why.push(format!("{}: {e}", r.name())),
        }
    }
    Ok(CheckRun::not_run(
        YOSYS_CHECK,
        String::new(),
        format!(
            "yosys 0.23 cannot read this RTL ({}): not checked",
            why.join("; ")
        ),
    ))
}

/// yosys's `check` of the RTL as `reader` gives it; `Err` (inner): why yosys could not read it.
fn check_with(
    list: &FileList,
    reader: &dyn RtlReader,
    work: &Path,
) -> Result<Result<Vec<Finding>, String>, String> {
    let read = match reader.sources(list, &[], "-nooverwrite") {
        Ok(s) => s.yosys_read,
        Err(e) => return Ok(Err(e)),
    };
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
        return Ok(Err(err));
    }
    Ok(Ok(text
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
        .collect()))
}

/// Both checks of `list`, with `waivers` applied.
pub fn run(list: &FileList, waivers: Option<&SiteWaivers>) -> Result<CheckReport, String> {
    let work = tempfile::tempdir().map_err(|e| format!("a scratch folder: {e}"))?;
    let checks = vec![verilator_lint(list)?, yosys_check(list, work.path())?];
    Ok(CheckReport::new(FORMAT, list, None, checks, waivers))
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
