//! Engineering analyses on top of the testbench, each written as CSV and SVG:
//!
//! * [`speed`]: `pmu50 speed-limit`, how fast the shaft may turn with the key off before a
//!   quadrant is skipped (docs/analysis.md);
//! * [`budget`]: `pmu50 budget`, what the key-off logic costs the battery, adaptive interval
//!   against a fixed cycle and an always-powered sensor (docs/power.md).
//!
//! Both only build scenario variants and read [`RunResult`]s; the model itself is not touched.

pub mod budget;
pub mod speed;

use crate::scenario::{Action, Event, Expect, Scenario};
use crate::sim::{self, RunResult, SimError, SimOptions};
use pmu50_env::{MotorProfile, Segment};

/// Errors of an analysis: bad input (exit 2) or a failed run.
#[derive(Debug, thiserror::Error)]
pub enum AnalysisError {
    #[error("{0}")]
    Input(String),
    #[error(transparent)]
    Sim(#[from] SimError),
    #[error(transparent)]
    Write(#[from] crate::atomic_file::OutputError),
}

/// A copy of `base` with another motor profile, timeline and length, no checks and no window.
pub fn variant(
    base: &Scenario,
    name: &str,
    start_deg: f64,
    segments: Vec<Segment>,
    events: Vec<Event>,
    ticks: u64,
) -> Result<Scenario, AnalysisError> {
    let motor = MotorProfile::new(start_deg, segments)
        .map_err(|e| AnalysisError::Input(format!("{name}: motor profile: {e}")))?;
    let mut sc = base.clone();
    sc.name = name.to_string();
    sc.motor = motor;
    sc.events = events;
    sc.ticks = ticks;
    sc.expect = Expect::default();
    sc.vcd_window = None;
    Ok(sc)
}

/// Run without observers (idle key-off gaps are fast-forwarded; results are identical).
pub fn run(sc: &Scenario) -> Result<RunResult, AnalysisError> {
    Ok(sim::run(sc, SimOptions::default(), &mut [])?)
}

/// [`run`] with an observer (a progress bar).
pub fn run_observed(
    sc: &Scenario,
    obs: &mut dyn sim::Observer,
) -> Result<RunResult, AnalysisError> {
    Ok(sim::run(sc, SimOptions::default(), &mut [obs])?)
}

/// An ignition event (made by an analysis, so it has no line in a file).
pub fn ig(tick: u64, on: bool) -> Event {
    Event {
        tick,
        action: Action::Ig(on),
        line: 0,
    }
}

/// Number of key-off samples at which both sign signals changed at once (quadrant skips).
pub fn skip_count(r: &RunResult) -> usize {
    r.pulses
        .run_boundaries()
        .filter(|(a, b)| a.cs != b.cs && a.cc != b.cc)
        .count()
}
