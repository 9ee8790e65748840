//! `pmu50 lint --rtl LIST [--waivers FILE] --out FILE.json`: the RTL's tool warnings (Verilator
//! `-Wall --lint-only`, yosys `check`), each waived with a reviewed reason or counted; the report
//! sealed with its provenance for the sign-off's lint row (docs/verification.md "Lint").

use super::common::write_file;
use super::error::{CliError, CmdResult, Outcome};
use super::io::{err, out};
use pmu50_verif::filelist::FileList;
use pmu50_verif::provenance::{self, Provenance, RtlId};
use pmu50_verif::waiver::SiteWaivers;
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct Args {
    /// The RTL's file list (top `pmu50`).
    #[arg(long, value_name = "FILELIST")]
    pub rtl: PathBuf,
    /// The lint waivers (TOML `[[waiver]]`: rule, file, line, reason, kind, reviewer, checksum).
    #[arg(long, value_name = "FILE.toml")]
    pub waivers: Option<PathBuf>,
    /// The report to write (sealed JSON).
    #[arg(long, value_name = "FILE.json")]
    pub out: PathBuf,
}

pub fn run(a: Args) -> CmdResult {
    let fl = FileList::read(&a.rtl)?;
    let waivers = match &a.waivers {
        Some(w) => Some(SiteWaivers::read(w).map_err(CliError::Usage)?),
        None => None,
    };
    let r = pmu50_verif::lint::run(&fl, waivers.as_ref()).map_err(CliError::Usage)?;
    for c in &r.checks {
        if c.ran {
            out!(
                "lint: {}: {} warning(s){}",
                c.tool,
                c.findings.len(),
                pmu50_verif::rtl_reader::read_by(&c.reader)
            );
        } else {
            out!("lint: {}: not run: {}", c.tool, c.reason);
        }
    }
    for u in &r.waivers {
        match &u.stale {
            Some(s) => err!(
                "lint: waiver {}:{} ({} {}:{}) does not apply, {s}",
                r.waivers_file,
                u.waiver.at,
                u.waiver.rule,
                u.waiver.file,
                u.waiver.line
            ),
            None => out!(
                "lint: waived {} {}:{}: {} warning(s): {}",
                u.waiver.rule,
                u.waiver.file,
                u.waiver.line,
                u.waived,
                u.waiver.review.reason
            ),
        }
    }
    for f in &r.unwaived {
        out!("lint: {}:{}: {}: {}", f.file, f.line, f.rule, f.message);
    }
    out!(
        "lint: {} warning(s) not waived{}",
        r.unwaived.len(),
        if r.clean() { "" } else { ": not clean" }
    );
    let v = serde_json::to_value(&r).map_err(|e| CliError::Usage(e.to_string()))?;
    let serde_json::Value::Object(m) = v else {
        return Err(CliError::Usage("the lint report is not an object".into()));
    };
    let p = Provenance::now(
        "pmu50 lint",
        Some(RtlId {
            list: a.rtl.display().to_string(),
            hash: fl.content_hash()?,
        }),
        "verilator+yosys",
        None,
    );
    write_file(&a.out, &provenance::seal(m, &p))?;
    Ok(Outcome::of(r.clean()))
}
