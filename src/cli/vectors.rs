//! `pmu50 vectors`: per-tick inputs and expected outputs of a scenario for HDL testbenches
//! (docs/spec.md 6.2), optionally with the model's VCD of the same run.

use super::common::Progress;
use super::error::{CliError, CmdResult, Outcome};
use super::io::{err, out};
use pmu50_testbench::atomic_file::{self, Batch};
use pmu50_testbench::observers::vectors::VectorWriter;
use pmu50_testbench::output::{output_paths, run_to_batch, FileOptions, RunError};
use pmu50_testbench::scenario::Scenario;
use pmu50_testbench::sim::{self, SimOptions};
use std::io::BufWriter;
use std::path::{Path, PathBuf};

/// The options of `pmu50 vectors`.
#[derive(clap::Args)]
pub struct Args {
    pub scenario: PathBuf,
    /// Vector file to write (`-`: standard output).
    #[arg(short, long)]
    pub output: PathBuf,
    /// Also write the model's VCD into this folder (same run).
    #[arg(long)]
    pub vcd_dir: Option<PathBuf>,
    /// Refuse a vector file larger than this (bytes; default 2 GB; one line per tick).
    #[arg(long, value_name = "BYTES")]
    pub max_vector_bytes: Option<u64>,
}

pub fn run(a: Args) -> CmdResult {
    let (scenario, output, vcd_dir) = (&a.scenario, &a.output, a.vcd_dir.as_deref());
    let mut sc = Scenario::load(scenario)?;
    pmu50_testbench::limits::check_vector_bytes(&sc, a.max_vector_bytes)?;
    // The model VCD written beside the vectors is compared tick by tick with the RTL's:
    // it must cover the whole run, whatever window the scenario asks for.
    sc.vcd_window = None;
    if let Some(d) = vcd_dir {
        // Same folder and name (the folders compared once they exist).
        let same = |a: &Path, b: &Path| {
            a == b
                || (a.file_name() == b.file_name()
                    && matches!((a.parent().map(std::fs::canonicalize), b.parent().map(std::fs::canonicalize)), (Some(Ok(x)), Some(Ok(y))) if x == y))
        };
        if let Some(p) = output_paths(d, &sc.name, false)
            .into_iter()
            .find(|p| same(p, output))
        {
            return Err(CliError::Usage(format!("-o {} is also the model's {} written into --vcd-dir; choose another name for the vectors", output.display(), p.display())));
        }
    }
    if atomic_file::same_file(scenario, output) {
        return Err(CliError::Usage(format!("-o {} is the scenario file itself; the vectors would overwrite it; choose another name", output.display())));
    }
    let ticks = (|| -> Result<u64, RunError> {
        // `-o -`: standard output (atomic_file::Sink); a device or a FIFO is refused.
        let f = atomic_file::Sink::open(output)?;
        let mut vw = VectorWriter::new(BufWriter::new(f), &sc)?;
        let mut prog = Progress::new(sc.ticks, &sc.name);
        let (ticks, mut batch) = match vcd_dir {
            Some(d) => {
                let (r, _, b) =
                    run_to_batch(&sc, d, FileOptions::default(), &mut [&mut vw, &mut prog])?;
                (r.ticks, b)
            }
            None => (
                sim::run(
                    &sc,
                    SimOptions {
                        fast_forward: false,
                    },
                    &mut [&mut vw, &mut prog],
                )?
                .ticks,
                Batch::new(),
            ),
        };
        let f = vw
            .into_inner()
            .into_inner()
            .map_err(|e| atomic_file::OutputError::Write {
                path: output.to_path_buf(),
                source: e.into_error(),
            })?;
        f.finish(&mut batch)?;
        batch.commit()?;
        Ok(ticks)
    })()?;
    if output.as_os_str() == "-" {
        err!("wrote the vectors to standard output ({ticks} ticks)");
    } else {
        out!("wrote {} ({} ticks)", output.display(), ticks);
    }
    Ok(Outcome::Pass)
}
