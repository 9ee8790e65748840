//! The fast kernel (`pmu50_core::kernel`, run by `Pmu50::step`) equals the per-block
//! specification (`pmu50_core::pmu50::eval`, stepped by `Pmu50Spec`): every register, every
//! output before and after each edge and every internal signal, on every tick.
//!
//! - one edge from an arbitrary register state (reachable or not) under arbitrary inputs and
//!   structural parameters;
//! - long runs from reset with random legal parameters and a stimulus with memory: key-on/off runs
//!   and one-tick `ig` glitches, Vs2 power-good mostly following the enable, comparator changes
//!   (single and double, so quadrant skips happen), bus writes of every address (legal, refused
//!   as illegal, refused while the key is off, read-only and unmapped), STATUS W1C clears, reads;
//! - a coverage check that this stimulus reaches every FIG. 17 and FIG. 18 path, refused and
//!   accepted writes, first samples, skips and W1C clears, so the comparison is not vacuous.

mod common;

use common::{Driver, Rng};
use pmu50_core::drive_interval_changing_56b::{Fig17, Fig18};
use pmu50_core::pmu50::{eval, Regs, Structural};
use pmu50_core::register_file::addr;
use pmu50_core::{
    action_switching_56a as sw, comparator_latch_58ab as cl, count_diagnosis as cd,
    drive_interval_changing_56b as di,
};
use pmu50_core::{
    kernel, register_file as rf, sensor_power_determination_57 as spd, timing_generator_56 as tg,
    updown_counter_58cd as uc,
};
use pmu50_core::{Inputs, Internals, Params, Pmu50, Pmu50Spec, TracedStep};
use proptest::prelude::*;
use std::collections::HashSet;

fn any_inputs() -> impl Strategy<Value = Inputs> {
    (any::<[bool; 5]>(), any::<u8>(), any::<u16>(), any::<bool>()).prop_map(|(b, a, d, mapped)| {
        Inputs {
            ig: b[0],
            vs2_ok: b[1],
            cmp_s: b[2],
            cmp_c: b[3],
            bus_we: b[4],
            bus_addr: if mapped { a % 0x16 } else { a },
            bus_wdata: d,
        }
    })
}

/// Any register state at all: every field over its full type range (also values no legal run
/// reaches: counters beyond their width, `tmr` past the period, `si` outside [min, x]).
fn any_regs() -> impl Strategy<Value = Regs> {
    (
        (
            any::<u8>(),
            any::<bool>(),
            any::<[u16; 9]>(),
            any::<u8>(),
            any::<bool>(),
            any::<u16>(),
        ),
        (any::<u16>(), any::<[bool; 4]>(), any::<u16>(), any::<u16>()),
        (any::<u16>(), any::<[bool; 3]>(), any::<u8>()),
    )
        .prop_map(
            |((sync, adaptive, p, cth, bus_err, rdata), (tmr, b, cnt_s, cnt_c), (si, h, cnt_r))| {
                Regs {
                    action_switching: sw::Regs { sync: sync & 0xF },
                    register_file: rf::Regs {
                        adaptive,
                        pw: p[0],
                        pi: p[1],
                        ps: p[2],
                        si_max: p[3],
                        si_min: p[4],
                        t1: p[5],
                        t2: p[6],
                        cth,
                        smp_on: p[7],
                        bus_err,
                        rdata,
                    },
                    timing_generator: tg::Regs { tmr },
                    sensor_power_determination: spd::Regs { sr: b[0] },
                    comparator_latch: cl::Regs {
                        cs: b[1],
                        cc: b[2],
                        vld: b[3],
                    },
                    updown_counter: uc::Regs {
                        cnt_s,
                        cnt_c,
                        quadrant_skip: h[0],
                    },
                    drive_interval: di::Regs {
                        si,
                        hist_s: h[1],
                        hist_c: h[2],
                        cnt_r,
                    },
                    count_diagnosis: cd::Regs {
                        diag: p[8] & 1 == 1,
                    },
                }
            },
        )
}

/// Legal register states are a subset worth sampling more densely: small periods so that the
/// timer sits at the interesting boundaries.
fn small_regs() -> impl Strategy<Value = Regs> {
    (
        any_regs(),
        0u16..8,
        0u16..8,
        1u16..8,
        0u16..40,
        0u16..40,
        0u16..30,
        0u16..40,
        0u8..6,
        0u16..12,
    )
        .prop_map(
            |(mut r, pw, pi, ps, si_max, si_min, tmr, si, cth, smp_on)| {
                let f = &mut r.register_file;
                (f.pw, f.pi, f.ps, f.si_max, f.si_min, f.cth, f.smp_on) =
                    (pw, pi, ps, si_max, si_min, cth, smp_on);
                f.t1 %= 50;
                f.t2 %= 50;
                r.timing_generator.tmr = tmr;
                r.drive_interval.si = si;
                r
            },
        )
}

proptest! {
    #![proptest_config(common::cases(4000))]

    #[test]
    fn one_edge_from_any_state(r in prop_oneof![any_regs(), small_regs()], i in any_inputs(), sd in 1u8..=4, w in 2u8..=16) {
        let s = Structural { sync_depth: sd, cnt_width: w };
        prop_assert_eq!(kernel::eval(&s, &r, &i), eval(&s, &r, &i));
    }

    /// The inline edge of `Pmu50::step` (`kernel::step`, with its read-side shadow built from the
    /// registers) from any state: the registers and the outputs after the edge, then a second
    /// edge through the shadow that the first one left (refreshed by a sample, rebuilt by a write
    /// or key edge, or untouched).
    #[test]
    fn step_from_any_state(r in prop_oneof![any_regs(), small_regs()], i in any_inputs(), i2 in any_inputs(), sd in 1u8..=4, w in 2u8..=16) {
        let s = Structural { sync_depth: sd, cnt_width: w };
        let c = kernel::Consts::new(&s);
        let mut sh = kernel::Shadow::of(&c, &r);
        let mut k = r;
        let out = kernel::step(&c, &mut k, &mut sh, &i);
        let (_, _, want) = eval(&s, &r, &i);
        prop_assert_eq!(k, want);
        prop_assert_eq!(out, pmu50_core::pmu50::ports(&s, &want));
        // Every address read through the shadow the first edge left, then `i2` as drawn.
        let reads = (0..=0x16u8).map(|a| Inputs { bus_we: false, bus_addr: a, ..i2 });
        for i2 in reads.chain([i2]) {
            let (mut k2, mut sh2) = (k, sh.clone());
            let out2 = kernel::step(&c, &mut k2, &mut sh2, &i2);
            let (_, _, want2) = eval(&s, &want, &i2);
            prop_assert_eq!(k2, want2);
            prop_assert_eq!(out2, pmu50_core::pmu50::ports(&s, &want2));
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 4000, failure_persistence: None, ..ProptestConfig::default() })]

    /// `Inputs::packed` (the tracer compares inputs as one word): input k of `Inputs::values`
    /// at byte k, `bus_wdata` at bytes 6-7; equal words exactly for equal inputs.
    #[test]
    fn packed_inputs_are_the_inputs_a_byte_each(a in any_inputs(), b in any_inputs()) {
        let (w, v) = (a.packed(), a.values());
        for (k, v) in v.iter().enumerate().take(6) {
            prop_assert_eq!(w >> (8 * k) & 0xFF, v.2, "byte {} is {}", k, v.0);
        }
        prop_assert_eq!(w >> 48, v[6].2, "bytes 6-7 are {}", v[6].0);
        prop_assert_eq!(a.packed() == b.packed(), a == b);
        let mut c = a;
        c.bus_wdata ^= 0x8000;
        prop_assert_ne!(c.packed(), w);
    }

    /// `Outputs::flags` (the bench's checksum): bit j is
    /// the j-th one-bit output of `Outputs::values`, eighteen of them, nothing above; written
    /// out as hdl/bench/bench.cpp's `mix` packs them.
    #[test]
    fn output_flags_are_the_one_bit_outputs_in_port_order(bits in 0u32..1 << 18, v in any::<[u16; 5]>()) {
        let f = |j: u32| bits >> j & 1 == 1;
        let o = pmu50_core::Outputs {
            sig: f(0), vr_hi: f(1), vm_en: f(2), vs1_en: f(3), vs2_en: f(4), vp_en: f(5), rail_hi: f(6), st: f(7), sr: f(8),
            ps_win: f(9), smp: f(10), cs: f(11), cc: f(12), hist_s: f(13), hist_c: f(14), diag: f(15), quadrant_skip: f(16), bus_err: f(17),
            cnt_s: v[0], cnt_c: v[1], cnt_r: v[2] as u8, si: v[3], bus_rdata: v[4],
        };
        let s = Structural { sync_depth: 2, cnt_width: 16 };
        let one_bit: Vec<_> = o.values(&s).into_iter().filter(|v| !["cnt_s", "cnt_c", "cnt_r", "si", "bus_rdata"].contains(&v.0)).collect();
        prop_assert_eq!(one_bit.len(), 18);
        for (j, v) in one_bit.iter().enumerate() {
            prop_assert_eq!(u64::from(o.flags() >> j & 1), v.2, "bit {} is {}", j, v.0);
        }
        let b = |v: bool, k: u32| u32::from(v) << k;
        let cpp = b(o.sig, 0) | b(o.vr_hi, 1) | b(o.vm_en, 2) | b(o.vs1_en, 3) | b(o.vs2_en, 4) | b(o.vp_en, 5) | b(o.rail_hi, 6) | b(o.st, 7) | b(o.sr, 8)
            | b(o.ps_win, 9) | b(o.smp, 10) | b(o.cs, 11) | b(o.cc, 12) | b(o.hist_s, 13) | b(o.hist_c, 14) | b(o.diag, 15) | b(o.quadrant_skip, 16) | b(o.bus_err, 17);
        prop_assert_eq!(o.flags(), cpp);
        prop_assert_eq!(o.flags(), bits);
    }

    /// `kernel::step_traced` from any state: the edge of the specification (its internals
    /// a byte each in `Internals::packed`, its registered outputs equal to their registers), and a narrow
    /// edge (`wide` false) writes only `kernel::NARROW_WRITES`, keeps `sig` and has all internals
    /// false but `upd`, which is what a tracer that compares only those after a narrow edge relies
    /// on.
    #[test]
    fn narrow_edges_write_only_their_registers(r in prop_oneof![any_regs(), small_regs()], i in any_inputs(), sd in 1u8..=4, w in 2u8..=16) {
        let s = Structural { sync_depth: sd, cnt_width: w };
        let c = kernel::Consts::new(&s);
        let mut sh = kernel::Shadow::of(&c, &r);
        let mut k = r;
        let TracedStep { internals: x, after: out, wide, .. } = kernel::step_traced(&c, &mut k, &mut sh, &i);
        let (_, want_x, want) = eval(&s, &r, &i);
        prop_assert_eq!(k, want);
        prop_assert_eq!(x, want_x);
        // the thirteen registered outputs (docs/signals.md) equal their registers
        let (u, d, f) = (&k.updown_counter, &k.drive_interval, &k.register_file);
        prop_assert_eq!((out.sr, out.diag, out.bus_rdata, out.bus_err), (k.sensor_power_determination.sr, k.count_diagnosis.diag, f.rdata, f.bus_err));
        prop_assert_eq!((out.cs, out.cc), (k.comparator_latch.cs, k.comparator_latch.cc));
        prop_assert_eq!((out.cnt_s, out.cnt_c, out.quadrant_skip), (u.cnt_s, u.cnt_c, u.quadrant_skip));
        prop_assert_eq!((out.si, out.hist_s, out.hist_c, out.cnt_r), (d.si, d.hist_s, d.hist_c, d.cnt_r));
        // `Internals::packed` (the tracer compares internals as one word): internal k of
        // `Internals::values` at byte k, nothing above
        let (w, v) = (x.packed(), x.values());
        for (k, v) in v.iter().enumerate() {
            prop_assert_eq!((w >> (8 * k)) as u64 & 0xFF, v.2, "byte {} is {}", k, v.0);
        }
        prop_assert_eq!(w >> 72, 0);
        prop_assert_eq!(out, pmu50_core::pmu50::ports(&s, &want));
        if !wide {
            prop_assert_eq!(narrow_writes_of(&r, &k), k, "a narrow edge wrote a register outside NARROW_WRITES");
            prop_assert_eq!(x, Internals { upd: x.upd, ..Internals::default() }, "a narrow edge set an internal other than upd");
            // and so only the outputs decoded from those registers change
            let mut only = pmu50_core::pmu50::ports(&s, &r);
            (only.vs2_en, only.st, only.sr, only.ps_win, only.smp, only.diag, only.bus_rdata) = (out.vs2_en, out.st, out.sr, out.ps_win, out.smp, out.diag, out.bus_rdata);
            prop_assert_eq!(only, out, "a narrow edge changed an output other than vs2_en, st, sr, ps_win, smp, diag, bus_rdata");
        }
    }
}

/// The registers `before` with the values of `kernel::NARROW_WRITES` taken from `after`: equal to
/// `after` exactly when the edge from `before` to `after` changed no other register.
fn narrow_writes_of(before: &Regs, after: &Regs) -> Regs {
    let mut r = *before;
    r.action_switching.sync = after.action_switching.sync;
    r.timing_generator.tmr = after.timing_generator.tmr;
    r.sensor_power_determination.sr = after.sensor_power_determination.sr;
    r.register_file.rdata = after.register_file.rdata;
    r.count_diagnosis.diag = after.count_diagnosis.diag;
    r
}

/// The key-on sampling strobes of the state `r` (with the key on the strobe is at one timer
/// value, `smp_on - 1`; every value below 64 is tried, so the small `smp_on` of [`small_regs`]
/// meets it, and with the key off no value is a key-on strobe), each checked as in [`key_on_strobes_that_move_nothing_are_narrow`]:
/// with the inputs `i`, and with a powered, valid latch whose comparators give the latched signs
/// (the quiet sample). Returns how many were narrow with `upd` set and how many were wide.
fn key_on_strobes(r: &Regs, i: &Inputs, s: &Structural) -> Result<(u32, u32), TestCaseError> {
    let c = kernel::Consts::new(s);
    let i = Inputs {
        bus_we: false,
        ..*i
    };
    let mut latched = *r;
    latched.sensor_power_determination.sr = true;
    latched.comparator_latch.vld = true;
    let same = Inputs {
        cmp_s: latched.comparator_latch.cs,
        cmp_c: latched.comparator_latch.cc,
        ..i
    };
    let (mut narrow_upd, mut wide_moved) = (0, 0);
    for (tmr, (r, i)) in (0..64).flat_map(|t| [(t, (*r, i)), (t, (latched, same))]) {
        let mut r = r;
        r.timing_generator.tmr = tmr;
        let before = pmu50_core::pmu50::ports(s, &r);
        let (_, want_x, want) = eval(s, &r, &i);
        if !(before.smp && before.sig && pmu50_core::pmu50::ports(s, &want).sig) {
            continue;
        }
        let mut sh = kernel::Shadow::of(&c, &r);
        let mut k = r;
        let TracedStep {
            internals: x, wide, ..
        } = kernel::step_traced(&c, &mut k, &mut sh, &i);
        prop_assert_eq!((k, x), (want, want_x));
        let quiet = narrow_writes_of(&r, &k) == k
            && x == Internals {
                upd: x.upd,
                ..Internals::default()
            };
        prop_assert_eq!(
            wide,
            !quiet,
            "a key-on strobe at tmr {}: wide {}, internals {:?}",
            tmr,
            wide,
            x
        );
        narrow_upd += u32::from(!wide && x.upd);
        wide_moved += u32::from(wide);
    }
    Ok((narrow_upd, wide_moved))
}

proptest! {
    #![proptest_config(common::cases(1000))]

    /// The other direction of the contract, which the tracer's speed rests on: a key-on sampling
    /// strobe (no bus write, no key edge) that writes no register outside
    /// `kernel::NARROW_WRITES` and sets no internal but `upd` (both signs found as latched) is
    /// narrow; one that presets or moves a latch or a counter is wide.
    #[test]
    fn key_on_strobes_that_move_nothing_are_narrow(r in small_regs(), i in any_inputs(), sd in 1u8..=4, w in 2u8..=16) {
        key_on_strobes(&r, &i, &Structural { sync_depth: sd, cnt_width: w })?;
    }
}

/// The strobe test is not vacuous: its states meet narrow strobes with `upd` and wide ones.
#[test]
fn key_on_strobe_cases_reach_both_kinds() {
    use proptest::strategy::ValueTree;
    let mut runner = proptest::test_runner::TestRunner::deterministic();
    let (mut narrow_upd, mut wide) = (0, 0);
    for _ in 0..300 {
        let r = small_regs().new_tree(&mut runner).unwrap().current();
        let i = any_inputs().new_tree(&mut runner).unwrap().current();
        let (n, w) = key_on_strobes(
            &r,
            &i,
            &Structural {
                sync_depth: 2,
                cnt_width: 16,
            },
        )
        .unwrap();
        narrow_upd += n;
        wide += w;
    }
    assert!(
        narrow_upd >= 20 && wide >= 20,
        "narrow strobes with upd {narrow_upd}, wide strobes {wide}"
    );
}

#[derive(Default)]
struct Coverage {
    fig17: HashSet<Fig17>,
    fig18: HashSet<Fig18>,
    refused: bool,
    accepted: bool,
    refused_key_off: bool,
    first: bool,
    skip: bool,
    skip_clr: bool,
    kon: bool,
    koff: bool,
    diag: bool,
}

/// Run both models `len` ticks from reset and compare everything on every tick.
fn lockstep(p: Params, seed: u64, len: u64, cov: &mut Coverage) -> Result<(), TestCaseError> {
    let mut fast = Pmu50::new(p).unwrap();
    let mut untraced = Pmu50::new(p).unwrap();
    let mut spec = Pmu50Spec::new(p).unwrap();
    let mut d = Driver::new(seed);
    prop_assert_eq!(fast.regs(), spec.regs());
    prop_assert_eq!(fast.peek(), spec.peek());
    for k in 0..len {
        let i = d.next(&spec.peek());
        let err_before = spec.regs().register_file.bus_err;
        let sig_before = spec.peek().sig;
        let regs_before = *spec.regs();
        let TracedStep {
            before: b1,
            internals: x1,
            after: a1,
            ..
        } = fast.step_traced(&i);
        let TracedStep {
            before: b2,
            internals: x2,
            after: a2,
            ..
        } = spec.step_traced(&i);
        prop_assert_eq!(
            b1,
            b2,
            "outputs before edge {} (seed {}, {:?})",
            k + 1,
            seed,
            p
        );
        prop_assert_eq!(x1, x2, "internals of cycle {} (seed {})", k, seed);
        prop_assert_eq!(a1, a2, "outputs after edge {} (seed {})", k + 1, seed);
        prop_assert_eq!(
            fast.regs(),
            spec.regs(),
            "registers after edge {} (seed {}, inputs {:?})",
            k + 1,
            seed,
            i
        );
        prop_assert_eq!(fast.tick(), spec.tick());
        // `Pmu50::step` (with the kernel's idle memo) from the same inputs.
        prop_assert_eq!(
            untraced.step(&i),
            a2,
            "untraced outputs after edge {} (seed {})",
            k + 1,
            seed
        );
        prop_assert_eq!(
            untraced.regs(),
            spec.regs(),
            "untraced registers after edge {} (seed {})",
            k + 1,
            seed
        );
        cov.fig17.insert(x2.fig17);
        cov.fig18.insert(x2.fig18);
        let now = spec.regs();
        if i.bus_we && !(sig_before && i.bus_addr == addr::STATUS) {
            if now.register_file.bus_err
                && (!err_before
                    || now.register_file
                        == rf::Regs {
                            rdata: now.register_file.rdata,
                            bus_err: true,
                            ..regs_before.register_file
                        })
            {
                cov.refused = true;
                cov.refused_key_off |= !sig_before;
            }
            if now.register_file.params(p.sync_depth, p.cnt_width)
                != regs_before.register_file.params(p.sync_depth, p.cnt_width)
            {
                cov.accepted = true;
            }
        }
        cov.first |= x2.first;
        cov.skip |= x2.chg_s && x2.chg_c;
        cov.skip_clr |= x2.skip_clr && regs_before.updown_counter.quadrant_skip;
        cov.kon |= x2.kon;
        cov.koff |= x2.koff;
        cov.diag |= a2.diag;
    }
    Ok(())
}

proptest! {
    #![proptest_config(common::cases(64))]

    #[test]
    fn long_runs_from_reset_with_random_legal_parameters(p in common::params(300, 700), seed in any::<u64>(), len in 1u64..40_000) {
        lockstep(p, seed, len, &mut Coverage::default())?;
    }
}

/// `Pmu50::step` (untraced) leaves the same registers and returns the same outputs as the spec.
#[test]
fn untraced_step_equals_the_spec() {
    let p = Params::default();
    let mut fast = Pmu50::new(p).unwrap();
    let mut spec = Pmu50Spec::new(p).unwrap();
    let mut d = Driver::new(42);
    for _ in 0..300_000 {
        let i = d.next(&spec.peek());
        assert_eq!(fast.step(&i), spec.step(&i));
        assert_eq!(fast.regs(), spec.regs());
    }
}

/// Held inputs (a parked car: long idle stretches) interrupted by input changes, bus writes,
/// resets and fast-forwards (`quiet_ticks` + `fast_forward`), `Pmu50::step` against the spec.
#[test]
fn memo_across_held_inputs_resets_and_fast_forward() {
    let mut r = Rng(99);
    for case in 0..300u64 {
        let p = Params {
            sync_depth: r.range(1, 4) as u8,
            cnt_width: r.range(2, 16) as u8,
            adaptive: r.bit(),
            pw: r.range(0, 3) as u16 + 1,
            pi: r.range(0, 3) as u16,
            ps: r.range(1, 3) as u16,
            si_max: r.range(20, 60) as u16,
            si_min: 15,
            t1: r.range(1, 30) as u16,
            t2: r.range(1, 30) as u16,
            cth: r.range(1, 4) as u8,
            smp_on: r.range(2, 12) as u16,
        };
        if p.validate().is_err() {
            continue;
        }
        let mut fast = Pmu50::new(p).unwrap();
        let mut spec = Pmu50Spec::new(p).unwrap();
        let mut i = Inputs::default();
        for k in 0..20_000u64 {
            if r.chance(1, 150) {
                i = Inputs {
                    ig: r.chance(1, 3),
                    vs2_ok: r.bit(),
                    cmp_s: r.bit(),
                    cmp_c: r.bit(),
                    bus_we: r.chance(1, 20),
                    bus_addr: r.range(0, 0x15) as u8,
                    bus_wdata: r.range(0, 80) as u16,
                };
            } else if i.bus_we {
                i.bus_we = false;
            }
            if r.chance(1, 5000) {
                fast.reset();
                spec.reset();
            }
            if r.chance(1, 700) {
                // fast-forward the core (the spec steps the same edges)
                let n = fast.quiet_ticks(&i).min(r.range(0, 500));
                fast.fast_forward(n, &i).unwrap();
                for _ in 0..n {
                    spec.step(&i);
                }
            }
            let a = fast.step(&i);
            let b = spec.step(&i);
            assert_eq!(a, b, "case {case} tick {k} {p:?}");
            assert_eq!(fast.regs(), spec.regs(), "case {case} tick {k} {p:?} {i:?}");
        }
    }
}

/// The stimulus of the long runs reaches every branch, so their comparison is not vacuous.
#[test]
fn the_stimulus_covers_every_branch() {
    let mut cov = Coverage::default();
    let mut r = Rng(2026);
    let mut seeds = 0;
    for seed in 0..400u64 {
        // Short periods and small thresholds, so that key-off pulses are many.
        let p = loop {
            let pw = r.range(0, 4) as u16;
            let pi = r.range(if pw == 0 { 1 } else { 0 }, 6) as u16;
            let ps = r.range(1, 4) as u16;
            let si_min = pw + pi + ps + r.range(1, 40) as u16;
            let p = Params {
                sync_depth: r.range(1, 4) as u8,
                cnt_width: r.range(2, 16) as u8,
                adaptive: !r.chance(1, 8),
                pw,
                pi,
                ps,
                si_max: si_min + r.range(0, 200) as u16,
                si_min,
                t1: r.range(1, 80) as u16,
                t2: r.range(1, 80) as u16,
                cth: r.range(1, 5) as u8,
                smp_on: r.range(2, 20) as u16,
            };
            if p.validate().is_ok() {
                break p;
            }
        };
        lockstep(p, seed, 20_000, &mut cov).unwrap();
        seeds += 1;
    }
    assert_eq!(seeds, 400);
    let all17 = [
        Fig17::Idle,
        Fig17::S1NoRise,
        Fig17::S5AtMin,
        Fig17::S6Shorten,
        Fig17::S7AtMax,
        Fig17::S9Count,
        Fig17::S10Expand,
        Fig17::Fixed,
    ];
    let all18 = [
        Fig18::Idle,
        Fig18::S23DetectedCs,
        Fig18::S21CsRepeat,
        Fig18::S28DetectedCc,
        Fig18::S26CcRepeat,
        Fig18::S25NoChange,
    ];
    for f in all17 {
        assert!(cov.fig17.contains(&f), "FIG. 17 path {f:?} never taken");
    }
    for f in all18 {
        assert!(cov.fig18.contains(&f), "FIG. 18 path {f:?} never taken");
    }
    assert!(
        cov.refused && cov.refused_key_off && cov.accepted,
        "bus writes: refused {} (key off {}), accepted {}",
        cov.refused,
        cov.refused_key_off,
        cov.accepted
    );
    assert!(cov.first && cov.skip && cov.skip_clr && cov.kon && cov.koff && cov.diag);
}
