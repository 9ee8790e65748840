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
}

pub fn run(a: Args) -> CmdResult {
    let so = pmu50_verif::signoff::run(&a.dir, a.thresholds.as_deref(), None)?;
    out!("{}", so.text().trim_end());
    Ok(Outcome::of(so.met()))
}
