//! The core's signals into a checked waveform frame, one step per tick, giving only the values
//! of the structs that changed.
//!
//! A tick of the core is four structs: its inputs, its outputs (Moore, from the registers before
//! the edge), its registers before the edge (one struct per block) and the internals of the
//! edge. Most of them are equal from one tick to the next: in a parked car only the free-running
//! timer `timing_generator.tmr` changes at most edges. [`CoreTrace`] keeps the structs of the
//! last tick, compares each with its successor as a whole (a few word compares) and hands the
//! writer ([`pmu50_waves::writer::FrameStep`]) only the fields of the structs that differ. The
//! writer still checks what it always checks (time order, double assignment, widths of the
//! values that changed, positions) and writes only the values that changed, so the file is
//! byte for byte the one [`Writer::dump_frame`] writes from every value of every tick
//! (`tests/core_trace.rs`).
//!
//! The frame's positions are given by a [`Layout`]: where each group starts in the frame, in the
//! order of the declarations (`Inputs::values`, `Outputs::values`, `Regs::values`,
//! `Internals::values`; docs/signals.md).

use pmu50_core::pmu50::{Inputs, Internals, Outputs, Regs};
use pmu50_waves::writer::{Emitter, Frame, FrameStep, WriteError, Writer};

/// Number of core inputs, outputs, registers and internals (the four groups of a frame).
pub const N_INPUTS: usize = 7;
pub const N_OUTPUTS: usize = 23;
pub const N_REGISTERS: usize = 26;
pub const N_INTERNALS: usize = 9;

/// Where each group of signals starts in the frame (positions of [`Writer::frame`]'s list); a
/// group that is not in the frame is `None`. Within a group the order is its declaration order.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Layout {
    pub inputs: Option<usize>,
    pub outputs: Option<usize>,
    pub registers: Option<usize>,
    pub internals: Option<usize>,
}

impl Layout {
    /// Inputs, outputs, registers, internals, one after the other from position 0.
    pub const ALL: Layout = Layout { inputs: Some(0), outputs: Some(N_INPUTS), registers: Some(N_INPUTS + N_OUTPUTS), internals: Some(N_INPUTS + N_OUTPUTS + N_REGISTERS) };

    /// Number of positions the layout uses (the frame must have exactly this many variables).
    pub fn len(&self) -> usize {
        [(self.inputs, N_INPUTS), (self.outputs, N_OUTPUTS), (self.registers, N_REGISTERS), (self.internals, N_INTERNALS)].iter().filter(|(b, _)| b.is_some()).map(|(_, n)| n).sum()
    }

    /// True when the layout holds no group.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// The structs of one tick, as dumped.
#[derive(Clone, Copy)]
struct Tick {
    i: Inputs,
    o: Outputs,
    r: Regs,
    x: Internals,
}

/// A frame of the core's signals and the structs of its last step (see the module documentation).
pub struct CoreTrace {
    frame: Frame,
    layout: Layout,
    /// The structs of the last complete dump, when `valid`.
    last: Tick,
    valid: bool,
}

/// A frame whose length is not the layout's, or groups that overlap or leave gaps.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("core trace layout {layout:?} needs a frame of {need} variables at positions 0..{need}, each group once without overlap; the frame has {got}")]
pub struct LayoutError {
    pub layout: Layout,
    pub need: usize,
    pub got: usize,
}

impl CoreTrace {
    /// Trace into `frame` (declared with [`Writer::frame`]) whose variables are the groups of
    /// `layout` at its positions.
    pub fn new(frame: Frame, layout: Layout) -> Result<CoreTrace, LayoutError> {
        let need = layout.len();
        let err = LayoutError { layout, need, got: frame.len() };
        if frame.len() != need {
            return Err(err);
        }
        let mut used = vec![false; need];
        for (b, n) in [(layout.inputs, N_INPUTS), (layout.outputs, N_OUTPUTS), (layout.registers, N_REGISTERS), (layout.internals, N_INTERNALS)] {
            if let Some(b) = b {
                for p in b..b + n {
                    match used.get_mut(p) {
                        Some(u) if !*u => *u = true,
                        _ => return Err(err),
                    }
                }
            }
        }
        Ok(CoreTrace { frame, layout, last: Tick { i: Inputs::default(), o: Outputs::default(), r: pmu50_core::pmu50::reset(&pmu50_core::Params::default()), x: Internals::default() }, valid: false })
    }

    /// The frame (for [`Writer::dump_frame`] after the trace, e.g. a final dump).
    pub fn frame_mut(&mut self) -> &mut Frame {
        &mut self.frame
    }

    /// Dump one tick at time `t`: the inputs `i` of the edge, the outputs `o` and registers `r`
    /// before it and its internals `x`. Equivalent to [`Writer::dump_frame`] with every value of
    /// the layout, with the same checks and errors.
    #[inline]
    pub fn dump<E: Emitter>(&mut self, w: &mut Writer<E>, t: u64, i: &Inputs, o: &Outputs, r: &Regs, x: &Internals) -> Result<(), WriteError> {
        let mut s = w.frame_step(&mut self.frame, t)?;
        // Every value when the frame's variables may hold other values than the last dump's
        // structs: first tick, a change to the writer in between, or a dump that failed half
        // way (`valid` is cleared here and set again only after a complete dump).
        let full = !(self.valid && s.is_current());
        self.valid = false;
        let (l, p) = (&self.layout, &mut self.last);
        if let Some(b) = l.inputs {
            if full || p.i != *i {
                inputs(&mut s, b, i, if full { None } else { Some(&p.i) })?;
                p.i = *i;
            }
        }
        if let Some(b) = l.outputs {
            if full || p.o != *o {
                outputs(&mut s, b, o, if full { None } else { Some(&p.o) })?;
                p.o = *o;
            }
        }
        if let Some(b) = l.registers {
            // the timer on its own, the other registers block by block
            let tmr = r.timing_generator.tmr;
            if full || p.r.timing_generator.tmr != tmr {
                s.set(b + 13, u64::from(tmr))?;
            }
            let q = &p.r;
            let same = !full
                && q.action_switching == r.action_switching
                && q.register_file == r.register_file
                && q.sensor_power_determination == r.sensor_power_determination
                && q.comparator_latch == r.comparator_latch
                && q.updown_counter == r.updown_counter
                && q.drive_interval == r.drive_interval
                && q.count_diagnosis == r.count_diagnosis;
            if !same {
                registers(&mut s, b, r, if full { None } else { Some(q) })?;
            }
            p.r = *r;
        }
        if let Some(b) = l.internals {
            if full || p.x != *x {
                internals(&mut s, b, x, if full { None } else { Some(&p.x) })?;
                p.x = *x;
            }
        }
        self.valid = true;
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

/// The fields of one group at positions `b + k`: every field without a last tick, else only
/// the fields that differ from it (one compare each, the code written out per field).
macro_rules! fields {
    ($s:ident, $b:ident, $cur:ident, $last:ident, [$($k:literal : $($f:ident).+),* $(,)?]) => {{
        match $last {
            None => {
                $( $s.set($b + $k, Value::value($cur.$($f).+))?; )*
            }
            Some(p) => {
                $( if $cur.$($f).+ != p.$($f).+ {
                    $s.set($b + $k, Value::value($cur.$($f).+))?;
                } )*
            }
        }
        Ok(())
    }};
}

#[inline(never)]
fn inputs<E: Emitter>(s: &mut FrameStep<'_, E>, b: usize, i: &Inputs, last: Option<&Inputs>) -> Result<(), WriteError> {
    fields!(s, b, i, last, [0: ig, 1: vs2_ok, 2: cmp_s, 3: cmp_c, 4: bus_we, 5: bus_addr, 6: bus_wdata])
}

#[inline(never)]
fn outputs<E: Emitter>(s: &mut FrameStep<'_, E>, b: usize, o: &Outputs, last: Option<&Outputs>) -> Result<(), WriteError> {
    fields!(s, b, o, last, [
        0: sig, 1: vr_hi, 2: vm_en, 3: vs1_en, 4: vs2_en, 5: vp_en, 6: rail_hi, 7: st, 8: sr, 9: ps_win, 10: smp, 11: cs, 12: cc,
        13: cnt_s, 14: cnt_c, 15: cnt_r, 16: si, 17: hist_s, 18: hist_c, 19: diag, 20: quadrant_skip, 21: bus_rdata, 22: bus_err,
    ])
}

/// The registers (the order of `Regs::values`) except the timer `timing_generator.tmr`
/// (position 13), which [`CoreTrace::dump`] compares on its own: it is the one that changes at
/// most edges.
#[inline(never)]
fn registers<E: Emitter>(s: &mut FrameStep<'_, E>, b: usize, r: &Regs, last: Option<&Regs>) -> Result<(), WriteError> {
    fields!(s, b, r, last, [
        0: action_switching.sync,
        1: register_file.adaptive, 2: register_file.pw, 3: register_file.pi, 4: register_file.ps, 5: register_file.si_max,
        6: register_file.si_min, 7: register_file.t1, 8: register_file.t2, 9: register_file.cth, 10: register_file.smp_on,
        11: register_file.bus_err, 12: register_file.rdata,
        14: sensor_power_determination.sr,
        15: comparator_latch.cs, 16: comparator_latch.cc, 17: comparator_latch.vld,
        18: updown_counter.cnt_s, 19: updown_counter.cnt_c, 20: updown_counter.quadrant_skip,
        21: drive_interval.si, 22: drive_interval.hist_s, 23: drive_interval.hist_c, 24: drive_interval.cnt_r,
        25: count_diagnosis.diag,
    ])
}

#[inline(never)]
fn internals<E: Emitter>(s: &mut FrameStep<'_, E>, b: usize, x: &Internals, last: Option<&Internals>) -> Result<(), WriteError> {
    fields!(s, b, x, last, [0: kon, 1: koff, 2: upd, 3: first, 4: chg_s, 5: chg_c, 6: skip_clr, 7: fig17, 8: fig18])
}
