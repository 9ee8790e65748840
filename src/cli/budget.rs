//! `pmu50 budget`: the key-off battery budget of a park, four ways (docs/power.md).

use super::error::{CmdResult, Outcome};
use super::io::out;
use pmu50_testbench::analysis::budget;
use pmu50_testbench::scenario::Scenario;
use std::path::PathBuf;

/// The options of `pmu50 budget`.
#[derive(clap::Args)]
pub struct Args {
    pub scenario: PathBuf,
    #[arg(long, default_value = "vcd_out")]
    pub out_dir: PathBuf,
    /// Refuse a scenario whose simulations (adaptive, fixed, fixed at min) would take more
    /// than this many key-on ticks together (default 1e9; parked ticks do not count).
    #[arg(long, value_name = "TICKS")]
    pub max_ticks: Option<u64>,
}

pub fn run(a: Args) -> CmdResult {
    let sc = Scenario::load(&a.scenario)?;
    pmu50_testbench::limits::check_ticks(&sc, budget::RUNS, a.max_ticks)?;
    let text = budget::run_cli(&sc, &a.out_dir)?;
    out!("{}", text.trim_end());
    Ok(Outcome::Pass)
}
