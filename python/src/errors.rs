//! The module's exceptions and the guard that keeps a Rust panic out of Python.

use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use std::panic::{catch_unwind, AssertUnwindSafe};

pyo3::create_exception!(
    pmu50,
    ConfigError,
    PyValueError,
    "An illegal `[core]` parameter value (same message as the CLI, without file:line)."
);
pyo3::create_exception!(
    pmu50,
    ScenarioError,
    PyValueError,
    "An invalid scenario: the message starts with `file:line:` and names the field, as the CLI's."
);
pyo3::create_exception!(
    pmu50,
    SimulationError,
    PyRuntimeError,
    "A scenario run failed (environment model or output file), as `pmu50 run` reports it."
);
pyo3::create_exception!(
    pmu50,
    InternalError,
    PyRuntimeError,
    "A Rust panic inside the model, caught at the boundary: a bug, please report it."
);

/// The text of a panic payload.
fn panic_text(p: &(dyn std::any::Any + Send)) -> &str {
    pmu50_core::panic_payload_text(p).unwrap_or("(no message)")
}

/// Run `f`; a panic becomes `pmu50.InternalError` instead of unwinding into Python.
pub(crate) fn guard<T>(what: &str, f: impl FnOnce() -> PyResult<T>) -> PyResult<T> {
    match catch_unwind(AssertUnwindSafe(f)) {
        Ok(r) => r,
        Err(p) => Err(InternalError::new_err(format!(
            "internal error in the PMU 50 model during {what}: Rust panic `{}`; this is a bug, please report it with the inputs that led to it",
            panic_text(p.as_ref())
        ))),
    }
}
