//! Up/down counters 58c/58d (docs/spec.md 2.5, 2.7) against a quadrant-based reference model.
//!
//! The reference does not use the [0096]-[0099] rule table at all. It only knows the quadrant
//! index q = f(Cs, Cc) (0:(1,1), 1:(1,0), 2:(0,0), 3:(0,1)) and that
//! - a forward step (q + 1 mod 4) adds +1 to the counter of the sign that changed, a backward step
//!   (q - 1 mod 4) adds -1, so the total cnt_s + cnt_c moves by exactly +-1;
//! - a 2-step (both signs change) holds both counters and sets the sticky `quadrant_skip`;
//! - the first sample after reset presets the counts reached from (0, 0) in quadrant 0 moving
//!   forward q steps: cnt_s = floor(q/2), cnt_c = ceil(q/2).
//!
//! Positions are tracked as unbounded integers and reduced to CNT_W bits only for comparison.

mod common;

use common::{quadrant, signed, signs, wrap, Rng};
use pmu50_core::count_diagnosis as cd;
use pmu50_core::pmu50::Structural;
use pmu50_core::register_file::addr;
use pmu50_core::updown_counter_58cd as uc;
use pmu50_core::{Inputs, Params, Pmu50, TracedStep};
use proptest::prelude::*;

/// Quadrant reference of the two counters.
#[derive(Clone, Debug)]
struct RefCounters {
    cnt_s: i64,
    cnt_c: i64,
    skip: bool,
    /// Quadrant of the last sample, None before the first sample.
    quadrant: Option<u8>,
    /// Number of 2-steps seen.
    skips: u32,
}

/// What the reference did at one sample.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Move {
    None,
    Preset,
    Hold,
    Forward,
    Backward,
    Skip,
}

impl RefCounters {
    fn reset() -> Self {
        RefCounters {
            cnt_s: 0,
            cnt_c: 0,
            skip: false,
            quadrant: None,
            skips: 0,
        }
    }

    /// The state reached from reset by a first sample in quadrant 0 and then `n` forward steps
    /// (negative: backward steps); its quadrant is n mod 4.
    fn at_position(n: i64) -> Self {
        RefCounters {
            cnt_s: n.div_euclid(2),
            cnt_c: n.div_euclid(2) + n.rem_euclid(2),
            skip: false,
            quadrant: Some(n.rem_euclid(4) as u8),
            skips: 0,
        }
    }

    /// One edge. `sample` = Some((cs, cc)) when a sample is taken at this edge.
    fn edge(&mut self, sample: Option<(bool, bool)>, skip_clr: bool) -> Move {
        let mut both = false;
        let mv = match sample {
            None => Move::None,
            Some((cs, cc)) => {
                let qn = quadrant(cs, cc);
                match self.quadrant {
                    None => {
                        self.cnt_s = i64::from(qn / 2);
                        self.cnt_c = i64::from(qn.div_ceil(2));
                        self.quadrant = Some(qn);
                        Move::Preset
                    }
                    Some(q) => {
                        let (old_cs, _) = signs(q);
                        let mut bump = |d: i64| {
                            if old_cs != cs {
                                self.cnt_s += d
                            } else {
                                self.cnt_c += d
                            }
                        };
                        let mv = match (qn + 4 - q) % 4 {
                            0 => Move::Hold,
                            1 => {
                                bump(1);
                                Move::Forward
                            }
                            3 => {
                                bump(-1);
                                Move::Backward
                            }
                            _ => {
                                both = true;
                                self.skips += 1;
                                Move::Skip
                            }
                        };
                        self.quadrant = Some(qn);
                        mv
                    }
                }
            }
        };
        self.skip = both || (self.skip && !skip_clr);
        mv
    }
}

/// Drive the block like the comparator latch would: (cs, cc, vld) are the latch registers.
struct Latch {
    cs: bool,
    cc: bool,
    vld: bool,
}

impl Latch {
    fn inputs(&self, sample: Option<(bool, bool)>, skip_clr: bool) -> uc::Inputs {
        let upd = sample.is_some();
        let (cs_new, cc_new) = sample.unwrap_or((self.cs, self.cc));
        uc::Inputs {
            upd,
            first: upd && !self.vld,
            cs: self.cs,
            cc: self.cc,
            cs_new,
            cc_new,
            skip_clr,
        }
    }
    fn commit(&mut self, sample: Option<(bool, bool)>) {
        if let Some((s, c)) = sample {
            self.cs = s;
            self.cc = c;
            self.vld = true;
        }
    }
}

/// One stimulus: `upd` = a sample is taken; `step` = quadrant step of that sample (0 hold,
/// 1 forward, 3 backward, 2 skip); `skip_clr` = W1C strobe.
fn op(drift: u32) -> impl Strategy<Value = (bool, u8, bool)> {
    let step = prop_oneof![
        3 => Just(0u8),
        (3 + drift) => Just(1u8),
        3 => Just(3u8),
        1 => Just(2u8),
    ];
    (prop::bool::weighted(0.8), step, prop::bool::weighted(0.1))
}

fn ops() -> impl Strategy<Value = Vec<(bool, u8, bool)>> {
    (0u32..12).prop_flat_map(|drift| prop::collection::vec(op(drift), 1..300))
}

/// Checks of one block edge against the reference and the invariants.
fn check_edge(
    w: u8,
    before: &uc::Regs,
    after: &uc::Regs,
    i: &uc::Inputs,
    rf: &RefCounters,
    mv: Move,
    q: u8,
) {
    let m = (1u32 << w) as i64;
    assert_eq!(
        after.cnt_s,
        wrap(rf.cnt_s, w),
        "cnt_s vs reference ({mv:?})"
    );
    assert_eq!(
        after.cnt_c,
        wrap(rf.cnt_c, w),
        "cnt_c vs reference ({mv:?})"
    );
    assert_eq!(
        after.quadrant_skip, rf.skip,
        "quadrant_skip vs reference ({mv:?})"
    );
    let sum = |r: &uc::Regs| i64::from(r.cnt_s) + i64::from(r.cnt_c);
    let dsum = (sum(after) - sum(before)).rem_euclid(m);
    match mv {
        Move::Forward => assert_eq!(dsum, 1, "forward step adds +1 to the total"),
        Move::Backward => assert_eq!(dsum, m - 1, "backward step adds -1 to the total"),
        Move::Skip => {
            assert_eq!(
                (after.cnt_s, after.cnt_c),
                (before.cnt_s, before.cnt_c),
                "2-step holds both"
            );
            assert!(after.quadrant_skip, "2-step sets quadrant_skip");
        }
        Move::Hold | Move::None => {
            assert_eq!((after.cnt_s, after.cnt_c), (before.cnt_s, before.cnt_c))
        }
        Move::Preset => {}
    }
    if mv != Move::Preset {
        if after.cnt_s != before.cnt_s {
            assert!(
                i.upd && i.cs != i.cs_new,
                "sine counter moved without a change of Cs"
            );
        }
        if after.cnt_c != before.cnt_c {
            assert!(
                i.upd && i.cc != i.cc_new,
                "cosine counter moved without a change of Cc"
            );
        }
    }
    if rf.quadrant.is_some() {
        let total = (i64::from(after.cnt_s) + i64::from(after.cnt_c)).rem_euclid(4);
        let diff = signed(after.cnt_s.wrapping_sub(after.cnt_c), w);
        if rf.skips == 0 {
            assert_eq!(total, i64::from(q), "(cnt_s + cnt_c) mod 4 == quadrant");
            assert!(diff.abs() <= 1, "|cnt_s - cnt_c| <= 1, got {diff}");
        } else {
            // Each skip leaves the total half a turn (2 quadrants) behind.
            assert_eq!(
                total,
                (i64::from(q) + 2 * i64::from(rf.skips)).rem_euclid(4)
            );
        }
    }
}

/// Run a sequence through the block from latch/counter state (`latch`, `regs`), checking each edge.
fn run_block(
    w: u8,
    mut latch: Latch,
    mut regs: uc::Regs,
    mut rf: RefCounters,
    first_q: u8,
    seq: &[(bool, u8, bool)],
) {
    let mut target = if latch.vld {
        quadrant(latch.cs, latch.cc)
    } else {
        first_q
    };
    for &(upd, step, clr) in seq {
        let sample = if upd {
            if latch.vld {
                target = (target + step) & 3;
            }
            Some(signs(target))
        } else {
            None
        };
        let i = latch.inputs(sample, clr);
        let b = uc::UpdownCounter::new(w);
        let (o, n) = (b.outputs(&regs), b.eval(&regs, &i));
        assert_eq!(
            (o.cnt_s, o.cnt_c, o.quadrant_skip),
            (regs.cnt_s, regs.cnt_c, regs.quadrant_skip),
            "outputs are the registers"
        );
        let mv = rf.edge(sample, clr);
        check_edge(w, &regs, &n, &i, &rf, mv, target);
        regs = n;
        latch.commit(sample);
    }
}

proptest! {
    #![proptest_config(common::cases(600))]

    /// From power-on reset: first sample presets, then random quadrant walks with holds, steps in
    /// both directions, 2-steps and W1C clears; widths 2..16 (small widths wrap many times).
    #[test]
    fn block_from_reset_matches_quadrant_reference(w in 2u8..=16, first_q in 0u8..4, seq in ops()) {
        run_block(w, Latch { cs: false, cc: false, vld: false }, uc::RESET, RefCounters::reset(), first_q, &seq);
    }

    /// From a consistent state anywhere on the count range, in particular next to the unsigned
    /// (0 / 2^W - 1) and signed (2^(W-1)) wrap points of both counters.
    #[test]
    fn block_across_wrap_points_matches_quadrant_reference(
        w in 2u8..=16,
        base in 0usize..4,
        off in -40i64..=40,
        seq in ops(),
    ) {
        let m = 1i64 << w;
        let n = [0, m, 2 * m, -m][base] + off; // counts ~ n/2: around 0, 2^(W-1), 2^W, -2^(W-1)
        let rf = RefCounters::at_position(n);
        let (cs, cc) = signs(rf.quadrant.unwrap());
        let regs = uc::Regs { cnt_s: wrap(rf.cnt_s, w), cnt_c: wrap(rf.cnt_c, w), quadrant_skip: false };
        run_block(w, Latch { cs, cc, vld: true }, regs, rf, 0, &seq);
    }

    /// One edge from an arbitrary (also inconsistent) register state: only the quadrant step
    /// decides, wrapping at W bits.
    #[test]
    fn block_single_edge_from_any_state(
        w in 2u8..=16,
        cnt_s in any::<u16>(),
        cnt_c in any::<u16>(),
        skip in any::<bool>(),
        (cs, cc, vld) in (any::<bool>(), any::<bool>(), any::<bool>()),
        sample in proptest::option::of((any::<bool>(), any::<bool>())),
        clr in any::<bool>(),
    ) {
        let regs = uc::Regs { cnt_s: cnt_s & uc::mask(w), cnt_c: cnt_c & uc::mask(w), quadrant_skip: skip };
        let latch = Latch { cs, cc, vld };
        let i = latch.inputs(sample, clr);
        let n = uc::UpdownCounter::new(w).eval(&regs, &i);
        let mut rf = RefCounters { cnt_s: i64::from(regs.cnt_s), cnt_c: i64::from(regs.cnt_c), skip, quadrant: vld.then(|| quadrant(cs, cc)), skips: 0 };
        rf.edge(sample, clr);
        prop_assert_eq!(n.cnt_s, wrap(rf.cnt_s, w));
        prop_assert_eq!(n.cnt_c, wrap(rf.cnt_c, w));
        prop_assert_eq!(n.quadrant_skip, rf.skip);
    }

    /// Count diagnosis (2.7) on any counter values: |signed W-bit difference| >= 2, or the skip.
    #[test]
    fn diag_is_the_w_bit_signed_difference(w in 2u8..=16, s in any::<u16>(), c in any::<u16>(), skip in any::<bool>(), old in any::<bool>()) {
        let (s, c) = (s & uc::mask(w), c & uc::mask(w));
        let d = (i64::from(s) - i64::from(c)).rem_euclid(1i64 << w);
        let d = if d >= 1i64 << (w - 1) { d - (1i64 << w) } else { d };
        let b = cd::CountDiagnosis::new(w);
        let r = cd::Regs { diag: old };
        let (o, n) = (b.outputs(&r), b.eval(&r, &cd::Inputs { cnt_s_nxt: s, cnt_c_nxt: c, skip_nxt: skip }));
        prop_assert_eq!(o.diag, old);
        prop_assert_eq!(n.diag, d.abs() >= 2 || skip);
    }
}

fn top_params() -> impl Strategy<Value = Params> {
    common::params(60, 200)
}

/// Through the full top level with the key on (ig = 1, vs2_ok = 1): the comparator inputs are
/// random garbage except at the edges where a sample is taken (`smp` & `sr` in the outputs of
/// the cycle), where they follow a random quadrant walk. Random W1C clears of `quadrant_skip`.
fn run_top(p: Params, seed: u64, samples: u32) {
    let mut m = Pmu50::new(p).unwrap();
    let Structural { cnt_width: w, .. } = m.structural();
    let mut rng = Rng(seed);
    let drift = rng.range(0, 10);
    let mut rf = RefCounters::reset();
    let mut target: u8 = rng.range(0, 3) as u8;
    let mut taken = 0;
    let mut ticks = 0u64;
    while taken < samples {
        ticks += 1;
        assert!(ticks < 100_000, "no sampling");
        let o = m.peek();
        let sampling = o.smp && o.sr;
        let mut i = Inputs {
            ig: true,
            vs2_ok: true,
            cmp_s: rng.bit(),
            cmp_c: rng.bit(),
            ..Default::default()
        };
        if sampling {
            if rf.quadrant.is_some() {
                let step = match rng.range(0, 9 + drift) {
                    0..=2 => 0,
                    3..=5 => 3,
                    6 => 2,
                    _ => 1,
                };
                target = (target + step) & 3;
            }
            (i.cmp_s, i.cmp_c) = signs(target);
        }
        let clr = o.sig && rng.chance(1, 40);
        if clr {
            i.bus_we = true;
            i.bus_addr = addr::STATUS;
            i.bus_wdata = (1 << 5) | (rng.next() as u16 & !(1 << 5));
        }
        let before = *m.regs();
        let TracedStep {
            internals: int,
            after: o2,
            ..
        } = m.step_traced(&i);
        assert_eq!(int.upd, sampling, "a sample is taken exactly when smp & sr");
        let mv = rf.edge(sampling.then(|| signs(target)), clr);
        if sampling {
            taken += 1;
            assert_eq!((o2.cs, o2.cc), signs(target));
        }
        let ui = uc::Inputs {
            upd: int.upd,
            first: int.first,
            cs: before.comparator_latch.cs,
            cc: before.comparator_latch.cc,
            cs_new: o2.cs,
            cc_new: o2.cc,
            skip_clr: clr,
        };
        check_edge(
            w,
            &before.updown_counter,
            &m.regs().updown_counter,
            &ui,
            &rf,
            mv,
            target,
        );
        // Outputs and register file views of the counters.
        assert_eq!(
            (o2.cnt_s, o2.cnt_c, o2.quadrant_skip),
            (wrap(rf.cnt_s, w), wrap(rf.cnt_c, w), rf.skip)
        );
        assert_eq!(
            m.read(addr::CNT_S),
            signed(o2.cnt_s, w) as i16 as u16,
            "CNT_S sign-extended"
        );
        assert_eq!(
            m.read(addr::CNT_C),
            signed(o2.cnt_c, w) as i16 as u16,
            "CNT_C sign-extended"
        );
        // 2.7: diag registered, aligned with the counters visible in the same cycle.
        let diff = signed(o2.cnt_s.wrapping_sub(o2.cnt_c), w);
        assert_eq!(
            o2.diag,
            diff.abs() >= 2 || o2.quadrant_skip,
            "diag at tick {} (diff {diff})",
            m.tick()
        );
    }
}

proptest! {
    #![proptest_config(common::cases(64))]

    #[test]
    fn top_level_key_on_counts_like_the_quadrant_reference(p in top_params(), seed in any::<u64>(), samples in 20u32..150) {
        run_top(p, seed, samples);
    }
}

/// Small widths wrap through the top level too.
#[test]
fn top_level_two_bit_counters_wrap() {
    let p = Params {
        cnt_width: 2,
        smp_on: 1,
        ..Params::default()
    };
    for seed in 0..8 {
        run_top(p, seed, 400);
    }
}
