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
    /// The history database this merge is appended to [default: $PMU50_HISTORY, else
    /// history.sqlite beside --out; `off`: none].
    #[arg(long, value_name = "FILE|URL")]
    pub history: Option<String>,
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
    if m.folders > 0 {
        super::common::record_history(
            a.history.as_deref(),
            &a.out,
            &pmu50_verif::history::record_of(&m.summary, "merge", &a.out),
        );
    }
    Ok(Outcome::of(
        m.summary.failed() == 0 && m.summary.missing.is_empty(),
    ))
}
