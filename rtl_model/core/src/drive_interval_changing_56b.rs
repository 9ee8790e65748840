//! Drive interval changing unit 56b.
//!
//! Paragraphs: [0214]-[0262] (shorten on a sign change, expand after Cth quiet pulses, change
//! history, power supply count CNTr, clamping to [minimum, x]), FIG. 17 S1-S11 [0263]-[0291] and
//! FIG. 18 S20-S28 [0268]-[0279] (normative; their step order wins where the prose is looser),
//! [0413] (the third embodiment's PMU uses the second embodiment's interval changing).
//!
//! The process runs once per intermittent output, at the sampling strobe of a key-off pulse
//! (`pulse`). Its result `si` is the interval from that pulse's `st` to the next `st` (the strobe
//! comes Wt after `st`, and Wt < minimum, so the timer has not reached the old or the new interval
//! yet).
//!
//! FIG. 18 (rotation detection, [0268]-[0279]), with `chg_s`/`chg_c` the sign changes of this
//! sample and `hist_s`/`hist_c` the change-history flip-flops [0243]:
//!
//! ```text
//! S20 chg_s? -Y-> S21 hist_s? -Y-> S24 not detected
//!                             -N-> S22 hist_s:=1, hist_c:=0 -> S23 detected
//!            -N-> S25 chg_c? -N-> S24 not detected
//!                            -Y-> S26 hist_c? -Y-> S24 not detected
//!                                             -N-> S27 hist_c:=1, hist_s:=0 -> S28 detected
//! ```
//!
//! When both signs change in one sample, S20 takes the Cs branch only (step order).
//!
//! FIG. 17 ([0264]-[0291]):
//!
//! ```text
//! S1 rise of Vs2 (sr)? -N-> end, interval unchanged
//! S2/S3 detected? -Y-> S4 cnt_r:=0 -> S5 si = min? -Y-> end
//!                                                  -N-> S6 si := max(si - T1, min)  [0260]-[0262]
//!                 -N-> S7 si = x? -Y-> end
//!                                 -N-> S8 cnt_r >= Cth? -N-> S9 cnt_r += 1 -> end
//!                                                       -Y-> S10 si := min(si + T2, x)
//!                                                            S11 hist_s, hist_c := 0
//!                                                            S9 cnt_r += 1 -> end   [0250], [0291]
//! ```
//!
//! [0291] ends S11 with "the process terminates after step S9": S11 continues to S9, which is what
//! [0250] ("expands ... every time CNTr increases by 1") and [0257] require. With Cth = 4 the first
//! expansion therefore happens at the fifth quiet pulse (`cnt_r` reads 4 at S8 only after four
//! increments), FIG. 16.
//!
//! Key-off and key-on (interpretation, docs/spec.md): at the edge where `sig` falls, `si` := x
//! ("the initial drive interval is the maximum interval x", [0226]) as x stands after that edge
//! (`si_max_nxt`: a write of SI_MAX in the same cycle counts, so `si` never starts above x), both history bits := 0 (the
//! history of the previous key-off says nothing about the new one) and `cnt_r` := 0. While the key
//! is on nothing here changes, so the MPU can read the state the last key-off period ended in.
//! With `adaptive` = 0 (first embodiment, fixed cycle T [0083]) every pulse reloads `si` := x and
//! nothing else changes.
//!
//! | port     | width | dir | meaning |
//! |----------|-------|-----|---------|
//! | `koff`   | 1     | in  | `sig` falls at this edge |
//! | `pulse`  | 1     | in  | sampling strobe of a key-off intermittent output |
//! | `sr`     | 1     | in  | activation signal: Vs2 rose (S1) |
//! | `chg_s`, `chg_c` | 1 | in | sign changes of this sample |
//! | `adaptive` | 1   | in  | CTRL.adaptive |
//! | `si_min`, `si_max`, `t1`, `t2` | 16 | in | programmed values in ticks |
//! | `si_max_nxt` | 16  | in  | SI_MAX after this edge (register file next state), loaded at `koff` |
//! | `cth`    | 8     | in  | count threshold Cth |
//! | `si`     | 16    | out | drive interval instruction Si in ticks (registered, [`outputs`]) |
//! | `hist_s`, `hist_c` | 1 | out | change history flip-flops (registered) |
//! | `cnt_r`  | 8     | out | power supply count CNTr (registered) |
//! | `fig17`  | 3     | out | FIG. 17 path taken at this edge ([`Fig17`]; combinational, [`Comb`] from [`eval`]) |
//! | `fig18`  | 3     | out | FIG. 18 path taken at this edge ([`Fig18`]; combinational) |
//!
//! | register | width | reset | meaning |
//! |----------|-------|-------|---------|
//! | `si`     | 16    | x (`si_max`) | drive interval |
//! | `hist_s` | 1     | 0     | change history of Cs |
//! | `hist_c` | 1     | 0     | change history of Cc |
//! | `cnt_r`  | 8     | 0     | power supply count, saturating at 255 |

/// FIG. 17 path of one evaluation; the discriminant is the RTL encoding of output `fig17`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
#[repr(u8)]
pub enum Fig17 {
    /// No key-off sampling strobe at this edge.
    #[default]
    Idle = 0,
    /// S1: N. Strobe without a detected rise of Vs2: nothing changes.
    S1NoRise = 1,
    /// S3: Y, S4, S5: Y. Rotation at the minimum interval: `cnt_r` := 0, `si` held.
    S5AtMin = 2,
    /// S3: Y, S4, S5: N, S6. Rotation: `cnt_r` := 0, `si` shortened by T1 (clamped).
    S6Shorten = 3,
    /// S3: N, S7: Y. Quiet at the maximum interval: nothing changes.
    S7AtMax = 4,
    /// S3: N, S7: N, S8: N, S9. Quiet: `cnt_r` += 1.
    S9Count = 5,
    /// S3: N, S7: N, S8: Y, S10, S11, S9. Quiet long enough: `si` expanded by T2 (clamped),
    /// history cleared, `cnt_r` += 1.
    S10Expand = 6,
    /// Adaptive interval off (first embodiment): `si` := x.
    Fixed = 7,
}

/// FIG. 18 path of one evaluation; the discriminant is the RTL encoding of output `fig18`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
#[repr(u8)]
pub enum Fig18 {
    /// Rotation detection not run at this edge.
    #[default]
    Idle = 0,
    /// S20: Y, S21: N, S22, S23: detected through Cs.
    S23DetectedCs = 1,
    /// S20: Y, S21: Y, S24: Cs changed again before Cc ([0232]-[0236]).
    S21CsRepeat = 2,
    /// S20: N, S25: Y, S26: N, S27, S28: detected through Cc.
    S28DetectedCc = 3,
    /// S20: N, S25: Y, S26: Y, S24: Cc changed again before Cs.
    S26CcRepeat = 4,
    /// S20: N, S25: N, S24: no change.
    S25NoChange = 5,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Regs {
    pub si: u16,
    pub hist_s: bool,
    pub hist_c: bool,
    pub cnt_r: u8,
}

/// Reset value with the patent's default x = 6.6 ms at a 10 us clock; the top level resets `si` to
/// the configured x (see [`reset`]).
pub const RESET: Regs = Regs {
    si: 660,
    hist_s: false,
    hist_c: false,
    cnt_r: 0,
};

/// Reset value for a given maximum interval x.
pub const fn reset(si_max: u16) -> Regs {
    Regs {
        si: si_max,
        ..RESET
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct Inputs {
    pub koff: bool,
    pub pulse: bool,
    pub sr: bool,
    pub chg_s: bool,
    pub chg_c: bool,
    pub adaptive: bool,
    pub si_min: u16,
    pub si_max: u16,
    pub si_max_nxt: u16,
    pub t1: u16,
    pub t2: u16,
    pub cth: u8,
}

/// Registered outputs.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct Outputs {
    pub si: u16,
    pub hist_s: bool,
    pub hist_c: bool,
    pub cnt_r: u8,
}

/// Combinational outputs of the cycle: the FIG. 17/18 paths taken at this edge.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct Comb {
    pub fig17: Fig17,
    pub fig18: Fig18,
}

/// Registered outputs, decoded from the registers.
pub fn outputs(r: &Regs) -> Outputs {
    Outputs {
        si: r.si,
        hist_s: r.hist_s,
        hist_c: r.hist_c,
        cnt_r: r.cnt_r,
    }
}

/// FIG. 18: returns (rotation detected, next hist_s, next hist_c, path).
fn rotation_detection(r: &Regs, chg_s: bool, chg_c: bool) -> (bool, bool, bool, Fig18) {
    if chg_s {
        if r.hist_s {
            (false, r.hist_s, r.hist_c, Fig18::S21CsRepeat)
        } else {
            (true, true, false, Fig18::S23DetectedCs)
        }
    } else if chg_c {
        if r.hist_c {
            (false, r.hist_s, r.hist_c, Fig18::S26CcRepeat)
        } else {
            (true, false, true, Fig18::S28DetectedCc)
        }
    } else {
        (false, r.hist_s, r.hist_c, Fig18::S25NoChange)
    }
}

/// Pure next-state function, with the combinational outputs of the cycle.
pub fn eval(r: &Regs, i: &Inputs) -> (Comb, Regs) {
    let mut o = Comb::default();
    if i.koff {
        return (o, reset(i.si_max_nxt));
    }
    if !i.pulse {
        return (o, *r);
    }
    if !i.adaptive {
        o.fig17 = Fig17::Fixed;
        return (o, Regs { si: i.si_max, ..*r });
    }
    if !i.sr {
        o.fig17 = Fig17::S1NoRise;
        return (o, *r);
    }
    let (detected, hist_s, hist_c, f18) = rotation_detection(r, i.chg_s, i.chg_c);
    o.fig18 = f18;
    let mut n = Regs {
        hist_s,
        hist_c,
        ..*r
    };
    if detected {
        n.cnt_r = 0; // S4
        if r.si <= i.si_min {
            o.fig17 = Fig17::S5AtMin;
        } else {
            // S6 with the clamp of [0260]-[0262]: never below the minimum.
            n.si = r.si.saturating_sub(i.t1).max(i.si_min);
            o.fig17 = Fig17::S6Shorten;
        }
    } else if r.si >= i.si_max {
        o.fig17 = Fig17::S7AtMax;
    } else if r.cnt_r >= i.cth {
        // S10 with the clamp of [0260]: never above x.
        n.si = (u32::from(r.si) + u32::from(i.t2)).min(u32::from(i.si_max)) as u16;
        n.hist_s = false; // S11
        n.hist_c = false;
        n.cnt_r = r.cnt_r.saturating_add(1); // S9
        o.fig17 = Fig17::S10Expand;
    } else {
        n.cnt_r = r.cnt_r.saturating_add(1); // S9
        o.fig17 = Fig17::S9Count;
    }
    (o, n)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The patent's parameters at a 10 us clock: T1 2.2 ms, T2 1.1 ms, x 6.6 ms, min 2.2 ms, Cth 4.
    fn pulse(chg_s: bool, chg_c: bool) -> Inputs {
        Inputs {
            pulse: true,
            sr: true,
            chg_s,
            chg_c,
            adaptive: true,
            si_min: 220,
            si_max: 660,
            si_max_nxt: 660,
            t1: 220,
            t2: 110,
            cth: 4,
            koff: false,
        }
    }

    fn run(r: Regs, i: Inputs) -> (Comb, Regs) {
        eval(&r, &i)
    }

    const X: Regs = reset(660);

    // ---- FIG. 18, every branch ----

    #[test]
    fn s20y_s21n_s22_s23_first_cs_change_is_a_rotation() {
        let (o, n) = run(Regs { hist_c: true, ..X }, pulse(true, false));
        assert_eq!(o.fig18, Fig18::S23DetectedCs);
        assert!(
            n.hist_s && !n.hist_c,
            "S22 stores Cs history and clears Cc history [0270]"
        );
    }

    #[test]
    fn s20y_s21y_s24_repeated_cs_change_is_not_a_rotation() {
        let (o, n) = run(
            Regs {
                si: 440,
                hist_s: true,
                ..X
            },
            pulse(true, false),
        );
        assert_eq!(o.fig18, Fig18::S21CsRepeat);
        assert_eq!(n.si, 440, "FIG. 15B/15C: no second shortening [0236]");
        assert!(n.hist_s);
    }

    #[test]
    fn s20n_s25y_s26n_s27_s28_first_cc_change_is_a_rotation() {
        let (o, n) = run(Regs { hist_s: true, ..X }, pulse(false, true));
        assert_eq!(o.fig18, Fig18::S28DetectedCc);
        assert!(!n.hist_s && n.hist_c, "S27 [0278]");
    }

    #[test]
    fn s20n_s25y_s26y_s24_repeated_cc_change_is_not_a_rotation() {
        let (o, n) = run(
            Regs {
                si: 440,
                hist_c: true,
                ..X
            },
            pulse(false, true),
        );
        assert_eq!(o.fig18, Fig18::S26CcRepeat);
        assert_eq!(n.si, 440);
    }

    #[test]
    fn s20n_s25n_s24_no_change_is_not_a_rotation() {
        let (o, _) = run(X, pulse(false, false));
        assert_eq!(o.fig18, Fig18::S25NoChange);
    }

    #[test]
    fn s20_both_changed_takes_the_cs_branch_only() {
        let (o, n) = run(Regs { hist_c: true, ..X }, pulse(true, true));
        assert_eq!(o.fig18, Fig18::S23DetectedCs);
        assert!(n.hist_s && !n.hist_c);
    }

    // ---- FIG. 17, every branch ----

    #[test]
    fn s1n_no_rise_of_vs2_changes_nothing() {
        let r = Regs {
            si: 440,
            hist_s: true,
            hist_c: false,
            cnt_r: 2,
        };
        let (o, n) = run(
            r,
            Inputs {
                sr: false,
                ..pulse(true, false)
            },
        );
        assert_eq!(o.fig17, Fig17::S1NoRise);
        assert_eq!(n, r);
    }

    #[test]
    fn s3y_s4_s5n_s6_rotation_shortens_by_t1_and_resets_cnt_r() {
        let (o, n) = run(Regs { cnt_r: 3, ..X }, pulse(true, false));
        assert_eq!(o.fig17, Fig17::S6Shorten);
        assert_eq!((n.si, n.cnt_r), (440, 0), "6.6 -> 4.4 ms [0226]");
    }

    #[test]
    fn s3y_s4_s5y_rotation_at_minimum_holds_and_resets_cnt_r() {
        let (o, n) = run(
            Regs {
                si: 220,
                cnt_r: 3,
                ..X
            },
            pulse(true, false),
        );
        assert_eq!(o.fig17, Fig17::S5AtMin);
        assert_eq!((n.si, n.cnt_r), (220, 0), "never below the minimum [0228]");
    }

    #[test]
    fn s6_clamps_to_the_minimum_0261_0262() {
        let (o, n) = run(Regs { si: 330, ..X }, pulse(false, true));
        assert_eq!(o.fig17, Fig17::S6Shorten);
        assert_eq!(
            n.si, 220,
            "3.3 ms - 2.2 ms would be 1.1 ms; clamped to 2.2 ms [0262]"
        );
    }

    #[test]
    fn s3n_s7y_quiet_at_x_changes_nothing() {
        let r = Regs {
            cnt_r: 8,
            hist_s: true,
            ..X
        };
        let (o, n) = run(r, pulse(false, false));
        assert_eq!(o.fig17, Fig17::S7AtMax);
        assert_eq!(n, r, "cnt_r not incremented at x (S7: Y ends the process)");
    }

    #[test]
    fn s3n_s7n_s8n_s9_quiet_counts() {
        let (o, n) = run(
            Regs {
                si: 220,
                cnt_r: 3,
                ..X
            },
            pulse(false, false),
        );
        assert_eq!(o.fig17, Fig17::S9Count);
        assert_eq!((n.si, n.cnt_r), (220, 4));
    }

    #[test]
    fn s3n_s7n_s8y_s10_s11_s9_quiet_expands_clears_history_and_counts() {
        let (o, n) = run(
            Regs {
                si: 220,
                cnt_r: 4,
                hist_s: true,
                hist_c: false,
            },
            pulse(false, false),
        );
        assert_eq!(o.fig17, Fig17::S10Expand);
        assert_eq!(
            (n.si, n.cnt_r, n.hist_s, n.hist_c),
            (330, 5, false, false),
            "2.2 -> 3.3 ms [0257]"
        );
    }

    #[test]
    fn s10_clamps_to_x_0260() {
        let (_, n) = run(
            Regs {
                si: 600,
                cnt_r: 9,
                ..X
            },
            pulse(false, false),
        );
        assert_eq!(n.si, 660);
    }

    #[test]
    fn repeated_change_counts_as_quiet_through_s7_s8_s9() {
        // [0236] + FIG. 17: a not-detected rotation goes S3: N, so CNTr keeps counting.
        let (o, n) = run(
            Regs {
                si: 440,
                hist_s: true,
                cnt_r: 1,
                ..X
            },
            pulse(true, false),
        );
        assert_eq!((o.fig17, n.cnt_r), (Fig17::S9Count, 2));
    }

    #[test]
    fn cnt_r_saturates_at_255() {
        let (_, n) = run(
            Regs {
                si: 220,
                cnt_r: 255,
                ..X
            },
            Inputs {
                cth: 255,
                t2: 1,
                ..pulse(false, false)
            },
        );
        assert_eq!(n.cnt_r, 255);
    }

    // ---- key-off, adaptive off, idle ----

    #[test]
    fn key_off_loads_x_and_clears_history_and_count() {
        let (_, n) = run(
            Regs {
                si: 220,
                hist_s: true,
                hist_c: true,
                cnt_r: 7,
            },
            Inputs {
                koff: true,
                ..pulse(true, true)
            },
        );
        assert_eq!(n, reset(660));
    }

    #[test]
    fn key_off_loads_x_as_written_in_the_same_cycle() {
        let (_, n) = run(
            Regs { si: 660, ..X },
            Inputs {
                koff: true,
                si_max_nxt: 440,
                ..pulse(false, false)
            },
        );
        assert_eq!(n.si, 440, "never above the new x");
    }

    #[test]
    fn fixed_cycle_when_adaptive_is_off() {
        let r = Regs {
            si: 220,
            hist_s: true,
            ..X
        };
        let (o, n) = run(
            r,
            Inputs {
                adaptive: false,
                ..pulse(true, false)
            },
        );
        assert_eq!(o.fig17, Fig17::Fixed);
        assert_eq!(n, Regs { si: 660, ..r });
    }

    #[test]
    fn no_pulse_no_change() {
        let r = Regs {
            si: 220,
            hist_s: true,
            hist_c: false,
            cnt_r: 2,
        };
        let (o, n) = run(
            r,
            Inputs {
                pulse: false,
                ..pulse(true, true)
            },
        );
        assert_eq!((o.fig17, o.fig18, n), (Fig17::Idle, Fig18::Idle, r));
    }
}
