//! The design under test of `pmu50 regress --dut model|verilator|icarus [--rtl FILELIST] [--map
//! FILE]`: one type per backend behind the [`Dut`] trait.
//!
//! - [`model::ModelDut`]: the model alone (its checks and invariants, no RTL).
//! - [`verilator::VerilatorDut`]: an RTL with the contract ports of docs/signals.md as a
//!   Verilator library, one build per set of the top's Verilog parameters, stepped by a DUT
//!   worker in lockstep with the core on the seed's inputs held in memory ([`super::lockstep`]).
//!   A gate-level netlist is such an RTL.
//! - [`icarus::IcarusDut`]: the same RTL on Icarus Verilog, replaying the model's vector file
//!   (hdl/tb/tb_vectors.v, method 1), which compares the outputs.
//!
//! Every backend reads the RTL on its ports (and on the signals a `--map` names): other
//! instance names, other registers or no hierarchy at all are the HDL team's own. The RTL is
//! analysed once, before any seed ([`super::rtl`]): a file list that does not elaborate, a
//! missing contract port or a port of the wrong width is bad input, one error, exit 2.
//!
//! A seed's check is two calls, so that a job can run the model of the next seed while the RTL
//! runs this one: [`Dut::send`] hands the stimulus over, [`InFlight::wait`] takes the verdict
//! within the per-seed time limit. A DUT that hangs or crashes fails its seed with the reason.

pub mod icarus;
pub mod model;
pub mod verilator;

use super::check::{fig_path, Failure};
use super::lockstep::Mismatch;
use super::map::MapError;
use super::rtl::{Fixed, RtlError};
use super::{DutKind, RunSpec};
use crate::scenario::Scenario;
use crate::sim::{self, Observer, SimError, SimOptions, TickView};
use pmu50_core::drive_interval_changing_56b::{Fig17, Fig18};
use std::path::{Path, PathBuf};
use std::time::Duration;

/// Why a DUT cannot be used at all (before any seed) or could not run one seed.
#[derive(Debug, thiserror::Error)]
pub enum DutError {
    /// The RTL is bad input: it does not elaborate, lacks a contract port, ...
    #[error(transparent)]
    Rtl(#[from] RtlError),
    #[error(transparent)]
    Map(#[from] MapError),
    /// Options that do not fit the RTL (`--cnt-width` against an RTL that fixes CNT_W, ...).
    #[error("{0}")]
    Usage(String),
    /// A tool or the machine failed (a build, a process, a file).
    #[error("{0}")]
    Tool(String),
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
    /// What the report and the repro's command line say of this DUT beside the verdicts: the
    /// knobs not drawn, the fixed values, the map.
    fn notes(&self) -> Vec<String> {
        Vec::new()
    }
    /// The code coverage of the RTL's last run of the scenario named `name` (`--code-coverage`),
    /// taken once: the counts of a seed whose RTL run ended with a verdict (not a hang or a
    /// crash).
    fn take_code_coverage(&self, _name: &str) -> Option<super::code_cov::SeedCode> {
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

/// The DUT of a run spec: the model, or the RTL (`spec.rtl`, default the twin) on a simulator,
/// with an optional map. The RTL is analysed and built here: bad input fails now.
pub fn prepare(spec: &RunSpec) -> Result<Box<dyn Dut>, DutError> {
    let map = match &spec.map {
        Some(m) => Some(super::map::RtlMap::read(Path::new(m))?),
        None => None,
    };
    let list = match &spec.rtl {
        Some(f) => PathBuf::from(f),
        None => hdl_dir().join("pmu50.f"),
    };
    match spec.dut {
        DutKind::Model => {
            if spec.code_coverage {
                return Err(DutError::Usage(
                    "--code-coverage measures the code of an RTL under test: add --dut verilator"
                        .into(),
                ));
            }
            if map.is_some() {
                return Err(DutError::Usage(
                    "--map needs an RTL simulator: add --dut verilator".into(),
                ));
            }
            Ok(Box::new(model::ModelDut::default()))
        }
        DutKind::Verilator => {
            if spec.code_coverage {
                // the RTL's paths in point keys relative to the file list's folder
                if let Some(dir) = list.canonicalize().ok().as_deref().and_then(Path::parent) {
                    super::code_cov::set_base(dir);
                }
            }
            Ok(Box::new(verilator::VerilatorDut::prepare_with(
                &list,
                map,
                spec.pins,
                spec.code_coverage,
            )?))
        }
        DutKind::Icarus => {
            if spec.code_coverage {
                return Err(DutError::Usage(
                    "--code-coverage is measured by Verilator: use --dut verilator".into(),
                ));
            }
            if map.is_some() {
                return Err(DutError::Usage("--map is compared by the Verilator lockstep: use --dut verilator (the Icarus replay compares the ports)".into()));
            }
            Ok(Box::new(icarus::IcarusDut::prepare(&list, spec.pins)?))
        }
    }
}

/// The HDL kit (the twin's file list, the benches): [`crate::hdl_kit::hdl_dir`].
pub fn hdl_dir() -> PathBuf {
    crate::hdl_kit::hdl_dir()
}

/// Where builds of RTL under test go: `PMU50_CACHE_DIR`, or `$XDG_CACHE_HOME/pmu50`, or
/// `~/.cache/pmu50`, or `pmu50-cache` in the temporary folder.
pub fn cache_dir() -> PathBuf {
    let env = |k: &str| {
        std::env::var_os(k)
            .filter(|v| !v.is_empty())
            .map(PathBuf::from)
    };
    env("PMU50_CACHE_DIR")
        .or_else(|| env("XDG_CACHE_HOME").map(|p| p.join("pmu50")))
        .or_else(|| env("HOME").map(|p| p.join(".cache/pmu50")))
        .unwrap_or_else(|| std::env::temp_dir().join("pmu50-cache"))
}

/// A stable 64-bit hash (FNV-1a) for cache keys.
pub fn fnv(parts: &[&[u8]]) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for p in parts {
        for &b in p.iter().chain(&[0xffu8]) {
            h = (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3);
        }
    }
    h
}

/// Write a record of files and their hashes (a build's or an elaboration's inputs).
pub fn write_record(record: &Path, files: &[PathBuf]) {
    let mut files: Vec<&PathBuf> = files.iter().filter(|f| f.is_file()).collect();
    files.sort();
    files.dedup();
    let text: String = files
        .iter()
        .map(|f| {
            format!(
                "{:016x} {}\n",
                std::fs::read(f).map(|b| fnv(&[&b])).unwrap_or(0),
                f.display()
            )
        })
        .collect();
    let tmp = record.with_extension("tmp");
    if std::fs::write(&tmp, text).is_ok() {
        let _ = std::fs::rename(&tmp, record);
    }
}

/// Whether every file of a record still has its hash (an empty or missing record: no).
pub fn files_unchanged(record: &Path) -> bool {
    let Ok(text) = std::fs::read_to_string(record) else {
        return false;
    };
    !text.is_empty()
        && text.lines().all(|l| match l.split_once(' ') {
            Some((h, p)) => std::fs::read(p)
                .map(|b| format!("{:016x}", fnv(&[&b])) == h)
                .unwrap_or(false),
            None => false,
        })
}

/// The block of a model signal path, for the failure's `block` (the producer of an internal).
fn block_of(signal: &str) -> Option<&'static str> {
    let b = match signal.split_once('.') {
        Some(("internals", "fig17" | "fig18")) => "drive_interval",
        Some(("internals", "kon" | "koff")) => "action_switching",
        Some(("internals", "upd" | "first" | "chg_s" | "chg_c")) => "comparator_latch",
        Some(("internals", "skip_clr")) => "register_file",
        Some(("internals", _)) => return None,
        Some((b, _)) => {
            return pmu50_core::signals::REGISTERS
                .iter()
                .find(|s| s.scope == b)
                .map(|s| s.scope)
        }
        None => return None,
    };
    Some(b)
}

/// The failure of a divergence the DUT reported: the first mismatch (the report lists a port
/// before the register that drives it), the block of the first divergent register, and the
/// FIG. 17/18 path of the cycle.
pub fn divergence(sc: &Scenario, tick: u64, combinational: bool, mm: &[Mismatch]) -> Failure {
    let first = mm.first().cloned().unwrap_or(Mismatch {
        signal: "?".into(),
        expected: 0,
        got: 0,
    });
    let block = mm
        .iter()
        .find_map(|m| block_of(&m.signal))
        .unwrap_or("ports")
        .to_string();
    // internals are compared during cycle `tick`, the rest after edge `tick` (the end of cycle
    // `tick - 1`): the FIG. path of that cycle
    let cycle = if combinational {
        Some(tick)
    } else {
        tick.checked_sub(1)
    };
    let shown: Vec<String> = mm
        .iter()
        .take(8)
        .map(|m| format!("{} expected {:x} got {:x}", m.signal, m.expected, m.got))
        .collect();
    let mut f = dut_failure(
        sc,
        cycle,
        format!(
            "the RTL diverges from the model at tick {tick}{}: {}{}",
            if combinational {
                " (before its rising edge)"
            } else {
                ""
            },
            shown.join(", "),
            if mm.len() > 8 {
                format!(" (and {} more)", mm.len() - 8)
            } else {
                String::new()
            }
        ),
    );
    f.tick = tick;
    f.signal = format!("pmu50.{}", first.signal);
    f.expected = format!("0x{:x}", first.expected);
    f.got = format!("0x{:x}", first.got);
    f.block = block;
    f
}

/// A DUT failure that names no signal (a hang, a crash), at bench cycle `cycle` when known.
pub fn dut_failure(sc: &Scenario, cycle: Option<u64>, detail: String) -> Failure {
    let fig = cycle.map_or_else(|| "-".to_string(), |c| fig_at(sc, c));
    Failure {
        kind: "dut".into(),
        tick: cycle.map_or(0, |c| c + 1),
        signal: "dut".into(),
        expected: "-".into(),
        got: "-".into(),
        block: "-".into(),
        fig,
        detail,
    }
}

/// The failure of a DUT that did not finish within the time limit.
pub fn timed_out(sc: &Scenario, timeout: Duration) -> Failure {
    dut_failure(
        sc,
        None,
        format!(
            "the DUT did not finish within the per-seed time limit of {} s",
            timeout.as_secs_f64()
        ),
    )
}

/// The FIG. 17/18 path of bench cycle `cycle` (the edge at its end), from a run of the model.
pub fn fig_at(sc: &Scenario, cycle: u64) -> String {
    struct At(u64, Fig17, Fig18);
    impl Observer for At {
        fn tick(&mut self, v: &TickView<'_>) -> Result<(), SimError> {
            if v.tick == self.0 {
                self.1 = v.internals.fig17;
                self.2 = v.internals.fig18;
            }
            Ok(())
        }
    }
    let mut at = At(cycle, Fig17::Idle, Fig18::Idle);
    let mut short = sc.clone();
    short.ticks = short.ticks.min(cycle + 1);
    match sim::run(&short, SimOptions::default(), &mut [&mut at]) {
        Ok(_) => fig_path(at.1, at.2),
        Err(_) => "-".into(),
    }
}

/// Run `sc` on the model with the recording `dut` needs, then hand it to the DUT and wait: the
/// check of one scenario (a repro, a shrink try).
pub fn check(dut: &dyn Dut, sc: &Scenario, timeout: Duration) -> Result<Option<Failure>, DutError> {
    let rec = record(dut, sc)?;
    dut.send(sc, rec)?.wait(sc, timeout)
}

/// The model's run of `sc` with the recording `dut` needs (no checks).
pub fn record(dut: &dyn Dut, sc: &Scenario) -> Result<Recorded, DutError> {
    match dut.needs() {
        Needs::Nothing => Ok(Recorded::None),
        Needs::Inputs => {
            let mut rec = super::lockstep::InputRecorder::default();
            sim::run(sc, SimOptions::default(), &mut [&mut rec])
                .map_err(|e| DutError::Tool(e.to_string()))?;
            Ok(Recorded::Inputs(rec.inputs))
        }
        Needs::Vectors => {
            let vec = dut.vector_file(sc)?;
            let mut w = crate::observers::vectors::VectorWriter::new(
                std::io::BufWriter::new(vec.as_file()),
                sc,
            )
            .map_err(|e| DutError::Tool(e.to_string()))?;
            sim::run(sc, SimOptions::default(), &mut [&mut w])
                .map_err(|e| DutError::Tool(e.to_string()))?;
            use std::io::Write;
            w.into_inner()
                .flush()
                .map_err(|e| DutError::Tool(format!("{}: {e}", vec.path().display())))?;
            Ok(Recorded::Vectors(vec))
        }
    }
}
