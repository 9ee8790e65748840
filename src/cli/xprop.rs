//! `pmu50 xprop --rtl LIST --out FILE.json [--iterations N] [--waivers FILE]`: X-propagation of
//! the RTL (a 4-state simulation of N regression seeds with the inputs X while they may float,
//! and every flip-flop's reset), sealed for the sign-off's X row (docs/verification.md
//! "X-propagation").

use super::common::write_file;
use super::error::{CliError, CmdResult, Outcome};
use super::io::{err, out};
use pmu50_verif::filelist::FileList;
use pmu50_verif::provenance::{self, Provenance, RtlId, Seeds};
use pmu50_verif::waiver::SiteWaivers;
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct Args {
    /// The RTL's file list (top `pmu50`).
    #[arg(long, value_name = "FILELIST")]
    pub rtl: PathBuf,
    /// The report to write (sealed JSON).
    #[arg(long, value_name = "FILE.json")]
    pub out: PathBuf,
    /// Regression seeds simulated (1..=N), 1 to 10 000.
    #[arg(long, default_value_t = 8)]
    pub iterations: u64,
    /// Waivers of flip-flops that need no reset (TOML `[[waiver]]`: rule = "no-reset", file,
    /// line, signal, reason, kind, reviewer, checksum).
    #[arg(long, value_name = "FILE.toml")]
    pub waivers: Option<PathBuf>,
}

pub fn run(a: Args) -> CmdResult {
    if !(1..=10_000).contains(&a.iterations) {
        return Err(CliError::Usage(format!(
            "--iterations {}: valid is 1 to 10000",
            a.iterations
        )));
    }
    let fl = FileList::read(&a.rtl)?;
    let waivers = match &a.waivers {
        Some(w) => Some(SiteWaivers::read(w).map_err(CliError::Usage)?),
        None => None,
    };
    let r =
        pmu50_verif::xprop::run(&fl, a.iterations, waivers.as_ref()).map_err(CliError::Usage)?;
    for c in &r.checks {
        if c.ran {
            out!(
                "xprop: {}: {} finding(s){}",
                c.tool,
                c.findings.len(),
                pmu50_verif::rtl_reader::read_by(&c.reader)
            );
        } else {
            out!("xprop: {}: not run: {}", c.tool, c.reason);
        }
    }
    for u in r.waivers.iter().filter(|u| u.stale.is_some()) {
        err!(
            "xprop: waiver {}:{} ({}) does not apply, {}",
            r.waivers_file,
            u.waiver.at,
            u.waiver.signal,
            u.stale.as_deref().unwrap_or("")
        );
    }
    for f in &r.unwaived {
        out!("xprop: {}", f.message);
    }
    out!(
        "xprop: {} finding(s) not waived over {} seed(s){}",
        r.unwaived.len(),
        a.iterations,
        if r.clean() { "" } else { ": not clean" }
    );
    let v = serde_json::to_value(&r).map_err(|e| CliError::Usage(e.to_string()))?;
    let serde_json::Value::Object(m) = v else {
        return Err(CliError::Usage("the X report is not an object".into()));
    };
    let p = Provenance::now(
        "pmu50 xprop",
        Some(RtlId {
            list: a.rtl.display().to_string(),
            hash: fl.content_hash()?,
        }),
        "icarus",
        Some(Seeds {
            start: 1,
            count: a.iterations,
        }),
    );
    write_file(&a.out, &provenance::seal(m, &p))?;
    Ok(Outcome::of(r.clean()))
}
