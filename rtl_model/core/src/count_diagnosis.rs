//! Count diagnosis flag `diag` (hardware twin of the check of diagnosis unit 67).
//!
//! Paragraphs: [0119] (abnormal when the difference between CNTs and CNTc is 2 or more), [0173].
//! The counts normally differ by 0 or 1 ([0100]: each counter moves once per half turn, in
//! alternation), so |cnt_s - cnt_c| >= 2 means a miscount, a stuck comparator or a corrupted
//! counter. A skipped quadrant (both signs changed in one sample, `updown_counter_58cd`) leaves the
//! counts equal but wrong by half a turn, so it raises the flag too.
//!
//! The difference is taken in the counters' own `cnt_width`-bit two's-complement arithmetic, so a
//! wrap of both counters past the extreme value is not a false alarm.
//!
//! `diag` is registered and aligned with the counters: it is computed from the values the
//! counters take at this edge, so in every cycle `diag` describes the `cnt_s`/`cnt_c` visible in
//! the same cycle.
//!
//! | port       | width | dir | meaning |
//! |------------|-------|-----|---------|
//! | `cnt_s_nxt`, `cnt_c_nxt` | W | in | counter values after this edge |
//! | `skip_nxt` | 1     | in  | `quadrant_skip` after this edge |
//! | `diag`     | 1     | out | diagnosis flag (registered, [`CountDiagnosis::outputs`]) |
//!
//! Structural parameter, fixed when the block is built ([`CountDiagnosis::new`]): `cnt_width`
//! (`CNT_W`) = W.
//!
//! | register | width | reset | meaning |
//! |----------|-------|-------|---------|
//! | `diag`   | 1     | 0     | diagnosis flag |

use crate::updown_counter_58cd::{mask, sext};

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Regs {
    pub diag: bool,
}

pub const RESET: Regs = Regs { diag: false };

#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct Inputs {
    pub cnt_s_nxt: u16,
    pub cnt_c_nxt: u16,
    pub skip_nxt: bool,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct Outputs {
    pub diag: bool,
}

/// Signed difference cnt_s - cnt_c in the counters' width.
pub fn difference(cnt_s: u16, cnt_c: u16, width: u8) -> i32 {
    sext(cnt_s.wrapping_sub(cnt_c) & mask(width), width)
}

/// The flag with its structural parameter, fixed at construction.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct CountDiagnosis {
    cnt_width: u8,
}

impl CountDiagnosis {
    pub const fn new(cnt_width: u8) -> Self {
        CountDiagnosis { cnt_width }
    }

    /// Registered outputs, decoded from the registers.
    pub fn outputs(&self, r: &Regs) -> Outputs {
        Outputs { diag: r.diag }
    }

    /// Pure next-state function (no combinational outputs).
    pub fn eval(&self, _r: &Regs, i: &Inputs) -> Regs {
        let d = difference(i.cnt_s_nxt, i.cnt_c_nxt, self.cnt_width);
        Regs {
            diag: d.abs() >= 2 || i.skip_nxt,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn diag(s: u16, c: u16, skip: bool, w: u8) -> bool {
        CountDiagnosis::new(w)
            .eval(
                &RESET,
                &Inputs {
                    cnt_s_nxt: s,
                    cnt_c_nxt: c,
                    skip_nxt: skip,
                },
            )
            .diag
    }

    #[test]
    fn threshold_is_two_0119() {
        assert!(!diag(5, 5, false, 16));
        assert!(!diag(5, 6, false, 16));
        assert!(!diag(6, 5, false, 16));
        assert!(diag(7, 5, false, 16));
        assert!(diag(5, 7, false, 16));
    }

    #[test]
    fn wrap_is_not_an_alarm() {
        assert!(!diag(0x0000, 0xFFFF, false, 16), "0 - (-1) = 1");
        assert!(!diag(0x0, 0x7, false, 3));
        assert!(diag(0x0, 0x6, false, 3));
    }

    #[test]
    fn quadrant_skip_raises_the_flag() {
        assert!(diag(5, 5, true, 16));
    }
}
