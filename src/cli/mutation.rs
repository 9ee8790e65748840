//! `pmu50 mutation`: the mutation table of the directed regression.

use super::common::{jobs, progress_line, timeout};
use super::error::{CmdResult, Outcome};
use super::io::out;
use pmu50_verif::mutation;
use std::path::PathBuf;
use std::sync::atomic::AtomicBool;

/// The options of `pmu50 mutation`.
#[derive(clap::Args)]
pub struct Args {
    /// Directed seeds per mutant.
    #[arg(long, default_value_t = 400)]
    pub iterations: u64,
    /// First seed.
    #[arg(long, default_value_t = 1)]
    pub start_seed: u64,
    /// Mutants checked at once (default: every core).
    #[arg(long)]
    pub jobs: Option<usize>,
    /// Only these mutants (comma-separated names).
    #[arg(long, value_delimiter = ',')]
    pub only: Vec<String>,
    /// The mutants' list [default: the kit's hdl/mutants.txt].
    #[arg(long, value_name = "FILE")]
    pub mutants: Option<PathBuf>,
    /// Output folder.
    #[arg(long, default_value = "regress_out/mutation")]
    pub out: PathBuf,
    /// Per-seed time limit for the DUT, seconds.
    #[arg(long, default_value_t = 120.0)]
    pub timeout: f64,
    /// Compare the contract's ports only, as a regression of an RTL without a map does (the
    /// default compares the twin's map too).
    #[arg(long)]
    pub ports_only: bool,
    /// The pool of parameter sets the directed seeds draw from, as `pmu50 regress
    /// --param-sets` (0: each seed its own) [default: regress's default for an RTL].
    #[arg(long, value_name = "P")]
    pub param_sets: Option<u32>,
}

pub fn run(a: Args) -> CmdResult {
    let timeout = timeout(a.timeout)?;
    let jobs = jobs(a.jobs)?;
    let hdl = pmu50_verif::hdl_kit::hdl_dir();
    let o = mutation::Options {
        mutants: a.mutants.unwrap_or_else(|| hdl.join("mutants.txt")),
        twin: hdl.join("pmu50.f"),
        map: (!a.ports_only).then(|| hdl.join("pmu50.map.toml")),
        start_seed: a.start_seed,
        iterations: a.iterations,
        jobs,
        timeout,
        only: a.only,
        out: a.out.clone(),
        param_sets: a
            .param_sets
            .unwrap_or(pmu50_verif::param_pool::DEFAULT_SETS),
    };
    let stop = AtomicBool::new(false);
    let r = mutation::run(&o, &stop, progress_line)?;
    out!("{}", r.text().trim_end());
    out!(
        "wrote {}/mutation.json, mutation.txt, mutation.md",
        a.out.display()
    );
    Ok(Outcome::of(r.ok()))
}
