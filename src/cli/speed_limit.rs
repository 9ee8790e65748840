//! `pmu50 speed-limit`: the highest motor speed tracked without a quadrant skip, against the
//! analytic bound (docs/analysis.md).

use super::error::{CmdResult, Outcome};
use super::io::out;
use pmu50_testbench::scenario::Scenario;
use std::path::{Path, PathBuf};

/// The options of `pmu50 speed-limit`.
#[derive(clap::Args)]
pub struct Args {
    /// Scenario whose [core] and [env] are used (defaults when omitted).
    pub scenario: Option<PathBuf>,
    #[arg(long, default_value = "vcd_out")]
    pub out_dir: PathBuf,
    /// Speed sweep step, deg/s (default: 1.5 x the steady-state bound / 60, rounded).
    #[arg(long)]
    pub step: Option<f64>,
    /// First speed of the sweep, deg/s (default: one step).
    #[arg(long)]
    pub from: Option<f64>,
    /// Last speed of the sweep, deg/s (default: 1.5 x 90 deg / min).
    #[arg(long)]
    pub to: Option<f64>,
    /// Skip the grid of configurations (x, min, Cth).
    #[arg(long)]
    pub no_grid: bool,
    /// Refuse a sweep of more speeds than this (default 2000).
    #[arg(long, value_name = "N")]
    pub max_points: Option<u64>,
    /// Refuse a sweep that would simulate more ticks than this (default 1e9).
    #[arg(long, value_name = "TICKS")]
    pub max_ticks: Option<u64>,
}

pub fn run(a: Args) -> CmdResult {
    let sc = match &a.scenario {
        Some(p) => Scenario::load(p)?,
        None => Scenario::parse(
            "duration = \"1 ms\"\n",
            "<defaults>",
            "defaults",
            Path::new(""),
        )?,
    };
    let text = pmu50_testbench::analysis::speed::run_cli(
        &sc,
        &a.out_dir,
        a.step,
        a.from,
        a.to,
        !a.no_grid,
        a.max_points,
        a.max_ticks,
    )?;
    out!("{}", text.trim_end());
    Ok(Outcome::Pass)
}
