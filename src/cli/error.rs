//! What a command ends with, and its exit code, decided here once: [`Outcome::Pass`] 0,
//! [`Outcome::Fail`] 1 (a check failed, a seed failed, the waveforms differ), a [`CliError`] 2
//! (bad input: a file, a value, an RTL; or a tool that could not run), printed as
//! `error: <what, where, what is valid>`.

use pmu50_core::Dur;
use pmu50_testbench::observers::waveform::{Level, WaveFormat};
use pmu50_testbench::output::human_bytes as human;
use std::path::PathBuf;

/// A command that ran to its end.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Outcome {
    /// Done; every check held (exit 0).
    Pass,
    /// Done; a check failed (exit 1).
    Fail,
}

impl Outcome {
    /// `Pass` when `ok`.
    pub fn of(ok: bool) -> Outcome {
        if ok {
            Outcome::Pass
        } else {
            Outcome::Fail
        }
    }
}

/// What a command returns.
pub type CmdResult = Result<Outcome, CliError>;

/// Why a command could not do its job (exit 2).
#[derive(Debug, thiserror::Error)]
pub enum CliError {
    /// A value of the command line, with what is valid.
    #[error("{0}")]
    Usage(String),
    #[error(transparent)]
    Scenario(#[from] pmu50_testbench::scenario::ScenarioError),
    #[error(transparent)]
    Output(#[from] pmu50_testbench::atomic_file::OutputError),
    #[error(transparent)]
    Run(#[from] pmu50_testbench::output::RunError),
    #[error(transparent)]
    Sim(#[from] pmu50_testbench::sim::SimError),
    #[error(transparent)]
    Limit(#[from] pmu50_testbench::limits::TooMuch),
    #[error(transparent)]
    Analysis(#[from] pmu50_testbench::analysis::AnalysisError),
    #[error(transparent)]
    Diff(#[from] pmu50_waves::diff::DiffError),
    #[error(transparent)]
    Regress(#[from] pmu50_verif::error::RegressError),
    #[error(transparent)]
    Dut(#[from] pmu50_verif::dut::DutError),
    #[error(transparent)]
    Rtl(#[from] pmu50_verif::rtl::RtlError),
    #[error(transparent)]
    FileList(#[from] pmu50_verif::filelist::FileListError),
    #[error(transparent)]
    Map(#[from] pmu50_verif::map::MapError),
    #[error(transparent)]
    Waivers(#[from] pmu50_verif::code_cov::WaiverError),
    #[error(transparent)]
    Mutation(#[from] pmu50_verif::mutation::MutationError),
    /// A failure of `pmu50 lockstep`, which the HDL scripts read as `LOCKSTEP ERROR: ...`.
    #[error("{0}")]
    Lockstep(String),
    /// Errors already printed, one per bad input (several scenarios); `what` says what was not
    /// done because of them.
    #[error("{what}")]
    Reported { what: String },
    #[error("--window {which}: {source}")]
    WindowDur {
        which: &'static str,
        #[source]
        source: pmu50_core::config::DurParseError,
    },
    #[error(
        "--window {which}: {value} is not a whole number of ticks of {clock} (scenario {file})"
    )]
    WindowTicks {
        which: &'static str,
        value: Dur,
        clock: Dur,
        file: String,
    },
    #[error("--window: END ({end}) must be after START ({start})")]
    WindowOrder { start: Dur, end: Dur },
    #[error("--window {start} {end} is outside the run of {file} (0 to {duration}); valid is 0 <= START < END <= {duration}")]
    WindowOutside {
        start: Dur,
        end: Dur,
        duration: Dur,
        file: String,
    },
    #[error("{file}: the {} at trace = {} would be about {} ({ticks} dumped ticks), above the limit of {}; {}", format.ext().to_uppercase(), level.name(), human(*estimate), human(*limit), too_large_hint(*level, *format))]
    VcdTooLarge {
        file: String,
        ticks: u64,
        estimate: u64,
        limit: u64,
        level: Level,
        format: WaveFormat,
    },
    #[error("{} would be written by two scenarios: {first} and {second} (both are named `{name}`); give one of them another `name`", path.display())]
    SameOutput {
        path: PathBuf,
        first: String,
        second: String,
        name: String,
    },
}

impl CliError {
    /// Print the error on stderr (once, by `main`), with the prefix the scripts read.
    pub fn print(&self) {
        match self {
            CliError::Reported { what } if what.is_empty() => {}
            CliError::Reported { what } => crate::cli::io::err!("error: {what}"),
            CliError::Lockstep(m) => crate::cli::io::err!("LOCKSTEP ERROR: {m}"),
            e => crate::cli::io::err!("error: {e}"),
        }
    }
}

/// What to do about a waveform over the limit: the smaller choices the run has not taken.
fn too_large_hint(level: Level, format: WaveFormat) -> String {
    let mut ways = vec!["dump part of the run with --window START END".to_string()];
    if level > Level::Ports {
        ways.push("trace fewer signals with --trace ports (or none)".into());
    } else {
        ways.push("write the summary only with --trace none".into());
    }
    if format == WaveFormat::Vcd {
        ways.push("write the compressed --format fst".into());
    }
    format!(
        "{}, or raise the limit with --max-vcd-bytes",
        ways.join(", ")
    )
}
