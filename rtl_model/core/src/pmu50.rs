//! Top level of the digital core of power management unit 50 (FIG. 14 / FIG. 20), third
//! embodiment with the second embodiment's adaptive drive interval ([0413]-[0414]).
//!
//! One call of [`Pmu50::step`] is one rising clock edge. [`eval`] reads every register, decodes
//! each block's registered outputs, evaluates the blocks' next-state functions in the fixed order
//! below (each block only uses signals of blocks above it, so there is no combinational loop by
//! construction), and returns the next value of every register, which the caller commits at
//! once, as Verilog non-blocking assignments do. The structural parameters are fixed when the
//! core is built ([`Structural`], [`Blocks`]).
//!
//! Evaluation order:
//! 1. `action_switching`   (56a, 51): `ig` synchronizer -> `sig`, `kon`, `koff`, rail enables
//! 2. `register_file`: parameters in force, W1C strobes, bus write, registered read
//! 3. `timing_generator`   (56, 54): `st`, `vs2_en`, `ps_win`, `smp` from the timer
//! 4. `sensor_power_determination` (57): `sr` <= `vs2_en` & `vs2_ok`
//! 5. `comparator_latch`   (58a, 58b): latch `cmp_s`, `cmp_c` at `smp` & `sr`
//! 6. `updown_counter`     (58c, 58d): count per [0096]-[0099]
//! 7. `drive_interval`     (56b): FIG. 17/18 at key-off strobes
//! 8. `count_diagnosis`    ([0119]): from the counters' next values
//!
//! Every top-level output ([`Outputs`]) is decoded from registers only (Moore): the environment can
//! read this cycle's outputs with [`Pmu50::peek`] before it computes this cycle's inputs. A test
//! checks that no input reaches an output combinationally.
//!
//! Top-level ports (the contract with the HDL team; names, widths and order are declared once in
//! [`crate::signals`], from which docs/signals.md is generated):
//!
//! | port        | width | dir | meaning |
//! |-------------|-------|-----|---------|
//! | `ig`        | 1     | in  | ignition key signal IG |
//! | `vs2_ok`    | 1     | in  | Vs2 rail power-good (analog) |
//! | `cmp_s`     | 1     | in  | raw decision of comparator 58a (sin2 >= Vr) |
//! | `cmp_c`     | 1     | in  | raw decision of comparator 58b (cos2 >= Vr) |
//! | `bus_we`    | 1     | in  | register write strobe |
//! | `bus_addr`  | 8     | in  | register address |
//! | `bus_wdata` | 16    | in  | register write data |
//! | `sig`       | 1     | out | operation switching signal Sig |
//! | `vr_hi`     | 1     | out | regulator 51 at 6 V (1) / 4 V (0) |
//! | `vm_en`     | 1     | out | Vm on (unit 52) |
//! | `vs1_en`    | 1     | out | Vs1 on (unit 53) |
//! | `vs2_en`    | 1     | out | Vs2 on (unit 54) |
//! | `vp_en`     | 1     | out | Vp on (always 1) |
//! | `rail_hi`   | 1     | out | Vs2/Vp at Vcc1 (1) or Vcc2 (0) |
//! | `st`        | 1     | out | timing signal St |
//! | `sr`        | 1     | out | activation signal Sr |
//! | `ps_win`    | 1     | out | sampling period Ps |
//! | `smp`       | 1     | out | sampling strobe |
//! | `cs`, `cc`  | 1     | out | sign signals Cs, Cc |
//! | `cnt_s`, `cnt_c` | W (16) | out | count values CNTs, CNTc |
//! | `cnt_r`     | 8     | out | power supply count CNTr |
//! | `si`        | 16    | out | drive interval Si, ticks |
//! | `hist_s`, `hist_c` | 1 | out | change history |
//! | `diag`      | 1     | out | count diagnosis |
//! | `quadrant_skip` | 1 | out | sticky quadrant skip |
//! | `bus_rdata` | 16    | out | registered read data |
//! | `bus_err`   | 1     | out | sticky refused write |
//!
//! Packed words, for the fast paths of a tracer and a checksum: [`Inputs`], [`Outputs`] and
//! [`Internals`] are `repr(C)` without padding between their fields (asserted at compile time).
//! [`Inputs::packed`] (a `u64`) and [`Internals::packed`] (a `u128`) are the fields a byte each
//! in declaration order, the struct's own bytes, so a compare of two ticks is one or two loads
//! and a changed signal is found by its byte. [`Outputs::flags`] gathers the eighteen one-bit
//! outputs as bits in port order from three loads (the thirteen flags from `sig` to `cc` come
//! first in the struct); the port order itself ([`Outputs::values`], waveforms, the C ABI) is
//! that of [`crate::signals`], not the field order. Tests: `packed_inputs_are_the_inputs_a_byte_each`
//! and `output_flags_are_the_one_bit_outputs_in_port_order` (`tests/kernel_equivalence.rs`).

use crate::action_switching_56a as sw;
use crate::comparator_latch_58ab as cl;
use crate::count_diagnosis as cd;
use crate::drive_interval_changing_56b as di;
use crate::params::Params;
use crate::register_file as rf;
use crate::sensor_power_determination_57 as spd;
use crate::timing_generator_56 as tg;
use crate::updown_counter_58cd as uc;

/// Every register of the core, one field per block. Field paths are the VCD hierarchy
/// (`pmu50.<block>.<register>`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Regs {
    pub action_switching: sw::Regs,
    pub register_file: rf::Regs,
    pub timing_generator: tg::Regs,
    pub sensor_power_determination: spd::Regs,
    pub comparator_latch: cl::Regs,
    pub updown_counter: uc::Regs,
    pub drive_interval: di::Regs,
    pub count_diagnosis: cd::Regs,
}

/// Power-on reset value for a given parameter set (the register file and `si` reset to the
/// configured values; everything else to its block's `RESET`).
pub fn reset(p: &Params) -> Regs {
    Regs {
        action_switching: sw::RESET,
        register_file: rf::reset(p),
        timing_generator: tg::RESET,
        sensor_power_determination: spd::RESET,
        comparator_latch: cl::RESET,
        updown_counter: uc::RESET,
        drive_interval: di::reset(p.si_max),
        count_diagnosis: cd::RESET,
    }
}

/// Structural parameters (Verilog `parameter`s), fixed for the life of a core instance.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Structural {
    pub sync_depth: u8,
    pub cnt_width: u8,
}

/// Top-level inputs for one clock cycle.
///
/// `repr(C)`: the fields in this order are eight bytes without padding (asserted below), so
/// comparing two inputs or packing them ([`Inputs::packed`]) is one 8-byte load, not seven.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, Hash)]
#[repr(C)]
pub struct Inputs {
    pub ig: bool,
    pub vs2_ok: bool,
    pub cmp_s: bool,
    pub cmp_c: bool,
    pub bus_we: bool,
    pub bus_addr: u8,
    pub bus_wdata: u16,
}

/// Top-level outputs (all Moore: functions of the registers only).
///
/// `repr(C)`: the thirteen one-bit outputs from `sig` to `cc` at bytes 0-12, `cnt_r` at 13, the
/// four 16-bit outputs at 14-21, the other five one-bit outputs at 22-26, no padding between
/// (asserted below), so [`Outputs::flags`] gathers the eighteen one-bit outputs from three
/// loads. The order of the ports (`Outputs::values`, the waveforms, the C ABI) is
/// [`signals::OUTPUTS`], not this one.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, Hash)]
#[repr(C)]
pub struct Outputs {
    pub sig: bool,
    pub vr_hi: bool,
    pub vm_en: bool,
    pub vs1_en: bool,
    pub vs2_en: bool,
    pub vp_en: bool,
    pub rail_hi: bool,
    pub st: bool,
    pub sr: bool,
    pub ps_win: bool,
    pub smp: bool,
    pub cs: bool,
    pub cc: bool,
    pub cnt_r: u8,
    pub cnt_s: u16,
    pub cnt_c: u16,
    pub si: u16,
    pub bus_rdata: u16,
    pub hist_s: bool,
    pub hist_c: bool,
    pub diag: bool,
    pub quadrant_skip: bool,
    pub bus_err: bool,
}

/// Internal combinational signals of one cycle (they depend on this cycle's inputs), for
/// waveforms, change logs and coverage of the FIG. 17/18 branches.
///
/// `repr(C)`: the fields in this order are nine bytes without padding (asserted below), which
/// [`Internals::packed`] gives as one word.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, Hash)]
#[repr(C)]
pub struct Internals {
    pub kon: bool,
    pub koff: bool,
    pub upd: bool,
    pub first: bool,
    pub chg_s: bool,
    pub chg_c: bool,
    pub skip_clr: bool,
    pub fig17: di::Fig17,
    pub fig18: di::Fig18,
}

impl Structural {
    /// The blocks that have structural parameters, built with them.
    pub const fn blocks(&self) -> Blocks {
        Blocks {
            action_switching: sw::ActionSwitching::new(self.sync_depth),
            register_file: rf::RegisterFile::new(self.sync_depth, self.cnt_width),
            updown_counter: uc::UpdownCounter::new(self.cnt_width),
            count_diagnosis: cd::CountDiagnosis::new(self.cnt_width),
        }
    }
}

/// The block instances whose behaviour depends on a structural parameter (the others are plain
/// functions), fixed for the life of a core.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Blocks {
    pub action_switching: sw::ActionSwitching,
    pub register_file: rf::RegisterFile,
    pub updown_counter: uc::UpdownCounter,
    pub count_diagnosis: cd::CountDiagnosis,
}

pub(crate) fn tg_inputs(sig: bool, kon: bool, koff: bool, p: &Params, si: u16) -> tg::Inputs {
    tg::Inputs {
        sig,
        kon,
        koff,
        si,
        pw: p.pw,
        pi: p.pi,
        ps: p.ps,
        smp_on: p.smp_on,
    }
}

/// Moore outputs, decoded from the registers.
pub fn ports(s: &Structural, r: &Regs) -> Outputs {
    let b = s.blocks();
    let a = b.action_switching.outputs(&r.action_switching);
    let f = b.register_file.outputs(&r.register_file);
    let t = tg::outputs(
        &r.timing_generator,
        &tg_inputs(a.sig, false, false, &f.params, r.drive_interval.si),
    );
    let d = spd::outputs(&r.sensor_power_determination);
    let c = cl::outputs(&r.comparator_latch);
    let u = b.updown_counter.outputs(&r.updown_counter);
    let v = di::outputs(&r.drive_interval);
    let g = b.count_diagnosis.outputs(&r.count_diagnosis);
    Outputs {
        sig: a.sig,
        vr_hi: a.vr_hi,
        vm_en: a.vm_en,
        vs1_en: a.vs1_en,
        vs2_en: t.vs2_en,
        vp_en: a.vp_en,
        rail_hi: a.rail_hi,
        st: t.st,
        sr: d.sr,
        ps_win: t.ps_win,
        smp: t.smp,
        cs: c.cs,
        cc: c.cc,
        cnt_s: u.cnt_s,
        cnt_c: u.cnt_c,
        cnt_r: v.cnt_r,
        si: v.si,
        hist_s: v.hist_s,
        hist_c: v.hist_c,
        diag: g.diag,
        quadrant_skip: u.quadrant_skip,
        bus_rdata: f.bus_rdata,
        bus_err: f.bus_err,
    }
}

fn status_view(r: &Regs, sig: bool) -> rf::StatusView {
    rf::StatusView {
        cnt_s: r.updown_counter.cnt_s,
        cnt_c: r.updown_counter.cnt_c,
        cnt_r: r.drive_interval.cnt_r,
        si: r.drive_interval.si,
        cs: r.comparator_latch.cs,
        cc: r.comparator_latch.cc,
        hist_s: r.drive_interval.hist_s,
        hist_c: r.drive_interval.hist_c,
        diag: r.count_diagnosis.diag,
        quadrant_skip: r.updown_counter.quadrant_skip,
        sig,
        vld: r.comparator_latch.vld,
        sr: r.sensor_power_determination.sr,
    }
}

/// The register file's read mux at `addr` for the registers `r` with the key mode `sig` (what
/// `bus_rdata` shows one edge later).
pub fn read(s: &Structural, r: &Regs, sig: bool, addr: u8) -> u16 {
    let i = rf::Inputs {
        view: status_view(r, sig),
        sig,
        ..Default::default()
    };
    s.blocks().register_file.read(&r.register_file, &i, addr)
}

/// One clock edge: (outputs before the edge, internals of this cycle, registers after the edge).
/// Each block's registered outputs are decoded from the registers before the edge; its `eval`
/// gives the combinational outputs of the cycle and its next state.
pub fn eval(s: &Structural, r: &Regs, i: &Inputs) -> (Outputs, Internals, Regs) {
    let (internals, next) = next(s, r, i);
    (ports(s, r), internals, next)
}

/// The edge of [`eval`] without the outputs before it: (internals of this cycle, registers
/// after the edge).
pub fn next(s: &Structural, r: &Regs, i: &Inputs) -> (Internals, Regs) {
    let b = s.blocks();
    // 1. Action switching unit 56a and regulator 51.
    let a = b.action_switching.outputs(&r.action_switching);
    let (ac, a_n) = b
        .action_switching
        .eval(&r.action_switching, &sw::Inputs { ig: i.ig });
    // 2. Register file: the parameters in force this cycle are the registers before the edge.
    let f = b.register_file.outputs(&r.register_file);
    let (fc, f_n) = b.register_file.eval(
        &r.register_file,
        &rf::Inputs {
            bus_we: i.bus_we,
            bus_addr: i.bus_addr,
            bus_wdata: i.bus_wdata,
            sig: a.sig,
            view: status_view(r, a.sig),
        },
    );
    let p = f.params;
    // 3. Timing generator of 56 with the window of 54.
    let ti = tg_inputs(a.sig, ac.kon, ac.koff, &p, r.drive_interval.si);
    let t = tg::outputs(&r.timing_generator, &ti);
    let t_n = tg::eval(&r.timing_generator, &ti);
    // 4. Sensor power determination unit 57.
    let d = spd::outputs(&r.sensor_power_determination);
    let d_n = spd::eval(
        &r.sensor_power_determination,
        &spd::Inputs {
            vs2_en: t.vs2_en,
            vs2_ok: i.vs2_ok,
        },
    );
    // 5. Comparator latches 58a/58b.
    let c = cl::outputs(&r.comparator_latch);
    let (cc, c_n) = cl::eval(
        &r.comparator_latch,
        &cl::Inputs {
            cmp_s: i.cmp_s,
            cmp_c: i.cmp_c,
            smp: t.smp,
            sr: d.sr,
        },
    );
    // 6. Up/down counters 58c/58d.
    let u_n = b.updown_counter.eval(
        &r.updown_counter,
        &uc::Inputs {
            upd: cc.upd,
            first: cc.first,
            cs: c.cs,
            cc: c.cc,
            cs_new: cc.cs_new,
            cc_new: cc.cc_new,
            skip_clr: fc.skip_clr,
        },
    );
    // 7. Drive interval changing unit 56b: one evaluation per key-off sampling strobe.
    let (vc, v_n) = di::eval(
        &r.drive_interval,
        &di::Inputs {
            koff: ac.koff,
            pulse: t.smp && !a.sig,
            sr: d.sr,
            chg_s: cc.chg_s,
            chg_c: cc.chg_c,
            adaptive: p.adaptive,
            si_min: p.si_min,
            si_max: p.si_max,
            si_max_nxt: f_n.si_max,
            t1: p.t1,
            t2: p.t2,
            cth: p.cth,
        },
    );
    // 8. Count diagnosis, aligned with the counters' next values.
    let g_n = b.count_diagnosis.eval(
        &r.count_diagnosis,
        &cd::Inputs {
            cnt_s_nxt: u_n.cnt_s,
            cnt_c_nxt: u_n.cnt_c,
            skip_nxt: u_n.quadrant_skip,
        },
    );
    let next = Regs {
        action_switching: a_n,
        register_file: f_n,
        timing_generator: t_n,
        sensor_power_determination: d_n,
        comparator_latch: c_n,
        updown_counter: u_n,
        drive_interval: v_n,
        count_diagnosis: g_n,
    };
    let internals = Internals {
        kon: ac.kon,
        koff: ac.koff,
        upd: cc.upd,
        first: cc.first,
        chg_s: cc.chg_s,
        chg_c: cc.chg_c,
        skip_clr: fc.skip_clr,
        fig17: vc.fig17,
        fig18: vc.fig18,
    };
    (internals, next)
}

const _: () = {
    use std::mem::{offset_of, size_of};
    assert!(
        offset_of!(Outputs, cc) == 12
            && offset_of!(Outputs, cnt_r) == 13
            && offset_of!(Outputs, cnt_s) == 14
    );
    assert!(
        offset_of!(Outputs, bus_rdata) == 20
            && offset_of!(Outputs, hist_s) == 22
            && offset_of!(Outputs, bus_err) == 26
    );
    assert!(
        size_of::<Outputs>() == 28,
        "Outputs: 27 bytes of fields, one byte of padding at the end"
    );
};

/// The bytes of `b` (each 0 or 1) as the bits of one byte: bit k is byte k. Multiplying by
/// this constant moves byte k's bit to bit 56 + k; every other product of a byte and a term
/// lands on a bit of its own below 56 or above 63, so no carry reaches bits 56-63.
#[inline(always)]
fn gather_bits(b: [u8; 8]) -> u32 {
    (u64::from_le_bytes(b).wrapping_mul(0x0102_0408_1020_4080) >> 56) as u32
}

impl Outputs {
    /// The eighteen one-bit outputs as bits, in the order of [`signals::OUTPUTS`] without the
    /// vectors: bits 0-12 `sig` .. `cc`, 13 `hist_s`, 14 `hist_c`, 15 `diag`,
    /// 16 `quadrant_skip`, 17 `bus_err`. Equal flags and equal vectors, equal outputs.
    #[inline(always)]
    pub fn flags(&self) -> u32 {
        let b = u8::from;
        let lo = gather_bits([
            b(self.sig),
            b(self.vr_hi),
            b(self.vm_en),
            b(self.vs1_en),
            b(self.vs2_en),
            b(self.vp_en),
            b(self.rail_hi),
            b(self.st),
        ]);
        let mid = gather_bits([
            b(self.sr),
            b(self.ps_win),
            b(self.smp),
            b(self.cs),
            b(self.cc),
            0,
            0,
            0,
        ]);
        let hi = gather_bits([
            b(self.hist_s),
            b(self.hist_c),
            b(self.diag),
            b(self.quadrant_skip),
            b(self.bus_err),
            0,
            0,
            0,
        ]);
        lo | mid << 8 | hi << 13
    }
}

const _: () = assert!(
    std::mem::size_of::<Inputs>() == 8,
    "Inputs: eight bytes, no padding"
);

impl Inputs {
    /// The inputs as one word, a byte each in the order of the fields (little-endian): `ig`,
    /// `vs2_ok`, `cmp_s`, `cmp_c`, `bus_we` at bytes 0-4 (0 or 1), `bus_addr` at byte 5,
    /// `bus_wdata` at bytes 6-7. Equal words, equal inputs. With the `repr(C)` layout this is
    /// the struct's own bytes, one load.
    #[inline(always)]
    pub fn packed(&self) -> u64 {
        let w = self.bus_wdata.to_le_bytes();
        u64::from_le_bytes([
            u8::from(self.ig),
            u8::from(self.vs2_ok),
            u8::from(self.cmp_s),
            u8::from(self.cmp_c),
            u8::from(self.bus_we),
            self.bus_addr,
            w[0],
            w[1],
        ])
    }
}

const _: () = assert!(
    std::mem::size_of::<Internals>() == 9,
    "Internals: nine bytes, no padding"
);

impl Internals {
    /// The internals as one word, a byte each in the order of the fields (little-endian):
    /// `kon`, `koff`, `upd`, `first`, `chg_s`, `chg_c`, `skip_clr` at bytes 0-6 (0 or 1), the
    /// encodings of `fig17` and `fig18` at bytes 7 and 8. Equal words, equal internals.
    #[inline(always)]
    pub fn packed(&self) -> u128 {
        u128::from_le_bytes([
            u8::from(self.kon),
            u8::from(self.koff),
            u8::from(self.upd),
            u8::from(self.first),
            u8::from(self.chg_s),
            u8::from(self.chg_c),
            u8::from(self.skip_clr),
            self.fig17 as u8,
            self.fig18 as u8,
            0,
            0,
            0,
            0,
            0,
            0,
            0,
        ])
    }
}

/// One traced clock edge ([`Pmu50::step_traced`], [`crate::Pmu50Spec::step_traced`],
/// [`crate::kernel::step_traced`]): what a waveform, a change log or a lockstep needs of it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, Hash)]
pub struct TracedStep {
    /// Outputs before the edge: those of the cycle that ends at it ([`Pmu50::peek`] before).
    pub before: Outputs,
    /// Internal combinational signals of that cycle.
    pub internals: Internals,
    /// Outputs after the edge.
    pub after: Outputs,
    /// Whether the edge was *wide*: it may have written any register and set any internal. A
    /// narrow edge (false) writes only the registers of [`crate::kernel::NARROW_WRITES`], keeps
    /// `sig` and has all internals false but `upd` (see [`crate::kernel::step_traced`]); the
    /// specification does not tell them apart and says true.
    pub wide: bool,
}
