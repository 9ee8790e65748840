//! The design under test as the regression sees it: the [`Dut`] trait, a seed in flight
//! ([`InFlight`]), what a backend needs of the model's run ([`Needs`], [`Recorded`]), the
//! DUT's values in a window ([`DutTrace`]) and why a DUT cannot run ([`DutError`]).

use crate::check::Failure;
use crate::gen::Pins;
use crate::map::{MapError, RtlMap};
use crate::rtl::{Fixed, RtlError};
use pmu50_testbench::scenario::Scenario;
use std::path::Path;
use std::time::Duration;

/// Why a DUT cannot be used at all (before any seed) or could not run one seed.
#[derive(Debug, thiserror::Error)]
pub enum DutError {
    /// The RTL is bad input: it does not elaborate, lacks a contract port, ...
    #[error(transparent)]
    Rtl(#[from] RtlError),
    /// A map that does not fit the RTL (boxed: its messages carry several names).
    #[error(transparent)]
    Map(Box<MapError>),
    /// Options that do not fit the RTL (`--cnt-width` against an RTL that fixes CNT_W, ...).
    #[error("{0}")]
    Usage(String),
    /// A tool or the machine failed (a build, a process, a file).
    #[error("{0}")]
    Tool(String),
}

impl From<MapError> for DutError {
    fn from(e: MapError) -> Self {
        DutError::Map(Box::new(e))
    }
}

impl DutError {
    /// Bad input (exit 2 before any seed), rather than a failure of one seed.
    pub fn is_bad_input(&self) -> bool {
        matches!(
            self,
            DutError::Rtl(_) | DutError::Map(_) | DutError::Usage(_)
        )
    }
}

/// What a backend needs from the model's run of a seed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Needs {
    /// Nothing: the model's checks are the verdict.
    Nothing,
    /// The core's inputs of every tick, in memory ([`super::lockstep::InputRecorder`]).
    Inputs,
    /// A vector file of the run (inputs and the model's outputs, docs/spec.md 6.2).
    Vectors,
}

/// The model's recording of a seed, handed to [`Dut::send`].
pub enum Recorded {
    None,
    Inputs(Vec<u32>),
    Vectors(tempfile::NamedTempFile),
}

/// A seed handed to a DUT, whose verdict is still to come.
pub trait InFlight: Send {
    /// The verdict within `timeout` from the send: `Ok(None)` equal, `Ok(Some)` the first
    /// divergence (or a hang, or a crash), `Err` a setup failure (the seed's verdict `error`).
    fn wait(self: Box<Self>, sc: &Scenario, timeout: Duration)
        -> Result<Option<Failure>, DutError>;
}

/// A design under test.
pub trait Dut: Send + Sync {
    /// `model`, `verilator` or `icarus`.
    fn name(&self) -> &'static str;
    /// What the seed's model run must record.
    fn needs(&self) -> Needs;
    /// The parameters this RTL fixes (its top lacks them); every seed keeps them.
    fn fixed(&self) -> &Fixed;
    /// A scratch vector file for `sc` ([`Needs::Vectors`]), removed when dropped.
    fn vector_file(&self, _sc: &Scenario) -> Result<tempfile::NamedTempFile, DutError> {
        Err(DutError::Tool(format!(
            "the {} DUT takes no vector file",
            self.name()
        )))
    }
    /// Hand a seed's recording to the DUT; it may run while the caller goes on.
    fn send<'a>(&'a self, sc: &Scenario, rec: Recorded)
        -> Result<Box<dyn InFlight + 'a>, DutError>;
    /// Build the RTL for each of these parameter sets now, `jobs` builds at once (build modes:
    /// a regression's pool is built before any seed). A set that does not build is left to
    /// the seeds that draw it, which fail with the reason; an RTL that builds for none of them
    /// (or, with no sets, not for its defaults) is bad input, refused here.
    fn prebuild(&self, _sets: &[crate::gen::ParamSet], _jobs: usize) -> Result<(), DutError> {
        Ok(())
    }
    /// What the report and the repro's command line say of this DUT beside the verdicts: the
    /// knobs not drawn, the fixed values, the map.
    fn notes(&self) -> Vec<String> {
        Vec::new()
    }
    /// The code coverage of the RTL's last run of the scenario named `name` (`--code-coverage`),
    /// taken once: the counts of a seed whose RTL run ended with a verdict (not a hang or a
    /// crash).
    fn take_code_coverage(&self, _name: &str) -> Option<crate::code_cov::points::SeedCode> {
        None
    }
    /// The RTL's own waveform of ticks `window.0..=window.1` of a recording, written to `out`
    /// (VCD, every signal of the RTL, time in ns from reset), where the backend can give it:
    /// the RTL's side of a failure folder.
    fn rtl_wave(
        &self,
        _sc: &Scenario,
        _rec: Recorded,
        _window: (u64, u64),
        _out: &Path,
    ) -> Option<Result<(), DutError>> {
        None
    }
    /// The DUT's values after each edge `from..=to` of a recording (for the picture of a
    /// failure), where the backend can give them.
    fn trace(
        &self,
        _sc: &Scenario,
        _rec: Recorded,
        _from: u64,
        _to: u64,
    ) -> Option<Result<DutTrace, DutError>> {
        None
    }
}

/// A DUT's values after each edge of a window: the output ports and the mapped registers, by
/// the model's names (`si`, `drive_interval.si`).
#[derive(Clone, Debug, Default)]
pub struct DutTrace {
    /// The first edge.
    pub from: u64,
    pub signals: Vec<(String, Vec<u64>)>,
}

/// A verdict known at once.
pub struct Ready(pub Option<Failure>);

impl InFlight for Ready {
    fn wait(
        self: Box<Self>,
        _sc: &Scenario,
        _timeout: Duration,
    ) -> Result<Option<Failure>, DutError> {
        Ok(self.0)
    }
}

/// What a backend can do.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Caps {
    /// It runs an RTL (`--rtl`, the twin by default); without it the model alone is checked.
    pub rtl: bool,
    /// It compares the registers and internals a `--map` names, beside the ports.
    pub map: bool,
    /// It measures the RTL's code coverage (`--code-coverage`).
    pub code_coverage: bool,
    /// It simulates four-state values (X and Z), not only 0 and 1.
    pub four_state: bool,
}

/// What a constructor gets: the RTL's file list, the map, the pinned structural parameters and
/// whether code coverage is measured (each only when the backend's [`Caps`] allow it).
pub struct Build<'a> {
    pub list: &'a Path,
    pub map: Option<RtlMap>,
    pub pins: Pins,
    pub code_coverage: bool,
    /// The caller builds its pool next ([`Dut::prebuild`], which refuses an RTL that builds
    /// for none of the sets): the constructor need not build the RTL's defaults to find a bad
    /// RTL, a build no seed of a pool may use.
    pub pool_next: bool,
}

/// One backend: a row of the registry (`super::registry::BACKENDS`).
pub struct Backend {
    /// Its `--dut` name, recorded in `regress.json`.
    pub name: &'static str,
    /// One line for `--help` and the docs.
    pub about: &'static str,
    pub caps: Caps,
    /// The backend for a run: the RTL analysed and built, bad input refused now.
    pub make: fn(&Build<'_>) -> Result<Box<dyn Dut>, DutError>,
}
