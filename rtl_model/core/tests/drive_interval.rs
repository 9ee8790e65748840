//! Drive interval changing unit 56b (docs/spec.md 2.6) against a step-by-step interpreter of the
//! flowcharts of FIG. 17 (S1..S11) and FIG. 18 (S20..S28), written from the patent's words
//! ([0263]-[0291]) with the spec's interpretations I5, I7-I11 where the patent leaves a choice.
//! The interpreter walks the steps one at a time and records the path; the `fig17`/`fig18` codes
//! are derived from the path, not computed alongside the state.

mod common;

use pmu50_core::drive_interval_changing_56b as di;
use proptest::prelude::*;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Step {
    S1,
    S2,
    S3,
    S4,
    S5,
    S6,
    S7,
    S8,
    S9,
    S10,
    S11,
    S20,
    S21,
    S22,
    S23,
    S24,
    S25,
    S26,
    S27,
    S28,
    End,
}
use Step::*;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct State {
    si: u16,
    hist_s: bool,
    hist_c: bool,
    cnt_r: u8,
}

#[derive(Clone, Copy, Debug)]
struct Param {
    si_min: u16,
    si_max: u16,
    /// SI_MAX after this edge (a write in the same cycle); what a key-off loads (spec 2.6).
    si_max_nxt: u16,
    t1: u16,
    t2: u16,
    cth: u8,
}

/// FIG. 18, the rotation detection process started in S2. Returns (rotation detected, path).
fn fig18(st: &mut State, cs_changed: bool, cc_changed: bool) -> (bool, Vec<Step>) {
    let mut path = vec![];
    let mut step = S20;
    loop {
        path.push(step);
        step = match step {
            // [0268] Did Cs change?
            S20 => {
                if cs_changed {
                    S21
                } else {
                    S25
                }
            }
            // [0269] Does the change history of Cs exist?
            S21 => {
                if st.hist_s {
                    S24
                } else {
                    S22
                }
            }
            // [0270] Store the Cs history, reset the Cc history.
            S22 => {
                st.hist_s = true;
                st.hist_c = false;
                S23
            }
            // [0271] Rotation detected.
            S23 => return (true, path),
            // [0272], [0274], [0276] Rotation not detected.
            S24 => return (false, path),
            // [0273]-[0274] Did Cc change?
            S25 => {
                if cc_changed {
                    S26
                } else {
                    S24
                }
            }
            // [0275]-[0276] Does the change history of Cc exist?
            S26 => {
                if st.hist_c {
                    S24
                } else {
                    S27
                }
            }
            // [0278] Store the Cc history, reset the Cs history.
            S27 => {
                st.hist_c = true;
                st.hist_s = false;
                S28
            }
            // [0279] Rotation detected.
            S28 => return (true, path),
            other => unreachable!("{other:?} is not a FIG. 18 step"),
        }
    }
}

/// FIG. 17 from S1, for one key-off intermittent output. Returns the path of FIG. 17 and of
/// FIG. 18 (empty when S2 is not reached).
fn fig17(
    st: &mut State,
    p: &Param,
    sr: bool,
    cs_changed: bool,
    cc_changed: bool,
) -> (Vec<Step>, Vec<Step>) {
    let mut path = vec![];
    let mut path18 = vec![];
    let mut detected = false;
    let mut step = S1;
    while step != End {
        path.push(step);
        step = match step {
            // [0264] Rise of Vs2 detected? No: terminate, the interval does not change.
            S1 => {
                if sr {
                    S2
                } else {
                    End
                }
            }
            // [0265]-[0266] Sr starts the rotation number detection; rotation detection process.
            S2 => {
                let (d, p18) = fig18(st, cs_changed, cc_changed);
                detected = d;
                path18 = p18;
                S3
            }
            // [0280]
            S3 => {
                if detected {
                    S4
                } else {
                    S7
                }
            }
            // [0281] Reset the power supply count.
            S4 => {
                st.cnt_r = 0;
                S5
            }
            // [0282]-[0283] Already the minimum interval? (I11: "at or below")
            S5 => {
                if st.si <= p.si_min {
                    End
                } else {
                    S6
                }
            }
            // [0284] Shorten by T1, [0260]-[0262] never below the minimum (I10).
            S6 => {
                let shortened = st.si.saturating_sub(p.t1); // "si - t1 saturates at 0"
                st.si = if shortened < p.si_min {
                    p.si_min
                } else {
                    shortened
                };
                End
            }
            // [0285]-[0286] Already the maximum interval x? (at or above)
            S7 => {
                if st.si >= p.si_max {
                    End
                } else {
                    S8
                }
            }
            // [0287]-[0288] CNTr >= Cth? (I8: tested before S9 increments)
            S8 => {
                if st.cnt_r >= p.cth {
                    S10
                } else {
                    S9
                }
            }
            // [0289] CNTr + 1 (an 8-bit counter that stops at 255).
            S9 => {
                st.cnt_r = st.cnt_r.saturating_add(1);
                End
            }
            // [0290] Expand by T2, [0260] never above x (I10).
            S10 => {
                let expanded = u32::from(st.si) + u32::from(p.t2);
                st.si = if expanded > u32::from(p.si_max) {
                    p.si_max
                } else {
                    expanded as u16
                };
                S11
            }
            // [0291] Reset the change histories; the process terminates after S9 (I7).
            S11 => {
                st.hist_s = false;
                st.hist_c = false;
                S9
            }
            other => unreachable!("{other:?} is not a FIG. 17 step"),
        };
    }
    (path, path18)
}

/// Reference of one edge: (next state, fig17 code, fig18 code).
#[allow(clippy::too_many_arguments)]
fn reference(
    st: State,
    p: &Param,
    koff: bool,
    pulse: bool,
    adaptive: bool,
    sr: bool,
    cs_changed: bool,
    cc_changed: bool,
) -> (State, u8, u8) {
    // Key-off: "the initial drive interval is the maximum interval x" [0226] (x as it stands after
    // this edge, spec 2.6), history and CNTr cleared ([0248], spec section 3).
    if koff {
        return (
            State {
                si: p.si_max_nxt,
                hist_s: false,
                hist_c: false,
                cnt_r: 0,
            },
            0,
            0,
        );
    }
    // The process runs once per key-off intermittent output.
    if !pulse {
        return (st, 0, 0);
    }
    // First embodiment: fixed cycle T = x (I13).
    if !adaptive {
        return (State { si: p.si_max, ..st }, 7, 0);
    }
    let mut n = st;
    let (path, path18) = fig17(&mut n, p, sr, cs_changed, cc_changed);
    let has = |s: Step| path.contains(&s);
    let last = *path.last().unwrap();
    let code17 = if last == S1 {
        1
    } else if has(S10) {
        6
    } else if last == S5 {
        2
    } else if last == S6 {
        3
    } else if last == S7 {
        4
    } else {
        assert_eq!(last, S9);
        5
    };
    let has18 = |s: Step| path18.contains(&s);
    let code18 = if path18.is_empty() {
        0
    } else if has18(S23) {
        1
    } else if has18(S21) {
        2
    } else if has18(S28) {
        3
    } else if has18(S26) {
        4
    } else {
        assert!(has18(S25) && has18(S24));
        5
    };
    (n, code17, code18)
}

fn param() -> impl Strategy<Value = Param> {
    let small_or_any = || prop_oneof![1u16..=400, 1u16..=u16::MAX, (u16::MAX - 50)..=u16::MAX];
    (
        prop_oneof![
            (1u16..=2000, 0u16..=2000),
            (1u16..=u16::MAX, 0u16..=u16::MAX)
        ],
        small_or_any(),
        small_or_any(),
        prop_oneof![1u8..=8, 1u8..=255, 250u8..=255],
        prop::option::weighted(0.3, any::<u16>()),
    )
        .prop_map(|((si_min, spread), t1, t2, cth, written)| {
            let si_max = si_min.saturating_add(spread);
            Param {
                si_min,
                si_max,
                si_max_nxt: written.unwrap_or(si_max),
                t1,
                t2,
                cth,
            }
        })
}

fn state(p: Param) -> impl Strategy<Value = State> {
    (
        prop_oneof![
            6 => p.si_min..=p.si_max,
            1 => Just(p.si_min),
            1 => Just(p.si_max),
            1 => any::<u16>(),
        ],
        any::<bool>(),
        any::<bool>(),
        prop_oneof![
            0u8..=12,
            any::<u8>(),
            Just(p.cth),
            Just(p.cth.saturating_sub(1)),
            250u8..=255
        ],
    )
        .prop_map(|(si, hist_s, hist_c, cnt_r)| State {
            si,
            hist_s,
            hist_c,
            cnt_r,
        })
}

fn eval(st: State, p: &Param, i: (bool, bool, bool, bool, bool, bool)) -> (di::Comb, State) {
    let (koff, pulse, adaptive, sr, chg_s, chg_c) = i;
    let r = di::Regs {
        si: st.si,
        hist_s: st.hist_s,
        hist_c: st.hist_c,
        cnt_r: st.cnt_r,
    };
    let (o, n) = di::eval(
        &r,
        &di::Inputs {
            koff,
            pulse,
            sr,
            chg_s,
            chg_c,
            adaptive,
            si_min: p.si_min,
            si_max: p.si_max,
            si_max_nxt: p.si_max_nxt,
            t1: p.t1,
            t2: p.t2,
            cth: p.cth,
        },
    );
    (
        o,
        State {
            si: n.si,
            hist_s: n.hist_s,
            hist_c: n.hist_c,
            cnt_r: n.cnt_r,
        },
    )
}

/// Inputs (koff, pulse, adaptive, sr, chg_s, chg_c), pulses and the adaptive path favoured.
fn inputs() -> impl Strategy<Value = (bool, bool, bool, bool, bool, bool)> {
    (
        prop::bool::weighted(0.08),
        prop::bool::weighted(0.85),
        prop::bool::weighted(0.85),
        prop::bool::weighted(0.85),
        any::<bool>(),
        any::<bool>(),
    )
}

proptest! {
    #![proptest_config(common::cases(4000))]

    /// Identical next state and identical FIG. 17 / FIG. 18 codes for any register state, any
    /// inputs and any legal (si_min <= si_max, non-zero steps, Cth >= 1) parameters.
    #[test]
    fn one_edge_matches_the_flowcharts((p, st) in param().prop_flat_map(|p| (Just(p), state(p))), i in inputs()) {
        let (o, n) = eval(st, &p, i);
        let (koff, pulse, adaptive, sr, chg_s, chg_c) = i;
        let (want, c17, c18) = reference(st, &p, koff, pulse, adaptive, sr, chg_s, chg_c);
        prop_assert_eq!(n, want, "next state");
        prop_assert_eq!(o.fig17 as u8, c17, "fig17 code");
        prop_assert_eq!(o.fig18 as u8, c18, "fig18 code");
        let ro = di::outputs(&di::Regs { si: st.si, hist_s: st.hist_s, hist_c: st.hist_c, cnt_r: st.cnt_r });
        prop_assert_eq!((ro.si, ro.hist_s, ro.hist_c, ro.cnt_r), (st.si, st.hist_s, st.hist_c, st.cnt_r), "outputs are the registers");
    }
}

proptest! {
    #![proptest_config(common::cases(400))]

    /// From reset (si = x) under constant legal parameters, random sequences of pulses (with
    /// key-offs, missing rises of Vs2, changes of either or both signs): si stays in
    /// [si_min, si_max], and the block keeps agreeing with the flowcharts.
    #[test]
    fn si_stays_within_min_and_max(p in param().prop_map(|p| Param { si_max_nxt: p.si_max, ..p }), adaptive in prop::bool::weighted(0.9), seq in prop::collection::vec(inputs(), 1..400)) {
        let mut st = State { si: p.si_max, hist_s: false, hist_c: false, cnt_r: 0 };
        let r = di::reset(p.si_max);
        prop_assert_eq!((r.si, r.hist_s, r.hist_c, r.cnt_r), (st.si, st.hist_s, st.hist_c, st.cnt_r));
        for (k, &(koff, pulse, _, sr, chg_s, chg_c)) in seq.iter().enumerate() {
            let i = (koff, pulse, adaptive, sr, chg_s, chg_c);
            let (_, n) = eval(st, &p, i);
            prop_assert!(p.si_min <= n.si && n.si <= p.si_max, "edge {}: si = {} outside [{}, {}]", k, n.si, p.si_min, p.si_max);
            let (want, _, _) = reference(st, &p, koff, pulse, adaptive, sr, chg_s, chg_c);
            prop_assert_eq!(n, want);
            st = n;
        }
    }
}

/// FIG. 15A/16A with the patent's numbers (x 6.6 ms, T1 2.2 ms, T2 1.1 ms, min 2.2 ms, Cth 4, at
/// a 10 us clock): Cs then Cc change -> 440 -> 220; quiet pulses: the first expansion is at the
/// fifth quiet pulse (I8), then one T2 per pulse up to x.
#[test]
fn patent_example_fig15a_fig16a() {
    let p = Param {
        si_min: 220,
        si_max: 660,
        si_max_nxt: 660,
        t1: 220,
        t2: 110,
        cth: 4,
    };
    let mut st = State {
        si: 660,
        hist_s: false,
        hist_c: false,
        cnt_r: 0,
    };
    let mut sis = vec![];
    let pulses = [(true, false), (false, true)]
        .into_iter()
        .chain(std::iter::repeat_n((false, false), 10));
    for (cs, cc) in pulses {
        let (_, n) = eval(st, &p, (false, true, true, true, cs, cc));
        assert_eq!(n, reference(st, &p, false, true, true, true, cs, cc).0);
        st = n;
        sis.push(st.si);
    }
    assert_eq!(
        sis,
        [440, 220, 220, 220, 220, 220, 330, 440, 550, 660, 660, 660]
    );
}
