//! `pmu50 lockstep`: verification method 2 on one vector file: the RTL (default the twin) built
//! by Verilator and stepped in lockstep with the model.

use super::error::{CliError, CmdResult, Outcome};
use super::io::out;
use pmu50_testbench::atomic_file::{self, Batch};
use pmu50_verif::{dut::VerilatorDut, lockstep, map as m, rtl as r};
use std::path::{Path, PathBuf};
use std::time::Duration;

/// The options of `pmu50 lockstep`.
#[derive(clap::Args)]
pub struct Args {
    /// The vector file (`pmu50 vectors`, docs/spec.md 6.2).
    pub file: PathBuf,
    /// The RTL's Verilog file list (default: the twin, hdl/pmu50.f).
    #[arg(long, value_name = "FILELIST")]
    pub rtl: Option<PathBuf>,
    /// Also compare the registers and internals this map names.
    #[arg(long, value_name = "FILE.toml")]
    pub map: Option<PathBuf>,
    /// A Verilog `define for the RTL (a mutant of hdl/mutants.txt), repeatable.
    #[arg(long = "define", value_name = "NAME")]
    pub defines: Vec<String>,
    /// Time limit, seconds.
    #[arg(long, default_value_t = 600.0)]
    pub timeout: f64,
    /// On a pass, also write the functional coverage of the run (the model sampled at
    /// every edge of the file's inputs) as a coverage.json, mergeable with `pmu50 merge`:
    /// a formal witness replayed through the RTL closes its bin.
    #[arg(long, value_name = "FILE.json")]
    pub coverage: Option<PathBuf>,
}

/// Every error of this command reads `LOCKSTEP ERROR: ...` (the HDL scripts grep for it).
fn fail(e: impl std::fmt::Display) -> CliError {
    CliError::Lockstep(e.to_string())
}

pub fn run(a: Args) -> CmdResult {
    if !(a.timeout.is_finite() && a.timeout > 0.0 && a.timeout <= 86_400.0) {
        return Err(fail(format!(
            "--timeout {}: give seconds, 0 < T <= 86400",
            a.timeout
        )));
    }
    let v = lockstep::read_vector_inputs(&a.file).map_err(fail)?;
    let list = a
        .rtl
        .clone()
        .unwrap_or_else(|| pmu50_verif::hdl_kit::hdl_dir().join("pmu50.f"));
    // defines: a file list with a file of `define lines first
    let scratch = tempfile::tempdir().map_err(|e| fail(format!("a scratch folder: {e}")))?;
    let list = if a.defines.is_empty() {
        list
    } else {
        with_defines(&list, &a.defines, scratch.path())?
    };
    let map = a
        .map
        .as_deref()
        .map(m::RtlMap::read)
        .transpose()
        .map_err(fail)?;
    let d = VerilatorDut::prepare(&list, map, Default::default()).map_err(fail)?;
    let (nr, nx) = d.mapped_counts();
    let answer = d
        .lockstep_inputs(&v.params, &v.inputs, Duration::from_secs_f64(a.timeout))
        .map_err(fail)?;
    match answer {
        lockstep::Answer::Reply(lockstep::Reply::Pass { ticks })
            if ticks != v.inputs.len() as u64 =>
        {
            Err(fail(format!(
                "{}: the RTL's run ended after {ticks} ticks, the vector file has {}: a run that ends early or late is not a pass",
                a.file.display(),
                v.inputs.len()
            )))
        }
        lockstep::Answer::Reply(lockstep::Reply::Pass { ticks }) => {
            out!(
                "PASS ticks={ticks} outputs={} registers={nr} internals={nx} (scenario {})",
                pmu50_core::signals::N_OUTPUTS,
                v.scenario
            );
            if let Some(path) = &a.coverage {
                let id = format!(
                    "lockstep/{}",
                    a.file.file_stem().unwrap_or_default().to_string_lossy()
                );
                let c = lockstep::model_coverage(&v)
                    .map_err(|e| fail(format!("{}: {e}", a.file.display())))?;
                // sealed with the RTL it ran on: `pmu50 merge` and the sign-off check it
                let (rtl, _) = pmu50_verif::evidence::rtl_of(&list).map_err(fail)?;
                let p = pmu50_verif::provenance::Provenance::now(
                    "pmu50 lockstep --coverage",
                    Some(rtl),
                    "verilator",
                    None,
                );
                let text = pmu50_verif::evidence::sealed_coverage(
                    &pmu50_coverage::db::of_run(&c, &id, "pass"),
                    &p,
                );
                let f = atomic_file::write_atomic(path, text.as_bytes()).map_err(fail)?;
                let mut b = Batch::new();
                b.add(f);
                b.commit().map_err(fail)?;
                out!("coverage: {} (run {id})", path.display());
            }
            Ok(Outcome::Pass)
        }
        lockstep::Answer::Reply(lockstep::Reply::Diverged {
            tick,
            combinational,
            mismatches,
        }) => {
            for x in &mismatches {
                out!(
                    "MISMATCH tick={tick} signal={} expected={:x} got={:x}",
                    x.signal,
                    x.expected,
                    x.got
                );
            }
            let when = if combinational {
                format!("combinational, before rising edge {}", tick + 1)
            } else {
                format!("after rising edge {tick}")
            };
            out!("LOCKSTEP FAIL {} (scenario {}): first divergence at tick {tick} ({when}), time {} ns", a.file.display(), v.scenario, tick * v.clock_ns);
            Ok(Outcome::Fail)
        }
        lockstep::Answer::Reply(lockstep::Reply::Error { reason }) => Err(fail(reason)),
        lockstep::Answer::Reply(lockstep::Reply::Probe { .. } | lockstep::Reply::Trace { .. }) => {
            Err(fail("the DUT worker answered another request"))
        }
        lockstep::Answer::TimedOut => {
            out!(
                "LOCKSTEP FAIL {} (scenario {}): the DUT did not finish within {} s",
                a.file.display(),
                v.scenario,
                a.timeout
            );
            Ok(Outcome::Fail)
        }
        lockstep::Answer::Died(how) => {
            out!(
                "LOCKSTEP FAIL {} (scenario {}): {how}",
                a.file.display(),
                v.scenario
            );
            Ok(Outcome::Fail)
        }
    }
}

/// The file list `list` with a file of `` `define `` lines first, in `scratch`.
fn with_defines(list: &Path, defines: &[String], scratch: &Path) -> Result<PathBuf, CliError> {
    if let Some(bad) = defines
        .iter()
        .find(|d| d.is_empty() || !d.chars().all(|c| c.is_ascii_alphanumeric() || c == '_'))
    {
        return Err(fail(format!(
            "--define `{bad}`: a Verilog macro name (letters, digits, _)"
        )));
    }
    let fl = r::FileList::read(list).map_err(fail)?;
    let defs: String = defines.iter().map(|d| format!("`define {d}\n")).collect();
    let body: String = std::iter::once(scratch.join("defines.vh"))
        .chain(fl.files.iter().cloned())
        .map(|f| format!("{}\n", f.display()))
        .collect();
    let mut batch = Batch::new();
    let written = atomic_file::write_atomic(&scratch.join("defines.vh"), defs.as_bytes())
        .map(|f| batch.add(f))
        .and_then(|()| atomic_file::write_atomic(&scratch.join("rtl.f"), body.as_bytes()))
        .map(|f| batch.add(f))
        .and_then(|()| batch.commit());
    if written.is_err() {
        return Err(fail("cannot write the file list with the defines"));
    }
    Ok(scratch.join("rtl.f"))
}
