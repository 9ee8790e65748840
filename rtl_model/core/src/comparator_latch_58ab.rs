//! Output latches of the first comparator 58a and the second comparator 58b.
//!
//! Paragraphs: [0086]-[0087] (sign signals Cs and Cc: 1 when the signal is equal to or above Vr),
//! [0211] (while Vs2 is off the internal power Vp maintains the outputs Cs and Cc), [0349] (key on:
//! sampled every on-key sampling period), [0354] (key off: the comparators obtain sin2/cos2 during
//! Ps), [0265] (S2: the unit started by Sr outputs Cs and Cc).
//!
//! The analog comparison happens outside the core (environment model `comparator`); the core
//! receives the raw decisions `cmp_s`, `cmp_c`. They are only meaningful late in the window, when
//! the sensor output has settled ([0326]-[0329]), so the latch takes them at the sampling strobe
//! `smp`, and only when the activation signal `sr` is 1 (FIG. 17 S1/S2). The raw inputs are not
//! synchronized: by construction of Pw + Pi they are static when sampled.
//!
//! `vld` records that a sample has been taken since power-on reset: the first sample after reset
//! (`first`) loads `cs`/`cc` without counting a change, and presets the counters (see
//! `updown_counter_58cd`).
//!
//! | port     | width | dir | meaning |
//! |----------|-------|-----|---------|
//! | `cmp_s`, `cmp_c` | 1 | in | raw comparator decisions (sin2 >= Vr, cos2 >= Vr) |
//! | `smp`    | 1     | in  | sampling strobe |
//! | `sr`     | 1     | in  | activation signal |
//! | `cs`, `cc` | 1   | out | latched sign signals (registered, [`outputs`]) |
//! | `upd`    | 1     | out | a sample is taken at this edge (`smp` & `sr`); this and the rows below are combinational ([`Comb`], from [`eval`]) |
//! | `first`  | 1     | out | this sample is the first since reset |
//! | `cs_new`, `cc_new` | 1 | out | the values `cs`/`cc` take at this edge |
//! | `chg_s`, `chg_c` | 1 | out | `cs`/`cc` change at this edge (never on the first sample) |
//!
//! | register | width | reset | meaning |
//! |----------|-------|-------|---------|
//! | `cs`     | 1     | 0     | sign signal Cs |
//! | `cc`     | 1     | 0     | sign signal Cc |
//! | `vld`    | 1     | 0     | a sample has been taken since reset |

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Regs {
    pub cs: bool,
    pub cc: bool,
    pub vld: bool,
}

pub const RESET: Regs = Regs {
    cs: false,
    cc: false,
    vld: false,
};

#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct Inputs {
    pub cmp_s: bool,
    pub cmp_c: bool,
    pub smp: bool,
    pub sr: bool,
}

/// Registered outputs.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct Outputs {
    pub cs: bool,
    pub cc: bool,
}

/// Combinational outputs of the cycle (they depend on this cycle's inputs).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct Comb {
    pub upd: bool,
    pub first: bool,
    pub cs_new: bool,
    pub cc_new: bool,
    pub chg_s: bool,
    pub chg_c: bool,
}

/// Registered outputs, decoded from the registers.
pub fn outputs(r: &Regs) -> Outputs {
    Outputs { cs: r.cs, cc: r.cc }
}

/// Pure next-state function, with the combinational outputs of the cycle.
pub fn eval(r: &Regs, i: &Inputs) -> (Comb, Regs) {
    let upd = i.smp && i.sr;
    let first = upd && !r.vld;
    let (cs_new, cc_new) = if upd {
        (i.cmp_s, i.cmp_c)
    } else {
        (r.cs, r.cc)
    };
    let counted = upd && r.vld;
    let o = Comb {
        upd,
        first,
        cs_new,
        cc_new,
        chg_s: counted && cs_new != r.cs,
        chg_c: counted && cc_new != r.cc,
    };
    (
        o,
        Regs {
            cs: cs_new,
            cc: cc_new,
            vld: r.vld || upd,
        },
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn holds_without_a_strobe_or_without_sr() {
        let r = Regs {
            cs: true,
            cc: false,
            vld: true,
        };
        for (smp, sr) in [(false, false), (false, true), (true, false)] {
            let (o, n) = eval(
                &r,
                &Inputs {
                    cmp_s: false,
                    cmp_c: true,
                    smp,
                    sr,
                },
            );
            assert_eq!(n, r, "held while Vs2 off or not sampling [0211]");
            assert!(!o.upd && !o.chg_s && !o.chg_c);
        }
    }

    #[test]
    fn samples_and_flags_changes() {
        let r = Regs {
            cs: true,
            cc: false,
            vld: true,
        };
        let (o, n) = eval(
            &r,
            &Inputs {
                cmp_s: false,
                cmp_c: false,
                smp: true,
                sr: true,
            },
        );
        assert_eq!((n.cs, n.cc), (false, false));
        assert!(o.upd && o.chg_s && !o.chg_c && !o.first);
    }

    #[test]
    fn first_sample_loads_without_a_change() {
        let (o, n) = eval(
            &RESET,
            &Inputs {
                cmp_s: true,
                cmp_c: true,
                smp: true,
                sr: true,
            },
        );
        assert!(o.first && !o.chg_s && !o.chg_c);
        assert!(n.vld && n.cs && n.cc);
    }
}
