//! `pmu50 list`: the scenarios of a folder, with their durations and descriptions.

use super::error::{CliError, CmdResult, Outcome};
use super::io::out;
use pmu50_core::Dur;
use pmu50_testbench::scenario::Scenario;
use std::path::PathBuf;

/// The options of `pmu50 list`.
#[derive(clap::Args)]
pub struct Args {
    #[arg(default_value = "scenarios")]
    pub dir: PathBuf,
}

pub fn run(a: Args) -> CmdResult {
    let mut files: Vec<PathBuf> = std::fs::read_dir(&a.dir)
        .map_err(|e| CliError::Usage(format!("{}: {e}", a.dir.display())))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    files.sort();
    for p in files {
        // Scenario::load refuses FIFOs, devices and folders before opening them.
        match Scenario::load(&p) {
            Ok(sc) => out!(
                "{:<18} {:>10}  {}",
                sc.name,
                Dur(sc.ticks * sc.clock_ns()).to_string(),
                sc.description
            ),
            Err(e) => out!("{:<18} INVALID: {e}", p.display()),
        }
    }
    Ok(Outcome::Pass)
}
