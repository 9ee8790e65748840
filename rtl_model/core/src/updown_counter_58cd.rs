//! Sine counter 58c and cosine counter 58d (up/down counters, powered by Vp).
//!
//! Paragraphs: [0094]-[0100] (counting rules and total count), [0211]/[0355] (counters on the
//! internal power Vp, so they keep counting across key-off), [0119] (a difference of 2 or more
//! between the counts is abnormal).
//!
//! Rules, exactly as written (`cs`, `cc` before the edge; a change is `cs` != `cs_new`):
//!
//! | rule   | condition                                   | action      |
//! |--------|---------------------------------------------|-------------|
//! | [0096] | Cs 0->1 while Cc = 1                        | `cnt_s` + 1 |
//! | [0096] | Cs 1->0 while Cc = 1                        | `cnt_s` - 1 |
//! | [0097] | Cs 1->0 while Cc = 0                        | `cnt_s` + 1 |
//! | [0097] | Cs 0->1 while Cc = 0                        | `cnt_s` - 1 |
//! | [0098] | Cc 0->1 while Cs = 0                        | `cnt_c` + 1 |
//! | [0098] | Cc 1->0 while Cs = 0                        | `cnt_c` - 1 |
//! | [0099] | Cc 1->0 while Cs = 1                        | `cnt_c` + 1 |
//! | [0099] | Cc 0->1 while Cs = 1                        | `cnt_c` - 1 |
//!
//! "While Cc = 1" is the value of the other sign signal, which does not change in the same sample
//! (a quadrant step changes exactly one sign). Interpretations (docs/spec.md):
//!
//! - **Both signs change in one sample** (the shaft moved two quadrants, or 180 deg +- 90 deg,
//!   between samples): the direction cannot be known. Both counters hold, and the sticky status
//!   bit `quadrant_skip` is set; it is cleared only by writing 1 to it in the register file. The
//!   count total is then off by 2 (half a turn), which the MPU's quadrant correction ([0145]-[0150],
//!   corrects +-1) cannot repair, hence the diagnosis output (`count_diagnosis`).
//! - **First sample after power-on reset**: the counters are preset from the sampled quadrant so that
//!   `cnt_s + cnt_c` mod 4 equals the quadrant index (0 = [0, 90) deg: Cs = 1, Cc = 1; 1 = [90, 180):
//!   Cs = 1, Cc = 0; 2 = [180, 270): 0, 0; 3 = [270, 360): 0, 1; [0092]-[0093]). This is what makes
//!   Q2 = CNT mod n of [0142] a quadrant number at all. Presets: q0 (0, 0), q1 (0, 1), q2 (1, 1),
//!   q3 (1, 2), which are the counts the rules reach from (0, 0) in q0 moving forward.
//! - **Width**: `cnt_width` bits (default 16), two's complement, wrapping like hardware.
//!
//! | port       | width | dir | meaning |
//! |------------|-------|-----|---------|
//! | `upd`, `first` | 1 | in  | from the comparator latch |
//! | `cs`, `cc` | 1     | in  | sign signals before the edge |
//! | `cs_new`, `cc_new` | 1 | in | sign signals after the edge |
//! | `skip_clr` | 1     | in  | write-1-to-clear of `quadrant_skip` (register file) |
//! | `cnt_s`, `cnt_c` | W | out | count values CNTs, CNTc (registered, [`UpdownCounter::outputs`]) |
//! | `quadrant_skip` | 1 | out | sticky: both signs changed in one sample (registered) |
//!
//! Structural parameter, fixed when the block is built ([`UpdownCounter::new`]): `cnt_width`
//! (`CNT_W`, 2..=16) = W. The block has no combinational outputs; [`UpdownCounter::eval`] is
//! the next-state function.
//!
//! | register | width | reset | meaning |
//! |----------|-------|-------|---------|
//! | `cnt_s`  | W (16)| 0     | sine count value CNTs |
//! | `cnt_c`  | W (16)| 0     | cosine count value CNTc |
//! | `quadrant_skip` | 1 | 0 | sticky skip status |

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Regs {
    pub cnt_s: u16,
    pub cnt_c: u16,
    pub quadrant_skip: bool,
}

pub const RESET: Regs = Regs {
    cnt_s: 0,
    cnt_c: 0,
    quadrant_skip: false,
};

#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct Inputs {
    pub upd: bool,
    pub first: bool,
    pub cs: bool,
    pub cc: bool,
    pub cs_new: bool,
    pub cc_new: bool,
    pub skip_clr: bool,
}

/// Registered outputs.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct Outputs {
    pub cnt_s: u16,
    pub cnt_c: u16,
    pub quadrant_skip: bool,
}

/// Mask of a `width`-bit counter.
pub fn mask(width: u8) -> u16 {
    (((1u32) << width.clamp(2, 16)) - 1) as u16
}

/// Two's-complement value of a `width`-bit register.
pub fn sext(v: u16, width: u8) -> i32 {
    let w = u32::from(width.clamp(2, 16));
    let v = i32::from(v) & ((1 << w) - 1);
    if v >> (w - 1) & 1 == 1 {
        v - (1 << w)
    } else {
        v
    }
}

/// Counter preset for the first sample after reset, indexed by (cs, cc).
fn preset(cs: bool, cc: bool) -> (u16, u16) {
    match (cs, cc) {
        (true, true) => (0, 0),   // quadrant 0: [0, 90) deg
        (true, false) => (0, 1),  // quadrant 1: [90, 180)
        (false, false) => (1, 1), // quadrant 2: [180, 270)
        (false, true) => (1, 2),  // quadrant 3: [270, 360)
    }
}

/// The counters with their structural parameter, fixed at construction.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct UpdownCounter {
    cnt_width: u8,
}

impl UpdownCounter {
    /// `cnt_width` bits (legal 2..=16; clamped by [`mask`]).
    pub const fn new(cnt_width: u8) -> Self {
        UpdownCounter { cnt_width }
    }

    /// Registered outputs, decoded from the registers.
    pub fn outputs(&self, r: &Regs) -> Outputs {
        Outputs {
            cnt_s: r.cnt_s,
            cnt_c: r.cnt_c,
            quadrant_skip: r.quadrant_skip,
        }
    }

    /// Pure next-state function.
    pub fn eval(&self, r: &Regs, i: &Inputs) -> Regs {
        next(self.cnt_width, r, i)
    }
}

fn next(width: u8, r: &Regs, i: &Inputs) -> Regs {
    let m = mask(width);
    let inc = |v: u16| v.wrapping_add(1) & m;
    let dec = |v: u16| v.wrapping_sub(1) & m;

    let chg_s = i.upd && !i.first && i.cs != i.cs_new;
    let chg_c = i.upd && !i.first && i.cc != i.cc_new;
    let both = chg_s && chg_c;

    let (mut cnt_s, mut cnt_c) = (r.cnt_s, r.cnt_c);
    if i.first {
        let (s, c) = preset(i.cs_new, i.cc_new);
        cnt_s = s & m;
        cnt_c = c & m;
    } else if chg_s && !both {
        // Sine counter 58c: the other sign Cc is unchanged in this sample.
        cnt_s = match (i.cs, i.cs_new, i.cc) {
            (false, true, true) => inc(r.cnt_s), // [0096] Cs 0->1 while Cc = 1
            (true, false, true) => dec(r.cnt_s), // [0096] Cs 1->0 (while Cc = 1)
            (true, false, false) => inc(r.cnt_s), // [0097] Cs 1->0 while Cc = 0
            (false, true, false) => dec(r.cnt_s), // [0097] Cs 0->1 (while Cc = 0)
            _ => r.cnt_s,
        };
    } else if chg_c && !both {
        // Cosine counter 58d: the other sign Cs is unchanged in this sample.
        cnt_c = match (i.cc, i.cc_new, i.cs) {
            (false, true, false) => inc(r.cnt_c), // [0098] Cc 0->1 while Cs = 0
            (true, false, false) => dec(r.cnt_c), // [0098] Cc 1->0 (while Cs = 0)
            (true, false, true) => inc(r.cnt_c),  // [0099] Cc 1->0 while Cs = 1
            (false, true, true) => dec(r.cnt_c),  // [0099] Cc 0->1 (while Cs = 1)
            _ => r.cnt_c,
        };
    }
    // Set wins over clear: a skip seen in the same cycle as the MPU's clear is not lost.
    let quadrant_skip = both || (r.quadrant_skip && !i.skip_clr);
    Regs {
        cnt_s,
        cnt_c,
        quadrant_skip,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample(r: &Regs, cs: bool, cc: bool, cs_new: bool, cc_new: bool) -> Regs {
        UpdownCounter::new(16).eval(
            r,
            &Inputs {
                upd: true,
                first: false,
                cs,
                cc,
                cs_new,
                cc_new,
                skip_clr: false,
            },
        )
    }

    const Z: Regs = RESET;

    #[test]
    fn rule_0096_up_and_down() {
        assert_eq!(sample(&Z, false, true, true, true).cnt_s, 1);
        assert_eq!(
            sample(&Z, true, true, false, true).cnt_s,
            0xFFFF,
            "-1 in 16 bit"
        );
    }

    #[test]
    fn rule_0097_up_and_down() {
        assert_eq!(sample(&Z, true, false, false, false).cnt_s, 1);
        assert_eq!(sample(&Z, false, false, true, false).cnt_s, 0xFFFF);
    }

    #[test]
    fn rule_0098_up_and_down() {
        assert_eq!(sample(&Z, false, false, false, true).cnt_c, 1);
        assert_eq!(sample(&Z, false, true, false, false).cnt_c, 0xFFFF);
    }

    #[test]
    fn rule_0099_up_and_down() {
        assert_eq!(sample(&Z, true, true, true, false).cnt_c, 1);
        assert_eq!(sample(&Z, true, false, true, true).cnt_c, 0xFFFF);
    }

    #[test]
    fn one_rule_moves_only_its_own_counter() {
        let n = sample(&Z, false, true, true, true);
        assert_eq!(n.cnt_c, 0);
        let n = sample(&Z, true, true, true, false);
        assert_eq!(n.cnt_s, 0);
    }

    #[test]
    fn both_changed_holds_and_sets_sticky_skip() {
        let r = Regs {
            cnt_s: 5,
            cnt_c: 5,
            quadrant_skip: false,
        };
        let n = sample(&r, true, true, false, false);
        assert_eq!((n.cnt_s, n.cnt_c, n.quadrant_skip), (5, 5, true));
        // Sticky across later ordinary samples.
        let n2 = sample(&n, false, false, false, true);
        assert!(n2.quadrant_skip);
        // Cleared by the W1C strobe, but a new skip in the same cycle wins.
        let clr = |r: &Regs, both: bool| {
            let (cs_new, cc_new) = if both { (true, true) } else { (false, false) };
            UpdownCounter::new(16).eval(
                r,
                &Inputs {
                    upd: true,
                    cs: false,
                    cc: false,
                    cs_new,
                    cc_new,
                    skip_clr: true,
                    ..Default::default()
                },
            )
        };
        assert!(!clr(&n, false).quadrant_skip);
        assert!(clr(&n, true).quadrant_skip);
    }

    #[test]
    fn first_sample_presets_from_the_quadrant() {
        for ((cs, cc), want) in [
            ((true, true), (0, 0)),
            ((true, false), (0, 1)),
            ((false, false), (1, 1)),
            ((false, true), (1, 2)),
        ] {
            let r = Regs {
                cnt_s: 77,
                cnt_c: 99,
                quadrant_skip: false,
            };
            let n = UpdownCounter::new(16).eval(
                &r,
                &Inputs {
                    upd: true,
                    first: true,
                    cs_new: cs,
                    cc_new: cc,
                    ..Default::default()
                },
            );
            assert_eq!((n.cnt_s, n.cnt_c), want);
        }
    }

    #[test]
    fn wraps_at_the_configured_width() {
        let r = Regs {
            cnt_s: 0x7,
            cnt_c: 0,
            quadrant_skip: false,
        };
        let n = UpdownCounter::new(3).eval(
            &r,
            &Inputs {
                upd: true,
                cs: false,
                cc: true,
                cs_new: true,
                cc_new: true,
                ..Default::default()
            },
        );
        assert_eq!(n.cnt_s, 0);
        assert_eq!(sext(0x7, 3), -1);
        assert_eq!(sext(0x3, 3), 3);
        assert_eq!(sext(0x8000, 16), -32768);
    }

    #[test]
    fn no_update_no_change() {
        let r = Regs {
            cnt_s: 3,
            cnt_c: 4,
            quadrant_skip: true,
        };
        let n = UpdownCounter::new(16).eval(
            &r,
            &Inputs {
                upd: false,
                cs: false,
                cs_new: true,
                ..Default::default()
            },
        );
        assert_eq!(n, r);
    }
}
