//! Helpers shared by the integration tests of `pmu50-core`: a tiny deterministic PRNG for long
//! simulations (the seed comes from proptest, so a failure is reproducible from its report),
//! an independent statement of the legal-parameter rules of docs/spec.md section 4, and a
//! proptest strategy for legal parameter sets.
#![allow(dead_code)]

use pmu50_core::register_file::{addr, status};
use pmu50_core::{Inputs, Outputs, Params};
use proptest::prelude::*;

/// The seeded generator of the stimuli (SplitMix64).
pub use pmu50_core::rng::SplitMix64 as Rng;

/// Any input vector at all (bus fields included; most addresses in the register map).
pub fn random_inputs(rng: &mut Rng) -> Inputs {
    let a = rng.next();
    Inputs {
        ig: a & 1 == 1,
        vs2_ok: a & 2 == 2,
        cmp_s: a & 4 == 4,
        cmp_c: a & 8 == 8,
        bus_we: a & 16 == 16,
        bus_addr: if a & 32 == 32 {
            (a >> 8) as u8
        } else {
            (a >> 8) as u8 % 0x15
        },
        bus_wdata: (a >> 16) as u16,
    }
}

/// The legal-parameter rules of docs/spec.md section 4, written from the spec (not by calling
/// `Params::validate`): no zero `ps`, `si_max`, `si_min`, `t1`, `t2`, `smp_on`; `cth` in 1..=255;
/// `si_min <= si_max`; `pw + pi >= 1` (the sample comes after the registered `sr` rose);
/// `pw + pi + ps` below the shortest interval (`si_min` if adaptive, else
/// `si_max`).
#[allow(clippy::too_many_arguments)]
pub fn legal_set(
    adaptive: bool,
    pw: u16,
    pi: u16,
    ps: u16,
    si_max: u16,
    si_min: u16,
    t1: u16,
    t2: u16,
    cth: u16,
    smp_on: u16,
) -> bool {
    let nonzero = [ps, si_max, si_min, t1, t2, smp_on].iter().all(|&v| v != 0);
    let cth_ok = (1..=255).contains(&cth);
    let order = si_min <= si_max;
    let wt = u32::from(pw) + u32::from(pi) + u32::from(ps);
    let shortest = if adaptive { si_min } else { si_max };
    let settle = u32::from(pw) + u32::from(pi) >= 1;
    nonzero && cth_ok && order && settle && wt < u32::from(shortest)
}

pub fn legal(p: &Params) -> bool {
    (1..=4).contains(&p.sync_depth)
        && (2..=16).contains(&p.cnt_width)
        && legal_set(
            p.adaptive,
            p.pw,
            p.pi,
            p.ps,
            p.si_max,
            p.si_min,
            p.t1,
            p.t2,
            u16::from(p.cth),
            p.smp_on,
        )
}

/// Legal parameter sets with short periods (so that simulations of a few periods are cheap):
/// Wt below ~70 ticks, `si_max` at most about `wt + 1 + gap + spread`.
pub fn params(gap: u16, spread: u16) -> impl Strategy<Value = Params> {
    (
        (
            1u8..=4,
            2u8..=16,
            any::<bool>(),
            0u16..=20,
            0u16..=30,
            1u16..=20,
        ),
        (0..=gap, 0..=spread, any::<bool>(), any::<u16>()),
        (
            1u16..=600,
            1u16..=600,
            prop_oneof![1u8..=6, 1u8..=255],
            1u16..=40,
        ),
    )
        .prop_map(
            |(
                (sync_depth, cnt_width, adaptive, pw, pi, ps),
                (g, s, low_min, r),
                (t1, t2, cth, smp_on),
            )| {
                let pw = if pw + pi == 0 { 1 } else { pw }; // section 4: pw + pi >= 1
                let wt = pw + pi + ps;
                let mut si_min = wt + 1 + g;
                let si_max = si_min + s;
                if !adaptive && low_min {
                    // With the fixed cycle only x has to exceed Wt: the minimum may be anything legal.
                    si_min = 1 + r % si_max;
                }
                let p = Params {
                    sync_depth,
                    cnt_width,
                    adaptive,
                    pw,
                    pi,
                    ps,
                    si_max,
                    si_min,
                    t1,
                    t2,
                    cth,
                    smp_on,
                };
                assert!(legal(&p), "strategy produced an illegal set {p:?}");
                p
            },
        )
}

/// Quadrant index of the sign pair, docs/spec.md 2.5: 0 = (1,1), 1 = (1,0), 2 = (0,0), 3 = (0,1).
pub fn quadrant(cs: bool, cc: bool) -> u8 {
    match (cs, cc) {
        (true, true) => 0,
        (true, false) => 1,
        (false, false) => 2,
        (false, true) => 3,
    }
}

/// Sign pair of a quadrant index (mod 4).
pub fn signs(q: u8) -> (bool, bool) {
    [(true, true), (true, false), (false, false), (false, true)][usize::from(q & 3)]
}

/// Two's complement value of the low `w` bits of `v`.
pub fn signed(v: u16, w: u8) -> i64 {
    let m = (1i64 << w) - 1;
    let x = i64::from(v) & m;
    if x >= 1i64 << (w - 1) {
        x - (1i64 << w)
    } else {
        x
    }
}

/// `v` reduced to `w` bits.
pub fn wrap(v: i64, w: u8) -> u16 {
    v.rem_euclid(1i64 << w) as u16
}

/// Proptest configuration with an explicit case count. Failures are not persisted to files next
/// to the sources (the report shows the minimal failing input, seeds included).
pub fn cases(n: u32) -> ProptestConfig {
    ProptestConfig {
        cases: n,
        failure_persistence: None,
        ..ProptestConfig::default()
    }
}

/// The programmable registers of the register file (docs/spec.md 2.8), written from the spec's
/// register map, not from the model: reset from a parameter set, the write map of 0x02..=0x0B,
/// their read and the legality of the set. Shared by the register-file reference of
/// `timing.rs` and the formal kit's shadow of `formal_twins.rs`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RefParams {
    pub adaptive: bool,
    pub pw: u16,
    pub pi: u16,
    pub ps: u16,
    pub si_max: u16,
    pub si_min: u16,
    pub t1: u16,
    pub t2: u16,
    /// 8 bits.
    pub cth: u16,
    pub smp_on: u16,
}

impl RefParams {
    /// The reset values: the configured parameters.
    pub fn new(p: &Params) -> RefParams {
        let (adaptive, pw, pi, ps, si_max, si_min, t1, t2, cth, smp_on) = (
            p.adaptive,
            p.pw,
            p.pi,
            p.ps,
            p.si_max,
            p.si_min,
            p.t1,
            p.t2,
            u16::from(p.cth),
            p.smp_on,
        );
        RefParams {
            adaptive,
            pw,
            pi,
            ps,
            si_max,
            si_min,
            t1,
            t2,
            cth,
            smp_on,
        }
    }

    /// The values the model's registers hold.
    pub fn of(r: &pmu50_core::register_file::Regs) -> RefParams {
        RefParams::new(&r.params(1, 16))
    }

    /// The set after a write of `d` at `a` (CTRL keeps bit 0, CTH the low byte), `None` when
    /// `a` is not one of 0x02..=0x0B.
    pub fn with_write(&self, a: u8, d: u16) -> Option<RefParams> {
        let mut c = *self;
        match a {
            0x02 => c.adaptive = d & 1 == 1,
            0x03 => c.pw = d,
            0x04 => c.pi = d,
            0x05 => c.ps = d,
            0x06 => c.si_max = d,
            0x07 => c.si_min = d,
            0x08 => c.t1 = d,
            0x09 => c.t2 = d,
            0x0A => c.cth = d & 0xFF,
            0x0B => c.smp_on = d,
            _ => return None,
        }
        Some(c)
    }

    /// What 0x02..=0x0B read, `None` at any other address.
    pub fn read(&self, a: u8) -> Option<u16> {
        Some(match a {
            0x02 => u16::from(self.adaptive),
            0x03 => self.pw,
            0x04 => self.pi,
            0x05 => self.ps,
            0x06 => self.si_max,
            0x07 => self.si_min,
            0x08 => self.t1,
            0x09 => self.t2,
            0x0A => self.cth,
            0x0B => self.smp_on,
            _ => return None,
        })
    }

    /// The rules of [`legal_set`].
    pub fn legal(&self) -> bool {
        legal_set(
            self.adaptive,
            self.pw,
            self.pi,
            self.ps,
            self.si_max,
            self.si_min,
            self.t1,
            self.t2,
            self.cth,
            self.smp_on,
        )
    }
}

/// Stimulus with memory, to reach deep states and every branch: `ig` in long runs with a few
/// glitches shorter than the synchronizer, comparators stepping through the quadrants or
/// jumping, `vs2_ok` mostly following `vs2_en`, bus writes (refused ones, W1C clears) and reads.
pub struct Driver {
    rng: Rng,
    ig: bool,
    run: u64,
    cmp: (bool, bool),
}

impl Driver {
    pub fn new(seed: u64) -> Driver {
        let mut rng = Rng(seed);
        let ig = rng.bit();
        let run = rng.range(0, 3000);
        Driver {
            rng,
            ig,
            run,
            cmp: (true, true),
        }
    }

    /// The inputs of the next cycle, whose outputs are `o`.
    pub fn next(&mut self, o: &Outputs) -> Inputs {
        let rng = &mut self.rng;
        if self.run == 0 {
            self.ig = !self.ig;
            // Mostly long phases; sometimes a glitch shorter than the synchronizer.
            self.run = if rng.chance(1, 8) {
                rng.range(1, 3)
            } else {
                rng.range(50, 4000)
            };
        }
        self.run -= 1;
        match rng.range(0, 99) {
            0..=3 => self.cmp = (rng.bit(), rng.bit()), // anything, also both signs
            4..=11 => self.cmp.0 = !self.cmp.0,         // one quadrant step through Cs
            12..=19 => self.cmp.1 = !self.cmp.1,        // one quadrant step through Cc
            _ => {}
        }
        let mut i = Inputs {
            ig: self.ig,
            vs2_ok: o.vs2_en != rng.chance(1, 40),
            cmp_s: self.cmp.0,
            cmp_c: self.cmp.1,
            ..Default::default()
        };
        if rng.chance(1, 60) {
            i.bus_we = true;
            i.bus_addr = match rng.range(0, 9) {
                0 => rng.next() as u8,
                1 => addr::STATUS,
                _ => rng.range(0, 0x15) as u8,
            };
            i.bus_wdata = match rng.range(0, 5) {
                0 => rng.next() as u16,
                1 => rng.range(0, 12) as u16,
                2 => o.si.wrapping_add(rng.range(0, 40) as u16).wrapping_sub(20),
                3 => rng.range(0, 700) as u16,
                4 => (1 << status::QUADRANT_SKIP) | (1 << status::BUS_ERR),
                _ => 0x3FF,
            };
        } else if rng.chance(1, 4) {
            i.bus_addr = rng.range(0, 0x20) as u8;
        }
        i
    }
}
