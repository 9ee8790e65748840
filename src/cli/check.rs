//! `pmu50 check`: validate scenarios without running them.

use super::error::{CliError, CmdResult, Outcome};
use super::io::{err, out};
use pmu50_testbench::scenario::Scenario;
use std::path::PathBuf;

/// The options of `pmu50 check`.
#[derive(clap::Args)]
pub struct Args {
    pub scenarios: Vec<PathBuf>,
}

pub fn run(a: Args) -> CmdResult {
    if a.scenarios.is_empty() {
        return Err(CliError::Usage(
            "check needs at least one scenario file".into(),
        ));
    }
    let mut bad = 0;
    for p in &a.scenarios {
        match Scenario::load(p) {
            Ok(sc) => out!("ok   {} ({}, {} ticks)", p.display(), sc.name, sc.ticks),
            Err(e) => {
                err!("error: {e}");
                bad += 1;
            }
        }
    }
    if bad > 0 {
        return Err(CliError::Reported {
            what: String::new(),
        });
    }
    Ok(Outcome::Pass)
}
