//! `pmu50 grade DIR`: the seeds of a regression ranked by the coverage each adds (greedy set
//! cover), the shortest list kept in DIR/graded.json, its curve in DIR/graded.svg.

use super::error::{CmdResult, Outcome};
use super::io::out;
use std::path::PathBuf;

/// The options of `pmu50 grade`.
#[derive(clap::Args)]
pub struct Args {
    /// The regression folder.
    pub dir: PathBuf,
}

pub fn run(a: Args) -> CmdResult {
    let g = pmu50_verif::grade::run(&a.dir)?;
    out!("{}", g.text().trim_end());
    out!(
        "wrote {}/graded.json, graded.svg; rerun the list with: pmu50 regress --seeds-from {}/graded.json --out DIR",
        a.dir.display(),
        a.dir.display()
    );
    Ok(Outcome::Pass)
}
