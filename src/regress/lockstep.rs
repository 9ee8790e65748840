//! `pmu50 regress --dut verilator`: the RTL stepped in lockstep with the core, in memory.
//!
//! The RTL is a Verilator build loaded as a shared library (hdl/tb/lockstep/dut_lib.cpp, one per
//! set of the top's Verilog parameters, built by [`super::dut::verilator`]). It runs in a DUT
//! worker, a child process of the regression (`pmu50 dut-worker`) that serves seed after seed:
//! the regression sends a seed's stimulus (the core's inputs of every tick, recorded from the
//! model's bench run by [`InputRecorder`]) and the scenario's parameters; the worker steps the
//! Rust core ([`pmu50_core::Pmu50`]) and the RTL side by side and compares, as verification
//! method 2 does (docs/verification.md): every output port after every edge, and the registers
//! and internals a `--map` names (after the edge, and before it). No vector file, no process
//! per seed.
//!
//! The worker is a process of its own so that the RTL cannot take the regression down: an RTL
//! that crashes or calls `$fatal` ends the worker, one that hangs is killed at the per-seed time
//! limit with its process group; the seed fails with the reason and the next seed gets a new
//! worker. An interrupted regression kills every worker ([`kill_children`]).
//!
//! Protocol (pipes, little-endian): request = magic `PMU6`, the kind ([`Request`], one byte),
//! path length (u32) and the library's path, the 12 HDL parameters (u64 each, in the order of
//! [`Params::hdl_parameters`]), the tick count (u64) and one packed input word (u32, [`pack`])
//! per tick (a trace request then the first and last edge, u64 each; a lockstep with code
//! coverage then the length (u32) and the path of the file the seed's counts go to, written
//! before the reply). Reply = one line of JSON,
//! a [`Reply`]. The worker writes its replies on its own
//! copy of stdout and sends the RTL's stdout (`$display`) to stderr, a log file kept to its last
//! [`LOG_KEEP`] bytes: nothing the RTL prints can be taken for a verdict.

use crate::sim::{Observer, SimError, TickView};
use pmu50_core::params::Params;
use pmu50_core::pmu50::{Inputs, Internals, Outputs, Regs};
use pmu50_core::signals::{self, Signal};
use pmu50_core::Pmu50;
use serde::{Deserialize, Serialize};
use std::collections::HashMap;
use std::ffi::{c_char, c_void, CStr};
use std::io::{Read, Write};
use std::os::fd::{AsRawFd, FromRawFd};
use std::os::unix::ffi::OsStringExt;
use std::path::{Path, PathBuf};
use std::process::{Child, ChildStdin, ChildStdout, Command, Stdio};
use std::time::{Duration, Instant};

const MAGIC: &[u8; 4] = b"PMU6";
/// Interface version of hdl/tb/lockstep/dut_lib.cpp this worker speaks.
const DUT_ABI: u32 = 3;

/// One tick's inputs as a word: `ig`, `vs2_ok`, `cmp_s`, `cmp_c`, `bus_we` in bits 0-4,
/// `bus_addr` in bits 8-15, `bus_wdata` in bits 16-31.
pub fn pack(i: &Inputs) -> u32 {
    u32::from(i.ig)
        | u32::from(i.vs2_ok) << 1
        | u32::from(i.cmp_s) << 2
        | u32::from(i.cmp_c) << 3
        | u32::from(i.bus_we) << 4
        | u32::from(i.bus_addr) << 8
        | u32::from(i.bus_wdata) << 16
}

/// The inverse of [`pack`].
pub fn unpack(w: u32) -> Inputs {
    Inputs {
        ig: w & 1 != 0,
        vs2_ok: w & 2 != 0,
        cmp_s: w & 4 != 0,
        cmp_c: w & 8 != 0,
        bus_we: w & 16 != 0,
        bus_addr: (w >> 8) as u8,
        bus_wdata: (w >> 16) as u16,
    }
}

/// Most ticks a stimulus may hold in memory (4 bytes a tick: 1 GiB).
pub const MAX_TICKS: usize = 1 << 28;

/// Records the core's inputs of every tick of a bench run: the stimulus the RTL replays.
///
/// It lets the bench skip repeated periods (docs/spec.md 5.1, key off and key on) and fills
/// them in by copying the last period's inputs ([`Observer::replay`]): the bench skips a period
/// only when its start state equals the one a period earlier with the same inputs ahead, so
/// tick `k + j·len + i` of a skipped stretch has the inputs of tick `k - len + i`
/// (`tests/regress.rs` compares the recording with one of every tick stepped).
#[derive(Default)]
pub struct InputRecorder {
    pub inputs: Vec<u32>,
}

fn too_long() -> SimError {
    SimError::observer(
        "lockstep stimulus",
        format!("more than {MAX_TICKS} ticks to hold in memory for the DUT"),
    )
}

impl Observer for InputRecorder {
    fn tick(&mut self, v: &TickView<'_>) -> Result<(), SimError> {
        if self.inputs.len() >= MAX_TICKS {
            return Err(too_long());
        }
        self.inputs.push(pack(v.inputs));
        Ok(())
    }
    fn replays_periods(&self) -> bool {
        true
    }
    fn can_replay(&self, k: u64, len: u64) -> bool {
        self.inputs.len() as u64 == k && len > 0 && k >= len
    }
    fn replay(&mut self, k: u64, periods: u64, len: u64) -> Result<(), SimError> {
        let total = periods
            .checked_mul(len)
            .and_then(|n| n.checked_add(k))
            .filter(|&n| n <= MAX_TICKS as u64)
            .ok_or_else(too_long)?;
        let (from, len) = ((k - len) as usize, len as usize);
        self.inputs.reserve((total - k) as usize);
        for _ in 0..periods {
            self.inputs.extend_from_within(from..from + len);
        }
        Ok(())
    }
}

/// A vector file's stimulus (docs/spec.md 6.2): its parameters, clock and scenario name, and the
/// inputs of every tick packed ([`pack`]). The expected-output columns are not read: the model
/// computes them.
pub struct VectorInputs {
    pub params: Params,
    pub clock_ns: u64,
    pub scenario: String,
    pub inputs: Vec<u32>,
}

/// The model's functional coverage over a vector file's inputs: every edge sampled (no
/// skipping), as the regression samples a seed.
pub fn model_coverage(v: &VectorInputs) -> Result<pmu50_coverage::Coverage, String> {
    let mut core = pmu50_core::Pmu50::new(v.params).map_err(|e| e.to_string())?;
    let mut cov = pmu50_coverage::Coverage::new(&v.params, v.clock_ns);
    for &w in &v.inputs {
        cov.step(&mut core, &unpack(w));
    }
    Ok(cov)
}

/// Read a vector file's header and input columns; an error names the line.
pub fn read_vector_inputs(path: &Path) -> Result<VectorInputs, String> {
    use std::io::BufRead;
    if let Some(kind) = crate::atomic_file::special_kind(path) {
        return Err(format!("{}: is {kind}, not a vector file", path.display()));
    }
    let f = std::fs::File::open(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let mut v = VectorInputs {
        params: Params::default(),
        clock_ns: 10_000,
        scenario: "?".into(),
        inputs: Vec::new(),
    };
    let mut ticks = None;
    for (n, line) in std::io::BufReader::new(f).lines().enumerate() {
        let line = line.map_err(|e| format!("{}:{}: {e}", path.display(), n + 1))?;
        let l = line.trim();
        if l.is_empty() {
            continue;
        }
        if let Some(h) = l.strip_prefix("//") {
            let w: Vec<&str> = h.split_whitespace().collect();
            match w.as_slice() {
                ["param", "CLOCK_US", x] => {
                    v.clock_ns = x
                        .parse::<u64>()
                        .map_err(|e| format!("{}:{}: CLOCK_US {x}: {e}", path.display(), n + 1))?
                        * 1000
                }
                ["param", name, x] => {
                    let x: u64 = x.parse().map_err(|e| {
                        format!("{}:{}: param {name} {x}: {e}", path.display(), n + 1)
                    })?;
                    v.params
                        .set_hdl_parameter(name, x)
                        .map_err(|e| format!("{}:{}: {e}", path.display(), n + 1))?;
                }
                ["clock_ns", x] => {
                    v.clock_ns = x
                        .parse()
                        .map_err(|e| format!("{}:{}: clock_ns {x}: {e}", path.display(), n + 1))?
                }
                ["scenario", x] => v.scenario = x.to_string(),
                ["ticks", x] => ticks = x.parse::<u64>().ok(),
                _ => {}
            }
            continue;
        }
        let f: Vec<u64> = l
            .split_whitespace()
            .take(signals::N_INPUTS)
            .map(|x| u64::from_str_radix(x, 16))
            .collect::<Result<_, _>>()
            .map_err(|e| format!("{}:{}: not a vector line: {e}", path.display(), n + 1))?;
        if f.len() < signals::N_INPUTS {
            return Err(format!(
                "{}:{}: {} fields, a vector line has {} inputs and the outputs",
                path.display(),
                n + 1,
                f.len(),
                signals::N_INPUTS
            ));
        }
        if v.inputs.len() >= MAX_TICKS {
            return Err(too_long().to_string());
        }
        let i = Inputs {
            ig: f[0] & 1 != 0,
            vs2_ok: f[1] & 1 != 0,
            cmp_s: f[2] & 1 != 0,
            cmp_c: f[3] & 1 != 0,
            bus_we: f[4] & 1 != 0,
            bus_addr: f[5] as u8,
            bus_wdata: f[6] as u16,
        };
        v.inputs.push(pack(&i));
    }
    if let Some(t) = ticks {
        if t != v.inputs.len() as u64 {
            return Err(format!(
                "{}: {} vector lines, the header says ticks {t}",
                path.display(),
                v.inputs.len()
            ));
        }
    }
    v.params
        .validate()
        .map_err(|e| format!("{}: illegal parameters: {e}", path.display()))?;
    Ok(v)
}

// ------------------------------------------------------------------------------------------
// the worker

type DutNew = unsafe extern "C" fn() -> *mut c_void;
type DutFree = unsafe extern "C" fn(*mut c_void);
type DutState = unsafe extern "C" fn(*mut c_void, *mut u64, *mut u64);
type DutTick = unsafe extern "C" fn(*mut c_void, *const u64, *mut u64, *mut u64, *mut u64);
type DutStep = unsafe extern "C" fn(*mut c_void, *const u64, u64) -> u64;
type DutCovWrite = unsafe extern "C" fn(*mut c_void, *const c_char) -> i32;

/// A loaded RTL library and where each of its values is in the model's signal table.
struct DutLib {
    new: DutNew,
    free: DutFree,
    state: DutState,
    tick: DutTick,
    step: DutStep,
    /// Whether the library counts code coverage, and its writer.
    has_coverage: bool,
    cov_write: DutCovWrite,
    /// The Verilog parameters the library was built with (name, value).
    params: Vec<(String, u64)>,
    /// For each mapped register of the library, its index in [`signals::REGISTERS`].
    regs: Vec<usize>,
    /// For each mapped internal, its index in [`signals::INTERNALS`].
    internals: Vec<usize>,
    _lib: libloading::Library,
}

impl DutLib {
    fn load(path: &Path) -> Result<DutLib, String> {
        // SAFETY: loading runs the library's static constructors; the library is one the
        // regression built (dut_lib.cpp with the Verilator output and runtime).
        let lib = unsafe { libloading::Library::new(path) }
            .map_err(|e| format!("cannot load {}: {e}", path.display()))?;
        // SAFETY: the symbols have the types of dut_lib.cpp (checked by its interface version).
        unsafe {
            let sym = |name: &str| -> Result<*const c_void, String> {
                let s: libloading::Symbol<*const c_void> = lib
                    .get(name.as_bytes())
                    .map_err(|e| format!("{}: no `{name}`: {e}", path.display()))?;
                Ok(*s)
            };
            let abi: unsafe extern "C" fn() -> u32 = std::mem::transmute(sym("pmu50_dut_abi")?);
            if abi() != DUT_ABI {
                return Err(format!(
                    "{}: interface version {}, this pmu50 speaks {DUT_ABI} (rebuild it)",
                    path.display(),
                    abi()
                ));
            }
            let count: unsafe extern "C" fn(u32) -> u32 =
                std::mem::transmute(sym("pmu50_dut_count")?);
            let name: unsafe extern "C" fn(u32, u32) -> *const c_char =
                std::mem::transmute(sym("pmu50_dut_name")?);
            let param: unsafe extern "C" fn(u32) -> u64 =
                std::mem::transmute(sym("pmu50_dut_param")?);
            let names = |group: u32| -> Vec<String> {
                (0..count(group))
                    .map(|i| {
                        let p = name(group, i);
                        if p.is_null() {
                            String::new()
                        } else {
                            CStr::from_ptr(p).to_string_lossy().into_owned()
                        }
                    })
                    .collect()
            };
            // The ports are in the order of the model's signal table; mapped values are a subset.
            let same = |group: u32, model: Vec<String>, what: &str| -> Result<(), String> {
                let lib_names = names(group);
                if lib_names == model {
                    Ok(())
                } else {
                    Err(format!("{}: its {what} are {lib_names:?}, the model's signal table has {model:?} (rebuild it)", path.display()))
                }
            };
            same(
                0,
                signals::INPUTS.iter().map(|s| s.name.to_string()).collect(),
                "inputs",
            )?;
            same(
                1,
                signals::OUTPUTS
                    .iter()
                    .map(|s| s.name.to_string())
                    .collect(),
                "outputs",
            )?;
            let index =
                |group: u32, model: Vec<String>, what: &str| -> Result<Vec<usize>, String> {
                    names(group)
                        .iter()
                        .map(|n| {
                            model.iter().position(|m| m == n).ok_or_else(|| {
                                format!(
                                    "{}: mapped {what} `{n}` is not in the model's signal table",
                                    path.display()
                                )
                            })
                        })
                        .collect()
                };
            let regs = index(
                2,
                signals::REGISTERS.iter().map(|s| s.path()).collect(),
                "register",
            )?;
            let internals = index(
                3,
                signals::INTERNALS
                    .iter()
                    .map(|s| s.name.to_string())
                    .collect(),
                "internal",
            )?;
            let params = names(4)
                .into_iter()
                .enumerate()
                .map(|(i, n)| (n, param(i as u32)))
                .collect();
            Ok(DutLib {
                new: std::mem::transmute::<*const c_void, DutNew>(sym("pmu50_dut_new")?),
                free: std::mem::transmute::<*const c_void, DutFree>(sym("pmu50_dut_free")?),
                state: std::mem::transmute::<*const c_void, DutState>(sym("pmu50_dut_state")?),
                tick: std::mem::transmute::<*const c_void, DutTick>(sym("pmu50_dut_tick")?),
                step: std::mem::transmute::<*const c_void, DutStep>(sym("pmu50_dut_step")?),
                has_coverage: std::mem::transmute::<*const c_void, unsafe extern "C" fn() -> u32>(
                    sym("pmu50_dut_has_coverage")?,
                )() == 1,
                cov_write: std::mem::transmute::<*const c_void, DutCovWrite>(sym(
                    "pmu50_dut_cov_write",
                )?),
                params,
                regs,
                internals,
                _lib: lib,
            })
        }
    }

    /// Whether the library was built for `p`: every parameter it was built with has `p`'s value.
    fn check_params(&self, p: &Params) -> Result<(), String> {
        let want = p.hdl_parameters();
        for (n, v) in &self.params {
            match want.iter().find(|(w, _)| w == n) {
                Some((_, pv)) if pv == v => {}
                Some((_, pv)) => {
                    return Err(format!(
                        "the library was built with {n}={v}, the seed needs {n}={pv}"
                    ))
                }
                None => {
                    return Err(format!(
                        "the library was built with parameter {n}, which the model does not have"
                    ))
                }
            }
        }
        Ok(())
    }
}

/// The parameters from their HDL values (the order of [`Params::hdl_parameters`]).
fn params_of(v: &[u64; 12]) -> Result<Params, String> {
    let mut p = Params::default();
    for ((name, _), &value) in Params::default().hdl_parameters().iter().zip(v) {
        p.set_hdl_parameter(name, value)
            .map_err(|e| e.to_string())?;
    }
    Ok(p)
}

/// One value that differs between the model and the RTL.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Mismatch {
    /// The model's path below `pmu50`: `si`, `drive_interval.si`, `internals.fig17`.
    pub signal: String,
    pub expected: u64,
    pub got: u64,
}

/// A worker's answer to one request, one JSON line on the protocol pipe (the RTL's own output
/// goes elsewhere, so nothing it prints can be taken for a verdict).
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Reply {
    /// Every compared value equal at every tick.
    Pass { ticks: u64 },
    /// The first divergent tick: after rising edge `tick` (outputs, registers), or during cycle
    /// `tick` before its edge (`combinational`: internals); every value that differs there.
    Diverged {
        tick: u64,
        combinational: bool,
        mismatches: Vec<Mismatch>,
    },
    /// `bus_rdata` after each tick of a probe.
    Probe { rdata: Vec<u64> },
    /// The RTL's values after each edge `from..=to` of a trace: for each, the output ports in
    /// table order, then the mapped registers (`regs` names them).
    Trace {
        from: u64,
        regs: Vec<String>,
        values: Vec<Vec<u64>>,
    },
    /// The request could not be run (the library, the parameters).
    Error { reason: String },
}

/// The differences between the model and the RTL in one group, at the table indices `at`.
fn compare<T>(out: &mut Vec<Mismatch>, table: &[Signal<T>], at: &[usize], model: &T, rtl: &[u64]) {
    for (&j, &g) in at.iter().zip(rtl) {
        let sig = &table[j];
        let e = (sig.get)(model);
        if e != g {
            out.push(Mismatch {
                signal: sig.path(),
                expected: e,
                got: g,
            });
        }
    }
}

/// The values of a group in the order of its signal table. Inlined with the table a constant,
/// the compiler turns each `get` into a direct load (no call through the table's pointers).
#[inline(always)]
fn words<T, const N: usize>(table: &'static [Signal<T>], model: &T) -> [u64; N] {
    std::array::from_fn(|j| (table[j].get)(model))
}

/// Whether two arrays are equal, without a call to `memcmp` (which is what `==` on arrays this
/// long becomes, at a third of the lockstep's time): one vectorised pass.
#[inline(always)]
fn same(a: &[u64], b: &[u64]) -> bool {
    a.iter().zip(b).fold(0, |acc, (x, y)| acc | (x ^ y)) == 0
}

/// The seven input values of a packed word, in the order of [`signals::INPUTS`].
fn input_words(w: u32) -> (Inputs, [u64; signals::N_INPUTS]) {
    let i = unpack(w);
    (
        i,
        [
            u64::from(i.ig),
            u64::from(i.vs2_ok),
            u64::from(i.cmp_s),
            u64::from(i.cmp_c),
            u64::from(i.bus_we),
            u64::from(i.bus_addr),
            u64::from(i.bus_wdata),
        ],
    )
}

/// A DUT handle, freed when dropped.
struct Handle<'a>(&'a DutLib, *mut c_void);

impl<'a> Handle<'a> {
    /// A DUT after reset.
    fn new(lib: &'a DutLib) -> Handle<'a> {
        // SAFETY: a function of the library, no arguments.
        Handle(lib, unsafe { (lib.new)() })
    }
}

impl Drop for Handle<'_> {
    fn drop(&mut self) {
        // SAFETY: a handle of this library's pmu50_dut_new, freed once.
        unsafe { (self.0.free)(self.1) }
    }
}

/// Verilator alone on a stimulus (the peer of `make bench`'s lockstep row): the RTL library at
/// `lib` stepped on `inputs` as a plain harness does (two evaluations a tick, the outputs
/// folded, nothing compared). Returns the fold.
pub fn replay_alone(lib: &Path, inputs: &[u32]) -> Result<u64, String> {
    let lib = DutLib::load(lib)?;
    let dut = Handle::new(&lib);
    let words: Vec<[u64; signals::N_INPUTS]> = inputs.iter().map(|&w| input_words(w).1).collect();
    let mut acc = 0xcbf2_9ce4_8422_2325u64;
    for w in &words {
        // SAFETY: an input array of the library's count (checked at load).
        acc = unsafe { (lib.step)(dut.1, w.as_ptr(), acc) };
    }
    Ok(acc)
}

/// Step the core and the RTL on `inputs`. Every output, and every mapped register and internal,
/// is compared at every tick, as whole arrays; a group that differs is compared value by value,
/// which names the divergent signals.
fn lockstep(lib: &DutLib, params: Params, inputs: &[u32]) -> Reply {
    lockstep_on(lib, &Handle::new(lib), params, inputs)
}

/// [`lockstep`], then the code coverage of the RTL's run written to `out` (a Verilator
/// coverage.dat; the library must be a build with code coverage).
fn lockstep_coverage(lib: &DutLib, params: Params, inputs: &[u32], out: &Path) -> Reply {
    if !lib.has_coverage {
        return Reply::Error {
            reason: "the library was built without code coverage (rebuild it)".into(),
        };
    }
    let Ok(path) = std::ffi::CString::new(out.as_os_str().as_encoded_bytes()) else {
        return Reply::Error {
            reason: format!("{}: a path with a NUL byte", out.display()),
        };
    };
    let dut = Handle::new(lib);
    let r = lockstep_on(lib, &dut, params, inputs);
    // SAFETY: a handle of this library and a NUL-terminated path.
    if unsafe { (lib.cov_write)(dut.1, path.as_ptr()) } != 0 {
        return Reply::Error {
            reason: "the library was built without code coverage (rebuild it)".into(),
        };
    }
    r
}

fn lockstep_on(lib: &DutLib, dut: &Handle<'_>, params: Params, inputs: &[u32]) -> Reply {
    if let Err(reason) = lib.check_params(&params) {
        return Reply::Error { reason };
    }
    let mut model = match Pmu50::new(params) {
        Ok(m) => m,
        Err(e) => {
            return Reply::Error {
                reason: format!("illegal parameters: {e}"),
            }
        }
    };
    let (nr, nx) = (lib.regs.len(), lib.internals.len());
    let mut out = [0u64; signals::N_OUTPUTS];
    let mut regs = [0u64; signals::N_REGISTERS];
    let mut x = [0u64; signals::N_INTERNALS];
    let mut expect_regs = [0u64; signals::N_REGISTERS];
    let mut expect_x = [0u64; signals::N_INTERNALS];
    let all_outputs: Vec<usize> = (0..signals::N_OUTPUTS).collect();
    let mut mm = Vec::new();
    // SAFETY: arrays of at least the library's counts (checked at load).
    unsafe { (lib.state)(dut.1, out.as_mut_ptr(), regs.as_mut_ptr()) };
    compare(&mut mm, signals::OUTPUTS, &all_outputs, &model.peek(), &out);
    compare(
        &mut mm,
        signals::REGISTERS,
        &lib.regs,
        model.regs(),
        &regs[..nr],
    );
    if !mm.is_empty() {
        return Reply::Diverged {
            tick: 0,
            combinational: false,
            mismatches: mm,
        };
    }
    for (k, &w) in inputs.iter().enumerate() {
        let k = k as u64;
        let (i, word) = input_words(w);
        // SAFETY: arrays of at least the library's counts (checked at load).
        unsafe {
            (lib.tick)(
                dut.1,
                word.as_ptr(),
                x.as_mut_ptr(),
                out.as_mut_ptr(),
                regs.as_mut_ptr(),
            )
        };
        // the internals are built only when the map compares some (the untraced edge is faster)
        let after = if nx > 0 {
            let step = model.step_traced(&i);
            // the mapped internals of cycle k, before edge k+1
            let all =
                words::<Internals, { signals::N_INTERNALS }>(signals::INTERNALS, &step.internals);
            for (d, &j) in expect_x.iter_mut().zip(&lib.internals) {
                *d = all[j];
            }
            if !same(&expect_x[..nx], &x[..nx]) {
                compare::<Internals>(
                    &mut mm,
                    signals::INTERNALS,
                    &lib.internals,
                    &step.internals,
                    &x[..nx],
                );
                return Reply::Diverged {
                    tick: k,
                    combinational: true,
                    mismatches: mm,
                };
            }
            step.after
        } else {
            model.step(&i)
        };
        // outputs (and mapped registers) after edge k+1
        let mut equal = same(
            &words::<Outputs, { signals::N_OUTPUTS }>(signals::OUTPUTS, &after),
            &out,
        );
        if nr > 0 {
            let all = words::<Regs, { signals::N_REGISTERS }>(signals::REGISTERS, model.regs());
            for (d, &j) in expect_regs.iter_mut().zip(&lib.regs) {
                *d = all[j];
            }
            equal &= same(&expect_regs[..nr], &regs[..nr]);
        }
        if !equal {
            compare::<Outputs>(&mut mm, signals::OUTPUTS, &all_outputs, &after, &out);
            compare::<Regs>(
                &mut mm,
                signals::REGISTERS,
                &lib.regs,
                model.regs(),
                &regs[..nr],
            );
            return Reply::Diverged {
                tick: k + 1,
                combinational: false,
                mismatches: mm,
            };
        }
    }
    Reply::Pass {
        ticks: inputs.len() as u64,
    }
}

/// Step the RTL alone on `inputs` (at most `ticks` of them), calling `each` with the edge
/// number and the outputs and mapped registers after it (edge 0: after reset).
fn step_alone(
    lib: &DutLib,
    inputs: &[u32],
    ticks: usize,
    mut each: impl FnMut(u64, &[u64], &[u64]),
) {
    let dut = Handle::new(lib);
    let (mut x, mut out, mut regs) = (
        [0u64; signals::N_INTERNALS],
        [0u64; signals::N_OUTPUTS],
        [0u64; signals::N_REGISTERS],
    );
    let nr = lib.regs.len();
    // SAFETY: arrays of at least the library's counts (checked at load).
    unsafe { (lib.state)(dut.1, out.as_mut_ptr(), regs.as_mut_ptr()) };
    each(0, &out, &regs[..nr]);
    for (k, &w) in inputs.iter().take(ticks).enumerate() {
        let (_, word) = input_words(w);
        // SAFETY: as above.
        unsafe {
            (lib.tick)(
                dut.1,
                word.as_ptr(),
                x.as_mut_ptr(),
                out.as_mut_ptr(),
                regs.as_mut_ptr(),
            )
        };
        each(k as u64 + 1, &out, &regs[..nr]);
    }
}

/// Step the RTL alone on `inputs` and return `bus_rdata` after each tick (the register bus
/// read back after reset: what an RTL without parameters fixes).
fn probe(lib: &DutLib, inputs: &[u32]) -> Reply {
    let rdata = signals::OUTPUTS
        .iter()
        .position(|s| s.name == "bus_rdata")
        .unwrap_or(0);
    let mut v = Vec::with_capacity(inputs.len());
    step_alone(lib, inputs, inputs.len(), |edge, out, _| {
        if edge > 0 {
            v.push(out[rdata]);
        }
    });
    Reply::Probe { rdata: v }
}

/// Step the RTL alone on `inputs` and return its outputs and mapped registers after each edge
/// `from..=to` (edge 0: after reset).
fn trace(lib: &DutLib, inputs: &[u32], from: u64, to: u64) -> Reply {
    let mut values = Vec::new();
    step_alone(
        lib,
        inputs,
        usize::try_from(to).unwrap_or(usize::MAX),
        |edge, out, regs| {
            if (from..=to).contains(&edge) {
                values.push(out.iter().chain(regs).copied().collect::<Vec<u64>>());
            }
        },
    );
    Reply::Trace {
        from,
        regs: lib
            .regs
            .iter()
            .map(|&j| signals::REGISTERS[j].path())
            .collect(),
        values,
    }
}

fn read_exact<R: Read>(r: &mut R, n: usize) -> std::io::Result<Vec<u8>> {
    let mut b = vec![0u8; n];
    r.read_exact(&mut b)?;
    Ok(b)
}

fn u64s(b: &[u8]) -> impl Iterator<Item = u64> + '_ {
    b.chunks_exact(8)
        .map(|c| u64::from_le_bytes(c.try_into().unwrap_or([0; 8])))
}

/// What a request asks.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Request {
    /// Step the model and the RTL side by side and compare.
    Lockstep = 0,
    /// Step the RTL alone and return `bus_rdata` after each tick.
    Probe = 1,
    /// Step the RTL alone and return its outputs and mapped registers after each edge of a
    /// window (the picture of a failure).
    Trace = 2,
    /// A lockstep, then the RTL's code coverage of the run written to a file.
    LockstepCoverage = 3,
}

/// A request as the worker read it: its kind, the library, the 12 HDL parameters, the inputs
/// and the window of a trace.
type Received = (
    Request,
    PathBuf,
    [u64; 12],
    Vec<u32>,
    (u64, u64),
    Option<PathBuf>,
);

/// `pmu50 dut-worker`: serve requests on stdin until it closes. Exit 0 at the end of the input,
/// 2 on a broken request.
pub fn worker_main() -> i32 {
    // Replies go to a copy of stdout; the RTL's own output (its $display) goes to stderr.
    // SAFETY: dup/dup2 on the process's standard descriptors.
    let proto = unsafe {
        let fd = libc::dup(1);
        if fd < 0 || libc::dup2(2, 1) < 0 {
            return 2;
        }
        std::fs::File::from_raw_fd(fd)
    };
    let mut reply = std::io::BufWriter::new(proto);
    let mut input = std::io::BufReader::with_capacity(1 << 20, std::io::stdin().lock());
    let mut libs: HashMap<PathBuf, Result<DutLib, String>> = HashMap::new();
    loop {
        let mut magic = [0u8; 4];
        match input.read_exact(&mut magic) {
            Ok(()) => {}
            Err(e) if e.kind() == std::io::ErrorKind::UnexpectedEof => return 0,
            Err(_) => return 2,
        }
        let request = (|| -> std::io::Result<Received> {
            if &magic != MAGIC {
                return Err(std::io::Error::other("not a lockstep request"));
            }
            let kind = match read_exact(&mut input, 1)?[0] {
                0 => Request::Lockstep,
                1 => Request::Probe,
                2 => Request::Trace,
                3 => Request::LockstepCoverage,
                k => return Err(std::io::Error::other(format!("unknown request kind {k}"))),
            };
            let len = u32::from_le_bytes(read_exact(&mut input, 4)?.try_into().unwrap_or([0; 4]))
                as usize;
            if len > 1 << 16 {
                return Err(std::io::Error::other("library path longer than 64 KiB"));
            }
            let path = PathBuf::from(std::ffi::OsString::from_vec(read_exact(&mut input, len)?));
            let mut hdl = [0u64; 12];
            for (d, v) in hdl.iter_mut().zip(u64s(&read_exact(&mut input, 96)?)) {
                *d = v;
            }
            let ticks = u64::from_le_bytes(read_exact(&mut input, 8)?.try_into().unwrap_or([0; 8]));
            let ticks = usize::try_from(ticks).map_err(std::io::Error::other)?;
            if ticks > MAX_TICKS {
                return Err(std::io::Error::other(format!(
                    "{ticks} ticks, at most {MAX_TICKS}"
                )));
            }
            let inputs = read_exact(&mut input, ticks * 4)?
                .chunks_exact(4)
                .map(|c| u32::from_le_bytes(c.try_into().unwrap_or([0; 4])))
                .collect();
            let window = if kind == Request::Trace {
                let w: Vec<u64> = u64s(&read_exact(&mut input, 16)?).collect();
                (w[0], w[1])
            } else {
                (0, 0)
            };
            let cov = if kind == Request::LockstepCoverage {
                let len =
                    u32::from_le_bytes(read_exact(&mut input, 4)?.try_into().unwrap_or([0; 4]))
                        as usize;
                if len > 1 << 16 {
                    return Err(std::io::Error::other("coverage path longer than 64 KiB"));
                }
                Some(PathBuf::from(std::ffi::OsString::from_vec(read_exact(
                    &mut input, len,
                )?)))
            } else {
                None
            };
            Ok((kind, path, hdl, inputs, window, cov))
        })();
        let Ok((kind, path, hdl, inputs, (from, to), cov)) = request else {
            return 2;
        };
        let answer = match (
            &*libs
                .entry(path.clone())
                .or_insert_with(|| DutLib::load(&path)),
            params_of(&hdl),
            kind,
        ) {
            (Ok(lib), _, Request::Probe) => probe(lib, &inputs),
            (Ok(lib), _, Request::Trace) => {
                trace(lib, &inputs, from, to.min(from.saturating_add(100_000)))
            }
            (Ok(lib), Ok(p), Request::Lockstep) => lockstep(lib, p, &inputs),
            (Ok(lib), Ok(p), Request::LockstepCoverage) => {
                lockstep_coverage(lib, p, &inputs, cov.as_deref().unwrap_or(Path::new("")))
            }
            (Err(e), _, _) => Reply::Error { reason: e.clone() },
            (_, Err(e), _) => Reply::Error { reason: e },
        };
        let line = serde_json::to_string(&answer)
            .unwrap_or_else(|e| format!("{{\"error\":{{\"reason\":\"{e}\"}}}}"));
        if reply
            .write_all(line.as_bytes())
            .and_then(|()| reply.write_all(b"\n"))
            .and_then(|()| reply.flush())
            .is_err()
        {
            return 0;
        }
    }
}

// ------------------------------------------------------------------------------------------
// the regression's side

/// What a worker answered for one request.
pub enum Answer {
    Reply(Reply),
    /// No reply within the time limit: the worker was killed.
    TimedOut,
    /// The worker ended without a reply: how, and the end of its stderr.
    Died(String),
}

/// Most bytes of a worker's log (the RTL's `$display` output) kept on disk and read back.
pub const LOG_KEEP: u64 = 64 * 1024;
/// A worker's log is cut back to its last [`LOG_KEEP`] bytes when it passes this size.
const LOG_LIMIT: u64 = 4 << 20;

/// The process groups of the running DUT workers and simulators, ended by the signal handler
/// of an interrupted regression ([`kill_children`]).
static CHILDREN: std::sync::Mutex<Vec<libc::pid_t>> = std::sync::Mutex::new(Vec::new());

/// Register a child process group (its leader's id) to be killed on an interrupt.
pub fn register_child(pgid: libc::pid_t) {
    CHILDREN
        .lock()
        .unwrap_or_else(|e| e.into_inner())
        .push(pgid);
}

/// Forget a child process group that has ended.
pub fn unregister_child(pgid: libc::pid_t) {
    CHILDREN
        .lock()
        .unwrap_or_else(|e| e.into_inner())
        .retain(|&p| p != pgid);
}

/// Kill every registered child process group (on SIGINT or SIGTERM, before the exit).
pub fn kill_children() {
    // try_lock: a signal can arrive while a job thread holds the lock for a moment
    for _ in 0..100 {
        if let Ok(c) = CHILDREN.try_lock() {
            for &g in c.iter() {
                // SAFETY: kill(2) with the negated id of a group a child leads.
                unsafe { libc::kill(-g, libc::SIGKILL) };
            }
            return;
        }
        std::thread::sleep(Duration::from_millis(1));
    }
}

/// The scratch folders of the running regression (vector files, worker logs), removed by
/// [`cleanup_on_signal`].
static SCRATCH: std::sync::Mutex<Vec<PathBuf>> = std::sync::Mutex::new(Vec::new());

pub fn register_scratch(p: &Path) {
    SCRATCH
        .lock()
        .unwrap_or_else(|e| e.into_inner())
        .push(p.to_path_buf());
}

pub fn unregister_scratch(p: &Path) {
    SCRATCH
        .lock()
        .unwrap_or_else(|e| e.into_inner())
        .retain(|q| q != p);
}

/// On SIGINT or SIGTERM (src/atomic_file.rs): kill every DUT worker and simulator with its
/// process group, and remove the scratch folders. An interrupted regression leaves neither.
pub fn cleanup_on_signal() {
    kill_children();
    for _ in 0..100 {
        if let Ok(s) = SCRATCH.try_lock() {
            for p in s.iter() {
                let _ = std::fs::remove_dir_all(p);
            }
            return;
        }
        std::thread::sleep(Duration::from_millis(1));
    }
}

/// The last `keep` bytes of a file, as text.
pub fn file_tail(path: &Path, keep: u64) -> String {
    use std::io::Seek;
    let Ok(mut f) = std::fs::File::open(path) else {
        return String::new();
    };
    let len = f.metadata().map_or(0, |m| m.len());
    let from = len.saturating_sub(keep);
    if f.seek(std::io::SeekFrom::Start(from)).is_err() {
        return String::new();
    }
    let mut b = Vec::new();
    let _ = f.take(keep).read_to_end(&mut b);
    String::from_utf8_lossy(&b).into_owned()
}

/// A running DUT worker.
pub struct Worker {
    child: Child,
    stdin: ChildStdin,
    stdout: ChildStdout,
    log: PathBuf,
    buf: Vec<u8>,
    /// When the last seed was sent.
    sent: Instant,
}

/// The `pmu50` executable that runs workers: `PMU50_EXE`, this one (under any name: a copy
/// renamed `pmu50-1.2` is still the command), or (when the caller is a test, bench or example
/// binary of target/<profile>/{deps,examples}/) the `pmu50` of the same target folder.
fn worker_exe() -> Result<PathBuf, String> {
    if let Some(p) = std::env::var_os("PMU50_EXE") {
        return Ok(PathBuf::from(p));
    }
    let me = std::env::current_exe().map_err(|e| format!("cannot find this executable: {e}"))?;
    let in_target = me
        .parent()
        .and_then(|d| d.file_name())
        .is_some_and(|d| d == "deps" || d == "examples");
    if me.file_stem().is_some_and(|s| s == "pmu50") || !in_target {
        return Ok(me);
    }
    let beside = |up: usize, tail: &str| me.ancestors().nth(up).map(|d| d.join(tail));
    let p = [beside(2, "pmu50"), beside(3, "release/pmu50")]
        .into_iter()
        .flatten()
        .find(|p| p.is_file())
        .unwrap_or_else(|| PathBuf::from("pmu50"));
    if p.is_file() {
        Ok(p)
    } else {
        Err(format!(
            "the DUT worker needs the pmu50 executable: {} is missing (cargo build --release)",
            p.display()
        ))
    }
}

impl Worker {
    pub fn spawn(scratch: &Path) -> Result<Worker, String> {
        Worker::spawn_exe(&worker_exe()?, scratch)
    }

    /// A worker from this executable (`EXE dut-worker`), its stderr (the RTL's output) in a log
    /// of `scratch` opened for appending, so that it can be cut back while the worker writes.
    fn spawn_exe(exe: &Path, scratch: &Path) -> Result<Worker, String> {
        use std::os::unix::process::CommandExt;
        let (file, log) = tempfile::Builder::new()
            .prefix("dut-worker.")
            .suffix(".log")
            .tempfile_in(scratch)
            .map_err(|e| format!("a log for the DUT worker in {}: {e}", scratch.display()))?
            .keep()
            .map_err(|e| format!("a log for the DUT worker: {e}"))?;
        drop(file);
        let append = std::fs::OpenOptions::new()
            .append(true)
            .open(&log)
            .map_err(|e| format!("{}: {e}", log.display()))?;
        let mut child = Command::new(exe)
            .arg("dut-worker")
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::from(append))
            .process_group(0)
            .spawn()
            .map_err(|e| format!("cannot start the DUT worker: {e}"))?;
        register_child(child.id() as libc::pid_t);
        let (Some(stdin), Some(stdout)) = (child.stdin.take(), child.stdout.take()) else {
            let _ = child.kill();
            return Err("the DUT worker has no pipes".into());
        };
        Ok(Worker {
            child,
            stdin,
            stdout,
            log,
            buf: Vec::with_capacity(4096),
            sent: Instant::now(),
        })
    }

    /// Run one request. After [`Answer::TimedOut`] or [`Answer::Died`] the worker is gone: drop it.
    pub fn run(
        &mut self,
        kind: Request,
        lib: &Path,
        params: &Params,
        inputs: &[u32],
        timeout: Duration,
    ) -> Result<Answer, String> {
        self.send(kind, lib, params, inputs);
        self.receive(timeout)
    }

    /// A trace request ([`Request::Trace`]) of the edges `from..=to`.
    pub fn trace(
        &mut self,
        lib: &Path,
        params: &Params,
        inputs: &[u32],
        from: u64,
        to: u64,
        timeout: Duration,
    ) -> Result<Answer, String> {
        self.send_with(Request::Trace, lib, params, inputs, &[from, to]);
        self.receive(timeout)
    }

    /// Hand a request to the worker; [`Worker::receive`] takes its answer. The log of the
    /// previous request is emptied.
    pub fn send(&mut self, kind: Request, lib: &Path, params: &Params, inputs: &[u32]) {
        self.send_with(kind, lib, params, inputs, &[]);
    }

    /// A lockstep whose code coverage the worker writes to `out` before its reply.
    pub fn send_coverage(&mut self, lib: &Path, params: &Params, inputs: &[u32], out: &Path) {
        let p = out.as_os_str().as_encoded_bytes();
        let mut t = Vec::with_capacity(4 + p.len());
        t.extend_from_slice(&(p.len() as u32).to_le_bytes());
        t.extend_from_slice(p);
        self.send_bytes(Request::LockstepCoverage, lib, params, inputs, &[], &t);
    }

    fn send_with(
        &mut self,
        kind: Request,
        lib: &Path,
        params: &Params,
        inputs: &[u32],
        trailer: &[u64],
    ) {
        self.send_bytes(kind, lib, params, inputs, trailer, &[]);
    }

    fn send_bytes(
        &mut self,
        kind: Request,
        lib: &Path,
        params: &Params,
        inputs: &[u32],
        trailer: &[u64],
        bytes: &[u8],
    ) {
        let _ = std::fs::OpenOptions::new()
            .write(true)
            .open(&self.log)
            .and_then(|f| f.set_len(0));
        let path = lib.as_os_str().as_encoded_bytes();
        let mut req = Vec::with_capacity(4 + 1 + 4 + path.len() + 96 + 8 + 4 * inputs.len());
        req.extend_from_slice(MAGIC);
        req.push(kind as u8);
        req.extend_from_slice(&(path.len() as u32).to_le_bytes());
        req.extend_from_slice(path);
        for (_, v) in params.hdl_parameters() {
            req.extend_from_slice(&v.to_le_bytes());
        }
        req.extend_from_slice(&(inputs.len() as u64).to_le_bytes());
        for w in inputs {
            req.extend_from_slice(&w.to_le_bytes());
        }
        for t in trailer {
            req.extend_from_slice(&t.to_le_bytes());
        }
        req.extend_from_slice(bytes);
        self.sent = Instant::now();
        // The worker reads a whole request before it works on it, so this write ends unless it
        // died (EPIPE), which `receive` reports.
        let _ = self.stdin.write_all(&req).and_then(|()| self.stdin.flush());
    }

    /// Cut the log back to its last [`LOG_KEEP`] bytes once it passes [`LOG_LIMIT`]: an RTL
    /// that prints in a loop fills no disk.
    fn bound_log(&self) {
        if std::fs::metadata(&self.log).is_ok_and(|m| m.len() > LOG_LIMIT) {
            let keep = file_tail(&self.log, LOG_KEEP);
            if let Ok(f) = std::fs::OpenOptions::new().write(true).open(&self.log) {
                let _ = f.set_len(0);
                let _ = std::fs::OpenOptions::new()
                    .append(true)
                    .open(&self.log)
                    .and_then(|mut a| a.write_all(keep.as_bytes()));
            }
        }
    }

    /// The answer to the request [`Worker::send`] gave, within `timeout` from the send (an
    /// answer already written is taken even when the caller comes late).
    pub fn receive(&mut self, timeout: Duration) -> Result<Answer, String> {
        self.buf.clear();
        let fd = self.stdout.as_raw_fd();
        loop {
            if let Some(end) = self.buf.iter().position(|&b| b == b'\n') {
                let line = &self.buf[..end];
                return match serde_json::from_slice::<Reply>(line) {
                    Ok(r) => Ok(Answer::Reply(r)),
                    Err(e) => {
                        self.kill();
                        Err(format!(
                            "the DUT worker's reply is not one of the protocol: {e}"
                        ))
                    }
                };
            }
            if self.buf.len() > 64 << 20 {
                self.kill();
                return Err("the DUT worker's reply passed 64 MiB".into());
            }
            let left = timeout.saturating_sub(self.sent.elapsed());
            let mut pfd = libc::pollfd {
                fd,
                events: libc::POLLIN,
                revents: 0,
            };
            // wake at least every 200 ms to keep the RTL's log bounded
            let ms = if left.is_zero() {
                0
            } else {
                left.as_millis().clamp(1, 200) as i32
            };
            // SAFETY: one valid pollfd.
            let r = unsafe { libc::poll(&mut pfd, 1, ms) };
            if r < 0 {
                let e = std::io::Error::last_os_error();
                if e.kind() == std::io::ErrorKind::Interrupted {
                    continue;
                }
                self.kill();
                return Err(format!("waiting for the DUT worker: {e}"));
            }
            if r == 0 {
                self.bound_log();
                if left.is_zero() {
                    self.kill();
                    return Ok(Answer::TimedOut);
                }
                continue;
            }
            let mut chunk = [0u8; 65536];
            match self.stdout.read(&mut chunk) {
                Ok(0) => return Ok(Answer::Died(self.death())),
                Ok(n) => self.buf.extend_from_slice(&chunk[..n]),
                Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
                Err(e) => {
                    self.kill();
                    return Err(format!("reading the DUT worker: {e}"));
                }
            }
        }
    }

    fn kill(&mut self) {
        let g = self.child.id() as libc::pid_t;
        // SAFETY: kill(2) with the negated id of the group the child leads.
        unsafe { libc::kill(-g, libc::SIGKILL) };
        let _ = self.child.wait();
        unregister_child(g);
    }

    /// How the worker ended, with the last lines of its stderr.
    fn death(&mut self) -> String {
        use std::os::unix::process::ExitStatusExt;
        let how = match self.child.wait() {
            Ok(s) => match (s.code(), s.signal()) {
                (Some(c), _) => format!("the DUT ended its process (exit {c})"),
                (_, Some(sig)) => format!("the DUT crashed (signal {sig})"),
                _ => "the DUT ended its process".to_string(),
            },
            Err(e) => format!("the DUT worker ended ({e})"),
        };
        self.kill();
        let log = file_tail(&self.log, LOG_KEEP);
        let tail: Vec<&str> = log.lines().filter(|l| !l.trim().is_empty()).collect();
        let tail = tail[tail.len().saturating_sub(3)..].join(" | ");
        if tail.is_empty() {
            how
        } else {
            format!("{how}: {tail}")
        }
    }
}

impl Drop for Worker {
    fn drop(&mut self) {
        self.kill();
        let _ = std::fs::remove_file(&self.log);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pack_and_unpack_are_inverse_on_every_field() {
        let i = Inputs {
            ig: true,
            vs2_ok: false,
            cmp_s: true,
            cmp_c: true,
            bus_we: true,
            bus_addr: 0xA5,
            bus_wdata: 0xBEEF,
        };
        assert_eq!(unpack(pack(&i)), i);
        let z = Inputs::default();
        assert_eq!(unpack(pack(&z)), z);
        for bit in 0..5 {
            let w = 1u32 << bit;
            assert_eq!(pack(&unpack(w)), w, "bit {bit}");
        }
    }

    /// A worker from a script just written: a test thread that forks meanwhile can hold the
    /// script open for writing a moment (ETXTBSY), so the start is tried again.
    fn spawn_fake(exe: &Path, dir: &Path) -> Worker {
        for _ in 0..200 {
            match Worker::spawn_exe(exe, dir) {
                Ok(w) => return w,
                Err(e) if e.contains("busy") => std::thread::sleep(Duration::from_millis(10)),
                Err(e) => panic!("{e}"),
            }
        }
        panic!("{} stays busy", exe.display())
    }

    fn fake_worker(dir: &Path, body: &str) -> PathBuf {
        use std::os::unix::fs::PermissionsExt;
        let p = dir.join("fake");
        let mut f = tempfile::NamedTempFile::new_in(dir).unwrap();
        f.write_all(format!("#!/bin/sh\n{body}\n").as_bytes())
            .unwrap();
        f.persist(&p).unwrap();
        std::fs::set_permissions(&p, std::fs::Permissions::from_mode(0o755)).unwrap();
        p
    }

    #[test]
    fn a_worker_that_hangs_is_killed_at_the_time_limit_with_its_group() {
        let dir = tempfile::tempdir().unwrap();
        // the worker leaves a child of its own behind, as a simulator under a script would
        let exe = fake_worker(
            dir.path(),
            "sleep 60 & echo $! > \"$(dirname \"$0\")/child.pid\"; exec sleep 60",
        );
        let mut w = spawn_fake(&exe, dir.path());
        let t = Instant::now();
        let a = w
            .run(
                Request::Lockstep,
                Path::new("/nonexistent.so"),
                &Params::default(),
                &[0; 100],
                Duration::from_millis(300),
            )
            .unwrap();
        assert!(matches!(a, Answer::TimedOut));
        assert!(t.elapsed() < Duration::from_secs(10));
        let pid: i32 = std::fs::read_to_string(dir.path().join("child.pid"))
            .unwrap()
            .trim()
            .parse()
            .unwrap();
        std::thread::sleep(Duration::from_millis(100));
        // SAFETY: signal 0 only asks whether the process exists.
        let alive = unsafe { libc::kill(pid, 0) } == 0
            && !std::fs::read_to_string(format!("/proc/{pid}/stat"))
                .unwrap_or_default()
                .contains(") Z ");
        assert!(!alive, "the worker's own child {pid} survived the kill");
    }

    #[test]
    fn an_rtl_that_prints_without_end_fills_no_disk() {
        let dir = tempfile::tempdir().unwrap();
        // 3 MiB every 50 ms on stderr (the RTL's $display, about 180 MiB in 3 s), never a reply
        let exe = fake_worker(
            dir.path(),
            "while :; do head -c 3145728 /dev/zero | tr '\\0' x >&2; sleep 0.05; done",
        );
        let mut w = spawn_fake(&exe, dir.path());
        let log = w.log.clone();
        let mut biggest = 0u64;
        w.send(
            Request::Lockstep,
            Path::new("/nonexistent.so"),
            &Params::default(),
            &[0; 10],
        );
        // the log is cut back while the worker writes, at every poll
        let a = w.receive(Duration::from_secs(3)).unwrap();
        assert!(matches!(a, Answer::TimedOut));
        biggest = biggest.max(std::fs::metadata(&log).map_or(0, |m| m.len()));
        assert!(
            biggest <= 32 << 20,
            "the log stays bounded: {biggest} bytes"
        );
        drop(w);
        assert!(!log.exists(), "a worker's log goes with it");
    }

    #[test]
    fn a_simulator_output_is_kept_to_its_last_bytes() {
        let big: Vec<u8> = (0..10_000_000u32).map(|i| b'a' + (i % 26) as u8).collect();
        let kept = file_tail_of(&big);
        assert_eq!(kept.len() as u64, LOG_KEEP);
        assert!(big.ends_with(kept.as_bytes()));
    }

    /// [`file_tail`] of bytes written to a file.
    fn file_tail_of(b: &[u8]) -> String {
        let d = tempfile::tempdir().unwrap();
        let p = d.path().join("log");
        std::fs::write(&p, b).unwrap();
        file_tail(&p, LOG_KEEP)
    }

    #[test]
    fn a_worker_that_ends_reports_how_with_its_last_words() {
        let dir = tempfile::tempdir().unwrap();
        let exe = fake_worker(
            dir.path(),
            "head -c 4 > /dev/null; echo '%Error: planted: the RTL gave up' >&2; exit 3",
        );
        let mut w = spawn_fake(&exe, dir.path());
        match w
            .run(
                Request::Lockstep,
                Path::new("/nonexistent.so"),
                &Params::default(),
                &[0; 100],
                Duration::from_secs(20),
            )
            .unwrap()
        {
            Answer::Died(how) => assert_eq!(
                how,
                "the DUT ended its process (exit 3): %Error: planted: the RTL gave up"
            ),
            _ => panic!("expected the worker's death"),
        }
    }

    #[test]
    fn parameters_come_back_from_their_hdl_values() {
        let p = Params::default();
        let v: Vec<u64> = p.hdl_parameters().iter().map(|(_, v)| *v).collect();
        assert_eq!(params_of(&v.try_into().unwrap()).unwrap(), p);
        let mut bad = [0u64; 12];
        bad[2] = 2;
        assert!(params_of(&bad).unwrap_err().contains("ADAPTIVE"));
    }
}
