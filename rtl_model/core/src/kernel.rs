//! Fast kernel of the PMU 50 core: the fast path that [`crate::Pmu50::step`] runs.
//!
//! This file is an implementation, not the specification. The specification is the readable
//! per-block model: one file per patent block and the top level [`crate::pmu50::eval`], stepped by
//! [`crate::reference::Pmu50Spec`]. This kernel computes the same clock edge as that model, hand
//! specialised for speed:
//!
//! - the registers stay in the spec's [`Regs`] (no conversion: waveforms, lockstep read-back and
//!   fast-forward read them directly) and are updated in place;
//! - the structural parameters are turned once into masks ([`Consts`]); the programmable
//!   parameters are read straight from the register file instead of being copied into a
//!   [`crate::Params`] every tick;
//! - the common edge (no bus write, no sample, no key edge) touches only the synchronizer, the
//!   timer, `sr`, `rdata` and `diag`; the rare events (bus write, key edge) are out of line and
//!   run the specification itself ([`crate::pmu50::next`]: the register file's read mux and
//!   write map, every block's next-state function), after which the caches are rebuilt;
//! - the registered read mux reads a table of what each address reads (filled from the
//!   register file's own read mux, [`crate::pmu50::read`]), and the timer is decoded
//!   with thresholds for the key mode of the registers ([`Shadow`]), both kept beside the
//!   registers and rebuilt where what they depend on changes outside the common edge;
//! - an edge is *narrow* or *wide* ([`step_traced`]), which a tracer uses to compare only
//!   what the edge can have changed (as Verilator's tracer uses its activity flags). A wide edge
//!   is a bus write, a key edge, a key-off sampling strobe (the 56b pulse, FIG. 17/18) or a key-on
//!   sample that presets the counters or finds a sign changed, and may write any register. A
//!   narrow edge changes only [`NARROW_WRITES`] (`sync`, `tmr`, `sr`, `rdata`, `diag`), keeps
//!   `sig`, and has all internals false but `upd` (a key-on sample that found both signs as
//!   latched writes the latches with the values they hold). Simulator knowledge, not a hardware
//!   signal or a clock enable. Tested from any register state
//!   (`narrow_edges_write_only_their_registers`) and, for key-on strobes, in both directions
//!   (`key_on_strobes_that_move_nothing_are_narrow`, `key_on_strobe_cases_reach_both_kinds`);
//! - `sig` is a test of the synchronizer stage's mask ([`Consts`]), not a shift by a variable;
//! - the counter rules of [0096]-[0099] are used in closed form (`cnt_s` counts up iff
//!   `cs_new == cc`, `cnt_c` counts up iff `cc_new != cs`), and the diagnosis of [0119]
//!   (|cnt_s - cnt_c| >= 2 in the counters' two's complement) as `((d + 1) & mask) > 2`.
//!
//! Equality with the specification is proven by tests that run both and compare every register
//! and every output on every tick, and the internals of every cycle:
//! `rtl_model/core/tests/kernel_equivalence.rs` (proptest: arbitrary register states and inputs
//! for one edge; random legal parameters with random input runs, bus writes including refused
//! ones, key edges and W1C clears for long runs) and `tests/kernel_scenarios.rs` (every shipped
//! scenario and the 200 seeded random scenarios of the co-simulation, `hdl/cosim.sh`, replayed
//! through both). The C ABI (`hdl/ffi`) calls `Pmu50::step_traced`, so the HDL lockstep and its
//! mutants run against this kernel.
//!
//! Evaluation order and paragraphs are those of [`crate::pmu50`]; each step below names the block
//! it stands for.

use crate::drive_interval_changing_56b::{Fig17, Fig18};
use crate::pmu50::{Inputs, Internals, Outputs, Regs, Structural, TracedStep};
use crate::register_file::{addr, status};

/// The structural parameters, pre-decoded into the masks the kernel uses.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Consts {
    /// As given: the rare edge and the read mux run the specification's blocks with them.
    structural: Structural,
    /// The stage of `sync` that is `sig`, as a mask: bit `sync_depth - 1` (depth clamped to
    /// 1..=4 as in 56a), tested instead of shifted by a variable.
    sig_bit: u8,
    /// Mask of the synchronizer stages.
    sync_mask: u8,
    /// Mask of a `cnt_width`-bit counter (width clamped to 2..=16 as in 58c/58d).
    cnt_mask: u16,
}

impl Consts {
    pub fn new(s: &Structural) -> Consts {
        let depth = s.sync_depth.clamp(1, 4);
        let width = s.cnt_width.clamp(2, 16);
        Consts {
            structural: *s,
            sig_bit: 1u8 << (depth - 1),
            sync_mask: (1u8 << depth) - 1,
            cnt_mask: ((1u32 << width) - 1) as u16,
        }
    }
}

/// The read side of register file 2, kept beside the registers by [`step`]: what each bus address
/// reads, and the timing generator's decode for the key mode and parameters of the registers
/// (both change only at a bus write or a key edge; the period with the key off is `si`, which a
/// 56b pulse refreshes).
///
/// A cache, not state: it is a function of the registers ([`Shadow::of`]) and is rebuilt whenever
/// that function's inputs change outside the common edge (a bus write or a key edge, which go
/// through [`edge_rare`]; a reset). In the common edge, the only readable values
/// that change are the counters and the STATUS bits of a sample (refreshed there) and
/// STATUS.`sig`/`sr`/`diag`, which the read adds from the registers at each edge. With it, the
/// registered read mux of every edge is one table load instead of a jump over 21 addresses
/// (the bus address changes on 18 % of the keyoff_turns edges and 59 % of the random ones, and
/// each change mispredicted the jump).
#[derive(Clone)]
pub struct Shadow {
    /// Read value of each address; STATUS without its `sig`, `sr` and `diag` bits.
    rd: [u16; 256],
    /// Timing generator 56's decode in the key mode of the registers (`sig`, which changes only
    /// at a key edge, where the shadow is rebuilt), so the common edge decodes the timer `t`
    /// without choosing between the modes: `st` = (t == `st_at`), `vs2_en` = (t < `vs2_lt`),
    /// `ps_win` = (t - `ps_lo` < `ps_len`, wrapping), `smp` = (t + 1 == `smp_at`), and the timer
    /// wraps at `period`. Key off: 0, Wt = pw + pi + ps, pw + pi, ps, Wt, `si`. Key on: never
    /// (`u32::MAX`), always (`u32::MAX`), never (0, 0), `smp_on`, `smp_on`.
    st_at: u32,
    vs2_lt: u32,
    ps_lo: u32,
    ps_len: u32,
    smp_at: u32,
    period: u32,
    /// Count diagnosis of the counters held (|cnt_s - cnt_c| >= 2 or `quadrant_skip`): the
    /// value `diag` takes at an edge that does not change them.
    diag: bool,
}

/// STATUS bits the common edge changes, read from the registers at each edge.
const STATUS_LIVE: u16 = (1 << status::SIG) | (1 << status::SR) | (1 << status::DIAG);

impl Shadow {
    /// The shadow of the registers `r` (built with the core, at reset, and for the tests).
    pub fn of(c: &Consts, r: &Regs) -> Shadow {
        let mut s = Shadow {
            rd: [0; 256],
            st_at: 0,
            vs2_lt: 0,
            ps_lo: 0,
            ps_len: 0,
            smp_at: 0,
            period: 0,
            diag: false,
        };
        s.rebuild(c, r);
        s
    }

    #[cold]
    #[inline(never)]
    fn rebuild(&mut self, c: &Consts, r: &Regs) {
        for a in 0..addr::STATUS {
            self.rd[usize::from(a)] = crate::pmu50::read(&c.structural, r, false, a);
        }
        self.refresh_reads(c, r, []);
        let f = &r.register_file;
        let ps_start = u32::from(f.pw) + u32::from(f.pi);
        let wt = ps_start + u32::from(f.ps);
        if sig_of(c, r.action_switching.sync) {
            (self.st_at, self.vs2_lt, self.ps_lo, self.ps_len) = (u32::MAX, u32::MAX, 0, 0);
            (self.smp_at, self.period) = (u32::from(f.smp_on), u32::from(f.smp_on));
        } else {
            (self.st_at, self.vs2_lt, self.ps_lo, self.ps_len) = (0, wt, ps_start, u32::from(f.ps));
            (self.smp_at, self.period) = (wt, u32::from(r.drive_interval.si));
        }
        self.diag = diag_of(c, &r.updown_counter);
    }

    /// After a sample that changed the latches or counters (the registers after the edge): the
    /// counters, their diagnosis and STATUS.
    #[inline(always)]
    fn refresh_sample(&mut self, c: &Consts, r: &Regs) {
        self.refresh_reads(c, r, [addr::CNT_S, addr::CNT_C]);
        self.diag = diag_of(c, &r.updown_counter);
    }

    /// After a 56b pulse (key off; the registers after the edge): `cnt_r`, `si`, STATUS
    /// (history) and the timer's period, which is `si` with the key off.
    #[inline(always)]
    fn refresh_pulse(&mut self, c: &Consts, r: &Regs) {
        self.refresh_reads(c, r, [addr::CNT_R, addr::SI]);
        self.period = u32::from(r.drive_interval.si);
    }

    /// The read values of the addresses `a` and of STATUS (without its live bits), from the
    /// register file's read mux.
    #[inline(always)]
    fn refresh_reads<const N: usize>(&mut self, c: &Consts, r: &Regs, a: [u8; N]) {
        for a in a {
            self.rd[usize::from(a)] = crate::pmu50::read(&c.structural, r, false, a);
        }
        self.rd[usize::from(addr::STATUS)] =
            crate::pmu50::read(&c.structural, r, false, addr::STATUS) & !STATUS_LIVE;
    }

    /// The read mux at `a` for the registers before the edge (`sig`, `sr` and `diag` of `r`).
    #[inline(always)]
    fn read(&self, r: &Regs, sig: bool, a: u8) -> u16 {
        let live = (u16::from(sig) << status::SIG)
            | (u16::from(r.sensor_power_determination.sr) << status::SR)
            | (u16::from(r.count_diagnosis.diag) << status::DIAG);
        let is_status = 0u16.wrapping_sub(u16::from(a == addr::STATUS));
        self.rd[usize::from(a)] | (live & is_status)
    }
}

impl std::fmt::Debug for Shadow {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Shadow")
            .field("period", &self.period)
            .field("diag", &self.diag)
            .finish_non_exhaustive()
    }
}

/// Count diagnosis 58e/[0119] of the counters: |cnt_s - cnt_c| >= 2 in the counters' two's
/// complement, i.e. (d + 1) mod 2^W > 2, or a quadrant skip.
#[inline(always)]
fn diag_of(c: &Consts, u: &crate::updown_counter_58cd::Regs) -> bool {
    let d = u.cnt_s.wrapping_sub(u.cnt_c).wrapping_add(1) & c.cnt_mask;
    (d > 2) | u.quadrant_skip
}

#[inline(always)]
fn sig_of(c: &Consts, sync: u8) -> bool {
    sync & c.sig_bit != 0
}

/// Timing generator 56 decode (Moore): (`st`, `vs2_en`, `ps_win`, `smp`) of the registers `r`.
#[inline(always)]
fn decode(r: &Regs, sig: bool) -> (bool, bool, bool, bool) {
    let f = &r.register_file;
    let t = u32::from(r.timing_generator.tmr);
    if sig {
        (false, true, false, t + 1 == u32::from(f.smp_on))
    } else {
        let ps_start = u32::from(f.pw) + u32::from(f.pi);
        let wt = ps_start + u32::from(f.ps);
        (t == 0, t < wt, t >= ps_start && t < wt, t + 1 == wt)
    }
}

/// The Moore outputs of the registers `r` (same as [`crate::pmu50::ports`]).
#[inline(always)]
pub fn ports(c: &Consts, r: &Regs) -> Outputs {
    outputs(&narrow_of(c, r), r)
}

/// The outputs an edge computes rather than reads from a register: `sig` (and the outputs that
/// are `sig`), the timer's decode, `sr`, `diag` and the read data. The common edge carries only
/// these out of its branch ([`step`]); [`outputs`] adds the rest.
struct Narrow {
    sig: bool,
    vs2_en: bool,
    st: bool,
    sr: bool,
    ps_win: bool,
    smp: bool,
    diag: bool,
    bus_rdata: u16,
}

/// [`Narrow`] decoded from the registers `r`.
#[inline(always)]
fn narrow_of(c: &Consts, r: &Regs) -> Narrow {
    let sig = sig_of(c, r.action_switching.sync);
    let (st, vs2_en, ps_win, smp) = decode(r, sig);
    Narrow {
        sig,
        vs2_en,
        st,
        sr: r.sensor_power_determination.sr,
        ps_win,
        smp,
        diag: r.count_diagnosis.diag,
        bus_rdata: r.register_file.rdata,
    }
}

/// The 23 outputs: `n`, and the ten that are registers of `r` (plus the constant `vp_en`).
#[inline(always)]
fn outputs(n: &Narrow, r: &Regs) -> Outputs {
    let u = &r.updown_counter;
    Outputs {
        sig: n.sig,
        vr_hi: n.sig,
        vm_en: n.sig,
        vs1_en: n.sig,
        vs2_en: n.vs2_en,
        vp_en: true,
        rail_hi: n.sig,
        st: n.st,
        sr: n.sr,
        ps_win: n.ps_win,
        smp: n.smp,
        cs: r.comparator_latch.cs,
        cc: r.comparator_latch.cc,
        cnt_s: u.cnt_s,
        cnt_c: u.cnt_c,
        cnt_r: r.drive_interval.cnt_r,
        si: r.drive_interval.si,
        hist_s: r.drive_interval.hist_s,
        hist_c: r.drive_interval.hist_c,
        diag: n.diag,
        quadrant_skip: u.quadrant_skip,
        bus_rdata: n.bus_rdata,
        bus_err: r.register_file.bus_err,
    }
}

/// Result of a sample edge for the comparator latch, the counters and FIG. 17/18.
struct Sample {
    first: bool,
    chg_s: bool,
    chg_c: bool,
}

/// Comparator latches 58a/58b and up/down counters 58c/58d at a sampling edge (`upd` = 1),
/// updating `r` in place; `skip_clr` is this cycle's W1C of `quadrant_skip`.
#[inline(always)]
fn sample(c: &Consts, r: &mut Regs, i: &Inputs) -> Sample {
    let (cs, cc, vld) = (
        r.comparator_latch.cs,
        r.comparator_latch.cc,
        r.comparator_latch.vld,
    );
    let (cs_new, cc_new) = (i.cmp_s, i.cmp_c);
    r.comparator_latch.cs = cs_new;
    r.comparator_latch.cc = cc_new;
    r.comparator_latch.vld = true;
    let m = c.cnt_mask;
    let u = &mut r.updown_counter;
    if !vld {
        // First sample after reset: preset from the quadrant.
        let (s, k) = match (cs_new, cc_new) {
            (true, true) => (0, 0),
            (true, false) => (0, 1),
            (false, false) => (1, 1),
            (false, true) => (1, 2),
        };
        u.cnt_s = s & m;
        u.cnt_c = k & m;
        return Sample {
            first: true,
            chg_s: false,
            chg_c: false,
        };
    }
    let chg_s = cs_new != cs;
    let chg_c = cc_new != cc;
    if chg_s && chg_c {
        u.quadrant_skip = true;
    } else if chg_s {
        // [0096]/[0097]: up iff the new Cs equals Cc.
        u.cnt_s = if cs_new == cc {
            u.cnt_s.wrapping_add(1)
        } else {
            u.cnt_s.wrapping_sub(1)
        } & m;
    } else if chg_c {
        // [0098]/[0099]: up iff the new Cc differs from Cs.
        u.cnt_c = if cc_new != cs {
            u.cnt_c.wrapping_add(1)
        } else {
            u.cnt_c.wrapping_sub(1)
        } & m;
    }
    Sample {
        first: false,
        chg_s,
        chg_c,
    }
}

/// Drive interval changing unit 56b at a key-off sampling strobe (`pulse` = 1, no `koff`), with the
/// pre-edge `sr`, the sign changes of this sample and the pre-edge parameters `f`. Returns the
/// FIG. 17 and FIG. 18 paths.
#[inline(always)]
fn drive_interval_pulse(
    d: &mut crate::drive_interval_changing_56b::Regs,
    f: &crate::register_file::Regs,
    sr: bool,
    chg_s: bool,
    chg_c: bool,
) -> (Fig17, Fig18) {
    if !f.adaptive {
        d.si = f.si_max;
        return (Fig17::Fixed, Fig18::Idle);
    }
    if !sr {
        return (Fig17::S1NoRise, Fig18::Idle);
    }
    // FIG. 18.
    let (detected, f18) = if chg_s {
        if d.hist_s {
            (false, Fig18::S21CsRepeat)
        } else {
            d.hist_s = true;
            d.hist_c = false;
            (true, Fig18::S23DetectedCs)
        }
    } else if chg_c {
        if d.hist_c {
            (false, Fig18::S26CcRepeat)
        } else {
            d.hist_s = false;
            d.hist_c = true;
            (true, Fig18::S28DetectedCc)
        }
    } else {
        (false, Fig18::S25NoChange)
    };
    // FIG. 17.
    let f17 = if detected {
        d.cnt_r = 0;
        if d.si <= f.si_min {
            Fig17::S5AtMin
        } else {
            d.si = d.si.saturating_sub(f.t1).max(f.si_min);
            Fig17::S6Shorten
        }
    } else if d.si >= f.si_max {
        Fig17::S7AtMax
    } else if d.cnt_r >= f.cth {
        d.si = (u32::from(d.si) + u32::from(f.t2)).min(u32::from(f.si_max)) as u16;
        d.hist_s = false;
        d.hist_c = false;
        d.cnt_r = d.cnt_r.saturating_add(1);
        Fig17::S10Expand
    } else {
        d.cnt_r = d.cnt_r.saturating_add(1);
        Fig17::S9Count
    };
    (f17, f18)
}

/// One edge, returning the outputs after it (the untraced path of [`crate::Pmu50::step`]).
///
/// The common edge (no bus write, no key edge: so no W1C, no key-off reset of 56b and the
/// parameters unchanged) is computed inline here, including the sampling strobe (`upd`, the
/// comparator latches, the counters and the FIG. 17/18 pulse); the eight outputs it computes
/// (`sig`, the timer's decode, `sr`, `diag`, the read data) come from the values just computed.
/// A bus write or a key edge goes through [`edge_rare`] out of line, and those eight are then decoded
/// from its registers. On both paths the other fifteen outputs (ten registers, the four copies of
/// `sig`, the constant `vp_en`) are built after the branch. Both give the same registers and
/// outputs as [`crate::pmu50::eval`] (tested on every tick).
#[inline(always)]
pub fn step(c: &Consts, r: &mut Regs, sh: &mut Shadow, i: &Inputs) -> Outputs {
    step_with::<false>(c, r, sh, i).0
}

/// The registers a narrow edge may change (see [`step_traced`]): the synchronizer
/// `action_switching.sync`, the timer `timing_generator.tmr`, `sensor_power_determination.sr`,
/// `register_file.rdata` and `count_diagnosis.diag`. Every other register keeps its value (a
/// narrow key-on sample writes the latches with the values they hold).
pub const NARROW_WRITES: [&str; 5] = [
    "action_switching.sync",
    "timing_generator.tmr",
    "sensor_power_determination.sr",
    "register_file.rdata",
    "count_diagnosis.diag",
];

/// [`step`], traced (the path of [`crate::Pmu50::step_traced`]: waveforms, the C ABI's
/// lockstep): the outputs before and after the edge, the internals of the cycle, and whether the
/// edge was *wide*. The same inline common edge; a bus write or key edge goes through
/// [`edge_rare`].
///
/// A wide edge is a bus write or a key edge (the out-of-line [`edge_rare`]), a sampling strobe
/// at key off (the 56b pulse, which sets `fig17` and `fig18`), or a key-on sample that presets
/// the counters or finds a sign changed. A narrow edge (`wide` false) changes only the registers
/// of [`NARROW_WRITES`], leaves `sig` (and so every output that is `sig`) unchanged, and has all
/// internals false but `upd` (a key-on sample, [0349], that found both signs as latched: the
/// latches are written with the values they hold and no counter moves). Simulator knowledge for
/// a tracer, not a clock enable: such a sample does write the latches.
/// Tested on any register state and inputs (`rtl_model/core/tests/kernel_equivalence.rs`). A
/// tracer uses it to compare only what a narrow edge can change.
#[inline(always)]
pub fn step_traced(c: &Consts, r: &mut Regs, sh: &mut Shadow, i: &Inputs) -> TracedStep {
    let before = ports(c, r);
    let (after, internals, wide) = step_with::<true>(c, r, sh, i);
    TracedStep {
        before,
        internals,
        after,
        wide,
    }
}

/// The edge of [`step`] and [`step_traced`]; with `TRACED` false the internals are not built
/// (the compiler drops them).
#[inline(always)]
fn step_with<const TRACED: bool>(
    c: &Consts,
    r: &mut Regs,
    sh: &mut Shadow,
    i: &Inputs,
) -> (Outputs, Internals, bool) {
    // 1. Synchronizer (56a).
    let sync = r.action_switching.sync;
    let sig = sig_of(c, sync);
    let sync_n = ((sync << 1) | u8::from(i.ig)) & c.sync_mask;
    let sig_n = sig_of(c, sync_n);
    // Only the eight outputs an edge computes are carried out of the branch (`Narrow`); the
    // other fifteen (ten registers read after the edge, the four copies of `sig`, the constant
    // `vp_en`) are built after it, on both paths. With all 23 carried, the harness loop around
    // the step kept them in stack slots.
    let (n, x, wide) = if (sig != sig_n) | i.bus_we {
        // A bus write or a key edge: the full edge out of line, the outputs from its registers
        // (an `Outputs` returned through memory by the out-of-line call costs a
        // store-forwarding stall in the caller every tick).
        let x = edge_rare(c, r, sh, i);
        (
            narrow_of(c, r),
            if TRACED { x } else { Internals::default() },
            true,
        )
    } else {
        edge_common::<TRACED>(c, r, sh, i, sig, sync_n)
    };
    (outputs(&n, r), x, wide)
}

/// The common edge (no bus write, no key edge) inline: the registers it writes, the outputs it
/// computes ([`Narrow`]), its internals and whether it was wide (a key-off strobe, or a key-on
/// sample that preset or moved the latches or counters: [`step_traced`]).
#[inline(always)]
fn edge_common<const TRACED: bool>(
    c: &Consts,
    r: &mut Regs,
    sh: &mut Shadow,
    i: &Inputs,
    sig: bool,
    sync_n: u8,
) -> (Narrow, Internals, bool) {
    // 3. Timing generator decode of the pre-edge registers (parameters before the edge, from
    // the shadow).
    let t = u32::from(r.timing_generator.tmr);
    let smp = t + 1 == sh.smp_at;
    let vs2_en = t < sh.vs2_lt;
    // t + 1 < period <= 0xFFFF in the else branch, so the increment cannot wrap.
    let t_n = if t + 1 >= sh.period { 0 } else { t + 1 };
    let sr_pre = r.sensor_power_determination.sr;
    // 2. Read mux (every register before the edge): the shadow's table.
    let rdata = sh.read(r, sig, i.bus_addr);
    // 4. Sensor power determination 57.
    let sr = vs2_en & i.vs2_ok;
    // 5.-7. Sampling strobe: latches and counters when `upd`, the 56b pulse at key-off (the
    // parameters before the edge; no write this cycle).
    let mut x = Internals::default();
    // A strobe is a wide edge when it may change a register outside `NARROW_WRITES` or set an
    // internal other than `upd`: a sample that presets or moves the latches and counters, or
    // the 56b pulse (key off: `fig17`, `fig18`, whatever it writes). A key-on sample that finds
    // both signs as latched writes their values again (`vld` stays set) and is narrow; of its
    // internals only `upd` is set.
    let mut wide = false;
    if smp {
        let s = if sr_pre {
            sample(c, r, i)
        } else {
            Sample {
                first: false,
                chg_s: false,
                chg_c: false,
            }
        };
        let moved = s.first | s.chg_s | s.chg_c;
        if moved {
            sh.refresh_sample(c, r);
        }
        wide = moved | !sig;
        if !sig {
            let (f17, f18) = drive_interval_pulse(
                &mut r.drive_interval,
                &r.register_file,
                sr_pre,
                s.chg_s,
                s.chg_c,
            );
            sh.refresh_pulse(c, r);
            if TRACED {
                (x.fig17, x.fig18) = (f17, f18);
            }
        }
        if TRACED {
            (x.upd, x.first, x.chg_s, x.chg_c) = (sr_pre, s.first, s.chg_s, s.chg_c);
        }
    }
    // 8. Count diagnosis from the counters after the edge (the shadow's, refreshed above when a
    // sample changed them).
    let diag = sh.diag;
    // Commit.
    r.action_switching.sync = sync_n;
    r.timing_generator.tmr = t_n as u16;
    r.sensor_power_determination.sr = sr;
    r.count_diagnosis.diag = diag;
    r.register_file.rdata = rdata;
    // Moore outputs after the edge that are not registers: `sig` and the parameters are
    // unchanged, the timer is `t_n` (the decode of the key mode, from the shadow).
    let st = t_n == sh.st_at;
    let vs2_en_n = t_n < sh.vs2_lt;
    let ps_win = t_n.wrapping_sub(sh.ps_lo) < sh.ps_len;
    let smp_n = t_n + 1 == sh.smp_at;
    (
        Narrow {
            sig,
            vs2_en: vs2_en_n,
            st,
            sr,
            ps_win,
            smp: smp_n,
            diag,
            bus_rdata: rdata,
        },
        x,
        wide,
    )
}

/// The edges [`step`] does not take inline: a bus write or a key edge. They run the
/// specification itself ([`crate::pmu50::next`], every block's next-state function), then the
/// shadow is rebuilt from the registers after the edge. Returns the internals of the cycle
/// (which only the traced edge keeps).
#[cold]
#[inline(never)]
fn edge_rare(c: &Consts, r: &mut Regs, sh: &mut Shadow, i: &Inputs) -> Internals {
    let (x, next) = crate::pmu50::next(&c.structural, r, i);
    *r = next;
    sh.rebuild(c, r);
    x
}

/// The kernel's edge with the signature of [`crate::pmu50::eval`]: (outputs before the edge,
/// internals of the cycle, registers after the edge), through a shadow built from `r`. For the
/// equivalence tests.
pub fn eval(s: &Structural, r: &Regs, i: &Inputs) -> (Outputs, Internals, Regs) {
    let c = Consts::new(s);
    let mut after = *r;
    let mut sh = Shadow::of(&c, r);
    let step = step_traced(&c, &mut after, &mut sh, i);
    (step.before, step.internals, after)
}
