//! Sensor power determination unit 57.
//!
//! Paragraphs: [0209] (57 determines whether Vs2 is supplied and generates the activation signal
//! Sr, 1 while Vs2 is supplied, 0 otherwise), [0210] (the rotation number detection unit operates
//! while Sr = 1), FIG. 17 steps S1-S2 [0264]-[0265] (on a detected rise of Vs2, Sr starts the
//! rotation detection; without a rise the process ends and the interval does not change).
//!
//! The digital core cannot see a voltage; it sees `vs2_ok`, the output of the analog power-good
//! comparator on the Vs2 rail (an environment model; 1 when Vs2 is within its regulation window).
//! `sr` is registered: `sr` <= `vs2_en` & `vs2_ok`. Requiring `vs2_en` as well means a rail that
//! reports good while the chip does not drive it (a short to another supply) never activates the
//! detection unit. While the key is on the same rule holds; with a healthy rail `sr` is then
//! continuously 1, as [0210] requires ("continually operates").
//!
//! | port     | width | dir | meaning |
//! |----------|-------|-----|---------|
//! | `vs2_en` | 1     | in  | unit 54 drives Vs2 (from the timing generator) |
//! | `vs2_ok` | 1     | in  | analog power-good of the Vs2 rail |
//! | `sr`     | 1     | out | activation signal Sr (registered, [`outputs`]) |
//!
//! | register | width | reset | meaning |
//! |----------|-------|-------|---------|
//! | `sr`     | 1     | 0     | activation signal Sr |

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Regs {
    pub sr: bool,
}

pub const RESET: Regs = Regs { sr: false };

#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct Inputs {
    pub vs2_en: bool,
    pub vs2_ok: bool,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct Outputs {
    pub sr: bool,
}

/// Registered outputs, decoded from the registers.
pub fn outputs(r: &Regs) -> Outputs {
    Outputs { sr: r.sr }
}

/// Pure next-state function (no combinational outputs).
pub fn eval(_r: &Regs, i: &Inputs) -> Regs {
    Regs {
        sr: i.vs2_en && i.vs2_ok,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sr_needs_both_the_enable_and_a_good_rail() {
        for (en, ok) in [(false, false), (false, true), (true, false), (true, true)] {
            let n = eval(
                &RESET,
                &Inputs {
                    vs2_en: en,
                    vs2_ok: ok,
                },
            );
            assert_eq!(n.sr, en && ok, "en={en} ok={ok}");
        }
    }

    #[test]
    fn sr_output_is_the_register() {
        assert!(outputs(&Regs { sr: true }).sr);
    }
}
