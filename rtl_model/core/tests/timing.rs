//! Top-level timing against docs/spec.md 2.1-2.3, 2.8 and section 3: the key-off pulse table,
//! the st-to-st cycle, key-on after SYNC_DEPTH edges with sampling every `smp_on`, key-off
//! restart, and the register file's write rules (refused while key off, legality, W1C).
//!
//! Convention (spec 6.1): "tick k" is the cycle after k edges; its outputs are `peek()` then, and
//! the inputs applied during tick k are those of edge k+1. The environment drives
//! `vs2_ok` = `vs2_en` of the current outputs.

mod common;

use common::{RefParams, Rng};
use pmu50_core::register_file::addr;
use pmu50_core::{Inputs, Outputs, Params, Pmu50, TracedStep};
use proptest::prelude::*;

fn wt(p: &Params) -> u64 {
    u64::from(p.pw) + u64::from(p.pi) + u64::from(p.ps)
}

/// Key off from reset, `ig` = 0, `vs2_ok` = previous `vs2_en`, comparators constant: the table of
/// spec 2.2 repeats every `si` = x ticks; nothing else moves after the first sample.
fn check_key_off_table(p: Params, cmp: (bool, bool)) {
    let mut m = Pmu50::new(p).unwrap();
    let si = u64::from(p.si_max);
    let wt = wt(&p);
    let ps_start = u64::from(p.pw) + u64::from(p.pi);
    let mut prev_vs2_en = false;
    for k in 0..3 * si + wt + 3 {
        let o = m.peek();
        let t = k % si;
        let ctx = format!("tick {k} (t = {t}), {p:?}, {o:?}");
        assert!(
            !o.sig && !o.vr_hi && !o.vm_en && !o.vs1_en && !o.rail_hi && o.vp_en,
            "{ctx}"
        );
        assert_eq!(o.st, t == 0, "st: {ctx}");
        assert_eq!(o.vs2_en, t < wt, "vs2_en high for pw+pi+ps from st: {ctx}");
        assert_eq!(o.ps_win, ps_start <= t && t < wt, "ps_win: {ctx}");
        assert_eq!(o.smp, t == wt - 1, "smp at the last tick of Ps: {ctx}");
        assert_eq!(o.sr, k >= 1 && prev_vs2_en, "sr one tick late: {ctx}");
        assert_eq!(
            (o.si, o.cnt_r, o.hist_s, o.hist_c),
            (p.si_max, 0, false, false),
            "{ctx}"
        );
        assert!(!o.bus_err && !o.quadrant_skip && !o.diag, "{ctx}");
        // (A one-tick window never samples: see the failing test below; not repeated here.)
        if wt >= 2 {
            assert_eq!(
                (o.cs, o.cc),
                if k >= wt { cmp } else { (false, false) },
                "{ctx}"
            );
        }
        prev_vs2_en = o.vs2_en;
        let TracedStep { internals: int, .. } = m.step_traced(&Inputs {
            vs2_ok: o.vs2_en,
            cmp_s: cmp.0,
            cmp_c: cmp.1,
            ..Default::default()
        });
        assert_eq!(int.upd, o.smp && o.sr, "{ctx}");
        assert!(!int.kon && !int.koff && !int.chg_s && !int.chg_c, "{ctx}");
    }
}

/// The spec's own example (defaults: Pw 5, Pi 12, Ps 5, x 660), tick by tick.
#[test]
fn spec_table_with_defaults() {
    let p = Params::default();
    let mut m = Pmu50::new(p).unwrap();
    let mut rows = vec![];
    for _ in 0..700 {
        let o = m.peek();
        rows.push(o);
        m.step(&Inputs {
            vs2_ok: o.vs2_en,
            ..Default::default()
        });
    }
    let on = |f: fn(&Outputs) -> bool| {
        rows.iter()
            .enumerate()
            .filter(|(_, o)| f(o))
            .map(|(k, _)| k)
            .collect::<Vec<_>>()
    };
    assert_eq!(on(|o| o.st), [0, 660]);
    assert_eq!(
        on(|o| o.vs2_en),
        (0..22).chain(660..682).collect::<Vec<_>>()
    );
    assert_eq!(
        on(|o| o.ps_win),
        (17..22).chain(677..682).collect::<Vec<_>>()
    );
    assert_eq!(on(|o| o.smp), [21, 681]);
    assert_eq!(on(|o| o.sr), (1..23).chain(661..683).collect::<Vec<_>>());
}

proptest! {
    #![proptest_config(common::cases(150))]

    #[test]
    fn key_off_pulse_table(p in common::params(300, 700), cmp in (any::<bool>(), any::<bool>())) {
        check_key_off_table(p, cmp);
    }
}

proptest! {
    #![proptest_config(common::cases(100))]

    /// Spec 2.3: `sr` <= `vs2_en` & `vs2_ok`, whatever the rail does (here a random power-good,
    /// independent of the enable), key on or off.
    #[test]
    fn sr_is_registered_vs2_en_and_vs2_ok(p in common::params(100, 300), seed in any::<u64>()) {
        let mut m = Pmu50::new(p).unwrap();
        let mut rng = Rng(seed);
        let mut ig = false;
        for k in 0..4 * u64::from(p.si_max) {
            if rng.chance(1, 300) {
                ig = !ig;
            }
            let o = m.peek();
            let ok = rng.bit();
            let cmp = (rng.bit(), rng.bit());
            let TracedStep { internals: int, after: o2, .. } = m.step_traced(&Inputs { ig, vs2_ok: ok, cmp_s: cmp.0, cmp_c: cmp.1, ..Default::default() });
            prop_assert_eq!(o2.sr, o.vs2_en && ok, "sr after edge {}", k + 1);
            // I2: without a good rail no sample; FIG. 17 ends at S1 (interval unchanged).
            let sampled = o.smp && o.sr;
            prop_assert_eq!(int.upd, sampled);
            prop_assert_eq!((o2.cs, o2.cc), if sampled { cmp } else { (o.cs, o.cc) }, "latch at edge {}", k + 1);
            if o.smp && !o.sig && !o.sr && p.adaptive && !int.koff {
                prop_assert_eq!(int.fig17 as u8, 1, "S1: N");
                prop_assert_eq!(o2.si, o.si);
            }
        }
    }
}

/// Spec section 4: `pw + pi >= 1`. With Pw = Pi = 0 the only sampling tick would be the tick Vs2
/// rises, when the registered `sr` is still 0, so no key-off sample would ever be taken (this test
/// found that; the rule was added). The set is refused, and the shortest legal window (Pw = 1,
/// Ps = 1) samples at every pulse.
#[test]
fn every_key_off_pulse_takes_a_sample_with_the_shortest_legal_window() {
    let p = Params {
        pw: 0,
        pi: 0,
        ps: 1,
        ..Params::default()
    };
    assert!(p.validate().is_err(), "Pw = Pi = 0 must be refused");
    let p = Params {
        pw: 1,
        pi: 0,
        ps: 1,
        ..Params::default()
    };
    let mut m = Pmu50::new(p).unwrap();
    let (mut pulses, mut samples) = (0, 0);
    for _ in 0..5 * u64::from(p.si_max) {
        let o = m.peek();
        let TracedStep { internals: int, .. } = m.step_traced(&Inputs {
            vs2_ok: o.vs2_en,
            cmp_s: true,
            ..Default::default()
        });
        pulses += u32::from(o.smp);
        samples += u32::from(int.upd);
    }
    assert!(pulses >= 5);
    assert_eq!(
        samples, pulses,
        "key-off pulses without a sample (Wt = 2 ticks)"
    );
}

proptest! {
    #![proptest_config(common::cases(120))]

    /// With rotation (comparators change between pulses): the st-to-st distance is the `si` in
    /// force at the second st, `si` only changes at a key-off sampling edge, stays in
    /// [si_min, si_max], and every window is Wt long.
    #[test]
    fn st_to_st_is_si(p in common::params(200, 500), seed in any::<u64>()) {
        let mut m = Pmu50::new(p).unwrap();
        let mut rng = Rng(seed);
        let wt = wt(&p);
        let mut cmp = (rng.bit(), rng.bit());
        let mut last_st: Option<u64> = None;
        let mut sts = 0;
        let mut k = 0u64;
        while sts < 12 {
            let o = m.peek();
            if o.st {
                if let Some(l) = last_st {
                    prop_assert_eq!(k - l, u64::from(o.si), "st at {} and {}", l, k);
                }
                last_st = Some(k);
                sts += 1;
            }
            if let Some(l) = last_st {
                prop_assert_eq!(o.vs2_en, k - l < wt);
            }
            prop_assert!(p.si_min <= o.si && o.si <= p.si_max);
            // New comparator values once the window is over (the shaft moved between pulses).
            if !o.vs2_en && rng.chance(1, 200) {
                cmp = (rng.bit(), rng.bit());
            }
            let TracedStep { after: o2, .. } = m.step_traced(&Inputs { vs2_ok: o.vs2_en, cmp_s: cmp.0, cmp_c: cmp.1, ..Default::default() });
            if o2.si != o.si {
                prop_assert!(o.smp && !o.sig, "si changed at tick {} without a key-off sample", k);
            }
            k += 1;
        }
    }

    /// Key-on `SYNC_DEPTH` edges after `ig` rises: Vs2 continuous, no st, samples every smp_on;
    /// `si`, history and `cnt_r` hold while on. Key-off `SYNC_DEPTH` edges after `ig` falls: the
    /// timer restarts with st, si = x, history and cnt_r cleared, signs and counters kept.
    #[test]
    fn key_on_and_off_through_the_synchronizer(p in common::params(200, 500), seed in any::<u64>()) {
        let mut m = Pmu50::new(p).unwrap();
        let mut rng = Rng(seed);
        let d = u64::from(p.sync_depth);
        let k_on = rng.range(0, 3 * u64::from(p.si_max)); // first edge with ig = 1 is k_on + 1
        let on_len = rng.range(d + 1, d + 20 * u64::from(p.smp_on) + 50);
        let k_off = k_on + on_len; // first edge with ig = 0 again is k_off + 1
        let end = k_off + d + 2 * u64::from(p.si_max);
        let mut cmp = (rng.bit(), rng.bit());
        let mut held: Option<(u16, u8, bool, bool)> = None;
        let write_x_at_koff = rng.bit();
        let mut x_now = p.si_max;
        let mut rf = RefRf::new(&p);
        for k in 0..end {
            let o = m.peek();
            let sig_want = k >= k_on + d && k < k_off + d;
            prop_assert_eq!(o.sig, sig_want, "sig at tick {}", k);
            prop_assert_eq!((o.vr_hi, o.vm_en, o.vs1_en, o.rail_hi, o.vp_en), (o.sig, o.sig, o.sig, o.sig, true));
            if o.sig {
                let j = k - (k_on + d);
                prop_assert!(o.vs2_en && !o.st && !o.ps_win, "tick {}", k);
                prop_assert_eq!(o.smp, j % u64::from(p.smp_on) == u64::from(p.smp_on) - 1, "key-on smp at tick {} (j = {})", k, j);
                if j >= 1 {
                    prop_assert!(o.sr);
                    // si, history and cnt_r hold while the key is on.
                    let now = (o.si, o.cnt_r, o.hist_s, o.hist_c);
                    prop_assert_eq!(now, *held.get_or_insert(now));
                }
            }
            if k == k_off + d {
                prop_assert!(o.st && o.vs2_en && !o.sig, "key-off starts a pulse at once");
                prop_assert_eq!(m.regs().timing_generator.tmr, 0);
                prop_assert_eq!((o.si, o.cnt_r, o.hist_s, o.hist_c), (x_now, 0, false, false), "si = x as it stands after the key-off edge");
            }
            if rng.chance(1, 15) {
                cmp = (rng.bit(), rng.bit());
            }
            let ig = k >= k_on && k < k_off;
            // Sometimes a write of SI_MAX at the key-off edge itself: it counts for the new key-off
            // period (spec 2.6 `si_max_nxt`) when it is legal.
            let x_write = (k + 1 == k_off + d && write_x_at_koff).then(|| rng.range(u64::from(p.si_min), u64::from(p.si_max) + 300) as u16);
            // Registered reads across the key edges (no writes here: the parameters are the reset ones).
            let a = if rng.bit() { addr::STATUS } else { rng.range(0, 0x15) as u8 };
            let want_rdata = rf.read(a, &p, &o, m.regs().comparator_latch.vld);
            let mut i = Inputs { ig, vs2_ok: o.vs2_en, cmp_s: cmp.0, cmp_c: cmp.1, bus_addr: a, ..Default::default() };
            if let Some(v) = x_write {
                (i.bus_we, i.bus_wdata) = (true, v);
                i.bus_addr = addr::SI_MAX;
            }
            let TracedStep { internals: int, after: o2, .. } = m.step_traced(&i);
            if let Some(v) = x_write {
                prop_assert!(o.sig, "the key-off edge still has sig = 1: the write is not refused for the key");
                rf.write(addr::SI_MAX, v, true);
                prop_assert_eq!(RefRf::of(&m), rf, "write SI_MAX <- {} at the key-off edge", v);
                x_now = rf.regs.si_max;
            } else {
                prop_assert_eq!(o2.bus_rdata, want_rdata, "bus_rdata after edge {} (address {:#04x})", k + 1, a);
            }
            prop_assert_eq!(int.kon, k + 1 == k_on + d, "kon at edge {}", k + 1);
            prop_assert_eq!(int.koff, k + 1 == k_off + d, "koff at edge {}", k + 1);
            // Latches: new values exactly at sampling edges, held otherwise (also across key edges).
            let sampled = o.smp && o.sr;
            prop_assert_eq!(int.upd, sampled);
            prop_assert_eq!((o2.cs, o2.cc), if sampled { cmp } else { (o.cs, o.cc) }, "latch at edge {}", k + 1);
            if !sampled {
                prop_assert_eq!((o2.cnt_s, o2.cnt_c), (o.cnt_s, o.cnt_c), "counters move only at samples");
            }
        }
    }
}

/// Reference register file: the programmable registers and `bus_err` (spec 2.8).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct RefRf {
    regs: RefParams,
    bus_err: bool,
}

impl RefRf {
    fn new(p: &Params) -> Self {
        RefRf {
            regs: RefParams::new(p),
            bus_err: false,
        }
    }
    fn of(m: &Pmu50) -> Self {
        let r = m.regs().register_file;
        RefRf {
            regs: RefParams::of(&r),
            bus_err: r.bus_err,
        }
    }
    /// The read mux at `a`, with the status and count registers taken from the cycle's outputs
    /// (and the latch's `vld`).
    fn read(&self, a: u8, p: &Params, o: &Outputs, vld: bool) -> u16 {
        let sx = |v: u16| common::signed(v, p.cnt_width) as i16 as u16;
        let b = |x: bool, n: u32| u16::from(x) << n;
        if let Some(v) = self.regs.read(a) {
            return v;
        }
        match a {
            0x00 => 0x5050,
            0x01 => 0x0001,
            0x0C => u16::from(p.sync_depth) | (u16::from(p.cnt_width) << 8),
            0x10 => sx(o.cnt_s),
            0x11 => sx(o.cnt_c),
            0x12 => u16::from(o.cnt_r),
            0x13 => o.si,
            0x14 => {
                b(o.cs, 0)
                    | b(o.cc, 1)
                    | b(o.hist_s, 2)
                    | b(o.hist_c, 3)
                    | b(o.diag, 4)
                    | b(o.quadrant_skip, 5)
                    | b(o.sig, 6)
                    | b(vld, 7)
                    | b(o.sr, 8)
                    | b(self.bus_err, 9)
            }
            _ => 0,
        }
    }
    /// One edge with a write (we = 1) while `sig` is `sig`.
    fn write(&mut self, a: u8, d: u16, sig: bool) {
        let mut refused = false;
        let mut clear = false;
        if a == 0x14 && sig {
            clear = d & (1 << 9) != 0;
        } else if !sig {
            refused = true;
        } else {
            match self.regs.with_write(a, d) {
                Some(c) if c.legal() => self.regs = c,
                _ => refused = true,
            }
        }
        self.bus_err = refused || (self.bus_err && !clear);
    }
}

fn any_write() -> impl Strategy<Value = (u8, u16)> {
    (
        prop_oneof![4 => 0u8..=0x16, 1 => any::<u8>()],
        prop_oneof![
            any::<u16>(),
            0u16..=40,
            300u16..=2000,
            Just(0x3FF),
            Just(1 << 9),
            Just(1 << 5)
        ],
    )
}

proptest! {
    #![proptest_config(common::cases(200))]

    /// While the key is off every write is refused: registers unchanged, bus_err set; a W1C of
    /// bus_err is refused too.
    #[test]
    fn writes_refused_while_key_off(p in common::params(100, 300), wait in 0u64..500, writes in prop::collection::vec(any_write(), 1..20)) {
        let mut m = Pmu50::new(p).unwrap();
        for _ in 0..wait {
            let o = m.peek();
            m.step(&Inputs { vs2_ok: o.vs2_en, ..Default::default() });
        }
        let rf0 = RefRf::new(&p);
        for (a, d) in writes {
            let o = m.peek();
            prop_assert!(!o.sig);
            let TracedStep { internals: int, after: o2, .. } = m.step_traced(&Inputs { vs2_ok: o.vs2_en, bus_we: true, bus_addr: a, bus_wdata: d, ..Default::default() });
            prop_assert!(o2.bus_err, "write {:#04x} <- {:#06x} while key off not flagged", a, d);
            prop_assert!(!int.skip_clr);
            prop_assert_eq!(RefRf { bus_err: false, ..RefRf::of(&m) }, rf0, "write {:#04x} <- {:#06x} taken while key off", a, d);
        }
    }

    /// While the key is on: legal parameter writes are taken, illegal ones and writes to read-only
    /// or unmapped addresses are refused (bus_err set), STATUS bit 9 clears bus_err; reads are
    /// registered (bus_rdata after edge k = register at the address of edge k, before the edge).
    #[test]
    fn writes_while_key_on_follow_the_rules(
        p in common::params(100, 300),
        ops in prop::collection::vec((prop::bool::weighted(0.7), any_write()), 1..80),
        seed in any::<u64>(),
    ) {
        let mut rng = Rng(seed);
        let mut m = Pmu50::new(p).unwrap();
        while !m.peek().sig {
            let o = m.peek();
            m.step(&Inputs { ig: true, vs2_ok: o.vs2_en, ..Default::default() });
        }
        let mut rf = RefRf::new(&p);
        prop_assert_eq!(RefRf::of(&m), rf);
        for (k, (we, (a, d))) in ops.into_iter().enumerate() {
            let o = m.peek();
            // Half of the parameter writes aim at a legality boundary (Wt vs the shortest interval,
            // si_min vs si_max), off by -1, 0 or +1.
            let mut d = d;
            if we && rng.bit() {
                let delta = rng.range(0, 2) as i64 - 1;
                let wt = i64::from(rf.regs.pw) + i64::from(rf.regs.pi) + i64::from(rf.regs.ps);
                let shortest = i64::from(if rf.regs.adaptive { rf.regs.si_min } else { rf.regs.si_max });
                let cur = |a: u8| i64::from(rf.read(a, &p, &o, false));
                let target = match a {
                    // Wt at the shortest interval, or pw + pi = 0 (section 4: pw + pi >= 1).
                    0x03 | 0x04 if rng.chance(1, 3) => Some(-(i64::from(rf.regs.pw) + i64::from(rf.regs.pi) - cur(a))),
                    0x03..=0x05 => Some(shortest - (wt - cur(a))),
                    0x06 => Some(if rng.bit() { i64::from(rf.regs.si_min) } else { wt }),
                    0x07 => Some(if rng.bit() { i64::from(rf.regs.si_max) } else { wt }),
                    _ => None,
                };
                if let Some(t) = target {
                    d = (t + delta).clamp(0, 0xFFFF) as u16;
                }
            }
            let expect_read = rf.read(a, &p, &o, m.regs().comparator_latch.vld);
            prop_assert_eq!(m.read(a), expect_read, "read mux at {:#04x}", a);
            let cmp = (rng.bit(), rng.bit());
            let TracedStep { internals: int, after: o2, .. } = m.step_traced(&Inputs { ig: true, vs2_ok: o.vs2_en, bus_we: we, bus_addr: a, bus_wdata: d, cmp_s: cmp.0, cmp_c: cmp.1 });
            if we {
                rf.write(a, d, true);
            }
            prop_assert_eq!(RefRf::of(&m), rf, "op {}: we {} {:#04x} <- {:#06x}", k, we, a, d);
            prop_assert_eq!(o2.bus_err, rf.bus_err);
            prop_assert_eq!(o2.bus_rdata, expect_read, "registered read of {:#04x}", a);
            prop_assert_eq!(int.skip_clr, we && a == addr::STATUS && d & (1 << 5) != 0);
        }
    }
}

/// Drive key on with the given comparator pair at the next sample; returns the outputs after it.
fn sample_on(m: &mut Pmu50, cmp: (bool, bool), bus: Option<(u8, u16)>) -> Outputs {
    for _ in 0..200_000 {
        let o = m.peek();
        let sampling = o.smp && o.sr;
        let mut i = Inputs {
            ig: true,
            vs2_ok: o.vs2_en,
            cmp_s: cmp.0,
            cmp_c: cmp.1,
            ..Default::default()
        };
        if sampling {
            if let Some((a, d)) = bus {
                (i.bus_we, i.bus_addr, i.bus_wdata) = (true, a, d);
            }
        }
        let o2 = m.step(&i);
        if sampling {
            return o2;
        }
    }
    panic!("no sample");
}

proptest! {
    #![proptest_config(common::cases(60))]

    /// quadrant_skip: set by a 2-step, sticky, cleared by W1C of STATUS bit 5 while on (diag with
    /// it), refused while off; a skip at the same edge as the clear wins. bus_err W1C (bit 9).
    #[test]
    fn w1c_of_quadrant_skip_and_bus_err(p in common::params(100, 300), other_bits in any::<u16>()) {
        let mut m = Pmu50::new(p).unwrap();
        sample_on(&mut m, (true, true), None); // first sample: preset
        let o = sample_on(&mut m, (false, false), None); // 2-step
        prop_assert!(o.quadrant_skip && o.diag);
        let o = sample_on(&mut m, (false, true), None); // ordinary step: still set
        prop_assert!(o.quadrant_skip && o.diag);
        // Clear without bit 5: nothing.
        let w = other_bits & !(1 << 5) & !(1 << 9);
        let o = m.step(&Inputs { ig: true, vs2_ok: true, cmp_s: false, cmp_c: true, bus_we: true, bus_addr: addr::STATUS, bus_wdata: w });
        prop_assert!(o.quadrant_skip && !o.bus_err);
        // Clear with bit 5 (the comparators hold the latched quadrant, so a sample at this edge,
        // if any, changes nothing).
        let o = m.step(&Inputs { ig: true, vs2_ok: true, cmp_s: false, cmp_c: true, bus_we: true, bus_addr: addr::STATUS, bus_wdata: other_bits | (1 << 5) });
        prop_assert!(!o.quadrant_skip, "W1C bit 5 did not clear quadrant_skip");
        prop_assert!(!o.diag, "diag follows the cleared skip (counts agree)");
        // A new skip at the same edge as a clear: set wins.
        let o = sample_on(&mut m, (true, false), Some((addr::STATUS, 1 << 5)));
        prop_assert!(o.quadrant_skip && o.diag, "set must win over clear");
        // bus_err: set by a refused write, cleared by bit 9 only.
        let o = m.step(&Inputs { ig: true, vs2_ok: true, cmp_s: true, cmp_c: false, bus_we: true, bus_addr: addr::ID, bus_wdata: 1 });
        prop_assert!(o.bus_err);
        let o = m.step(&Inputs { ig: true, vs2_ok: true, cmp_s: true, cmp_c: false, bus_we: true, bus_addr: addr::STATUS, bus_wdata: 1 << 5 });
        prop_assert!(o.bus_err && !o.quadrant_skip);
        let o = m.step(&Inputs { ig: true, vs2_ok: true, cmp_s: true, cmp_c: false, bus_we: true, bus_addr: addr::STATUS, bus_wdata: 1 << 9 });
        prop_assert!(!o.bus_err, "W1C bit 9 did not clear bus_err");
        // Key off: another skip, then the W1C is refused.
        sample_on(&mut m, (false, true), None);
        let o = sample_on(&mut m, (true, false), None);
        prop_assert!(o.quadrant_skip);
        while m.peek().sig {
            let o = m.peek();
            m.step(&Inputs { vs2_ok: o.vs2_en, cmp_s: true, cmp_c: false, ..Default::default() });
        }
        let o = m.step(&Inputs { bus_we: true, bus_addr: addr::STATUS, bus_wdata: (1 << 5) | (1 << 9), cmp_s: true, ..Default::default() });
        prop_assert!(o.quadrant_skip && o.bus_err, "W1C while key off must be refused");
    }
}

/// A write is accepted while `sig` = 1, which includes the key-off edge itself. A write lowering
/// SI_MAX at exactly that edge must not leave `si` at the old x, above the new one, for the whole
/// key-off period (S7 `si >= si_max` would hold it there; [0228], [0252]). This test found that
/// the key-off edge loaded the x in force before the edge; spec 2.6 now loads `si_max_nxt`.
#[test]
fn si_within_min_and_max_in_key_off_even_with_a_write_at_the_key_off_edge() {
    let p = Params::default();
    let d = u64::from(p.sync_depth);
    let mut m = Pmu50::new(p).unwrap();
    for _ in 0..50 {
        let o = m.peek();
        m.step(&Inputs {
            ig: true,
            vs2_ok: o.vs2_en,
            ..Default::default()
        });
    }
    assert!(m.peek().sig);
    // ig falls: sig falls at the d-th edge; that edge carries the write x := 440.
    for k in 1..=d {
        let o = m.peek();
        let mut i = Inputs {
            vs2_ok: o.vs2_en,
            ..Default::default()
        };
        if k == d {
            (i.bus_we, i.bus_addr, i.bus_wdata) = (true, addr::SI_MAX, 440);
        }
        let TracedStep { internals: int, .. } = m.step_traced(&i);
        assert_eq!(int.koff, k == d);
    }
    let o = m.peek();
    assert!(
        !o.sig && !o.bus_err,
        "the write was accepted at the key-off edge"
    );
    assert_eq!(m.read(addr::SI_MAX), 440);
    let mut sts = vec![];
    for k in 0..1500u64 {
        let o = m.peek();
        assert!(
            o.si <= 440,
            "tick {k} after key-off: si = {} > x = 440",
            o.si
        );
        if o.st {
            sts.push(k);
        }
        m.step(&Inputs {
            vs2_ok: o.vs2_en,
            ..Default::default()
        });
    }
    assert_eq!(&sts[..3], [0, 440, 880]);
}
