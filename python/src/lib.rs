//! Python bindings of the PMU 50 reference model (docs/python.md), the native part of the package
//! `pmu50` (`pmu50._native`; `python/pmu50/__init__.py` re-exports it, `_native.pyi` types it).
//!
//! - [`core::Core`]: the digital core of power management unit 50 (US 2022/0041215 A1, FIG. 14 /
//!   FIG. 20, [0205]-[0414]) one rising clock edge per `step`, configured with the scenario
//!   `[core]` names and limits (docs/spec.md);
//! - [`scenario::Scenario`]: a scenario file, run with its environment to the same summary as
//!   `pmu50 run` (pulses, drive intervals, key-on read-outs, checks, dark current), optionally
//!   with the VCD;
//! - [`coverage::Coverage`]: the functional coverage model (crate `pmu50-coverage`) sampled at
//!   every edge of a `Core`, written as `coverage.json`; `merge_coverage` merges such files;
//! - the signal table ([`signals`]), taken from the core.
//!
//! Errors are Python exceptions with the messages of the CLI; no Rust panic crosses into
//! Python: every entry point runs inside [`errors::guard`], which turns a panic into `pmu50.InternalError`.

use errors::{guard, ConfigError, InternalError, ScenarioError, SimulationError};
use pyo3::prelude::*;

mod config;
mod core;
mod coverage;
mod errors;
mod scenario;
mod signals;

/// Test hook: panics inside [`guard`], to prove that a Rust panic reaches Python as
/// `pmu50.InternalError` (python/tests/test_errors.py).
#[pyfunction]
fn _panic_for_test(msg: &str) -> PyResult<()> {
    guard("_panic_for_test", || panic!("{msg}"))
}

#[pymodule]
#[pyo3(name = "_native")]
fn native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("ConfigError", py.get_type::<ConfigError>())?;
    m.add("ScenarioError", py.get_type::<ScenarioError>())?;
    m.add("SimulationError", py.get_type::<SimulationError>())?;
    m.add("InternalError", py.get_type::<InternalError>())?;
    m.add("CoverageError", py.get_type::<coverage::CoverageError>())?;
    macro_rules! add_classes {
        ($($class:ty),* $(,)?) => {
            $(m.add_class::<$class>()?;)*
        };
    }
    add_classes!(
        core::Core,
        core::Outputs,
        core::Internals,
        core::InputValues,
        core::Trace,
        core::Signal,
        coverage::Coverage
    );
    add_classes!(
        scenario::Scenario,
        scenario::RunResult,
        scenario::Pulse,
        scenario::PulseRun,
        scenario::PulseTable
    );
    add_classes!(
        scenario::Readout,
        scenario::KeyOff,
        scenario::Check,
        scenario::DarkCurrent
    );
    for f in [
        wrap_pyfunction!(coverage::merge_coverage, m)?,
        wrap_pyfunction!(coverage::export_ucis, m)?,
    ] {
        m.add_function(f)?;
    }
    m.add_function(wrap_pyfunction!(core::signal_table, m)?)?;
    m.add_function(wrap_pyfunction!(_panic_for_test, m)?)?;
    m.add("CORE_PARAMETERS", pmu50_core::config::FIELDS.to_vec())?;
    // The register map of docs/spec.md: (name, address, width, access).
    let map: Vec<(&str, u8, u8, &str)> = pmu50_core::register_file::MAP.to_vec();
    m.add("REGISTER_MAP", map)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
