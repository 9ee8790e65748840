//! `Core(**params)`: the scenario `[core]` table as Python keyword arguments.
//!
//! Same names, same units (durations are strings with a unit: `"2.2 ms"`), same limits and the
//! same messages as a scenario file: the CLI prints `error: FILE:LINE: `core.t2`: MESSAGE`, the
//! bindings raise `ConfigError("`core.t2`: MESSAGE")` (python/tests/test_core.py compares the two
//! through `Scenario.from_str`). The rules themselves are `CoreConfig::to_params` and
//! `Params::validate` of the core; nothing here restates a limit.

use crate::errors::ConfigError;
use pmu50_core::config::FIELDS;
use pmu50_core::{ConfigError as CoreConfigError, CoreConfig, Dur, Params};
use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyInt, PyString};

/// Which Python type a field takes.
enum Ty {
    Duration,
    Int,
    Bool,
}

fn ty(field: &str) -> Ty {
    match field {
        "adaptive" => Ty::Bool,
        "sync_depth" | "cnt_width" | "cth" => Ty::Int,
        _ => Ty::Duration,
    }
}

fn type_name(v: &Bound<'_, PyAny>) -> String {
    v.get_type()
        .name()
        .map(|n| n.to_string())
        .unwrap_or_else(|_| "?".into())
}

fn repr(v: &Bound<'_, PyAny>) -> String {
    v.repr()
        .map(|r| r.to_string())
        .unwrap_or_else(|_| "?".into())
}

/// An integer field's value as the field's Rust type, or the CLI's out-of-range message (the
/// same table and words, `pmu50_testbench::scenario::CORE_INTS`).
fn int_value(field: &'static str, v: &Bound<'_, PyAny>) -> PyResult<Result<u32, String>> {
    if v.is_instance_of::<PyBool>() || !v.is_instance_of::<PyInt>() {
        return Err(PyTypeError::new_err(format!(
            "`core.{field}` takes an integer, got {} {}",
            type_name(v),
            repr(v)
        )));
    }
    let out_of_range = |msg: String| Ok(Err(format!("`core.{field}`: {msg}")));
    match v.extract::<i64>() {
        Ok(x) => match pmu50_testbench::scenario::core_int_out_of_range(field, &x.to_string(), x) {
            Some(msg) => out_of_range(msg),
            None => Ok(Ok(x as u32)),
        },
        // Beyond any i64: out of range whatever the field.
        Err(_) => out_of_range(
            pmu50_testbench::scenario::core_int_out_of_range(field, &repr(v), i64::MAX)
                .unwrap_or_default(),
        ),
    }
}

/// Check keyword arguments against the `[core]` table and convert them to register values
/// (`TypeError` for a wrong type or name, `ConfigError` with the CLI's message for a bad value).
pub fn from_kwargs(kwargs: Option<&Bound<'_, PyDict>>) -> PyResult<(CoreConfig, Params)> {
    let mut core = CoreConfig::default();
    let mut given: Vec<&'static str> = Vec::new();
    if let Some(kw) = kwargs {
        for (k, v) in kw.iter() {
            let key: String = k.extract()?;
            let Some(&field) = FIELDS.iter().find(|f| **f == key) else {
                return Err(PyTypeError::new_err(format!(
                    "Core() got an unexpected keyword argument `{key}`; the [core] parameters are {}",
                    FIELDS.join(", ")
                )));
            };
            match ty(field) {
                Ty::Duration => {
                    if !v.is_instance_of::<PyString>() {
                        return Err(PyTypeError::new_err(format!(
                            "`core.{field}` takes a duration string with a unit, e.g. \"2.2 ms\", \"220 us\", \"10 ns\"; got {} {}",
                            type_name(&v),
                            repr(&v)
                        )));
                    }
                    let s: String = v.extract()?;
                    let d = Dur::parse(&s)
                        .map_err(|e| ConfigError::new_err(format!("`core.{field}`: {e}")))?;
                    match field {
                        "clock" => core.clock = d,
                        "pw" => core.pw = d,
                        "pi" => core.pi = d,
                        "ps" => core.ps = d,
                        "x" => core.x = d,
                        "min" => core.min = d,
                        "t1" => core.t1 = d,
                        "t2" => core.t2 = d,
                        _ => core.smp_on = d,
                    }
                }
                Ty::Bool => {
                    if !v.is_instance_of::<PyBool>() {
                        return Err(PyTypeError::new_err(format!(
                            "`core.{field}` takes True or False, got {} {}",
                            type_name(&v),
                            repr(&v)
                        )));
                    }
                    core.adaptive = v.extract()?;
                }
                Ty::Int => {
                    let x = int_value(field, &v)?.map_err(ConfigError::new_err)?;
                    match field {
                        "sync_depth" => core.sync_depth = x as u8,
                        "cnt_width" => core.cnt_width = x as u8,
                        _ => core.cth = x,
                    }
                }
            }
            given.push(field);
        }
    }
    let params = core
        .to_params()
        .map_err(|e| ConfigError::new_err(message(&e, &given)))?;
    Ok((core, params))
}

/// The message of `testbench/src/scenario.rs` for a core error, without `file:line: `: the involved field
/// given last names it (the scenario takes the one written last in the file).
fn message(e: &CoreConfigError, given: &[&'static str]) -> String {
    match given.iter().rev().find(|n| e.fields().contains(n)) {
        Some(n) => format!("`core.{n}`: {e}"),
        None => format!(
            "`core.{}`: {e} (with the default values of the fields not given)",
            e.fields().first().copied().unwrap_or("core")
        ),
    }
}

/// The configuration as keyword arguments of `Core()` (durations in their shortest exact form).
pub fn to_dict<'py>(py: Python<'py>, c: &CoreConfig) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("clock", c.clock.to_string())?;
    d.set_item("sync_depth", c.sync_depth)?;
    d.set_item("cnt_width", c.cnt_width)?;
    d.set_item("adaptive", c.adaptive)?;
    d.set_item("pw", c.pw.to_string())?;
    d.set_item("pi", c.pi.to_string())?;
    d.set_item("ps", c.ps.to_string())?;
    d.set_item("x", c.x.to_string())?;
    d.set_item("min", c.min.to_string())?;
    d.set_item("t1", c.t1.to_string())?;
    d.set_item("t2", c.t2.to_string())?;
    d.set_item("cth", c.cth)?;
    d.set_item("smp_on", c.smp_on.to_string())?;
    Ok(d)
}

/// The Verilog parameters of the twin for these register values (names of the `// param` lines
/// of a vector file, docs/spec.md 6.2).
pub fn hdl_parameters<'py>(py: Python<'py>, p: &Params) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    for (n, v) in p.hdl_parameters() {
        d.set_item(n, v)?;
    }
    Ok(d)
}
