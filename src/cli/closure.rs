//! `pmu50 closure`: the closure curves of regression folders in one SVG.

use super::error::{CmdResult, Outcome};
use super::io::out;
use std::path::PathBuf;

/// The options of `pmu50 closure`.
#[derive(clap::Args)]
pub struct Args {
    #[arg(short, long)]
    pub output: PathBuf,
    pub dirs: Vec<PathBuf>,
}

pub fn run(a: Args) -> CmdResult {
    let text = pmu50_verif::report::closure_cli(&a.dirs, &a.output)?;
    out!("{}", text.trim_end());
    Ok(Outcome::Pass)
}
