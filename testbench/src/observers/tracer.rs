//! The core's 65 signals into a checked waveform frame, one edge per step, comparing only what
//! the edge can have changed.
//!
//! A traced tick of the core is its inputs, its outputs and registers before the edge, and the
//! internals of the edge (docs/signals.md; the frame order below). Comparing all 65 values with
//! the last tick's costs as much as the edge itself, and most edges change almost nothing: the
//! kernel says which. A *narrow* edge ([`pmu50_core::kernel::step_traced`]: no bus write,
//! no key edge, no key-off sampling strobe, no key-on sample that presets or moves the latches
//! or counters) changes only `sync`, `tmr`, `sr`, `rdata` and `diag`, keeps `sig`, and has all
//! internals false but `upd`. So after a narrow edge [`CoreTracer`] compares only those
//! registers, the outputs decoded from them (`vs2_en`, `st`, `sr`, `ps_win`, `smp`, `diag`,
//! `bus_rdata`) and the inputs; after a wide edge, every value. This is how Verilator's tracer
//! skips the signals of logic that was not evaluated (its activity flags); here the flag comes
//! from the kernel and its contract is tested on any register state
//! (`rtl_model/core/tests/kernel_equivalence.rs`, `narrow_edges_write_only_their_registers`).
//! The internals (one word) are compared after every edge.
//!
//! The tracer steps in a run ([`CoreTracer::run`], [`TracerRun::step`]): the writer is lent to
//! its frame ([`pmu50_waves::writer::FrameRun`]) for as many edges as the caller likes, so a
//! step inside the window writes its changed values straight from the frame's copy when the
//! next one begins, without the writer's per-variable bookkeeping (the way Verilator's tracer
//! owns its file). For a VCD, [`CoreTracer::text_run`] goes further ([`TracerTextRun::step`]):
//! the writer's text buffer is lent to the frame ([`pmu50_waves::writer::TextRun`]), so each
//! changed value's line is written at once, with the same checks and the same file. There the
//! writer's three checks of a value (position order, changed, fits its width) are the tracer's
//! own guarantees ([`pmu50_waves::writer::TextStep::change`], asserted in debug builds): its
//! positions increase by construction, it gives a value only when its own compare found a
//! change, and [`CoreTracer::new`] checks once that every variable of the frame is exactly as
//! wide as the core's signal. The signals of a fixed width on the common path (the inputs, the
//! narrow outputs and registers, the internals) are then written by
//! [`pmu50_waves::writer::TextStep::change_w`], their widths known at compile time. A frame of
//! other widths keeps the checked [`TextStep::line`] (which reports a value that does not fit).
//! [`CoreTracer::step`] is one edge in a run of its own. The writer keeps every
//! check (time order, double assignment, the width of every value that changed, positions, and
//! in a run increasing positions) and writes only the values that changed, so the file is byte
//! for byte the one [`Writer::dump_frame`] writes from every value of every tick:
//! `tests/tracer.rs` compares the two on random runs, stepped both ways. The tracer owns the
//! core and the frame, so no edge and no other dump of the frame can happen behind its back;
//! other writes to the frame's variables between runs (single changes, overlapping frames) make
//! its next step give every value ([`pmu50_waves::writer::RunStep::is_current`]).
//!
//! Frame order (positions of the `ids` given to [`Writer::frame`]): the 7 inputs
//! (`Inputs::values`), the 23 outputs (`Outputs::values`), the 26 registers (`Regs::values`), the
//! 9 internals (`Internals::values`).

use pmu50_core::pmu50::{Inputs, Internals, Outputs, Regs};
use pmu50_core::signals::{self, Width};
use pmu50_core::Pmu50;
use pmu50_waves::writer::{
    Emitter, Frame, FrameRun, RunStep, SigId, TextRun, TextStep, VcdWriter, WriteError, Writer,
};
use std::io::Write;

/// Number of signals in a [`CoreTracer`]'s frame, and where each group starts.
pub const N_SIGNALS: usize = 65;
const INPUTS: usize = 0;
const OUTPUTS: usize = 7;
const REGISTERS: usize = 30;
const INTERNALS: usize = 56;

/// Positions among the registers (the order of `Regs::values`) of the registers a narrow edge
/// writes, [`pmu50_core::kernel::NARROW_WRITES`]: the ones the step compares after a narrow edge
/// (`narrow_registers` below lists the same; `tests/tracer.rs` checks the names).
pub const NARROW_REGISTERS: [usize; 5] = [0, 12, 13, 14, 25];

/// A frame of another length than [`N_SIGNALS`].
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("a core tracer needs a frame of {N_SIGNALS} variables (inputs, outputs, registers, internals in declaration order); this frame has {got}")]
pub struct FrameSizeError {
    /// variables in the frame given
    pub got: usize,
}

/// Traces every edge of the [`Pmu50`] it owns into a frame of its 65 signals (see the module
/// documentation). It owns the core so that no edge, reset or fast-forward can happen behind
/// its back ([`CoreTracer::core`] reads it, [`CoreTracer::into_core`] gives it back), and it
/// owns the frame so that no other dump of the frame can go unnoticed.
pub struct CoreTracer {
    core: Pmu50,
    frame: Frame,
    held: Held,
    /// every variable of the frame is exactly as wide as the core's signal at its position (so
    /// every value the core gives fits, [`TextStep::change`], and a signal of a fixed width is
    /// written by [`TextStep::change_w`])
    exact: bool,
}

/// What a [`CoreTracer`] keeps between steps.
struct Held {
    /// The values the frame holds (when `valid`): inputs ([`Inputs::packed`]), outputs,
    /// registers, internals.
    last_i: u64,
    last_o: Outputs,
    last_r: Regs,
    /// ([`Internals::packed`])
    last_x: u128,
    /// The outputs after the last edge, i.e. before the next one (the core's `peek`).
    outputs: Outputs,
    /// The last edge was wide: the next step compares every register and output.
    wide: bool,
    /// The last step was complete (a failed step leaves some values of its tick assigned).
    valid: bool,
}

impl CoreTracer {
    /// Trace the core `m` into `frame`, declared with [`Writer::frame`] from the 65 signals in
    /// the order of the module documentation.
    pub fn new(frame: Frame, m: Pmu50) -> Result<CoreTracer, FrameSizeError> {
        if frame.len() != N_SIGNALS {
            return Err(FrameSizeError { got: frame.len() });
        }
        let (r, o) = (*m.regs(), m.peek());
        let s = m.structural();
        let widths: Vec<u8> = (Inputs::default().values().into_iter().map(|v| v.1))
            .chain(o.values(&s).into_iter().map(|v| v.1))
            .chain(r.values(&s).into_iter().map(|v| v.width))
            .chain(Internals::default().values().into_iter().map(|v| v.1))
            .collect();
        let exact = widths
            .into_iter()
            .enumerate()
            .all(|(k, w)| frame.max(k) == Some(u64::MAX >> (64 - u32::from(w).clamp(1, 64))));
        Ok(CoreTracer {
            core: m,
            frame,
            exact,
            held: Held {
                last_i: 0,
                last_o: o,
                last_r: r,
                last_x: 0,
                outputs: o,
                wide: true,
                valid: false,
            },
        })
    }

    /// The core (its registers, tick count, read-out).
    pub fn core(&self) -> &Pmu50 {
        &self.core
    }

    /// Every variable of the frame is exactly as wide as the core's signal, so a text run writes
    /// the tracer's lines without the writer's per-value checks ([`TracerTextRun::step`]);
    /// otherwise it writes them through the checked [`TextStep::line`].
    pub fn exact(&self) -> bool {
        self.exact
    }

    /// The core back, at the end of the trace.
    pub fn into_core(self) -> Pmu50 {
        self.core
    }

    /// Lend the writer to the tracer for a run of edges ([`TracerRun::step`]), the fast way
    /// to trace many: the writer is a [`FrameRun`] of the tracer's frame until the run is
    /// dropped (then the last edge's values become the writer's pending step).
    pub fn run<'a, E: Emitter>(
        &'a mut self,
        w: &'a mut Writer<E>,
    ) -> Result<TracerRun<'a, E>, WriteError> {
        Ok(TracerRun {
            run: w.frame_run(&mut self.frame)?,
            held: &mut self.held,
            core: &mut self.core,
        })
    }

    /// Lend a VCD writer to the tracer for a run of edges written at once
    /// ([`TracerTextRun::step`]): the fastest way to trace many. The writer is a
    /// [`TextRun`] of the tracer's frame until the run is dropped; a step that cannot be
    /// written at once (the first, one outside the writer's window, one after a failed step or
    /// after other writes to the frame's variables) goes through a [`FrameRun`] as in
    /// [`CoreTracer::run`]. The file is the same.
    pub fn text_run<'a, W: Write>(
        &'a mut self,
        w: &'a mut VcdWriter<W>,
    ) -> Result<TracerTextRun<'a, W>, WriteError> {
        Ok(TracerTextRun {
            run: w.text_run(&mut self.frame)?,
            held: &mut self.held,
            core: &mut self.core,
            exact: self.exact,
        })
    }

    /// One traced edge, as [`TracerRun::step`] in a run of its own (each call ends its run:
    /// when a value changed, the writer takes the frame's 65 values; [`CoreTracer::run`] for
    /// many edges).
    pub fn step<E: Emitter>(
        &mut self,
        w: &mut Writer<E>,
        t: u64,
        i: &Inputs,
    ) -> Result<&Outputs, WriteError> {
        self.run(w)?.step(t, i)?;
        Ok(&self.held.outputs)
    }
}

/// A [`CoreTracer`] with the writer lent to it ([`CoreTracer::run`]).
pub struct TracerRun<'a, E: Emitter> {
    run: FrameRun<'a, E>,
    held: &'a mut Held,
    core: &'a mut Pmu50,
}

impl<E: Emitter> TracerRun<'_, E> {
    /// The core (its registers, tick count, read-out).
    pub fn core(&self) -> &Pmu50 {
        self.core
    }

    /// The `real` variable `id` (declared after the frame's signals: the analog values of a
    /// run) at the time of the last step, in the same step ([`FrameRun::real`]).
    #[inline]
    pub fn real(&mut self, id: SigId, v: f64) -> Result<(), WriteError> {
        self.run.real(id, v)
    }

    /// One rising edge of the core with inputs `i`, traced at time `t` (the inputs, the outputs
    /// and registers before the edge, its internals); returns the outputs after the edge. The
    /// file is the one [`Writer::dump_frame`] writes with every value, with the same checks.
    /// When the step cannot start (time backwards, a variable of the frame already assigned at
    /// `t`) the edge is not taken; once it has started the edge is always taken, and a value
    /// that does not fit its variable is reported after it (the values before it are assigned,
    /// and the next step gives every value again).
    #[inline]
    pub fn step(&mut self, t: u64, i: &Inputs) -> Result<&Outputs, WriteError> {
        let s = self.run.step(t)?;
        // Every value at the first step, after other writes to the frame's variables, and after
        // a failed step.
        let full = !(self.held.valid && s.is_current());
        self.held.edge(s, self.core, i, full)?;
        Ok(&self.held.outputs)
    }
}

/// A [`CoreTracer`] with a VCD writer's text buffer lent to it ([`CoreTracer::text_run`]).
pub struct TracerTextRun<'a, W: Write> {
    run: TextRun<'a, W>,
    held: &'a mut Held,
    core: &'a mut Pmu50,
    exact: bool,
}

impl<W: Write> TracerTextRun<'_, W> {
    /// The core (its registers, tick count, read-out).
    pub fn core(&self) -> &Pmu50 {
        self.core
    }

    /// The `real` variable `id` (declared after the frame's signals: the analog values of a
    /// run) at the time of the last step, written in the same step ([`TextRun::real`]: at once
    /// after the step's lines when it was written at once, through the writer's checked
    /// `change_real` otherwise).
    #[inline]
    pub fn real(&mut self, id: SigId, v: f64) -> Result<(), WriteError> {
        self.run.real(id, v)
    }

    /// One rising edge of the core with inputs `i`, traced at time `t`, as [`TracerRun::step`]
    /// (the same file, the same checks and errors); the changed values' lines are written at
    /// once when the step allows it ([`TextRun::step`]). When every variable of the frame is
    /// exactly as wide as the core's signal, they are written by [`TextStep::change`] (and
    /// [`TextStep::change_w`] for the fixed widths of the common path): the tracer's own
    /// compares say what changed, its frame order keeps the positions increasing, and the
    /// widths were checked when it was created; otherwise by [`TextStep::line`], which checks
    /// each value.
    #[inline(always)]
    pub fn step(&mut self, t: u64, i: &Inputs) -> Result<&Outputs, WriteError> {
        if self.held.valid {
            if let Some(s) = self.run.step(t)? {
                // the frame holds the tracer's values: only what changed
                if self.exact {
                    self.held.edge(Changes(s), self.core, i, false)?;
                } else {
                    self.held.edge(s, self.core, i, false)?;
                }
                return Ok(&self.held.outputs);
            }
        }
        let mut fr = self.run.frame_run()?;
        let s = fr.step(t)?;
        let full = !(self.held.valid && s.is_current());
        self.held.edge(s, self.core, i, full)?;
        Ok(&self.held.outputs)
    }
}

impl Held {
    /// One traced edge into a step `s` that has started: the inputs, outputs and registers
    /// before the edge (every value when `full`), the edge, its internals. The step is held
    /// by value and lent to the out-of-line groups by value too (they give it back), so it
    /// stays in registers on the common path (a [`TextStep`] keeps its end of text there).
    #[inline(always)]
    fn edge<S: StepSink>(
        &mut self,
        s: S,
        m: &mut Pmu50,
        i: &Inputs,
        full: bool,
    ) -> Result<(), WriteError> {
        let h = self;
        h.valid = false;
        let before = h.before_edge(s, m.regs(), i, full);
        let pmu50_core::TracedStep {
            internals: x,
            after,
            wide,
            ..
        } = m.step_traced(i);
        if wide {
            h.outputs = after;
        } else {
            copy_narrow_outputs(&mut h.outputs, &after);
        }
        h.wide = wide;
        let mut s = before?;
        if full {
            h.last_x = x.packed();
            all_internals(s, &x)?;
        } else {
            // after every edge: a narrow one may set `upd` (a sample that moved nothing), and
            // has every other internal false
            let narrow = Internals {
                upd: x.upd,
                ..Internals::default()
            }
            .packed();
            debug_assert!(
                wide || x.packed() == narrow,
                "a narrow edge set an internal other than upd: {x:?}"
            );
            let x = if wide { x.packed() } else { narrow };
            if x != h.last_x {
                diff_internals(&mut s, x, std::mem::replace(&mut h.last_x, x))?;
            }
        }
        h.valid = true;
        Ok(())
    }

    /// The inputs, outputs and registers of the step (before the edge).
    #[inline(always)]
    fn before_edge<S: StepSink>(
        &mut self,
        mut s: S,
        r: &Regs,
        i: &Inputs,
        full: bool,
    ) -> Result<S, WriteError> {
        let i = i.packed();
        if full {
            self.last_i = i;
            self.last_o = self.outputs;
            self.last_r = *r;
            let s = all_inputs(s, i)?;
            let s = all_outputs(s, &self.outputs)?;
            return all_registers(s, r);
        }
        if self.last_i != i {
            diff_inputs(&mut s, i, std::mem::replace(&mut self.last_i, i))?;
        }
        // the groups in the frame's order, so the writer's list of changes stays sorted
        if self.wide {
            let s = diff_outputs(s, &self.outputs, &mut self.last_o)?;
            diff_registers(s, r, &mut self.last_r)
        } else {
            narrow_outputs(&mut s, &self.outputs, &mut self.last_o)?;
            narrow_registers(&mut s, r, &mut self.last_r)?;
            Ok(s)
        }
    }
}

/// Where a step's values go: a frame run's step ([`RunStep::set`]) or a text run's
/// ([`TextStep::line`], written at once).
trait StepSink {
    fn put(&mut self, k: usize, v: u64) -> Result<(), WriteError>;

    /// [`StepSink::put`] of a signal that is `N` bits wide in the core (0: a width known only
    /// at run time, from the structural parameters).
    #[inline(always)]
    fn put_w<const N: usize>(&mut self, k: usize, v: u64) -> Result<(), WriteError> {
        self.put(k, v)
    }
}

impl<E: Emitter> StepSink for RunStep<'_, E> {
    #[inline(always)]
    fn put(&mut self, k: usize, v: u64) -> Result<(), WriteError> {
        self.set(k, v)
    }
}

impl<W: Write> StepSink for TextStep<'_, '_, W> {
    #[inline(always)]
    fn put(&mut self, k: usize, v: u64) -> Result<(), WriteError> {
        self.line(k, v)
    }
}

/// A text step given only values that changed, of a frame whose widths are the core's
/// ([`TextStep::change`]; [`TextStep::change_w`] where the width is known at compile time).
struct Changes<'s, 'a, W: Write>(TextStep<'s, 'a, W>);

impl<W: Write> StepSink for Changes<'_, '_, W> {
    #[inline(always)]
    fn put(&mut self, k: usize, v: u64) -> Result<(), WriteError> {
        self.0.change(k, v);
        Ok(())
    }

    #[inline(always)]
    fn put_w<const N: usize>(&mut self, k: usize, v: u64) -> Result<(), WriteError> {
        if N == 0 {
            self.0.change(k, v);
        } else {
            self.0.change_w::<N>(k, v);
        }
        Ok(())
    }
}

/// A traced value as the frame's integer.
trait Value: Copy + PartialEq {
    fn value(self) -> u64;
}

impl Value for bool {
    #[inline(always)]
    fn value(self) -> u64 {
        u64::from(self)
    }
}

impl Value for u8 {
    #[inline(always)]
    fn value(self) -> u64 {
        u64::from(self)
    }
}

impl Value for u16 {
    #[inline(always)]
    fn value(self) -> u64 {
        u64::from(self)
    }
}

impl Value for pmu50_core::drive_interval_changing_56b::Fig17 {
    #[inline(always)]
    fn value(self) -> u64 {
        self as u64
    }
}

impl Value for pmu50_core::drive_interval_changing_56b::Fig18 {
    #[inline(always)]
    fn value(self) -> u64 {
        self as u64
    }
}

/// `diff`: compare each field of a group with the held value, give the writer the ones that
/// differ (at positions `base + k`) and update the held value; the code written out per field.
macro_rules! diff_fn {
    // inline: the step lent
    (inline, $diff:ident, $t:ty, $base:expr, [$($k:literal : $($f:ident).+ $(/ $w:literal)?),* $(,)?]) => {
        #[inline(always)]
        fn $diff<S: StepSink>(s: &mut S, cur: &$t, held: &mut $t) -> Result<(), WriteError> {
            diff_fields!(s, cur, held, $base, [$($k : $($f).+ $(/ $w)?),*]);
            Ok(())
        }
    };
    // out of line: the step by value, given back
    (outline, $diff:ident, $t:ty, $base:expr, [$($k:literal : $($f:ident).+ $(/ $w:literal)?),* $(,)?]) => {
        #[inline(never)]
        fn $diff<S: StepSink>(mut s: S, cur: &$t, held: &mut $t) -> Result<S, WriteError> {
            diff_fields!(s, cur, held, $base, [$($k : $($f).+ $(/ $w)?),*]);
            Ok(s)
        }
    };
}

/// The body of [`diff_fn!`]: per field, when `cur`'s differs from `held`'s, the value to the
/// step `s` and `held` updated. A field written `field / N` is `N` bits wide in the core
/// ([`StepSink::put_w`]); without a width, its width is known only at run time (0).
macro_rules! diff_fields {
    ($s:ident, $cur:ident, $held:ident, $base:expr, [$($k:literal : $($f:ident).+ $(/ $w:literal)?),*]) => {
        $( if $cur.$($f).+ != $held.$($f).+ {
            $s.put_w::<{ 0 $(+ $w)? }>($base + $k, Value::value($cur.$($f).+))?;
            $held.$($f).+ = $cur.$($f).+;
        } )*
    };
}

/// Functions over one group's fields: `all` gives the writer every field, `diff` as
/// [`diff_fn!`] (both out of line: they run at the first step and after wide edges).
macro_rules! group {
    ($all:ident, $diff:ident, $t:ty, $base:expr, [$($k:literal : $($f:ident).+),* $(,)?]) => {
        #[inline(never)]
        fn $all<S: StepSink>(mut s: S, cur: &$t) -> Result<S, WriteError> {
            $( s.put($base + $k, Value::value(cur.$($f).+))?; )*
            Ok(s)
        }

        diff_fn!(outline, $diff, $t, $base, [$($k : $($f).+),*]);
    };
}

/// The few fields a narrow edge can change: [`diff_fn!`] inlined (each field with its width in
/// the core, or none when it depends on the structural parameters), and (with `$copy`) a copy
/// of just those fields from one struct into another.
macro_rules! narrow {
    ($diff:ident, $t:ty, $base:expr, $table:expr, [$($k:literal : $($f:ident).+ $(/ $w:literal)?),* $(,)?]) => {
        diff_fn!(inline, $diff, $t, $base, [$($k : $($f).+ $(/ $w)?),*]);
        $($( const _: () = assert!(fixed_width($table[$k].width, $w), "a width in the tracer's list is not the signal table's"); )?)*
    };
    ($diff:ident, $copy:ident, $t:ty, $base:expr, $table:expr, [$($k:literal : $($f:ident).+ $(/ $w:literal)?),* $(,)?]) => {
        narrow!($diff, $t, $base, $table, [$($k : $($f).+ $(/ $w)?),*]);

        #[inline(always)]
        fn $copy(dst: &mut $t, src: &$t) {
            $( dst.$($f).+ = src.$($f).+; )*
        }
    };
}

/// The signal table gives `w` as a fixed width of `n` bits (the widths the tracer passes to
/// [`StepSink::put_w`] are checked against the table at compile time with it).
const fn fixed_width(w: Width, n: usize) -> bool {
    matches!(w, Width::Bits(b) if b as usize == n)
}

/// The fixed width `w` of the signal table, at compile time (a structural width does not
/// compile).
const fn bits(w: Width) -> usize {
    match w {
        Width::Bits(b) => b as usize,
        _ => panic!("the tracer gives this signal a fixed width; the signal table's is structural"),
    }
}

/// The widths of the inputs `bus_addr` and `bus_wdata` and of the internals `fig17`/`fig18`, from
/// the signal table; the other inputs and internals are flags (checked below).
const BUS_ADDR_BITS: usize = bits(signals::INPUTS[5].width);
const BUS_WDATA_BITS: usize = bits(signals::INPUTS[6].width);
const FIG_BITS: usize = bits(signals::INTERNALS[7].width);

// The inputs as one word ([`Inputs::packed`]): input k (the order of `Inputs::values`) is byte k,
// `bus_wdata` bytes 6 and 7.
const INPUT_SHIFT: [u32; 7] = [0, 8, 16, 24, 32, 40, 48];
const INPUT_MASK: [u64; 7] = [0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFFFF];
/// The input at each byte of the word.
const INPUT_OF_BYTE: [usize; 8] = [0, 1, 2, 3, 4, 5, 6, 6];

/// Every input of the packed word `cur`.
#[inline(never)]
fn all_inputs<S: StepSink>(mut s: S, cur: u64) -> Result<S, WriteError> {
    for k in 0..INPUT_SHIFT.len() {
        s.put(INPUTS + k, cur >> INPUT_SHIFT[k] & INPUT_MASK[k])?;
    }
    Ok(s)
}

/// The inputs of the packed word `cur` that differ from `held`'s, in increasing positions: one
/// test a changed input, none for the others.
#[inline(always)]
fn diff_inputs<S: StepSink>(s: &mut S, cur: u64, held: u64) -> Result<(), WriteError> {
    let mut x = cur ^ held;
    while x != 0 {
        let k = INPUT_OF_BYTE[(x.trailing_zeros() / 8) as usize];
        let m = INPUT_MASK[k] << INPUT_SHIFT[k];
        let v = (cur & m) >> INPUT_SHIFT[k];
        match k {
            5 => s.put_w::<BUS_ADDR_BITS>(INPUTS + k, v)?,
            6 => s.put_w::<BUS_WDATA_BITS>(INPUTS + k, v)?,
            _ => s.put_w::<1>(INPUTS + k, v)?,
        }
        x &= !m;
    }
    Ok(())
}

group!(all_outputs, diff_outputs, Outputs, OUTPUTS, [
    0: sig, 1: vr_hi, 2: vm_en, 3: vs1_en, 4: vs2_en, 5: vp_en, 6: rail_hi, 7: st, 8: sr, 9: ps_win, 10: smp, 11: cs, 12: cc,
    13: cnt_s, 14: cnt_c, 15: cnt_r, 16: si, 17: hist_s, 18: hist_c, 19: diag, 20: quadrant_skip, 21: bus_rdata, 22: bus_err,
]);

// The outputs a narrow edge can change: the timer's decode, `sr`, `diag`, the read data (the
// others are `sig` or decoded from registers it does not write).
narrow!(narrow_outputs, copy_narrow_outputs, Outputs, OUTPUTS, signals::OUTPUTS, [4: vs2_en / 1, 7: st / 1, 8: sr / 1, 9: ps_win / 1, 10: smp / 1, 19: diag / 1, 21: bus_rdata / 16]);

// Every register in the order of `Regs::values`.
group!(all_registers, diff_registers, Regs, REGISTERS, [
    0: action_switching.sync,
    1: register_file.adaptive, 2: register_file.pw, 3: register_file.pi, 4: register_file.ps, 5: register_file.si_max,
    6: register_file.si_min, 7: register_file.t1, 8: register_file.t2, 9: register_file.cth, 10: register_file.smp_on,
    11: register_file.bus_err, 12: register_file.rdata,
    13: timing_generator.tmr,
    14: sensor_power_determination.sr,
    15: comparator_latch.cs, 16: comparator_latch.cc, 17: comparator_latch.vld,
    18: updown_counter.cnt_s, 19: updown_counter.cnt_c, 20: updown_counter.quadrant_skip,
    21: drive_interval.si, 22: drive_interval.hist_s, 23: drive_interval.hist_c, 24: drive_interval.cnt_r,
    25: count_diagnosis.diag,
]);

// The registers a narrow edge writes (`kernel::NARROW_WRITES`), at `NARROW_REGISTERS`.
narrow!(narrow_registers, Regs, REGISTERS, signals::REGISTERS, [0: action_switching.sync, 12: register_file.rdata / 16, 13: timing_generator.tmr / 16, 14: sensor_power_determination.sr / 1, 25: count_diagnosis.diag / 1]);

/// Every internal.
#[inline(never)]
fn all_internals<S: StepSink>(mut s: S, x: &Internals) -> Result<S, WriteError> {
    let x = x.packed();
    for k in 0..9 {
        s.put(INTERNALS + k, (x >> (8 * k)) as u64 & 0xFF)?;
    }
    Ok(s)
}

/// The internals of the packed word `cur` ([`Internals::packed`]: internal k of
/// `Internals::values` at byte k) that differ from `held`'s, in increasing positions.
#[inline(always)]
fn diff_internals<S: StepSink>(s: &mut S, cur: u128, held: u128) -> Result<(), WriteError> {
    let mut x = cur ^ held;
    while x != 0 {
        let k = (x.trailing_zeros() / 8) as usize;
        let v = (cur >> (8 * k)) as u64 & 0xFF;
        if k < 7 {
            s.put_w::<1>(INTERNALS + k, v)?;
        } else {
            s.put_w::<FIG_BITS>(INTERNALS + k, v)?;
        }
        x &= !(0xFF << (8 * k));
    }
    Ok(())
}

// The flags `diff_inputs` and `diff_internals` give as 1 bit wide are so in the signal table,
// and `fig18` is as wide as `fig17`.
const _: () = {
    let (i, x) = (signals::INPUTS, signals::INTERNALS);
    assert!(
        i.len() == 7 && x.len() == 9,
        "the tracer's input and internal widths assume 7 inputs and 9 internals"
    );
    let mut k = 0;
    while k < 5 {
        assert!(
            fixed_width(i[k].width, 1),
            "an input the tracer writes as a flag is not 1 bit wide"
        );
        k += 1;
    }
    let mut k = 0;
    while k < 7 {
        assert!(
            fixed_width(x[k].width, 1),
            "an internal the tracer writes as a flag is not 1 bit wide"
        );
        k += 1;
    }
    assert!(
        fixed_width(x[8].width, FIG_BITS),
        "fig17 and fig18 differ in width"
    );
};
