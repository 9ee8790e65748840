//! `pmu50 signoff`: the sign-off table of a regression folder against its thresholds.

use super::error::{CmdResult, Outcome};
use super::io::out;
use std::path::PathBuf;

/// The options of `pmu50 signoff`.
#[derive(clap::Args)]
pub struct Args {
    /// The regression folder.
    pub dir: PathBuf,
    /// TOML file with a table [thresholds]: functional, unreachable_proven, code_line,
    /// code_toggle, properties, seeds (percent) and undecided (a count); any subset.
    #[arg(long, value_name = "FILE.toml")]
    pub thresholds: Option<PathBuf>,
    /// The history database (the soak row reads it; this sign-off is appended to it): a SQLite
    /// file or postgres://USER[:PASSWORD]@HOST[:PORT]/DB [default: $PMU50_HISTORY, else
    /// history.sqlite beside DIR; `off`: none].
    #[arg(long, value_name = "FILE|URL")]
    pub history: Option<String>,
}

pub fn run(a: Args) -> CmdResult {
    let loc = pmu50_verif::history::Location::choose(a.history.as_deref(), &a.dir);
    let (so, summary) = pmu50_verif::signoff::run(&a.dir, a.thresholds.as_deref(), loc.as_ref())?;
    out!("{}", so.text().trim_end());
    super::common::record_history(a.history.as_deref(), &a.dir, &so.record(&summary, &a.dir));
    Ok(Outcome::of(so.met()))
}
