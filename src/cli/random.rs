//! `pmu50 random`: a seeded random scenario (for co-simulation), or the scenario of a
//! regression seed.

use super::error::{CmdResult, Outcome};
use pmu50_testbench::atomic_file::{self, Batch};
use std::io::Write;
use std::path::PathBuf;

/// The options of `pmu50 random`.
#[derive(clap::Args)]
pub struct Args {
    #[arg(long)]
    pub seed: u64,
    /// The scenario `pmu50 regress` runs for this seed (uniform random; a directed seed
    /// also depends on the coverage before it: its repro is in failures/ of its run).
    #[arg(long)]
    pub regress: bool,
    /// Scenario file to write (`-`: standard output).
    #[arg(short, long)]
    pub output: PathBuf,
}

pub fn run(a: Args) -> CmdResult {
    let text = if a.regress {
        pmu50_verif::gen::Stimulus::generate(a.seed, &pmu50_verif::gen::Bias::uniform())
            .to_toml(&format!("regress_{}", a.seed))
    } else {
        pmu50_testbench::random::random_scenario(a.seed)
    };
    // `-o -`: standard output (atomic_file::Sink); a device or a FIFO is refused.
    let mut f = atomic_file::Sink::open(&a.output)?;
    f.write_all(text.as_bytes())
        .map_err(|source| atomic_file::OutputError::Write {
            path: a.output.clone(),
            source,
        })?;
    let mut b = Batch::new();
    f.finish(&mut b)?;
    b.commit()?;
    Ok(Outcome::Pass)
}
