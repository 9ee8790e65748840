//! VCD output of a run, with its GTKWave save file.
//!
//! Hierarchy = the model's structure (docs/signals.md):
//! - `pmu50`: the core's ports (inputs and outputs), names exactly as the HDL contract;
//! - `pmu50.<block>`: every register of that block (`pmu50::Regs` field paths);
//! - `pmu50.internals`: combinational signals of the cycle (`kon`, `fig17`, ...);
//! - `env`: analog values as `real` (θ, sin2, cos2, Vs2, Vp, Vr, θ1, θm).
//!
//! A [`Level`] below `all` declares the same hierarchy with fewer signals (names unchanged):
//! `ports` the core's inputs and outputs and `env`; `registers` adds every `pmu50.<block>`
//! register; `all` adds `pmu50.internals`.
//!
//! Time convention: docs/spec.md 6.1. Timescale: the largest of 1 us, 100 ns, 10 ns, 1 ns that
//! divides the clock period. Reals are rounded (angles to 0.001 deg, volts to 0.1 mV) so that
//! settling tails do not flood the file; only changes are written.

use crate::atomic_file::AtomicFile;
use crate::observers::thread::Threaded;
use crate::observers::tracer::{CoreTracer, TracerRun, TracerTextRun};
use crate::sim::replay::PeriodRecorder;
use crate::sim::{Observer, SimError, TickView};
use pmu50_core::pmu50::Structural;
use pmu50_core::signals::{self, Dir, Radix, Signal};
use pmu50_core::Pmu50;
use pmu50_waves::fst::{start_fst, FstOut, FstWriter};
use pmu50_waves::gtkw::{Analog, Color, Format, GtkwSave, Trace};
use pmu50_waves::writer::{
    BitType, Emitter, Frame, SigId, VcdBuilder, VcdWriter, WriteError, Writer,
};
use pmu50_waves::{TimeUnit, Timescale};
use std::io::BufWriter;
use std::path::{Path, PathBuf};

const VERSION: &str = concat!("pmu50 reference model ", env!("CARGO_PKG_VERSION"));

/// The per-tick dump: every signal of the table is declared once, in two frames
/// (`pmu50_waves::writer::Frame`), so a tick compares plain integers and formats only changes.
struct Ids {
    /// ports, registers, inputs and internals: dumped every tick (`None` when the tracer
    /// dumps them: [`Out::Traced`])
    all: Option<Frame>,
    /// ports and registers: the final dump (`finish`), which has no inputs of its own
    state: Frame,
    env: Vec<SigId>,
    /// values of the current tick, in the order of `all` (`state` is its prefix)
    values: Vec<u64>,
    /// which signals are declared and dumped
    level: Level,
    /// the variables of `all`, in order (replay of skipped periods)
    all_ids: Vec<SigId>,
}

pub use crate::scenario::Level;

/// Fill `out` with the values of the current tick in the order of the frames: ports, registers
/// (from `Level::Registers`), then (with `with_inputs`) inputs and internals (`Level::All`).
fn frame_values(out: &mut Vec<u64>, v: &TickView<'_>, with_inputs: bool, level: Level) {
    out.clear();
    out.extend(signals::OUTPUTS.iter().map(|s| (s.get)(v.ports)));
    if level.registers() {
        out.extend(signals::REGISTERS.iter().map(|s| (s.get)(v.regs)));
    }
    if with_inputs {
        out.extend(signals::INPUTS.iter().map(|s| (s.get)(v.inputs)));
        if level.internals() {
            out.extend(signals::INTERNALS.iter().map(|s| (s.get)(v.internals)));
        }
    }
}

/// Waveform file format of `pmu50 run --format`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum WaveFormat {
    /// Value Change Dump, text (IEEE 1364 §18).
    #[default]
    Vcd,
    /// GTKWave's Fast Signal Trace: compressed blocks, for long runs (GTKWave and Surfer read it).
    Fst,
}

impl WaveFormat {
    /// File extension, without the dot.
    pub fn ext(self) -> &'static str {
        match self {
            WaveFormat::Vcd => "vcd",
            WaveFormat::Fst => "fst",
        }
    }

    /// `vcd` or `fst`.
    pub fn parse(s: &str) -> Option<WaveFormat> {
        match s {
            "vcd" => Some(WaveFormat::Vcd),
            "fst" => Some(WaveFormat::Fst),
            _ => None,
        }
    }
}

/// The VCD text of a run, staged in a temporary file.
type VcdFile = BufWriter<AtomicFile>;

/// A VCD of every signal: the writer lent to the tracer ([`CoreTracer::text_run`]) from one
/// tick to the next (a run ends only for a replay and at the end). The tracer steps a core of
/// its own with the bench's inputs, the same edges as the bench's core (checked every tick).
#[ouroboros::self_referencing]
struct TracedVcd {
    writer: Box<VcdWriter<VcdFile>>,
    tracer: CoreTracer,
    #[borrows(mut writer, mut tracer)]
    #[not_covariant]
    run: TracerTextRun<'this, VcdFile>,
}

impl TracedVcd {
    fn start(writer: Box<VcdWriter<VcdFile>>, tracer: CoreTracer) -> Result<TracedVcd, WriteError> {
        TracedVcdTryBuilder {
            writer,
            tracer,
            run_builder: |w, t| t.text_run(w),
        }
        .try_build()
    }
}

/// An FST of every signal: the writer lent to the tracer ([`CoreTracer::run`]) from one tick to
/// the next, as [`TracedVcd`].
#[ouroboros::self_referencing]
struct TracedFst {
    writer: Box<FstWriter>,
    tracer: CoreTracer,
    #[borrows(mut writer, mut tracer)]
    #[not_covariant]
    run: TracerRun<'this, FstOut>,
}

impl TracedFst {
    fn start(writer: Box<FstWriter>, tracer: CoreTracer) -> Result<TracedFst, WriteError> {
        TracedFstTryBuilder {
            writer,
            tracer,
            run_builder: |w, t| t.run(w),
        }
        .try_build()
    }
}

/// The checked writer of either format (the same declarations, frames and checks).
enum Out {
    /// `Level::All` in a VCD: the tracer writes the ticks.
    Traced(Box<TracedVcd>),
    /// `Level::All` in an FST: the tracer steps the frame (the temporary file as in `Fst`).
    TracedFst(Box<TracedFst>, AtomicFile),
    Vcd(Box<VcdWriter<VcdFile>>),
    /// The FST writer writes the temporary file of the `AtomicFile` by its own path.
    Fst(Box<FstWriter>, AtomicFile),
}

/// Observer writing the waveform (VCD or FST) of a run and its GTKWave save file. The writing
/// runs on a thread of its own ([`crate::observers::thread::Threaded`]) where the machine has a
/// second core, so that the text of tick `k` is written while the bench evaluates the ticks
/// after it; the file is the same byte for byte either way (`tests/writer_thread.rs`).
/// `PMU50_WRITER_THREAD=0` in the environment keeps it on the bench's thread (the least CPU
/// time), `1` starts the thread on any machine.
pub struct VcdObserver {
    route: Route,
}

enum Route {
    /// on the bench's thread; moved to its own at `begin` when `thread` says so
    Here {
        wave: Box<Wave>,
        thread: bool,
    },
    Thread(Box<Threaded<Wave>>),
    /// its thread ended: the observer back from it
    Back(Box<Wave>),
    Gone,
}

/// The environment variable that says where the waveform is written: `0` on the bench's
/// thread, `1` on a thread of its own; unset, on its own thread when the machine has a second
/// core.
pub const WRITER_THREAD_VAR: &str = "PMU50_WRITER_THREAD";

/// Whether a waveform is written on a thread of its own ([`WRITER_THREAD_VAR`]).
pub fn writer_thread_default() -> Result<bool, String> {
    match std::env::var(WRITER_THREAD_VAR) {
        Ok(v) if v == "0" => Ok(false),
        Ok(v) if v == "1" => Ok(true),
        Ok(v) => Err(format!("{WRITER_THREAD_VAR}={v:?}: use 0 (write the waveform on the bench's thread) or 1 (on a thread of its own)")),
        Err(std::env::VarError::NotPresent) => Ok(std::thread::available_parallelism().is_ok_and(|n| n.get() > 1)),
        Err(std::env::VarError::NotUnicode(v)) => Err(format!("{WRITER_THREAD_VAR}={v:?}: use 0 or 1")),
    }
}

impl VcdObserver {
    /// Create `<dir>/<name>.<vcd|fst>` and `<dir>/<name>.gtkw` (pointing at the waveform file)
    /// with the signals of `level` (the save file lists only them). `core` is the bench's core
    /// at reset (a VCD of every signal is written by a tracer stepping a copy of it); `window`
    /// is in ticks. The writing moves to a thread of its own at `begin` when
    /// [`writer_thread_default`] says so.
    #[allow(clippy::too_many_arguments)]
    pub fn create(
        dir: &Path,
        name: &str,
        core: &Pmu50,
        clock_ns: u64,
        window: Option<(u64, u64)>,
        format: WaveFormat,
        level: Level,
        first: &TickView<'_>,
    ) -> Result<VcdObserver, SimError> {
        let path = dir.join(format!("{name}.{}", format.ext()));
        let thread = writer_thread_default().map_err(|e| err(&path, e))?;
        let wave = Box::new(Wave::create(
            dir, name, core, clock_ns, window, format, level, first,
        )?);
        Ok(VcdObserver {
            route: Route::Here { wave, thread },
        })
    }

    /// Write on a thread of its own (`true`) or on the bench's (`false`), whatever the
    /// environment says: the same file either way. Before `begin`.
    pub fn on_own_thread(mut self, yes: bool) -> VcdObserver {
        if let Route::Here { thread, .. } = &mut self.route {
            *thread = yes;
        }
        self
    }

    /// The complete waveform (after `finish`, still a temporary file) and its save file.
    pub fn into_outputs(mut self) -> (Option<AtomicFile>, Option<GtkwSave>) {
        match std::mem::replace(&mut self.route, Route::Gone) {
            Route::Here { wave, .. } | Route::Back(wave) => wave.into_outputs(),
            Route::Thread(t) => t.into_inner().map_or((None, None), Wave::into_outputs),
            Route::Gone => (None, None),
        }
    }

    fn wave(&mut self) -> Result<&mut dyn Observer, SimError> {
        match &mut self.route {
            Route::Here { wave, .. } | Route::Back(wave) => Ok(&mut **wave),
            Route::Thread(t) => Ok(&mut **t),
            Route::Gone => Err(SimError::observer("waveform", "writer already closed")),
        }
    }
}

impl Observer for VcdObserver {
    fn begin(&mut self, v: &TickView<'_>) -> Result<(), SimError> {
        if let Route::Here { thread: true, .. } = self.route {
            let Route::Here { wave, .. } = std::mem::replace(&mut self.route, Route::Gone) else {
                unreachable!("matched above")
            };
            let what = wave.path.display().to_string();
            self.route = match Threaded::spawn(*wave, &what) {
                Ok(t) => Route::Thread(Box::new(t)),
                // no thread to be had: on the bench's
                Err(wave) => Route::Here {
                    wave: Box::new(wave),
                    thread: false,
                },
            };
        }
        self.wave()?.begin(v)
    }

    #[inline]
    fn tick(&mut self, v: &TickView<'_>) -> Result<(), SimError> {
        match &mut self.route {
            Route::Thread(t) => t.tick(v),
            _ => self.wave()?.tick(v),
        }
    }

    fn finish(&mut self, v: &TickView<'_>) -> Result<(), SimError> {
        self.wave()?.finish(v)?;
        if let Route::Thread(_) = self.route {
            if let Route::Thread(t) = std::mem::replace(&mut self.route, Route::Gone) {
                self.route = t
                    .into_inner()
                    .map_or(Route::Gone, |w| Route::Back(Box::new(w)));
            }
        }
        Ok(())
    }

    fn needs_every_tick(&self) -> bool {
        true
    }

    fn replays_periods(&self) -> bool {
        true
    }

    fn period_boundary(&mut self, k: u64) -> Result<(), SimError> {
        self.wave()?.period_boundary(k)
    }

    fn moving_boundary(&mut self, k: u64) -> Result<(), SimError> {
        self.wave()?.moving_boundary(k)
    }

    fn can_replay(&self, k: u64, len: u64) -> bool {
        match &self.route {
            Route::Here { wave, .. } | Route::Back(wave) => wave.can_replay(k, len),
            Route::Thread(t) => t.can_replay(k, len),
            Route::Gone => false,
        }
    }

    fn replay(&mut self, k: u64, periods: u64, len: u64) -> Result<(), SimError> {
        self.wave()?.replay(k, periods, len)
    }
}

/// The writer of a run's waveform (VCD or FST) and its GTKWave save file: the observer
/// [`VcdObserver`] runs it on its own thread, or on the bench's.
struct Wave {
    out: Option<Out>,
    /// The tracer while its writer is lent out of it (a replay: [`Wave::untraced`]).
    tracer: Option<CoreTracer>,
    /// The complete VCD (temporary file) after `finish`, and the save file, for the caller to
    /// rename into place (crate::atomic_file).
    file: Option<AtomicFile>,
    gtkw: Option<GtkwSave>,
    ids: Ids,
    unit_ns: u64,
    path: PathBuf,
    /// Replay of skipped key-off periods (crate::sim::replay): per tick the values of `all`,
    /// then the bits of the analog values.
    rec: PeriodRecorder,
    rec_values: Vec<u64>,
    /// the analog values of the last tick
    env: EnvCache,
    clock_ns: u64,
    window: Option<(u64, u64)>,
}

fn err(path: &Path, e: impl Into<Box<dyn std::error::Error + Send + Sync + 'static>>) -> SimError {
    SimError::observer(path.display().to_string(), e)
}

/// Timescale for a clock period in ns.
pub fn timescale_for(clock_ns: u64) -> (Timescale, u64) {
    for (unit, ns, ts) in [
        (1_000u64, 1_000u64, Timescale::new(1, TimeUnit::Us)),
        (100, 100, Timescale::new(100, TimeUnit::Ns)),
        (10, 10, Timescale::new(10, TimeUnit::Ns)),
    ] {
        if clock_ns.is_multiple_of(unit) {
            return (ts, ns);
        }
    }
    (Timescale::new(1, TimeUnit::Ns), 1)
}

fn round(v: f64, q: f64) -> f64 {
    let r = (v / q).round() * q;
    if r == 0.0 {
        0.0
    } else {
        r
    }
}

fn env_values(v: &TickView<'_>) -> [f64; 8] {
    let raw = EnvCache::raw(v);
    std::array::from_fn(|j| round(f64::from_bits(raw[j]), ENV_STEPS[j]))
}

/// The analog values of the last tick, as given and rounded ([`env_values`]): a value given
/// with the same bits as the tick before is not rounded again, and a value whose rounded bits
/// did not change is not given to the writer again (a real keeps its value until changed, and
/// the writer writes a real only when its bits change).
struct EnvCache {
    raw: [u64; 8],
    rounded: [f64; 8],
    /// the values whose rounded bits changed at the last [`EnvCache::update`], one bit each
    changed: u8,
}

/// The rounding step of each analog value, in the order of [`ENV_NAMES`]: angles to 0.001
/// deg, volts to 0.1 mV.
const ENV_STEPS: [f64; 8] = [1e-3, 1e-4, 1e-4, 1e-4, 1e-4, 1e-4, 1e-3, 1e-3];

impl EnvCache {
    fn raw(v: &TickView<'_>) -> [u64; 8] {
        let e = v.env;
        [
            e.theta_deg,
            e.sin2_v,
            e.cos2_v,
            e.vs2_v,
            e.vp_v,
            e.vr_v,
            e.theta1_deg.unwrap_or(0.0),
            e.theta_m_deg.unwrap_or(0.0),
        ]
        .map(f64::to_bits)
    }

    fn new(v: &TickView<'_>) -> EnvCache {
        EnvCache {
            raw: Self::raw(v),
            rounded: env_values(v),
            changed: 0,
        }
    }

    #[inline]
    fn update(&mut self, v: &TickView<'_>) {
        let raw = Self::raw(v);
        self.changed = 0;
        for (j, r) in raw.into_iter().enumerate() {
            if r != self.raw[j] {
                self.raw[j] = r;
                let x = round(f64::from_bits(r), ENV_STEPS[j]);
                if x.to_bits() != self.rounded[j].to_bits() {
                    self.rounded[j] = x;
                    self.changed |= 1 << j;
                }
            }
        }
    }

    /// `(index, rounded value)` of the values that changed at the last update.
    fn changes(&self) -> impl Iterator<Item = (usize, f64)> + '_ {
        (0..8)
            .filter(|j| self.changed & 1 << j != 0)
            .map(|j| (j, self.rounded[j]))
    }
}

/// Register groups shown collapsed in the save file (the parameter registers rarely change).
const COLLAPSED_BLOCKS: &[&str] = &["register_file"];

/// GTKWave display format of a signal: a bit for 1-bit signals, else the table's radix.
fn format_of<T>(sig: &Signal<T>, s: &Structural) -> Format {
    match sig.radix {
        _ if sig.bits(s) == 1 => Format::Binary,
        Radix::Decimal if sig.signed => Format::SignedDecimal,
        Radix::Decimal => Format::Decimal,
        Radix::Hex => Format::Hex,
        Radix::Binary => Format::Binary,
    }
}

/// Declare every signal of `list` with its value in `v`: `reg` for registers, `wire` otherwise,
/// in the table's scopes (below the current scope `pmu50`).
fn declare<T>(
    b: &mut VcdBuilder,
    list: &[Signal<T>],
    v: &T,
    s: &Structural,
) -> Result<Vec<SigId>, pmu50_waves::writer::WriteError> {
    let mut ids = Vec::with_capacity(list.len());
    let mut scope = "";
    for sig in list {
        if sig.scope != scope {
            if !scope.is_empty() {
                b.pop_scope()?;
            }
            if !sig.scope.is_empty() {
                b.push_scope(sig.scope)?;
            }
            scope = sig.scope;
        }
        let ty = if sig.dir == Dir::Reg {
            BitType::Reg
        } else {
            BitType::Wire
        };
        let width = sig.bits(s);
        let value = (sig.get)(v);
        ids.push(if width == 1 {
            b.add_bit(ty, sig.name, (value != 0).into())?
        } else {
            b.add_vector(ty, sig.name, u32::from(width) - 1, 0, value)?
        });
    }
    if !scope.is_empty() {
        b.pop_scope()?;
    }
    Ok(ids)
}

const ENV_NAMES: [&str; 8] = [
    "theta_deg",
    "sin2_v",
    "cos2_v",
    "vs2_v",
    "vp_v",
    "vr_v",
    "theta1_deg",
    "theta_m_deg",
];

impl Wave {
    /// Create `<dir>/<name>.<vcd|fst>` and `<dir>/<name>.gtkw` (pointing at the waveform file)
    /// with the signals of `level` (the save file lists only them). `core` is the bench's core
    /// at reset (a VCD of every signal is written by a tracer stepping a copy of it); `window`
    /// is in ticks.
    #[allow(clippy::too_many_arguments)]
    fn create(
        dir: &Path,
        name: &str,
        core: &Pmu50,
        clock_ns: u64,
        window: Option<(u64, u64)>,
        format: WaveFormat,
        level: Level,
        first: &TickView<'_>,
    ) -> Result<Wave, SimError> {
        let s = core.structural();
        let file_name = format!("{name}.{}", format.ext());
        let path = dir.join(&file_name);
        let (ts, unit_ns) = timescale_for(clock_ns);
        let mut b = VcdBuilder::new(ts, VERSION).map_err(|e| err(&path, e))?;
        if let Some((a, z)) = window {
            b.window(a * clock_ns / unit_ns, z * clock_ns / unit_ns)
                .map_err(|e| err(&path, e))?;
        }
        let mut gt = GtkwSave::new(&file_name).map_err(|e| err(&path, e))?;
        b.push_scope("pmu50").map_err(|e| err(&path, e))?;
        let inputs =
            declare(&mut b, signals::INPUTS, first.inputs, &s).map_err(|e| err(&path, e))?;
        let ports =
            declare(&mut b, signals::OUTPUTS, first.ports, &s).map_err(|e| err(&path, e))?;
        let regs = if level.registers() {
            declare(&mut b, signals::REGISTERS, first.regs, &s).map_err(|e| err(&path, e))?
        } else {
            Vec::new()
        };
        let internals = if level.internals() {
            declare(&mut b, signals::INTERNALS, first.internals, &s).map_err(|e| err(&path, e))?
        } else {
            Vec::new()
        };
        b.pop_scope().map_err(|e| err(&path, e))?;
        b.push_scope("env").map_err(|e| err(&path, e))?;
        let ev = env_values(first);
        let env = ENV_NAMES
            .iter()
            .zip(ev)
            .map(|(n, v)| b.add_real(n, v).map_err(|e| err(&path, e)))
            .collect::<Result<Vec<_>, _>>()?;
        b.pop_scope().map_err(|e| err(&path, e))?;

        // GTKWave save file: the contract ports first, then the inputs, one group per block, the
        // internals; display formats from the signal table.
        let gerr = |e: pmu50_waves::gtkw::GtkwError| err(&path, e);
        let trace = |gt: &mut GtkwSave, id: SigId, f: Format| -> Result<(), SimError> {
            let n = b.gtkwave_name(id).map_err(|e| err(&path, e))?;
            gt.trace(Trace::new(n).format(f)).map_err(gerr)
        };
        gt.begin_group("ports", false).map_err(gerr)?;
        for (id, sig) in inputs
            .iter()
            .zip(signals::INPUTS)
            .filter(|(_, sig)| sig.contract)
        {
            trace(&mut gt, *id, format_of(sig, &s))?;
        }
        for (id, sig) in ports.iter().zip(signals::OUTPUTS) {
            trace(&mut gt, *id, format_of(sig, &s))?;
        }
        gt.end_group().map_err(gerr)?;
        gt.begin_group("inputs", true).map_err(gerr)?;
        for (id, sig) in inputs.iter().zip(signals::INPUTS) {
            trace(&mut gt, *id, format_of(sig, &s))?;
        }
        gt.end_group().map_err(gerr)?;
        let mut block = "";
        for (id, sig) in regs.iter().zip(signals::REGISTERS) {
            if sig.scope != block {
                if !block.is_empty() {
                    gt.end_group().map_err(gerr)?;
                }
                gt.begin_group(sig.scope, COLLAPSED_BLOCKS.contains(&sig.scope))
                    .map_err(gerr)?;
                block = sig.scope;
            }
            trace(&mut gt, *id, format_of(sig, &s))?;
        }
        if !block.is_empty() {
            gt.end_group().map_err(gerr)?;
        }
        if !internals.is_empty() {
            gt.begin_group("internals", true).map_err(gerr)?;
            for (id, sig) in internals.iter().zip(signals::INTERNALS) {
                trace(&mut gt, *id, format_of(sig, &s))?;
            }
            gt.end_group().map_err(gerr)?;
        }
        let name_of = |b: &VcdBuilder, id: SigId| b.gtkwave_name(id).map_err(|e| err(&path, e));
        gt.begin_group("env", false).map_err(gerr)?;
        let colors = [
            Color::Yellow,
            Color::Orange,
            Color::Green,
            Color::Red,
            Color::Violet,
            Color::Indigo,
            Color::Blue,
            Color::Yellow,
        ];
        for ((id, n), c) in env.iter().zip(ENV_NAMES).zip(colors) {
            let rows = if n.starts_with("theta") || n.ends_with("2_v") {
                6
            } else {
                3
            };
            gt.trace(
                Trace::new(name_of(&b, *id)?)
                    .analog(Analog::Interpolated, rows)
                    .color(c),
            )
            .map_err(gerr)?;
        }
        gt.end_group().map_err(gerr)?;
        gt.size(1400, 900);
        if let Some((a, z)) = window {
            gt.fit(a * clock_ns / unit_ns, z * clock_ns / unit_ns);
        }
        let file = AtomicFile::stage(&path).map_err(|e| err(&path, e))?;
        let state_ids: Vec<SigId> = ports.iter().chain(&regs).copied().collect();
        let all_ids: Vec<SigId> = state_ids
            .iter()
            .chain(&inputs)
            .chain(&internals)
            .copied()
            .collect();
        let (w, all, state) = match format {
            WaveFormat::Vcd if level == Level::All => {
                // the tracer's frame: every signal in declaration order
                let mut w = Box::new(b.start(BufWriter::new(file)).map_err(|e| err(&path, e))?);
                let traced: Vec<SigId> = inputs
                    .iter()
                    .chain(&ports)
                    .chain(&regs)
                    .chain(&internals)
                    .copied()
                    .collect();
                let frame = w.frame(&traced).map_err(|e| err(&path, e))?;
                let state = w.frame(&state_ids).map_err(|e| err(&path, e))?;
                let tracer = CoreTracer::new(frame, core.clone()).map_err(|e| err(&path, e))?;
                (
                    Out::Traced(Box::new(
                        TracedVcd::start(w, tracer).map_err(|e| err(&path, e))?,
                    )),
                    None,
                    state,
                )
            }
            WaveFormat::Vcd => {
                let mut w = b.start(BufWriter::new(file)).map_err(|e| err(&path, e))?;
                let all = w.frame(&all_ids).map_err(|e| err(&path, e))?;
                let state = w.frame(&state_ids).map_err(|e| err(&path, e))?;
                (Out::Vcd(Box::new(w)), Some(all), state)
            }
            WaveFormat::Fst if level == Level::All => {
                // the tracer's frame, as for a VCD
                let mut w = Box::new(start_fst(b, file.temp_path()).map_err(|e| err(&path, e))?);
                let traced: Vec<SigId> = inputs
                    .iter()
                    .chain(&ports)
                    .chain(&regs)
                    .chain(&internals)
                    .copied()
                    .collect();
                let frame = w.frame(&traced).map_err(|e| err(&path, e))?;
                let state = w.frame(&state_ids).map_err(|e| err(&path, e))?;
                let tracer = CoreTracer::new(frame, core.clone()).map_err(|e| err(&path, e))?;
                (
                    Out::TracedFst(
                        Box::new(TracedFst::start(w, tracer).map_err(|e| err(&path, e))?),
                        file,
                    ),
                    None,
                    state,
                )
            }
            WaveFormat::Fst => {
                let mut w = start_fst(b, file.temp_path()).map_err(|e| err(&path, e))?;
                let all = w.frame(&all_ids).map_err(|e| err(&path, e))?;
                let state = w.frame(&state_ids).map_err(|e| err(&path, e))?;
                (Out::Fst(Box::new(w), file), Some(all), state)
            }
        };
        let ids = Ids {
            all,
            state,
            env,
            values: Vec::with_capacity(all_ids.len()),
            level,
            all_ids,
        };
        Ok(Wave {
            out: Some(w),
            tracer: None,
            file: None,
            gtkw: Some(gt),
            ids,
            unit_ns,
            path,
            rec: PeriodRecorder::new(),
            rec_values: Vec::new(),
            env: EnvCache::new(first),
            clock_ns,
            window,
        })
    }

    /// The complete VCD (after `finish`, still a temporary file) and its save file.
    fn into_outputs(self) -> (Option<AtomicFile>, Option<GtkwSave>) {
        (self.file, self.gtkw)
    }

    /// The tracer's writer back (its run ended), for a replay or the final dump.
    fn untraced(&mut self) {
        self.out = match self.out.take() {
            Some(Out::Traced(tv)) => {
                let heads = tv.into_heads();
                self.tracer = Some(heads.tracer);
                Some(Out::Vcd(heads.writer))
            }
            Some(Out::TracedFst(tf, file)) => {
                let heads = tf.into_heads();
                self.tracer = Some(heads.tracer);
                Some(Out::Fst(heads.writer, file))
            }
            w => w,
        };
    }

    /// The writer lent to the tracer again after [`Wave::untraced`].
    fn retraced(&mut self) -> Result<(), SimError> {
        let Some(tracer) = self.tracer.take() else {
            return Ok(());
        };
        self.out = match self.out.take() {
            Some(Out::Vcd(w)) => Some(Out::Traced(Box::new(
                TracedVcd::start(w, tracer).map_err(|e| err(&self.path, e))?,
            ))),
            Some(Out::Fst(w, file)) => Some(Out::TracedFst(
                Box::new(TracedFst::start(w, tracer).map_err(|e| err(&self.path, e))?),
                file,
            )),
            w => w,
        };
        Ok(())
    }

    fn dump(&mut self, v: &TickView<'_>, with_inputs: bool) -> Result<(), SimError> {
        let path = &self.path;
        let t = v.time_ns / self.unit_ns;
        // One tick through the tracer's run (the VCD's or the FST's): the bench's inputs and the
        // changed analog values; the tracer's core must then hold the bench's registers.
        macro_rules! traced_tick {
            ($traced:expr, $env:expr, $cache:expr) => {{
                let (env, cache) = ($env, $cache);
                cache.update(v);
                let same = $traced.with_run_mut(|run| -> Result<bool, WriteError> {
                    run.step(t, v.inputs)?;
                    for (j, val) in cache.changes() {
                        run.real(env[j], val)?;
                    }
                    Ok(run.core().regs() == v.after)
                });
                match same {
                    Ok(true) => Ok(()),
                    Ok(false) => return Err(err(path, format!("the traced core left the bench's at tick {}: its registers after the edge differ", v.tick))),
                    Err(e) => Err(e),
                }
            }};
        }
        let r = match self.out.as_mut() {
            Some(Out::Traced(tv)) => traced_tick!(tv, &self.ids.env, &mut self.env),
            Some(Out::TracedFst(tf, _)) => traced_tick!(tf, &self.ids.env, &mut self.env),
            Some(Out::Vcd(w)) => dump_into(w, &mut self.ids, &mut self.env, v, t, with_inputs),
            Some(Out::Fst(w, _)) => dump_into(w, &mut self.ids, &mut self.env, v, t, with_inputs),
            None => return Err(err(path, "writer already closed")),
        };
        r.map_err(|e| err(path, e))
    }
}

/// One tick into either writer: the frame of this dump, then the analog values.
fn dump_into<E: Emitter>(
    w: &mut Writer<E>,
    ids: &mut Ids,
    env: &mut EnvCache,
    v: &TickView<'_>,
    t: u64,
    with_inputs: bool,
) -> Result<(), WriteError> {
    frame_values(&mut ids.values, v, with_inputs, ids.level);
    let frame = match (with_inputs, ids.all.as_mut()) {
        (true, Some(all)) => all,
        (true, None) => return Err(WriteError::UnknownFrame),
        (false, _) => &mut ids.state,
    };
    w.dump_frame(frame, t, &ids.values)?;
    if with_inputs {
        env.update(v);
        for (j, val) in env.changes() {
            w.change_real(ids.env[j], val)?;
        }
    }
    Ok(())
}

/// One replayed tick of a skipped period: slots below `all.len()` are variables of the frame
/// `all`, the others the analog values (bits of the `f64`), through the writer's checked calls
/// (the same values as the frame and `change_real` of a stepped tick, hence the same bytes).
fn replay_into<E: Emitter>(
    w: &mut Writer<E>,
    all: &[SigId],
    env: &[SigId],
    t: u64,
    changes: &[(u32, u64)],
) -> Result<(), WriteError> {
    w.set_time(t)?;
    for &(slot, v) in changes {
        match all.get(slot as usize) {
            Some(id) => w.change_vector(*id, v)?,
            None => w.change_real(env[slot as usize - all.len()], f64::from_bits(v))?,
        }
    }
    Ok(())
}

impl Observer for Wave {
    fn tick(&mut self, v: &TickView<'_>) -> Result<(), SimError> {
        self.dump(v, true)?;
        if self.rec.active() {
            if self.ids.all.is_none() {
                // the tracer dumped the tick: its values for the recorder
                frame_values(&mut self.rec_values, v, true, self.ids.level);
            } else {
                self.rec_values.clear();
                self.rec_values.extend_from_slice(&self.ids.values);
            }
            self.rec_values.extend(self.env.rounded.map(f64::to_bits));
            self.rec.record_taking(v.tick, &mut self.rec_values);
        }
        Ok(())
    }

    /// A waveform needs every tick, but replays skipped periods (crate::sim::replay).
    fn replays_periods(&self) -> bool {
        true
    }

    crate::sim::replay::recorder_boundaries!(rec);

    fn can_replay(&self, k: u64, len: u64) -> bool {
        self.rec.can_replay(k, len)
    }

    fn replay(&mut self, k: u64, periods: u64, len: u64) -> Result<(), SimError> {
        self.untraced();
        self.replay_untraced(k, periods, len)?;
        self.retraced()
    }

    fn finish(&mut self, v: &TickView<'_>) -> Result<(), SimError> {
        self.untraced();
        self.tracer = None;
        self.finish_untraced(v)
    }
}

impl Wave {
    fn replay_untraced(&mut self, k: u64, periods: u64, len: u64) -> Result<(), SimError> {
        let (clk, unit) = (self.clock_ns, self.unit_ns);
        let (all, env) = (&self.ids.all_ids, &self.ids.env);
        let r = match self.out.as_mut() {
            Some(Out::Vcd(w)) => self.rec.replay(k, periods, len, self.window, |tick, c| {
                replay_into(w, all, env, tick * clk / unit, c)
            }),
            Some(Out::Fst(w, _)) => self.rec.replay(k, periods, len, self.window, |tick, c| {
                replay_into(w, all, env, tick * clk / unit, c)
            }),
            Some(Out::Traced(_) | Out::TracedFst(..)) | None => {
                return Err(err(&self.path, "writer already closed"))
            }
        };
        r.map_err(|e| err(&self.path, e))
    }

    fn finish_untraced(&mut self, v: &TickView<'_>) -> Result<(), SimError> {
        self.dump(v, false)?;
        let path = self.path.clone();
        let w = self
            .out
            .take()
            .ok_or_else(|| err(&path, "writer already closed"))?;
        self.file = Some(match w {
            Out::Traced(_) | Out::TracedFst(..) => {
                return Err(err(&path, "the tracer still holds the writer"))
            }
            Out::Vcd(w) => (*w)
                .finish()
                .map_err(|e| err(&path, e))?
                .into_inner()
                .map_err(|e| err(&path, e.into_error()))?,
            Out::Fst(w, file) => {
                w.finish().map_err(|e| err(&path, e))?;
                file
            }
        });
        Ok(())
    }
}
