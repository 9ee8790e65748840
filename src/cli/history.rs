//! `pmu50 history`: the runs the history database holds, printed, and its dashboard as one
//! static HTML page (`--html FILE`).

use super::common::write_file;
use super::error::{CliError, CmdResult, Outcome};
use super::io::out;
use pmu50_verif::history::{self, Location};
use std::path::PathBuf;

/// The options of `pmu50 history`.
#[derive(clap::Args)]
pub struct Args {
    /// The database: a SQLite file or postgres://USER[:PASSWORD]@HOST[:PORT]/DB [default:
    /// $PMU50_HISTORY, else regress_out/history.sqlite].
    #[arg(long, value_name = "FILE|URL")]
    pub history: Option<String>,
    /// Write the dashboard here (pass rate and coverage over time per RTL, signatures, test-plan
    /// areas).
    #[arg(long, value_name = "FILE.html")]
    pub html: Option<PathBuf>,
}

pub fn run(a: Args) -> CmdResult {
    let loc = Location::choose(a.history.as_deref(), std::path::Path::new("regress_out/x"))
        .ok_or_else(|| CliError::Usage("PMU50_HISTORY=off: no history to show".into()))?;
    if let Location::Sqlite(p) = &loc {
        if !p.is_file() {
            return Err(CliError::Usage(format!(
                "history {}: no such database (pmu50 regress, merge and signoff write it)",
                p.display()
            )));
        }
    }
    let usage = |e: history::HistoryError| CliError::Usage(e.to_string());
    let mut db = loc.open().map_err(usage)?;
    let runs = history::runs(db.as_mut()).map_err(usage)?;
    out!(
        "{:<10} {:<8} {:<19} {:>7} {:>6} {:>5} {:>5} {:>9} {:<8} folder",
        "day",
        "kind",
        "rtl",
        "seeds",
        "pass",
        "fail",
        "error",
        "coverage",
        "signoff"
    );
    for r in &runs {
        out!(
            "{:<10} {:<8} {:<19} {:>7} {:>6} {:>5} {:>5} {:>9} {:<8} {}",
            r.day,
            r.kind,
            r.rtl_hash.chars().take(19).collect::<String>(),
            r.seed_count,
            r.pass,
            r.fail,
            r.error,
            format!("{}/{}", r.func_hit, r.func_total),
            match r.signoff_met {
                Some(true) => "met",
                Some(false) => "missed",
                None => "-",
            },
            r.folder
        );
    }
    out!("{} runs in {}", runs.len(), loc.text());
    if let Some(p) = &a.html {
        let page = history::dashboard(db.as_mut(), &loc.text()).map_err(usage)?;
        write_file(p, &page)?;
        out!("wrote {}", p.display());
    }
    Ok(Outcome::Pass)
}
