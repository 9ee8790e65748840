//! `pmu50.Core`: the digital core, one rising clock edge per `step` (rtl_model/core/src/pmu50.rs).
//!
//! Time convention (docs/spec.md 6.1): during tick *k* the core shows the outputs after edge *k*
//! (`peek()`); `step(**inputs)` applies the inputs of tick *k* at edge *k+1* and returns the
//! outputs after it, which is exactly line *k* of a vector file (spec 6.2). All outputs are Moore,
//! so a testbench may `peek()` before it decides this tick's inputs.

use crate::config;
use crate::errors::guard;
use crate::signals;
use pmu50_core::pmu50::Structural;
use pmu50_core::{CoreConfig, Inputs, Params, Pmu50};
use pyo3::exceptions::{PyAttributeError, PyKeyError, PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyInt, PyString};

/// Values of a group of signals (outputs, internals or inputs) in table order.
type Vals = Vec<(&'static str, u8, u64)>;

fn find(vals: &Vals, name: &str) -> Option<u64> {
    vals.iter().find(|v| v.0 == name).map(|v| v.2)
}

fn fmt_vals(class: &str, vals: &Vals) -> String {
    let body: Vec<String> = vals.iter().map(|(n, _, v)| format!("{n}={v}")).collect();
    format!("{class}({})", body.join(", "))
}

/// A read-only bag of signal values with attribute access, shared by `Outputs`, `Internals` and
/// `InputValues` (each a Python class of its own, for the stubs and `isinstance`).
macro_rules! signal_bag {
    ($rust:ident, $py:literal, $doc:literal) => {
        #[doc = $doc]
        #[pyclass(module = "pmu50", name = $py, frozen)]
        #[derive(Clone)]
        pub struct $rust {
            pub(crate) vals: Vals,
        }

        #[pymethods]
        impl $rust {
            /// The value of signal `name` (an int; one-bit signals are 0 or 1).
            fn __getattr__(&self, name: &str) -> PyResult<u64> {
                find(&self.vals, name).ok_or_else(|| {
                    let names: Vec<&str> = self.vals.iter().map(|v| v.0).collect();
                    PyAttributeError::new_err(format!(
                        "{} has no signal `{name}`; signals are {}",
                        $py,
                        names.join(", ")
                    ))
                })
            }

            /// `values["cnt_s"]`: the same as `values.cnt_s`.
            fn __getitem__(&self, name: &str) -> PyResult<u64> {
                find(&self.vals, name).ok_or_else(|| PyKeyError::new_err(name.to_string()))
            }

            fn __contains__(&self, name: &str) -> bool {
                find(&self.vals, name).is_some()
            }

            fn __len__(&self) -> usize {
                self.vals.len()
            }

            fn __dir__(&self) -> Vec<&'static str> {
                let mut d: Vec<&'static str> = self.vals.iter().map(|v| v.0).collect();
                d.extend(["to_dict", "names", "values", "widths", "mismatches"]);
                d
            }

            fn __repr__(&self) -> String {
                fmt_vals($py, &self.vals)
            }

            fn __eq__(&self, other: &Bound<'_, PyAny>) -> PyResult<Py<PyAny>> {
                let py = other.py();
                if let Ok(o) = other.cast::<$rust>() {
                    return Ok(PyBool::new(py, o.get().vals == self.vals)
                        .to_owned()
                        .into_any()
                        .unbind());
                }
                if let Ok(d) = other.cast::<PyDict>() {
                    let mine = self.to_dict(py)?;
                    return Ok(PyBool::new(py, mine.eq(d)?).to_owned().into_any().unbind());
                }
                Ok(py.NotImplemented())
            }

            /// Signal values as ints, in table order (the order of `names()`).
            fn values(&self) -> Vec<u64> {
                self.vals.iter().map(|v| v.2).collect()
            }

            /// Signal names, in table order.
            fn names(&self) -> Vec<&'static str> {
                self.vals.iter().map(|v| v.0).collect()
            }

            /// `{name: width}` in table order.
            fn widths<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
                let d = PyDict::new(py);
                for (n, w, _) in &self.vals {
                    d.set_item(n, w)?;
                }
                Ok(d)
            }

            /// `{name: value}` in table order.
            fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
                let d = PyDict::new(py);
                for (n, _, v) in &self.vals {
                    d.set_item(n, v)?;
                }
                Ok(d)
            }

            /// Compare with the values of another implementation (a mapping name -> int, e.g.
            /// read from a simulator): `[(signal, expected, got), ...]` for every signal that
            /// differs, in table order; `[]` when all agree. Every signal must be present.
            fn mismatches(
                &self,
                got: &Bound<'_, PyAny>,
            ) -> PyResult<Vec<(&'static str, u64, Py<PyAny>)>> {
                let mut out = Vec::new();
                for (n, _, v) in &self.vals {
                    let g = got.get_item(*n).map_err(|_| {
                        PyKeyError::new_err(format!("mismatches(): no value for signal `{n}`"))
                    })?;
                    let same = match g.extract::<u64>() {
                        Ok(x) => x == *v,
                        Err(_) => false,
                    };
                    if !same {
                        out.push((*n, *v, g.unbind()));
                    }
                }
                Ok(out)
            }
        }
    };
}

signal_bag!(
    Outputs,
    "Outputs",
    "The 23 top-level outputs of one tick, by name (`out.si`, `out[\"si\"]`)."
);
signal_bag!(Internals, "Internals", "The combinational internals of one cycle (`kon`, `koff`, `upd`, `first`, `chg_s`, `chg_c`, `skip_clr`, `fig17`, `fig18`).");
signal_bag!(
    InputValues,
    "InputValues",
    "The 7 top-level inputs of one cycle as the core applied them."
);

/// One row of the signal table (the core's, rtl_model/core/src/signals.rs): `kind` ("input",
/// "output", "register", "internal"), `name` (registers: `block.register`, the VCD path below
/// `pmu50`), `width` in bits, `signed` (two's complement), `reset` (a register's reset value in
/// this configuration, else None), `meaning` and the `patent` paragraphs.
#[pyclass(module = "pmu50", name = "Signal", frozen, get_all)]
#[derive(Clone)]
pub struct Signal {
    kind: &'static str,
    name: String,
    width: u8,
    signed: bool,
    reset: Option<u64>,
    meaning: &'static str,
    patent: &'static str,
}

#[pymethods]
impl Signal {
    fn __repr__(&self) -> String {
        format!(
            "Signal(kind={:?}, name={:?}, width={})",
            self.kind, self.name, self.width
        )
    }
    fn __eq__(&self, o: &Bound<'_, PyAny>) -> bool {
        o.cast::<Signal>().is_ok_and(|o| {
            let o = o.get();
            (o.kind, &o.name, o.width, o.signed, o.reset)
                == (self.kind, &self.name, self.width, self.signed, self.reset)
        })
    }
}

fn table(p: &Params, kind: Option<&str>) -> PyResult<Vec<Signal>> {
    const KINDS: [&str; 4] = ["input", "output", "register", "internal"];
    if let Some(k) = kind {
        if !KINDS.contains(&k) {
            return Err(PyValueError::new_err(format!(
                "unknown signal kind `{k}`; kinds are {}",
                KINDS.join(", ")
            )));
        }
    }
    let s = Structural {
        sync_depth: p.sync_depth,
        cnt_width: p.cnt_width,
    };
    Ok(signals::table(&s, &p.hdl_parameters())
        .into_iter()
        .filter(|r| kind.is_none_or(|k| r.kind == k))
        .map(|r| Signal {
            kind: r.kind,
            name: r.name,
            width: r.width,
            signed: r.signed,
            reset: r.reset,
            meaning: r.meaning,
            patent: r.patent,
        })
        .collect())
}

/// The signal table of the core for a structural configuration (`sync_depth` and `cnt_width`
/// set the widths of `action_switching.sync`, `cnt_s` and `cnt_c`), optionally one kind only.
#[pyfunction]
#[pyo3(signature = (kind=None, *, sync_depth=2, cnt_width=16))]
pub fn signal_table(kind: Option<&str>, sync_depth: u8, cnt_width: u8) -> PyResult<Vec<Signal>> {
    let p = Params {
        sync_depth,
        cnt_width,
        ..Params::default()
    };
    p.validate()
        .map_err(|e| crate::errors::ConfigError::new_err(e.to_string()))?;
    table(&p, kind)
}

/// One edge with its detail: the outputs before and after it, the internals of the cycle and the
/// inputs as applied.
#[pyclass(module = "pmu50", name = "Trace", frozen, get_all)]
#[derive(Clone)]
pub struct Trace {
    pub(crate) tick: u64,
    pub(crate) before: Outputs,
    pub(crate) internals: Internals,
    pub(crate) after: Outputs,
    pub(crate) inputs: InputValues,
}

#[pymethods]
impl Trace {
    fn __repr__(&self) -> String {
        format!(
            "Trace(tick={}, inputs={}, internals={}, after={})",
            self.tick,
            fmt_vals("InputValues", &self.inputs.vals),
            fmt_vals("Internals", &self.internals.vals),
            fmt_vals("Outputs", &self.after.vals)
        )
    }
}

/// The digital core of PMU 50 at power-on reset, configured with the scenario `[core]` names:
/// `Core(clock="10 us", x="6.6 ms", cth=4, adaptive=True, ...)` (durations are strings with a
/// unit; defaults are the patent's). An illegal value raises `pmu50.ConfigError` (a ValueError)
/// with the CLI's message.
#[pyclass(module = "pmu50", name = "Core")]
#[derive(Clone)]
pub struct Core {
    pub(crate) model: Pmu50,
    pub(crate) cfg: CoreConfig,
    pub(crate) params: Params,
}

impl Core {
    fn s(&self) -> Structural {
        self.model.structural()
    }

    pub(crate) fn outputs(&self, o: &pmu50_core::Outputs) -> Outputs {
        Outputs {
            vals: signals::output_values(&self.s(), o),
        }
    }

    /// The Python view of the edge `t` this core has just taken with inputs `i`.
    pub(crate) fn trace(&self, i: &Inputs, t: &pmu50_core::TracedStep) -> Trace {
        Trace {
            tick: self.model.tick(),
            before: self.outputs(&t.before),
            internals: Internals {
                vals: signals::internal_values(&t.internals),
            },
            after: self.outputs(&t.after),
            inputs: InputValues {
                vals: signals::input_values(i),
            },
        }
    }

    /// Inputs from keyword arguments, each checked against its width. Unset inputs are 0.
    pub(crate) fn inputs(kw: Option<&Bound<'_, PyDict>>) -> PyResult<Inputs> {
        let mut i = Inputs::default();
        let Some(kw) = kw else { return Ok(i) };
        let table = signals::input_values(&Inputs::default());
        for (k, v) in kw.iter() {
            let name: String = k.extract()?;
            let Some(&(_, w, _)) = table.iter().find(|t| t.0 == name) else {
                let names: Vec<&str> = table.iter().map(|t| t.0).collect();
                return Err(PyTypeError::new_err(format!(
                    "step() got an unexpected keyword argument `{name}`; the inputs are {}",
                    names.join(", ")
                )));
            };
            // ints, bools, and integer-like objects (`__index__`: numpy integers, simulator values)
            let v = if v.is_instance_of::<PyInt>() {
                v
            } else if !v.is_instance_of::<PyString>() && v.hasattr("__index__")? {
                v.call_method0("__index__")?
            } else {
                return Err(PyTypeError::new_err(format!(
                    "input `{name}` takes an int or a bool, got {}",
                    v.get_type().name()?
                )));
            };
            let max = (1u64 << w) - 1;
            let x = match v.extract::<u64>() {
                Ok(x) if x <= max => x,
                _ => {
                    return Err(PyValueError::new_err(format!(
                        "input `{name}` = {} does not fit its {w} bit(s); valid is 0..={max}",
                        v.repr()?
                    )))
                }
            };
            signals::set_input(&mut i, &name, x);
        }
        Ok(i)
    }
}

/// `{block: {register: value}}` of the rows of `signals::register_values`.
pub(crate) fn register_dict<'py>(
    py: Python<'py>,
    vals: Vec<(&str, &str, u8, u64)>,
) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    for (b, n, _, v) in vals {
        let blk = match d.get_item(b)? {
            Some(x) => x.cast_into::<PyDict>()?,
            None => {
                let x = PyDict::new(py);
                d.set_item(b, &x)?;
                x
            }
        };
        blk.set_item(n, v)?;
    }
    Ok(d)
}

#[pymethods]
impl Core {
    #[new]
    #[pyo3(signature = (**params))]
    fn new(params: Option<&Bound<'_, PyDict>>) -> PyResult<Core> {
        guard("Core()", || {
            let (cfg, p) = config::from_kwargs(params)?;
            let m =
                Pmu50::new(p).map_err(|e| crate::errors::ConfigError::new_err(e.to_string()))?;
            Ok(Core {
                model: m,
                cfg,
                params: p,
            })
        })
    }

    /// One rising clock edge with these inputs (keyword arguments `ig`, `vs2_ok`, `cmp_s`,
    /// `cmp_c`, `bus_we`, `bus_addr`, `bus_wdata`; ints or bools; missing ones are 0); returns
    /// the outputs after the edge.
    #[pyo3(signature = (**inputs))]
    fn step(&mut self, inputs: Option<&Bound<'_, PyDict>>) -> PyResult<Outputs> {
        guard("Core.step()", || {
            let i = Core::inputs(inputs)?;
            let o = self.model.step(&i);
            Ok(self.outputs(&o))
        })
    }

    /// Like `step`, with the detail of the edge: outputs before and after, internals, inputs.
    #[pyo3(signature = (**inputs))]
    fn step_traced(&mut self, inputs: Option<&Bound<'_, PyDict>>) -> PyResult<Trace> {
        guard("Core.step_traced()", || {
            let i = Core::inputs(inputs)?;
            let t = self.model.step_traced(&i);
            Ok(self.trace(&i, &t))
        })
    }

    /// The outputs of the current tick (Moore: registers only; no edge is taken).
    fn peek(&self) -> PyResult<Outputs> {
        guard("Core.peek()", || Ok(self.outputs(&self.model.peek())))
    }

    /// Every register: `{block: {register: value}}` (the VCD scopes `pmu50.<block>`).
    fn regs<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let vals = guard("Core.regs()", || {
            Ok(signals::register_values(&self.s(), self.model.regs()))
        })?;
        register_dict(py, vals)
    }

    /// The register file's read mux at `addr` (0..=255) this tick, as the MPU reads it: what
    /// `bus_rdata` shows after the next edge when `bus_addr = addr` is applied now.
    fn read(&self, addr: &Bound<'_, PyAny>) -> PyResult<u16> {
        let a = match addr.extract::<u64>() {
            Ok(a) if a <= 255 && addr.is_instance_of::<PyInt>() => a as u8,
            _ => {
                return Err(PyValueError::new_err(format!(
                    "read(): address {} is not 0..=255",
                    addr.repr()?
                )))
            }
        };
        guard("Core.read()", || Ok(self.model.read(a)))
    }

    /// Back to power-on reset with the same parameters; `tick` restarts at 0.
    fn reset(&mut self) -> PyResult<()> {
        guard("Core.reset()", || {
            self.model.reset();
            Ok(())
        })
    }

    /// Number of edges taken since reset.
    #[getter]
    fn tick(&self) -> u64 {
        self.model.tick()
    }

    /// The `[core]` configuration as keyword arguments of `Core()`.
    #[getter]
    fn config<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        config::to_dict(py, &self.cfg)
    }

    /// The Verilog parameters of the twin for this configuration (`SYNC_DEPTH`, `CNT_W`,
    /// `ADAPTIVE`, `PW`, ... in ticks), as the `// param` lines of a vector file.
    #[getter]
    fn hdl_parameters<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        config::hdl_parameters(py, &self.params)
    }

    /// Clock period in nanoseconds.
    #[getter]
    fn clock_ns(&self) -> u64 {
        self.cfg.clock.0
    }

    /// The signal table of this core (names and widths from the Rust side), optionally one
    /// `kind`: "input", "output", "register" or "internal".
    #[pyo3(signature = (kind=None))]
    fn signals(&self, kind: Option<&str>) -> PyResult<Vec<Signal>> {
        table(&self.params, kind)
    }

    /// An independent copy (same registers and tick).
    fn copy(&self) -> Core {
        self.clone()
    }

    fn __copy__(&self) -> Core {
        self.clone()
    }

    fn __deepcopy__(&self, _memo: &Bound<'_, PyAny>) -> Core {
        self.clone()
    }

    fn __repr__(&self, py: Python<'_>) -> PyResult<String> {
        let cfg = config::to_dict(py, &self.cfg)?;
        let mut parts = Vec::new();
        for (k, v) in cfg.iter() {
            parts.push(format!("{}={}", k, v.repr()?));
        }
        Ok(format!(
            "Core(tick={}, {})",
            self.model.tick(),
            parts.join(", ")
        ))
    }
}
