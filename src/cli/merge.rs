//! `pmu50 merge`: regression folders and coverage files merged into one folder.

use super::error::{CmdResult, Outcome};
use super::io::{err, out};
use std::path::PathBuf;

/// The options of `pmu50 merge`.
#[derive(clap::Args)]
pub struct Args {
    /// Output folder: a new folder, neither an input nor holding one.
    #[arg(long, default_value = "regress_out/merged")]
    pub out: PathBuf,
    /// Replace the files of an output folder that holds a regression already.
    #[arg(long)]
    pub force: bool,
    pub inputs: Vec<PathBuf>,
}

pub fn run(a: Args) -> CmdResult {
    let m = pmu50_verif::merge::merge(&a.inputs, &a.out, a.force)?;
    out!(
        "merged {} regression folder(s) and {} coverage file(s) into {}",
        m.folders,
        m.coverage_files,
        a.out.display()
    );
    out!("{}", m.summary.text().trim_end());
    if let Some(code) = &m.summary.code {
        err!("{}", code.text().trim_end());
    }
    Ok(Outcome::of(
        m.summary.failed() == 0 && m.summary.missing.is_empty(),
    ))
}
