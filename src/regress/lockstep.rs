//! `pmu50 regress --dut verilator`: the RTL stepped in lockstep with the core, in memory.
//!
//! The RTL is a Verilator build loaded as a shared library (hdl/tb/lockstep/dut_lib.cpp, one per
//! (SYNC_DEPTH, CNT_W), built by `hdl/scripts/build_lockstep.sh ... lib`). It runs in a DUT
//! worker, a child process of the regression (`pmu50 dut-worker`) that serves seed after seed:
//! the regression sends a seed's stimulus (the core's inputs of every tick, recorded from the
//! model's bench run by [`InputRecorder`]) and the scenario's parameters; the worker steps the
//! Rust core ([`pmu50_core::Pmu50`]) and the RTL side by side and compares, as verification
//! method 2 does (docs/verification.md): the internals of every cycle before its edge, every
//! output and every register after it. No vector file, no text parsing, no process per seed.
//!
//! The worker is a process of its own so that the RTL cannot take the regression down: an RTL
//! that crashes or calls `$fatal` ends the worker, one that hangs is killed at the per-seed time
//! limit with its process group; the seed fails with the reason and the next seed gets a new
//! worker.
//!
//! Protocol (pipes, little-endian): request = magic `PMU5`, path length (u32) and the library's
//! path, the 12 HDL parameters (u64 each, in the order of [`Params::hdl_parameters`]), the tick
//! count (u64) and one packed input word (u32, [`pack`]) per tick. Reply = text lines ending with
//! `END`: `PASS ticks=<n>`, or the `MISMATCH tick=<k> signal=<path> expected=<hex> got=<hex>`
//! lines of the first divergent tick and `LOCKSTEP FAIL first divergence at tick <k>`, or
//! `LOCKSTEP ERROR <reason>`. The worker writes its replies on its own copy of stdout and sends
//! the RTL's stdout (`$display`) to stderr, so the RTL cannot corrupt the protocol.

use crate::sim::{Observer, SimError, TickView};
use pmu50_core::params::Params;
use pmu50_core::pmu50::{Inputs, Internals, Outputs, Regs};
use pmu50_core::signals::{self, Signal};
use pmu50_core::Pmu50;
use std::collections::HashMap;
use std::ffi::{c_char, c_void, CStr};
use std::io::{Read, Write};
use std::os::fd::{AsRawFd, FromRawFd};
use std::path::{Path, PathBuf};
use std::process::{Child, ChildStdin, ChildStdout, Command, Stdio};
use std::time::{Duration, Instant};

const MAGIC: &[u8; 4] = b"PMU5";
/// Interface version of hdl/tb/lockstep/dut_lib.cpp this worker speaks.
const DUT_ABI: u32 = 1;
const END: &str = "END\n";

/// One tick's inputs as a word: `ig`, `vs2_ok`, `cmp_s`, `cmp_c`, `bus_we` in bits 0-4,
/// `bus_addr` in bits 8-15, `bus_wdata` in bits 16-31.
pub fn pack(i: &Inputs) -> u32 {
    u32::from(i.ig) | u32::from(i.vs2_ok) << 1 | u32::from(i.cmp_s) << 2 | u32::from(i.cmp_c) << 3 | u32::from(i.bus_we) << 4 | u32::from(i.bus_addr) << 8 | u32::from(i.bus_wdata) << 16
}

/// The inverse of [`pack`].
pub fn unpack(w: u32) -> Inputs {
    Inputs { ig: w & 1 != 0, vs2_ok: w & 2 != 0, cmp_s: w & 4 != 0, cmp_c: w & 8 != 0, bus_we: w & 16 != 0, bus_addr: (w >> 8) as u8, bus_wdata: (w >> 16) as u16 }
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
    SimError::observer("lockstep stimulus", format!("more than {MAX_TICKS} ticks to hold in memory for the DUT"))
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
        let total = periods.checked_mul(len).and_then(|n| n.checked_add(k)).filter(|&n| n <= MAX_TICKS as u64).ok_or_else(too_long)?;
        let (from, len) = ((k - len) as usize, len as usize);
        self.inputs.reserve((total - k) as usize);
        for _ in 0..periods {
            self.inputs.extend_from_within(from..from + len);
        }
        Ok(())
    }
}

// ------------------------------------------------------------------------------------------
// the worker

type DutNew = unsafe extern "C" fn(*const u64) -> *mut c_void;
type DutFree = unsafe extern "C" fn(*mut c_void);
type DutState = unsafe extern "C" fn(*mut c_void, *mut u64, *mut u64);
type DutTick = unsafe extern "C" fn(*mut c_void, *const u64, *mut u64, *mut u64, *mut u64);
type DutStep = unsafe extern "C" fn(*mut c_void, *const u64, u64) -> u64;

/// A loaded RTL library and where each model signal is in its arrays.
struct DutLib {
    new: DutNew,
    free: DutFree,
    state: DutState,
    tick: DutTick,
    step: DutStep,
    sync_depth: u8,
    cnt_width: u8,
    /// For each of the library's reset values, the index in [`Params::hdl_parameters`].
    reset: Vec<usize>,
    _lib: libloading::Library,
}

impl DutLib {
    fn load(path: &Path) -> Result<DutLib, String> {
        // SAFETY: loading runs the library's static constructors; the library is ours
        // (dut_lib.cpp with the Verilator output and runtime), built by build_lockstep.sh.
        let lib = unsafe { libloading::Library::new(path) }.map_err(|e| format!("cannot load {}: {e}", path.display()))?;
        // SAFETY: the symbols have the types of dut_lib.cpp (checked by its interface version).
        unsafe {
            let sym = |name: &str| -> Result<*const c_void, String> {
                let s: libloading::Symbol<*const c_void> = lib.get(name.as_bytes()).map_err(|e| format!("{}: no `{name}`: {e}", path.display()))?;
                Ok(*s)
            };
            let abi: unsafe extern "C" fn() -> u32 = std::mem::transmute(sym("pmu50_dut_abi")?);
            if abi() != DUT_ABI {
                return Err(format!("{}: interface version {}, this pmu50 speaks {DUT_ABI} (rebuild it)", path.display(), abi()));
            }
            let sd: unsafe extern "C" fn() -> u32 = std::mem::transmute(sym("pmu50_dut_sync_depth")?);
            let w: unsafe extern "C" fn() -> u32 = std::mem::transmute(sym("pmu50_dut_cnt_width")?);
            let count: unsafe extern "C" fn(u32) -> u32 = std::mem::transmute(sym("pmu50_dut_count")?);
            let name: unsafe extern "C" fn(u32, u32) -> *const c_char = std::mem::transmute(sym("pmu50_dut_name")?);
            let names = |group: u32| -> Vec<String> { (0..count(group)).map(|i| CStr::from_ptr(name(group, i)).to_string_lossy().into_owned()).collect() };
            // The library's arrays must be in the order of the model's signal table.
            let same = |group: u32, model: Vec<String>, what: &str| -> Result<(), String> {
                let lib_names = names(group);
                if lib_names == model {
                    Ok(())
                } else {
                    Err(format!("{}: its {what} are {lib_names:?}, the model's signal table has {model:?} (rebuild it from hdl/tb/lockstep/dut_lib.cpp)", path.display()))
                }
            };
            same(0, signals::INPUTS.iter().map(|s| s.name.to_string()).collect(), "inputs")?;
            same(1, signals::OUTPUTS.iter().map(|s| s.name.to_string()).collect(), "outputs")?;
            same(2, signals::REGISTERS.iter().map(|s| s.path()).collect(), "registers")?;
            same(3, signals::INTERNALS.iter().map(|s| s.name.to_string()).collect(), "internals")?;
            let hdl: Vec<&str> = Params::default().hdl_parameters().iter().map(|(n, _)| *n).collect();
            let reset = names(4).iter().map(|n| hdl.iter().position(|h| h == n).ok_or_else(|| format!("{}: reset value `{n}` is no HDL parameter", path.display()))).collect::<Result<_, _>>()?;
            Ok(DutLib {
                new: std::mem::transmute::<*const c_void, DutNew>(sym("pmu50_dut_new")?),
                free: std::mem::transmute::<*const c_void, DutFree>(sym("pmu50_dut_free")?),
                state: std::mem::transmute::<*const c_void, DutState>(sym("pmu50_dut_state")?),
                tick: std::mem::transmute::<*const c_void, DutTick>(sym("pmu50_dut_tick")?),
                step: std::mem::transmute::<*const c_void, DutStep>(sym("pmu50_dut_step")?),
                sync_depth: sd() as u8,
                cnt_width: w() as u8,
                reset,
                _lib: lib,
            })
        }
    }
}

/// The parameters from their HDL values (the order of [`Params::hdl_parameters`]).
fn params_of(v: &[u64; 12]) -> Result<Params, String> {
    let mut p = Params::default();
    for ((name, _), &value) in Params::default().hdl_parameters().iter().zip(v) {
        p.set_hdl_parameter(name, value).map_err(|e| e.to_string())?;
    }
    Ok(p)
}

/// The differences between the model and the RTL in one group, as `MISMATCH` lines (the
/// library's arrays are in the order of the model's signal table, checked at load).
fn compare<T>(out: &mut String, tick: u64, table: &[Signal<T>], model: &T, rtl: &[u64]) -> usize {
    let mut n = 0;
    for (sig, &g) in table.iter().zip(rtl) {
        let e = (sig.get)(model);
        if e != g {
            out.push_str(&format!("MISMATCH tick={tick} signal={} expected={e:x} got={g:x}\n", sig.path()));
            n += 1;
        }
    }
    n
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
    (i, [u64::from(i.ig), u64::from(i.vs2_ok), u64::from(i.cmp_s), u64::from(i.cmp_c), u64::from(i.bus_we), u64::from(i.bus_addr), u64::from(i.bus_wdata)])
}

/// A DUT handle, freed when dropped.
struct Handle<'a>(&'a DutLib, *mut c_void);

impl<'a> Handle<'a> {
    /// A DUT after reset with the reset values of `params`.
    fn new(lib: &'a DutLib, params: &Params) -> Handle<'a> {
        let hdl = params.hdl_parameters();
        let reset: Vec<u64> = lib.reset.iter().map(|&k| hdl[k].1).collect();
        // SAFETY: `reset` holds pmu50_dut_count(4) values.
        Handle(lib, unsafe { (lib.new)(reset.as_ptr()) })
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
pub fn replay_alone(lib: &Path, params: &Params, inputs: &[u32]) -> Result<u64, String> {
    let lib = DutLib::load(lib)?;
    let dut = Handle::new(&lib, params);
    let words: Vec<[u64; signals::N_INPUTS]> = inputs.iter().map(|&w| input_words(w).1).collect();
    let mut acc = 0xcbf2_9ce4_8422_2325u64;
    for w in &words {
        // SAFETY: an input array of the library's count (checked at load).
        acc = unsafe { (lib.step)(dut.1, w.as_ptr(), acc) };
    }
    Ok(acc)
}

/// Step the core and the RTL on `inputs`; the reply's lines (without `END`). Every output,
/// register and internal is compared at every tick, as whole arrays; a group that differs is
/// compared value by value, which names the divergent signals.
fn lockstep(lib: &DutLib, params: Params, inputs: &[u32]) -> String {
    if params.sync_depth != lib.sync_depth || params.cnt_width != lib.cnt_width {
        return format!("LOCKSTEP ERROR the library was built for SYNC_DEPTH={} CNT_W={}, the seed needs SYNC_DEPTH={} CNT_W={}\n", lib.sync_depth, lib.cnt_width, params.sync_depth, params.cnt_width);
    }
    let mut model = match Pmu50::new(params) {
        Ok(m) => m,
        Err(e) => return format!("LOCKSTEP ERROR illegal parameters: {e}\n"),
    };
    let dut = Handle::new(lib, &params);
    let mut out = [0u64; signals::N_OUTPUTS];
    let mut regs = [0u64; signals::N_REGISTERS];
    let mut x = [0u64; signals::N_INTERNALS];
    let mut report = String::new();
    // SAFETY: arrays of the library's counts (checked at load).
    unsafe { (lib.state)(dut.1, out.as_mut_ptr(), regs.as_mut_ptr()) };
    if compare(&mut report, 0, signals::OUTPUTS, &model.peek(), &out) + compare(&mut report, 0, signals::REGISTERS, model.regs(), &regs) > 0 {
        return report + "LOCKSTEP FAIL first divergence at tick 0 (after reset)\n";
    }
    for (k, &w) in inputs.iter().enumerate() {
        let k = k as u64;
        let (i, word) = input_words(w);
        // SAFETY: arrays of the library's counts (checked at load).
        unsafe { (lib.tick)(dut.1, word.as_ptr(), x.as_mut_ptr(), out.as_mut_ptr(), regs.as_mut_ptr()) };
        let step = model.step_traced(&i);
        let (internals, after) = (step.internals, step.after);
        // the internals of cycle k, before edge k+1
        if !same(&words::<Internals, { signals::N_INTERNALS }>(signals::INTERNALS, &internals), &x) && compare::<Internals>(&mut report, k, signals::INTERNALS, &internals, &x) > 0 {
            return report + &format!("LOCKSTEP FAIL first divergence at tick {k} (combinational, before rising edge {})\n", k + 1);
        }
        // outputs and registers after edge k+1
        let equal = same(&words::<Outputs, { signals::N_OUTPUTS }>(signals::OUTPUTS, &after), &out) & same(&words::<Regs, { signals::N_REGISTERS }>(signals::REGISTERS, model.regs()), &regs);
        if !equal && compare::<Outputs>(&mut report, k + 1, signals::OUTPUTS, &after, &out) + compare::<Regs>(&mut report, k + 1, signals::REGISTERS, model.regs(), &regs) > 0 {
            return report + &format!("LOCKSTEP FAIL first divergence at tick {} (after rising edge {})\n", k + 1, k + 1);
        }
    }
    format!("PASS ticks={}\n", inputs.len())
}

fn read_exact<R: Read>(r: &mut R, n: usize) -> std::io::Result<Vec<u8>> {
    let mut b = vec![0u8; n];
    r.read_exact(&mut b)?;
    Ok(b)
}

fn u64s(b: &[u8]) -> impl Iterator<Item = u64> + '_ {
    b.chunks_exact(8).map(|c| u64::from_le_bytes(c.try_into().unwrap_or([0; 8])))
}

/// `pmu50 dut-worker`: serve lockstep requests on stdin until it closes. Exit 0 at the end of
/// the input, 2 on a broken request.
pub fn worker_main() -> i32 {
    // Replies go to a copy of stdout; the RTL's own output (its $display) goes to stderr.
    // SAFETY: dup/dup2 on the process's standard descriptors.
    let proto = unsafe {
        let fd = libc::dup(1);
        if fd < 0 || libc::dup2(2, 1) < 0 {
            eprintln!("dut-worker: cannot set up its descriptors");
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
            Err(e) => {
                eprintln!("dut-worker: {e}");
                return 2;
            }
        }
        let request = (|| -> std::io::Result<(PathBuf, [u64; 12], Vec<u32>)> {
            if &magic != MAGIC {
                return Err(std::io::Error::other("not a lockstep request"));
            }
            let len = u32::from_le_bytes(read_exact(&mut input, 4)?.try_into().unwrap_or([0; 4])) as usize;
            let path = PathBuf::from(String::from_utf8_lossy(&read_exact(&mut input, len)?).into_owned());
            let mut hdl = [0u64; 12];
            for (d, v) in hdl.iter_mut().zip(u64s(&read_exact(&mut input, 96)?)) {
                *d = v;
            }
            let ticks = u64::from_le_bytes(read_exact(&mut input, 8)?.try_into().unwrap_or([0; 8]));
            let ticks = usize::try_from(ticks).map_err(std::io::Error::other)?;
            if ticks > MAX_TICKS {
                return Err(std::io::Error::other(format!("{ticks} ticks, at most {MAX_TICKS}")));
            }
            let inputs = read_exact(&mut input, ticks * 4)?.chunks_exact(4).map(|c| u32::from_le_bytes(c.try_into().unwrap_or([0; 4]))).collect();
            Ok((path, hdl, inputs))
        })();
        let (path, hdl, inputs) = match request {
            Ok(r) => r,
            Err(e) => {
                eprintln!("dut-worker: broken request: {e}");
                return 2;
            }
        };
        let text = match (&*libs.entry(path.clone()).or_insert_with(|| DutLib::load(&path)), params_of(&hdl)) {
            (Ok(lib), Ok(p)) => lockstep(lib, p, &inputs),
            (Err(e), _) => format!("LOCKSTEP ERROR {e}\n"),
            (_, Err(e)) => format!("LOCKSTEP ERROR {e}\n"),
        };
        if reply.write_all(text.as_bytes()).and_then(|()| reply.write_all(END.as_bytes())).and_then(|()| reply.flush()).is_err() {
            return 0;
        }
    }
}

// ------------------------------------------------------------------------------------------
// the regression's side

/// What a worker answered for one seed.
pub enum Answer {
    /// The reply's lines (without `END`).
    Reply(String),
    /// No reply within the time limit: the worker was killed.
    TimedOut,
    /// The worker ended without a reply: how, and the end of its stderr.
    Died(String),
}

/// A running DUT worker.
pub struct Worker {
    child: Child,
    stdin: ChildStdin,
    stdout: ChildStdout,
    stderr: tempfile::NamedTempFile,
    buf: Vec<u8>,
    /// When the last seed was sent.
    sent: Instant,
}

/// The `pmu50` executable that runs workers: this one, or the release build of this checkout
/// (when the caller is a test binary), or `PMU50_EXE`.
fn worker_exe() -> Result<PathBuf, String> {
    if let Some(p) = std::env::var_os("PMU50_EXE") {
        return Ok(PathBuf::from(p));
    }
    let me = std::env::current_exe().map_err(|e| format!("cannot find this executable: {e}"))?;
    if me.file_stem().is_some_and(|s| s == "pmu50") {
        return Ok(me);
    }
    let p = Path::new(env!("CARGO_MANIFEST_DIR")).join("target/release/pmu50");
    if p.is_file() {
        Ok(p)
    } else {
        Err(format!("the DUT worker needs the pmu50 executable: {} is missing (cargo build --release)", p.display()))
    }
}

impl Worker {
    pub fn spawn(scratch: &Path) -> Result<Worker, String> {
        Worker::spawn_exe(&worker_exe()?, scratch)
    }

    /// A worker from this executable (`EXE dut-worker`).
    fn spawn_exe(exe: &Path, scratch: &Path) -> Result<Worker, String> {
        use std::os::unix::process::CommandExt;
        let stderr = tempfile::Builder::new().prefix("dut-worker.").suffix(".log").tempfile_in(scratch).map_err(|e| format!("a log for the DUT worker in {}: {e}", scratch.display()))?;
        let log = stderr.reopen().map_err(|e| format!("{}: {e}", stderr.path().display()))?;
        let mut child = Command::new(exe)
            .arg("dut-worker")
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::from(log))
            .process_group(0)
            .spawn()
            .map_err(|e| format!("cannot start the DUT worker: {e}"))?;
        let (Some(stdin), Some(stdout)) = (child.stdin.take(), child.stdout.take()) else {
            let _ = child.kill();
            return Err("the DUT worker has no pipes".into());
        };
        Ok(Worker { child, stdin, stdout, stderr, buf: Vec::with_capacity(4096), sent: Instant::now() })
    }

    /// Run one seed. After [`Answer::TimedOut`] or [`Answer::Died`] the worker is gone: drop it.
    pub fn run(&mut self, lib: &Path, params: &Params, inputs: &[u32], timeout: Duration) -> Result<Answer, String> {
        self.send(lib, params, inputs);
        self.receive(timeout)
    }

    /// Hand a seed to the worker; [`Worker::receive`] takes its answer.
    pub fn send(&mut self, lib: &Path, params: &Params, inputs: &[u32]) {
        let path = lib.as_os_str().as_encoded_bytes();
        let mut req = Vec::with_capacity(4 + 4 + path.len() + 96 + 8 + 4 * inputs.len());
        req.extend_from_slice(MAGIC);
        req.extend_from_slice(&(path.len() as u32).to_le_bytes());
        req.extend_from_slice(path);
        for (_, v) in params.hdl_parameters() {
            req.extend_from_slice(&v.to_le_bytes());
        }
        req.extend_from_slice(&(inputs.len() as u64).to_le_bytes());
        for w in inputs {
            req.extend_from_slice(&w.to_le_bytes());
        }
        self.sent = Instant::now();
        // The worker reads a whole request before it works on it, so this write ends unless it
        // died (EPIPE), which `receive` reports.
        let _ = self.stdin.write_all(&req).and_then(|()| self.stdin.flush());
    }

    /// The answer to the seed [`Worker::send`] gave, within `timeout` from the send (an answer
    /// already written is taken even when the caller comes late).
    pub fn receive(&mut self, timeout: Duration) -> Result<Answer, String> {
        self.buf.clear();
        let fd = self.stdout.as_raw_fd();
        loop {
            if self.buf.ends_with(END.as_bytes()) {
                let text = String::from_utf8_lossy(&self.buf[..self.buf.len() - END.len()]).into_owned();
                return Ok(Answer::Reply(text));
            }
            let left = timeout.saturating_sub(self.sent.elapsed());
            let mut pfd = libc::pollfd { fd, events: libc::POLLIN, revents: 0 };
            let ms = if left.is_zero() { 0 } else { left.as_millis().clamp(1, i32::MAX as u128) as i32 };
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
                if left.is_zero() {
                    self.kill();
                    return Ok(Answer::TimedOut);
                }
                continue;
            }
            let mut chunk = [0u8; 4096];
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
        // SAFETY: kill(2) with the negated id of the group the child leads.
        unsafe { libc::kill(-(self.child.id() as libc::pid_t), libc::SIGKILL) };
        let _ = self.child.wait();
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
        let log = std::fs::read_to_string(self.stderr.path()).unwrap_or_default();
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
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pack_and_unpack_are_inverse_on_every_field() {
        let i = Inputs { ig: true, vs2_ok: false, cmp_s: true, cmp_c: true, bus_we: true, bus_addr: 0xA5, bus_wdata: 0xBEEF };
        assert_eq!(unpack(pack(&i)), i);
        let z = Inputs::default();
        assert_eq!(unpack(pack(&z)), z);
        for bit in 0..5 {
            let w = 1u32 << bit;
            assert_eq!(pack(&unpack(w)), w, "bit {bit}");
        }
    }

    fn fake_worker(dir: &Path, body: &str) -> PathBuf {
        use std::os::unix::fs::PermissionsExt;
        let p = dir.join("fake");
        let mut f = tempfile::NamedTempFile::new_in(dir).unwrap();
        f.write_all(format!("#!/bin/sh\n{body}\n").as_bytes()).unwrap();
        f.persist(&p).unwrap();
        std::fs::set_permissions(&p, std::fs::Permissions::from_mode(0o755)).unwrap();
        p
    }

    #[test]
    fn a_worker_that_hangs_is_killed_at_the_time_limit_with_its_group() {
        let dir = tempfile::tempdir().unwrap();
        // the worker leaves a child of its own behind, as a simulator under a script would
        let exe = fake_worker(dir.path(), "sleep 60 & echo $! > \"$(dirname \"$0\")/child.pid\"; exec sleep 60");
        let mut w = Worker::spawn_exe(&exe, dir.path()).unwrap();
        let t = Instant::now();
        let a = w.run(Path::new("/nonexistent.so"), &Params::default(), &[0; 100], Duration::from_millis(300)).unwrap();
        assert!(matches!(a, Answer::TimedOut));
        assert!(t.elapsed() < Duration::from_secs(10));
        let pid: i32 = std::fs::read_to_string(dir.path().join("child.pid")).unwrap().trim().parse().unwrap();
        std::thread::sleep(Duration::from_millis(100));
        // SAFETY: signal 0 only asks whether the process exists.
        let alive = unsafe { libc::kill(pid, 0) } == 0 && !std::fs::read_to_string(format!("/proc/{pid}/stat")).unwrap_or_default().contains(") Z ");
        assert!(!alive, "the worker's own child {pid} survived the kill");
    }

    #[test]
    fn a_worker_that_ends_reports_how_with_its_last_words() {
        let dir = tempfile::tempdir().unwrap();
        let exe = fake_worker(dir.path(), "head -c 4 > /dev/null; echo '%Error: planted: the RTL gave up' >&2; exit 3");
        let mut w = Worker::spawn_exe(&exe, dir.path()).unwrap();
        match w.run(Path::new("/nonexistent.so"), &Params::default(), &[0; 100], Duration::from_secs(20)).unwrap() {
            Answer::Died(how) => assert_eq!(how, "the DUT ended its process (exit 3): %Error: planted: the RTL gave up"),
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
