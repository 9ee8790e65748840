//! `pmu50.Coverage`: the functional coverage model of the core (crate `pmu50-coverage`,
//! rtl_model/coverage), sampled from Python at every clock edge of a `pmu50.Core`, and
//! `pmu50.merge_coverage`, the merge of `coverage.json` files.
//!
//! The bins are the crate's, sampled by the crate's `Coverage::sample` from the core's registers
//! before and after the edge, the outputs before it, the inputs and the internals: the same
//! numbers as `pmu50 regress` and the C ABI give for the same stimulus
//! (python/tests/test_coverage.py, hdl/ffi/tests/coverage.rs). Files are written as
//! `pmu50_coverage::db::of_run(..).to_text()`, to a temporary file renamed into place.

use crate::core::{Core, Outputs, Trace};
use crate::errors::guard;
use pmu50_core::pmu50::Structural;
use pmu50_core::Params;
use pmu50_coverage::db::{self, CoverageFile, DbError};
use pmu50_coverage::{layout, Edge, Kind};
use pyo3::exceptions::{PyOSError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::path::{Path, PathBuf};

pyo3::create_exception!(
    pmu50,
    CoverageError,
    PyValueError,
    "A coverage file that cannot be read or merged (corrupt, of another model or format, a run counted twice); the message names the file and the reason."
);

/// A `DbError` as a Python exception: I/O problems as `OSError`, everything else as
/// `CoverageError` (a `ValueError`); both carry the file and the reason.
fn db_err(e: DbError) -> PyErr {
    match e {
        DbError::Io { .. } => PyOSError::new_err(e.to_string()),
        _ => CoverageError::new_err(e.to_string()),
    }
}

/// `text` into `path` through a temporary file in the same folder, renamed into place; a device,
/// a FIFO or a folder at `path` is refused (`OSError`) and left as it is.
pub(crate) fn write_atomic(path: &Path, text: &str) -> PyResult<()> {
    db::write_file(path, text).map_err(db_err)
}

/// Functional coverage of one run: every bin of the model (docs/verification.md) with its hits.
///
/// `Coverage(core)` samples the configuration of `core` (its parameter registers now, at its
/// clock); `Coverage(**config)` takes the keyword arguments of `Core()` instead. Then
/// `cov.step(core, **inputs)` is `core.step(**inputs)` with the edge sampled.
#[pyclass(module = "pmu50", name = "Coverage")]
#[derive(Clone)]
pub struct Coverage {
    cov: pmu50_coverage::Coverage,
    structural: Structural,
    clock_ns: u64,
    edges: u64,
}

impl Coverage {
    fn of(p: &Params, clock_ns: u64) -> Coverage {
        Coverage {
            cov: pmu50_coverage::Coverage::new(p, clock_ns),
            structural: Structural {
                sync_depth: p.sync_depth,
                cnt_width: p.cnt_width,
            },
            clock_ns,
            edges: 0,
        }
    }

    /// One edge of `core` with `inputs`, sampled.
    fn edge(
        &mut self,
        core: &mut Core,
        inputs: &pmu50_core::Inputs,
    ) -> PyResult<pmu50_core::TracedStep> {
        let s = core.model.structural();
        if (s.sync_depth, s.cnt_width) != (self.structural.sync_depth, self.structural.cnt_width) {
            return Err(PyValueError::new_err(format!(
                "Coverage.step(): this coverage was made for sync_depth={} cnt_width={}, the core has sync_depth={} cnt_width={}",
                self.structural.sync_depth, self.structural.cnt_width, s.sync_depth, s.cnt_width
            )));
        }
        let before = *core.model.regs();
        let t = core.model.step_traced(inputs);
        let after = *core.model.regs();
        self.cov.sample(&Edge {
            before: &before,
            after: &after,
            out: &t.before,
            inputs,
            internals: &t.internals,
        });
        self.edges += 1;
        Ok(t)
    }

    fn file(&self, run_id: &str, verdict: &str) -> PyResult<CoverageFile> {
        if run_id.is_empty() {
            return Err(PyValueError::new_err("Coverage.write(): the run id is empty; give each run a unique id, e.g. \"cocotb/test_random/7\""));
        }
        Ok(db::of_run(&self.cov, run_id, verdict))
    }
}

#[pymethods]
impl Coverage {
    #[new]
    #[pyo3(signature = (core=None, **config))]
    fn new(
        core: Option<PyRef<'_, Core>>,
        config: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<Coverage> {
        guard("Coverage()", || match core {
            Some(c) => {
                if config.is_some_and(|d| !d.is_empty()) {
                    return Err(PyValueError::new_err("Coverage(core) takes its configuration from the core: give either a core or keyword arguments, not both"));
                }
                let s = c.model.structural();
                let p = c
                    .model
                    .regs()
                    .register_file
                    .params(s.sync_depth, s.cnt_width);
                Ok(Coverage::of(&p, c.cfg.clock.0))
            }
            None => {
                let (cfg, p) = crate::config::from_kwargs(config)?;
                p.validate()
                    .map_err(|e| crate::errors::ConfigError::new_err(e.to_string()))?;
                Ok(Coverage::of(&p, cfg.clock.0))
            }
        })
    }

    /// `core.step(**inputs)` with the edge sampled: the outputs after the edge.
    #[pyo3(signature = (core, **inputs))]
    fn step(
        &mut self,
        mut core: PyRefMut<'_, Core>,
        inputs: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<Outputs> {
        guard("Coverage.step()", || {
            let i = Core::inputs(inputs)?;
            let t = self.edge(&mut core, &i)?;
            Ok(core.outputs(&t.after))
        })
    }

    /// `core.step_traced(**inputs)` with the edge sampled.
    #[pyo3(signature = (core, **inputs))]
    fn step_traced(
        &mut self,
        mut core: PyRefMut<'_, Core>,
        inputs: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<Trace> {
        guard("Coverage.step_traced()", || {
            let i = Core::inputs(inputs)?;
            let t = self.edge(&mut core, &i)?;
            Ok(core.trace(&i, &t))
        })
    }

    /// `{bin name: hits}` for every bin, in the model's order (`group.point.bin`,
    /// `cross.<name>.<a>*<b>`).
    fn hits<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        for (b, h) in layout().bins.iter().zip(self.cov.hits()) {
            d.set_item(&b.name, h)?;
        }
        Ok(d)
    }

    /// (bins hit at least once, bins that can be hit).
    fn closure(&self) -> (usize, usize) {
        let l = layout();
        let reachable = l.bins.iter().filter(|b| b.unreachable.is_none()).count();
        let hit = l
            .bins
            .iter()
            .zip(self.cov.hits())
            .filter(|(b, h)| b.unreachable.is_none() && **h > 0)
            .count();
        (hit, reachable)
    }

    /// Edges sampled so far.
    #[getter]
    fn edges(&self) -> u64 {
        self.edges
    }

    /// Clock period of the run in nanoseconds (sampled as `config.clock`).
    #[getter]
    fn clock_ns(&self) -> u64 {
        self.clock_ns
    }

    /// The text of `coverage.json` for this run (`run_id` unique across everything merged).
    #[pyo3(signature = (run_id, verdict="pass"))]
    fn to_json(&self, run_id: &str, verdict: &str) -> PyResult<String> {
        guard("Coverage.to_json()", || {
            Ok(self.file(run_id, verdict)?.to_text())
        })
    }

    /// Write `coverage.json` for this run to `path` (a temporary file renamed into place).
    #[pyo3(signature = (path, run_id, verdict="pass"))]
    fn write(&self, path: PathBuf, run_id: &str, verdict: &str) -> PyResult<()> {
        guard("Coverage.write()", || {
            write_atomic(&path, &self.file(run_id, verdict)?.to_text())
        })
    }

    /// Every bin of the model: `[(name, kind "point" | "cross", cite, unreachable reason or None)]`.
    #[staticmethod]
    fn bins() -> Vec<(String, &'static str, &'static str, Option<&'static str>)> {
        layout()
            .bins
            .iter()
            .map(|b| {
                (
                    b.name.clone(),
                    if b.kind == Kind::Point {
                        "point"
                    } else {
                        "cross"
                    },
                    b.cite,
                    b.unreachable,
                )
            })
            .collect()
    }

    /// The model's identity, carried by every coverage file (files merge only within one model).
    #[staticmethod]
    fn model() -> String {
        pmu50_coverage::model_id(layout())
    }

    fn __copy__(&self) -> Coverage {
        self.clone()
    }

    fn __repr__(&self) -> String {
        let (hit, reachable) = self.closure();
        format!(
            "Coverage(edges={}, bins hit {hit} of {reachable} reachable)",
            self.edges
        )
    }
}

/// Merge `coverage.json` files into `out` as `pmu50 merge` does: hits added bin by bin, runs
/// united. A corrupt or foreign file or a run counted twice raises `CoverageError` naming the
/// file, and nothing is written. Returns (bins hit, reachable bins, runs).
#[pyfunction]
pub fn merge_coverage(paths: Vec<PathBuf>, out: PathBuf) -> PyResult<(usize, usize, usize)> {
    guard("merge_coverage()", || {
        if paths.is_empty() {
            return Err(PyValueError::new_err("merge_coverage(): no input files"));
        }
        // An output that is one of the inputs is refused (`CoverageError`), before anything is read.
        let refs: Vec<&Path> = paths.iter().map(PathBuf::as_path).collect();
        let merged = db::merge_files(&refs, &out).map_err(db_err)?;
        let (hit, reachable) = merged.closure();
        Ok((hit, reachable, merged.runs.len()))
    })
}

/// Export a `coverage.json` file to UCIS 1.0 XML (`out`), which UCIS tools (pyucis, simulators'
/// coverage viewers) read and merge: one history node per run, one covergroup `pmu50` with a
/// coverpoint per model point (`fig17.path`) and a cross per model cross; bins that can never be
/// hit have type `ignore`. Raises `CoverageError` or `OSError` as `merge_coverage`.
#[pyfunction]
pub fn export_ucis(path: PathBuf, out: PathBuf) -> PyResult<()> {
    guard("export_ucis()", || {
        let f = CoverageFile::read(&path).map_err(db_err)?;
        write_atomic(&out, &pmu50_coverage::to_ucis_xml(&f))
    })
}
