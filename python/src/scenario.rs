//! `pmu50.Scenario`: a scenario file (testbench/src/scenario.rs) run with its environment (testbench/src/sim/mod.rs) to
//! the summary `pmu50 run` prints, as Python objects.

use crate::errors::{guard, ScenarioError, SimulationError};
use pmu50_core::pmu50::Structural;
use pmu50_env::DarkCurrentReport;
use pmu50_testbench::output::{run_to_files, summary, FileOptions};
use pmu50_testbench::scenario::{Action, Scenario as RsScenario, ScenarioError as RsScenarioError};
use pmu50_testbench::sim::{
    self, KeyOffRow, KeyOnRow, PulseRow, RunResult as RsRunResult, SimOptions,
};
use pyo3::exceptions::PyOSError;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::path::{Path, PathBuf};

use crate::core::{register_dict, Outputs};
use crate::signals;

fn scenario_err(e: RsScenarioError) -> PyErr {
    match e {
        RsScenarioError::Io { .. } => PyOSError::new_err(e.to_string()),
        _ => ScenarioError::new_err(e.to_string()),
    }
}

/// One row of the per-pulse event table: the state after a key-off sampling edge.
#[pyclass(module = "pmu50", name = "Pulse", frozen, get_all)]
#[derive(Clone)]
pub struct Pulse {
    /// Edge number (the sample was taken at the end of tick `tick - 1`).
    tick: u64,
    time_ns: u64,
    cs: bool,
    cc: bool,
    hist_s: bool,
    hist_c: bool,
    cnt_r: u8,
    /// Drive interval after the edge, ticks.
    si: u16,
    /// Drive interval after the edge, milliseconds.
    si_ms: f64,
    /// Count values, sign-extended from `cnt_width`.
    cnt_s: i32,
    cnt_c: i32,
    /// FIG. 17 branch taken at this edge (`S10Expand`, ...) and FIG. 18 path.
    fig17: String,
    fig18: String,
}

/// One key-on read-out by the MPU (FIG. 12-13): counts, quadrants, θm against the true angle.
#[pyclass(module = "pmu50", name = "Readout", frozen, get_all)]
#[derive(Clone)]
pub struct Readout {
    tick: u64,
    time_ns: u64,
    cnt_s: i16,
    cnt_c: i16,
    cnt: i32,
    q1: u8,
    q2: u8,
    quadrant_diff: i32,
    equation: String,
    cnt_a: i32,
    nr: i32,
    theta1_deg: f64,
    theta_m_deg: f64,
    theta_o_deg: f64,
    theta_i_deg: f64,
    true_deg: f64,
    error_deg: f64,
    diag: bool,
    quadrant_skip: bool,
    theta_abnormal: bool,
    quadrant_mismatch: bool,
    counts_abnormal: bool,
}

/// θm tracked up to a key-off, against the true angle.
#[pyclass(module = "pmu50", name = "KeyOff", frozen, get_all)]
#[derive(Clone)]
pub struct KeyOff {
    tick: u64,
    true_deg: f64,
    theta_m_deg: f64,
    theta_o_deg: f64,
    theta_i_deg: f64,
}

/// One `[expect]` check of the scenario.
#[pyclass(module = "pmu50", name = "Check", frozen, get_all)]
#[derive(Clone)]
pub struct Check {
    name: String,
    ok: bool,
    detail: String,
}

/// Dark-current figures of the key-off time: rail on-times, Vs2 duty, charge, average current.
#[pyclass(module = "pmu50", name = "DarkCurrent", frozen, get_all)]
#[derive(Clone)]
pub struct DarkCurrent {
    key_off_ns: u64,
    vm_on_ns: u64,
    vs1_on_ns: u64,
    vs2_on_ns: u64,
    vp_on_ns: u64,
    /// vs2_on_ns / key_off_ns; None without key-off time.
    vs2_duty: Option<f64>,
    charge_uc: f64,
    /// Average key-off current in microamperes; None without key-off time.
    avg_current_ua: Option<f64>,
}

/// `repr` for the record classes: `Name(field=value, ...)`.
macro_rules! record_repr {
    ($t:ident, $name:literal, $($f:ident),+) => {
        #[pymethods]
        impl $t {
            fn __repr__(&self) -> String {
                let parts: Vec<String> = vec![$(format!("{}={:?}", stringify!($f), self.$f)),+];
                format!("{}({})", $name, parts.join(", "))
            }
        }
    };
}
record_repr!(
    Pulse, "Pulse", tick, time_ns, cs, cc, hist_s, hist_c, cnt_r, si, si_ms, cnt_s, cnt_c, fig17,
    fig18
);
record_repr!(
    Readout,
    "Readout",
    tick,
    time_ns,
    cnt_s,
    cnt_c,
    cnt,
    q1,
    q2,
    quadrant_diff,
    equation,
    cnt_a,
    nr,
    theta1_deg,
    theta_m_deg,
    true_deg,
    error_deg,
    diag,
    quadrant_skip,
    theta_abnormal
);
record_repr!(
    KeyOff,
    "KeyOff",
    tick,
    true_deg,
    theta_m_deg,
    theta_o_deg,
    theta_i_deg
);
record_repr!(Check, "Check", name, ok, detail);
record_repr!(
    DarkCurrent,
    "DarkCurrent",
    key_off_ns,
    vm_on_ns,
    vs1_on_ns,
    vs2_on_ns,
    vp_on_ns,
    vs2_duty,
    charge_uc,
    avg_current_ua
);

fn pulse(p: &PulseRow, clock_ns: u64) -> Pulse {
    Pulse {
        tick: p.tick,
        time_ns: p.time_ns,
        cs: p.cs,
        cc: p.cc,
        hist_s: p.hist_s,
        hist_c: p.hist_c,
        cnt_r: p.cnt_r,
        si: p.si,
        si_ms: f64::from(p.si) * clock_ns as f64 / 1e6,
        cnt_s: p.cnt_s,
        cnt_c: p.cnt_c,
        fig17: format!("{:?}", p.fig17),
        fig18: format!("{:?}", p.fig18),
    }
}

fn readout(k: &KeyOnRow) -> Readout {
    let r = &k.readout;
    Readout {
        tick: k.tick,
        time_ns: k.time_ns,
        cnt_s: r.cnt_s,
        cnt_c: r.cnt_c,
        cnt: r.cnt,
        q1: r.q1,
        q2: r.q2,
        quadrant_diff: r.quadrant_diff,
        equation: format!("{:?}", r.equation),
        cnt_a: r.cnt_a,
        nr: r.nr,
        theta1_deg: r.theta1_deg,
        theta_m_deg: r.theta_m_deg,
        theta_o_deg: k.angles.theta_o_deg,
        theta_i_deg: k.angles.theta_i_deg,
        true_deg: k.true_deg,
        error_deg: k.error_deg,
        diag: k.diag,
        quadrant_skip: k.quadrant_skip,
        theta_abnormal: k.theta_abnormal,
        quadrant_mismatch: r.quadrant_mismatch,
        counts_abnormal: r.counts_abnormal,
    }
}

fn keyoff(k: &KeyOffRow) -> KeyOff {
    KeyOff {
        tick: k.tick,
        true_deg: k.true_deg,
        theta_m_deg: k.theta_m_deg,
        theta_o_deg: k.angles.theta_o_deg,
        theta_i_deg: k.angles.theta_i_deg,
    }
}

fn dark(d: &DarkCurrentReport) -> DarkCurrent {
    DarkCurrent {
        key_off_ns: d.key_off_ns,
        vm_on_ns: d.vm_on_ns,
        vs1_on_ns: d.vs1_on_ns,
        vs2_on_ns: d.vs2_on_ns,
        vp_on_ns: d.vp_on_ns,
        vs2_duty: d.vs2_duty,
        charge_uc: d.charge_uc,
        avg_current_ua: d.avg_current_ua,
    }
}

/// A run of identical pulses (run-length table of the pulse log): `first`, then `count - 1` more
/// every `stride` ticks, differing only in time.
#[pyclass(module = "pmu50", name = "PulseRun", frozen, get_all)]
#[derive(Clone)]
pub struct PulseRun {
    first: Pulse,
    count: u64,
    /// Ticks between two pulses of the run (0 when `count` is 1).
    stride: u64,
}

#[pymethods]
impl PulseRun {
    fn __repr__(&self) -> String {
        format!(
            "PulseRun(first={}, count={}, stride={})",
            self.first.__repr__(),
            self.count,
            self.stride
        )
    }
}

/// The per-pulse event table of a run, stored run-length encoded (days of parking have hundreds
/// of millions of identical pulses): a sequence of `Pulse` (`len`, index, iteration, built on
/// demand) plus its `runs`.
#[pyclass(module = "pmu50", name = "PulseTable", frozen, sequence)]
pub struct PulseTable {
    runs: Vec<PulseRun>,
    /// Index of the first pulse of each run.
    starts: Vec<u64>,
    len: u64,
    clock_ns: u64,
}

impl PulseTable {
    fn new(log: &pmu50_testbench::sim::PulseLog, clock_ns: u64) -> PulseTable {
        let mut starts = Vec::new();
        let mut runs = Vec::new();
        let mut n = 0u64;
        for r in log.runs() {
            starts.push(n);
            n += r.count;
            runs.push(PulseRun {
                first: pulse(&r.first, clock_ns),
                count: r.count,
                stride: r.stride,
            });
        }
        PulseTable {
            runs,
            starts,
            len: n,
            clock_ns,
        }
    }

    fn row(&self, i: u64) -> Pulse {
        let k = self.starts.partition_point(|&s| s <= i) - 1;
        let r = &self.runs[k];
        let tick = r.first.tick + (i - self.starts[k]) * r.stride;
        Pulse {
            tick,
            time_ns: tick * self.clock_ns,
            ..r.first.clone()
        }
    }
}

#[pymethods]
impl PulseTable {
    fn __len__(&self) -> usize {
        self.len as usize
    }

    /// `table[i]` (negative from the end) or `table[a:b:c]` (a list).
    fn __getitem__<'py>(&self, py: Python<'py>, i: &Bound<'py, PyAny>) -> PyResult<Py<PyAny>> {
        if let Ok(sl) = i.cast::<pyo3::types::PySlice>() {
            let ind = sl.indices(self.len as isize)?;
            let mut out = Vec::new();
            let mut k = ind.start;
            for _ in 0..ind.slicelength {
                out.push(self.row(k as u64));
                k += ind.step;
            }
            return Ok(out.into_pyobject(py)?.into_any().unbind());
        }
        let i: isize = i.extract()?;
        let n = self.len as i128;
        let j = if i < 0 { n + i as i128 } else { i as i128 };
        if !(0..n).contains(&j) {
            return Err(pyo3::exceptions::PyIndexError::new_err(format!(
                "pulse index {i} out of range ({} pulses)",
                self.len
            )));
        }
        Ok(self.row(j as u64).into_pyobject(py)?.into_any().unbind())
    }

    fn __iter__(slf: Bound<'_, Self>) -> PulseIter {
        PulseIter {
            table: slf.unbind(),
            next: 0,
        }
    }

    /// The run-length rows: `[PulseRun(first, count, stride)]`.
    #[getter]
    fn runs(&self) -> Vec<PulseRun> {
        self.runs.clone()
    }

    fn __repr__(&self) -> String {
        format!("PulseTable(len={}, runs={})", self.len, self.runs.len())
    }
}

/// Iterator over a `PulseTable`, one `Pulse` at a time.
#[pyclass(module = "pmu50", name = "PulseIter")]
pub struct PulseIter {
    table: Py<PulseTable>,
    next: u64,
}

#[pymethods]
impl PulseIter {
    fn __iter__(slf: PyRef<'_, Self>) -> PyRef<'_, Self> {
        slf
    }

    fn __next__(&mut self) -> Option<Pulse> {
        let t = self.table.get();
        if self.next >= t.len {
            return None;
        }
        self.next += 1;
        Some(t.row(self.next - 1))
    }
}

/// The result of `Scenario.run()`: what `pmu50 run` prints, as Python objects.
#[pyclass(module = "pmu50", name = "RunResult", frozen, get_all)]
pub struct RunResult {
    name: String,
    ticks: u64,
    clock_ns: u64,
    /// Ticks evaluated one by one (the rest were fast-forwarded or skipped).
    evaluated_ticks: u64,
    /// Ticks skipped as whole repeated key-off periods (docs/spec.md 5.1).
    skipped_ticks: u64,
    /// The per-pulse event table (one row per key-off sampling edge).
    pulses: Py<PulseTable>,
    /// Successive distinct drive intervals at key-off pulses, ms (`[expect] si_sequence_ms`).
    intervals_ms: Vec<f64>,
    /// Key-on read-outs by the MPU.
    readouts: Vec<Readout>,
    /// θm at each key-off.
    keyoffs: Vec<KeyOff>,
    /// The scenario's `[expect]` checks.
    checks: Vec<Check>,
    /// True when every check passed (`pmu50 run` exits 1 otherwise).
    passed: bool,
    dark: DarkCurrent,
    /// Outputs at the end of the run.
    final_outputs: Outputs,
    /// Registers at the end of the run, `{block: {register: value}}`.
    final_regs: Py<PyDict>,
    /// The text summary `pmu50 run` prints.
    summary: String,
    /// Written files when `run(out_dir=...)` was given, else None.
    vcd_path: Option<PathBuf>,
    gtkw_path: Option<PathBuf>,
    log_path: Option<PathBuf>,
}

#[pymethods]
impl RunResult {
    fn __repr__(&self) -> String {
        format!(
            "RunResult(name={:?}, ticks={}, pulses={}, intervals_ms={:?}, readouts={}, passed={}{})",
            self.name,
            self.ticks,
            self.pulses.get().len,
            self.intervals_ms,
            self.readouts.len(),
            if self.passed { "True" } else { "False" },
            self.vcd_path.as_ref().map(|p| format!(", vcd_path={:?}", p.display().to_string())).unwrap_or_default()
        )
    }

    fn __str__(&self) -> String {
        self.summary.clone()
    }
}

/// A validated scenario (docs/spec.md, testbench/src/scenario.rs): `Scenario.load(path)` or
/// `Scenario.from_str(text)`; invalid input raises `pmu50.ScenarioError` (a ValueError) whose
/// message is the CLI's, `file:line: `field`: what is wrong and what is valid`.
#[pyclass(module = "pmu50", name = "Scenario", frozen)]
#[derive(Clone)]
pub struct Scenario {
    sc: RsScenario,
}

#[pymethods]
impl Scenario {
    /// Read and validate a scenario file.
    #[staticmethod]
    fn load(path: PathBuf) -> PyResult<Scenario> {
        guard("Scenario.load()", || {
            RsScenario::load(&path)
                .map(|sc| Scenario { sc })
                .map_err(scenario_err)
        })
    }

    /// Validate scenario text. `filename` is used in error messages (`filename:line: ...`) and
    /// its stem is the default scenario name (the `name` key overrides it).
    #[staticmethod]
    #[pyo3(signature = (text, filename="scenario.toml"))]
    fn from_str(text: &str, filename: &str) -> PyResult<Scenario> {
        guard("Scenario.from_str()", || {
            let path = Path::new(filename);
            let stem = path
                .file_stem()
                .map(|s| s.to_string_lossy().into_owned())
                .unwrap_or_else(|| "scenario".into());
            RsScenario::parse(text, filename, &stem, path)
                .map(|sc| Scenario { sc })
                .map_err(scenario_err)
        })
    }

    /// The scenario's name (the `name` key, else the file stem): names the output files.
    #[getter]
    fn name(&self) -> &str {
        &self.sc.name
    }

    /// The `description` key ("" when absent).
    #[getter]
    fn description(&self) -> &str {
        &self.sc.description
    }

    /// Run length in ticks.
    #[getter]
    fn ticks(&self) -> u64 {
        self.sc.ticks
    }

    /// Clock period in nanoseconds (`[core] clock`).
    #[getter]
    fn clock_ns(&self) -> u64 {
        self.sc.clock_ns()
    }

    /// The `[core]` configuration (defaults filled in) as keyword arguments of `pmu50.Core`, so
    /// `Core(**sc.core)` is the scenario's core.
    #[getter]
    fn core<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        crate::config::to_dict(py, &self.sc.core)
    }

    /// The Verilog parameters of the twin for this scenario (as a vector file's `// param` lines).
    #[getter]
    fn hdl_parameters<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        crate::config::hdl_parameters(py, &self.sc.params)
    }

    /// The timeline: `[(tick, action, value), ...]`, action "ig", "vs2_fault", "vs2_pg_leak",
    /// "write" (a register write or a raw bus write) or "read"
    /// (value: bool, `(register, address, data)` for a write, the address for a read).
    fn events<'py>(&self, py: Python<'py>) -> PyResult<Vec<(u64, &'static str, Py<PyAny>)>> {
        let mut out = Vec::new();
        for e in &self.sc.events {
            let (a, v): (&'static str, Py<PyAny>) = match &e.action {
                Action::Ig(b) => ("ig", b.into_pyobject(py)?.to_owned().into_any().unbind()),
                Action::Vs2Fault(b) => (
                    "vs2_fault",
                    b.into_pyobject(py)?.to_owned().into_any().unbind(),
                ),
                Action::Vs2PgLeak(b) => (
                    "vs2_pg_leak",
                    b.into_pyobject(py)?.to_owned().into_any().unbind(),
                ),
                Action::Read { addr } => (
                    "read",
                    addr.into_pyobject(py)?.to_owned().into_any().unbind(),
                ),
                Action::Write { addr, name, value } => (
                    "write",
                    (name.clone(), *addr, *value)
                        .into_pyobject(py)?
                        .into_any()
                        .unbind(),
                ),
            };
            out.push((e.tick, a, v));
        }
        Ok(out)
    }

    /// Run the scenario. Without `out_dir` (or when the scenario says `[vcd] trace = "none"`)
    /// nothing is written and idle key-off gaps and repeated key-off periods are skipped
    /// (identical results); with it, `<out_dir>/<name>.vcd` and `.gtkw` (and `.log` when `log`) are written
    /// as by `pmu50 run`, and their paths are in the result. The GIL is released during the run.
    #[pyo3(signature = (out_dir=None, *, log=false))]
    fn run(&self, py: Python<'_>, out_dir: Option<PathBuf>, log: bool) -> PyResult<RunResult> {
        let sc = self.sc.clone();
        let done = py.detach(move || {
            guard("Scenario.run()", || {
                // A scenario with `[vcd] trace = "none"` (days of parking) writes no files, as
                // with `pmu50 run`; otherwise the level is chosen as `pmu50 run` chooses it.
                let level = pmu50_testbench::output::choose_trace(
                    &sc,
                    None,
                    None,
                    pmu50_testbench::observers::waveform::WaveFormat::Vcd,
                )
                .trace
                .level();
                let r = match (&out_dir, level) {
                    (Some(d), Some(level)) => run_to_files(
                        &sc,
                        d,
                        FileOptions {
                            log,
                            level,
                            ..FileOptions::default()
                        },
                        &mut [],
                    )
                    .map(|(r, w)| (r, Some(w)))
                    .map_err(|e| e.to_string()),
                    _ => sim::run(&sc, SimOptions::default(), &mut [])
                        .map(|r| (r, None))
                        .map_err(|e| e.to_string()),
                };
                Ok(r.map(|(r, w)| (summary(&sc, &r), r, w)))
            })
        })?;
        let (text, r, written) = done.map_err(|e| SimulationError::new_err(e.to_string()))?;
        let s = Structural {
            sync_depth: self.sc.params.sync_depth,
            cnt_width: self.sc.params.cnt_width,
        };
        guard("Scenario.run()", || result(py, s, text, &r, written))
    }

    fn __repr__(&self) -> String {
        format!(
            "Scenario(name={:?}, ticks={}, clock_ns={}, path={:?})",
            self.sc.name,
            self.sc.ticks,
            self.sc.clock_ns(),
            self.sc.path.display().to_string()
        )
    }
}

fn result(
    py: Python<'_>,
    s: Structural,
    summary: String,
    r: &RsRunResult,
    w: Option<pmu50_testbench::output::Written>,
) -> PyResult<RunResult> {
    let regs = register_dict(py, signals::register_values(&s, &r.final_regs))?;
    Ok(RunResult {
        name: r.name.clone(),
        ticks: r.ticks,
        clock_ns: r.clock_ns,
        evaluated_ticks: r.evaluated_ticks,
        skipped_ticks: r.skipped_ticks,
        pulses: Py::new(py, PulseTable::new(&r.pulses, r.clock_ns))?,
        intervals_ms: r.si_sequence_ms(),
        readouts: r.keyons.iter().map(readout).collect(),
        keyoffs: r.keyoffs.iter().map(keyoff).collect(),
        checks: r
            .checks
            .iter()
            .map(|c| Check {
                name: c.name.clone(),
                ok: c.ok,
                detail: c.detail.clone(),
            })
            .collect(),
        passed: r.passed(),
        dark: dark(&r.dark),
        final_outputs: Outputs {
            vals: signals::output_values(&s, &r.final_ports),
        },
        final_regs: regs.unbind(),
        summary,
        vcd_path: w.as_ref().map(|w| w.vcd.clone()),
        gtkw_path: w.as_ref().map(|w| w.gtkw.clone()),
        log_path: w.and_then(|w| w.log),
    })
}
