//! `Pmu50::quiet_ticks` / `fast_forward` (docs/spec.md section 5) are exact: for reachable states
//! and constant inputs, q = quiet_ticks(i) edges change no register but `timing_generator.tmr`,
//! the edge after them changes another register, `fast_forward(n)` for n <= q equals n steps
//! (registers and tick count), and `fast_forward(q + 1)` is refused.

mod common;

use common::Rng;
use pmu50_core::register_file::addr;
use pmu50_core::{Inputs, Params, Pmu50, Regs};
use proptest::prelude::*;

/// Steps checked one by one; a longer finite q is checked on its first CAP edges only.
const CAP: u64 = 5000;

fn others(r: &Regs) -> Regs {
    let mut x = *r;
    x.timing_generator.tmr = 0;
    x
}

/// Build a reachable state: random history with key on/off runs, then optionally a key-off phase
/// with the environment's `vs2_ok` (= `vs2_en` of the cycle), stopped at a random tick, so that
/// many states are between two key-off pulses.
fn reach(p: Params, seed: u64, len: u64, end_key_off: bool) -> (Pmu50, Rng) {
    let mut m = Pmu50::new(p).unwrap();
    let mut rng = Rng(seed);
    let mut ig = rng.bit();
    let mut run = rng.range(0, 600);
    let mut cmp = (rng.bit(), rng.bit());
    for _ in 0..len {
        if run == 0 {
            ig = !ig;
            run = rng.range(1, 1200);
        }
        run -= 1;
        if rng.chance(1, 20) {
            cmp = (rng.bit(), rng.bit());
        }
        let o = m.peek();
        let mut i = Inputs {
            ig,
            vs2_ok: o.vs2_en && !rng.chance(1, 40),
            cmp_s: cmp.0,
            cmp_c: cmp.1,
            ..Default::default()
        };
        if rng.chance(1, 40) {
            i.bus_we = true;
            i.bus_addr = rng.range(0, 0x15) as u8;
            i.bus_wdata = if rng.bit() {
                rng.range(0, 60) as u16
            } else {
                m.read(i.bus_addr)
                    .wrapping_add(rng.range(0, 9) as u16)
                    .wrapping_sub(4)
            };
        }
        m.step(&i);
    }
    if end_key_off {
        let extra = rng.range(0, 3 * u64::from(p.si_max));
        for _ in 0..u64::from(p.sync_depth) + extra {
            let o = m.peek();
            m.step(&Inputs {
                vs2_ok: o.vs2_en,
                cmp_s: cmp.0,
                cmp_c: cmp.1,
                ..Default::default()
            });
        }
    }
    (m, rng)
}

/// The constant inputs of the check.
fn constant_inputs(m: &Pmu50, rng: &mut Rng, kind: u8) -> Inputs {
    let o = m.peek();
    match kind {
        // The idle key-off gap: key off, Vs2 not good, comparators low.
        0 => Inputs::default(),
        // Same key state, random Vs2 good, comparators at the latched values or random.
        1 => {
            let (s, c) = if rng.bit() {
                (o.cs, o.cc)
            } else {
                (rng.bit(), rng.bit())
            };
            Inputs {
                ig: o.sig,
                vs2_ok: rng.bit(),
                cmp_s: s,
                cmp_c: c,
                bus_addr: rng.range(0, 0x15) as u8,
                ..Default::default()
            }
        }
        // Key on, healthy rail, comparators at the latched values: only the timer moves.
        2 => Inputs {
            ig: true,
            vs2_ok: true,
            cmp_s: o.cs,
            cmp_c: o.cc,
            ..Default::default()
        },
        // Key on, healthy rail, comparators away from the latched values: the next sample counts.
        4 => Inputs {
            ig: true,
            vs2_ok: true,
            cmp_s: !o.cs,
            cmp_c: o.cc ^ rng.bit(),
            ..Default::default()
        },
        // Anything, including a constant bus write (refused or not; half of them writing the
        // value the register holds).
        _ => {
            let mut i = common::random_inputs(rng);
            i.bus_addr %= 0x18;
            if rng.bit() {
                i.bus_wdata = m.read(i.bus_addr);
            }
            i
        }
    }
}

/// Check one quiet window; returns the core after the edge that ends it (None: q = MAX or > CAP).
fn check_exact(m: &Pmu50, i: &Inputs) -> Option<Pmu50> {
    let q = m.quiet_ticks(i);
    let ctx = || {
        format!(
            "q = {q}, tick {}, regs {:?}, inputs {i:?}",
            m.tick(),
            m.regs()
        )
    };
    // `n` steps from `m` change no register but tmr (`why`: the message around the edge that
    // did), and fast_forward(n) lands where they do; the core after the steps
    let quiet_steps = |n: u64, why: (&str, &str)| {
        let mut a = m.clone();
        for k in 0..n {
            let before = others(a.regs());
            a.step(i);
            assert_eq!(
                others(a.regs()),
                before,
                "{} {k} {}; {}",
                why.0,
                why.1,
                ctx()
            );
        }
        let mut b = m.clone();
        b.fast_forward(n, i).unwrap();
        assert_eq!(b, a, "fast_forward({n}) != {n} steps; {}", ctx());
        a
    };
    if q == u64::MAX {
        let o = m.peek();
        let p = m.regs().register_file;
        let period = if o.sig {
            u64::from(p.smp_on)
        } else {
            u64::from(m.regs().drive_interval.si)
        };
        quiet_steps(
            3 * period.max(u64::from(m.regs().timing_generator.tmr) + 1),
            ("q = MAX but edge", "changed a register"),
        );
        return None;
    }
    let n = q.min(CAP);
    let mut a = quiet_steps(n, ("edge", "< q changed a register other than tmr"));
    // A shorter jump from the start, too.
    if n > 1 {
        let k = n / 2;
        let mut c = m.clone();
        c.fast_forward(k, i).unwrap();
        let mut d = m.clone();
        for _ in 0..k {
            d.step(i);
        }
        assert_eq!(c, d, "fast_forward({k}) != {k} steps; {}", ctx());
    }
    if q <= CAP {
        let before = others(a.regs());
        a.step(i);
        assert_ne!(
            others(a.regs()),
            before,
            "edge q did not change any register but tmr: q is not exact; {}",
            ctx()
        );
        let mut e = m.clone();
        assert!(
            e.fast_forward(q + 1, i).is_err(),
            "fast_forward(q + 1) accepted; {}",
            ctx()
        );
        assert_eq!(&e, m, "a refused fast_forward changed the core");
        return Some(a);
    }
    None
}

proptest! {
    #![proptest_config(common::cases(400))]

    #[test]
    fn quiet_ticks_is_exact(
        p in common::params(300, 700),
        seed in any::<u64>(),
        len in 0u64..4000,
        end_key_off in prop::bool::weighted(0.6),
        kind in prop_oneof![3 => Just(0u8), 2 => Just(1u8), 1 => Just(2u8), 2 => Just(3u8), 1 => Just(4u8)],
    ) {
        let (m, mut rng) = reach(p, seed, len, end_key_off);
        let i = constant_inputs(&m, &mut rng, kind);
        // Several consecutive quiet windows under the same constant inputs.
        let mut m = m;
        for _ in 0..8 {
            match check_exact(&m, &i) {
                Some(next) => m = next,
                None => break,
            }
        }
    }
}

/// The main use (spec section 5): key off with the environment, the whole idle gap between two
/// pulses. With Vs2 kept good (`vs2_ok` = 1, what the environment applies from the next `st` on)
/// the quiet run ends exactly at the edge where `sr` rises again: q = si - tmr from every tick
/// after `sr` has fallen; with `vs2_ok` = 0 nothing but the timer ever moves (q = MAX).
#[test]
fn idle_gap_is_one_fast_forward() {
    for (p, cmp) in [
        (Params::default(), (true, true)),
        (
            Params {
                adaptive: false,
                ..Params::default()
            },
            (false, true),
        ),
        (
            Params {
                pw: 1,
                pi: 0,
                ps: 1,
                si_min: 3,
                si_max: 9,
                t1: 3,
                t2: 1,
                cth: 1,
                sync_depth: 1,
                ..Params::default()
            },
            (true, false),
        ),
    ] {
        let mut m = Pmu50::new(p).unwrap();
        let wt = u64::from(p.pw + p.pi + p.ps);
        let mut gaps = 0;
        for _ in 0..5 * u64::from(p.si_max) {
            let o = m.peek();
            let tmr = u64::from(m.regs().timing_generator.tmr);
            if !o.sig && !o.sr && !o.vs2_en && tmr > wt {
                let si = u64::from(o.si);
                let idle = Inputs {
                    cmp_s: cmp.0,
                    cmp_c: cmp.1,
                    ..Default::default()
                };
                let good = Inputs {
                    vs2_ok: true,
                    ..idle
                };
                assert_eq!(m.quiet_ticks(&good), si - tmr, "tmr {tmr}, si {si}");
                assert_eq!(m.quiet_ticks(&idle), u64::MAX, "tmr {tmr}");
                assert!(check_exact(&m, &good).is_some());
                assert!(check_exact(&m, &idle).is_none());
                if tmr == wt + 1 {
                    gaps += 1;
                }
            }
            m.step(&Inputs {
                vs2_ok: o.vs2_en,
                cmp_s: cmp.0,
                cmp_c: cmp.1,
                ..Default::default()
            });
        }
        assert!(gaps >= 3, "{gaps} gaps seen");
    }
}

/// Writes keep the core busy: a refused write sets `bus_err` (q = 0), but once `bus_err` is set
/// the same refused write changes nothing, and the read port reads a constant register.
#[test]
fn constant_refused_write_is_quiet_once_flagged() {
    let mut m = Pmu50::new(Params::default()).unwrap();
    let w = Inputs {
        bus_we: true,
        bus_addr: addr::T2,
        bus_wdata: 1,
        ..Default::default()
    };
    assert_eq!(m.quiet_ticks(&w), 0);
    m.step(&w);
    assert!(m.peek().bus_err);
    assert!(m.quiet_ticks(&w) > 0);
    check_exact(&m, &w);
}
