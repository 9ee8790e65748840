//! Timing-signal generator of power control unit 56, with the output window of third power
//! supply unit 54.
//!
//! Paragraphs: [0336] (timing signal St with cycle T marks the start of each intermittent output),
//! [0318]-[0323] (FIG. 19A/19B: window Wt = Pw + Pi + Ps, programmable), [0347] (unit 54 outputs
//! Vs2 at the timing of St for Wt), [0354] (comparators sample during Ps), [0349] (while the key
//! is on, sampling at a period shorter than T), [0206] (cycle = drive interval Si).
//!
//! One 16-bit timer `tmr` counts ticks from the last cycle start. The outputs ([`outputs`]) are
//! decoded from `tmr` and the programmed periods, which are registers of other blocks (Moore at
//! the top level), so the environment can read them before it computes this tick's inputs; the
//! key strobes `kon`/`koff` only enter the next state ([`eval`]).
//!
//! Key off (`sig` = 0), cycle length = drive interval `si`:
//!
//! ```text
//! tmr      0    1 .. pw-1   pw .. pw+pi-1   pw+pi .. wt-1   wt .. si-1
//! st       1    0           0               0               0
//! vs2_en   1    1           1               1               0
//! ps_win   0    0           0               1               0
//! smp      0    0           0               1 at wt-1 only  0
//! ```
//!
//! Key on (`sig` = 1): `vs2_en` = 1 continuously, `st` = 0, `ps_win` = 0, and `smp` pulses at
//! `tmr` = `smp_on` - 1, cycle length `smp_on`.
//!
//! At the edge where `sig` changes (`kon`/`koff`) the timer restarts at 0, so the first tick with
//! `sig` = 0 starts an intermittent output (`st` = 1): the first key-off sample is taken Wt after
//! key-off (docs/spec.md, "Key-off and key-on").
//!
//! | port     | width | dir | meaning |
//! |----------|-------|-----|---------|
//! | `sig`    | 1     | in  | operation switching signal |
//! | `kon`, `koff` | 1 | in | `sig` changes at this edge (next state only) |
//! | `si`     | 16    | in  | drive interval in ticks (from 56b) |
//! | `pw`, `pi`, `ps`, `smp_on` | 16 | in | programmed periods in ticks |
//! | `st`     | 1     | out | timing signal St |
//! | `vs2_en` | 1     | out | third power supply unit 54 outputs Vs2 |
//! | `ps_win` | 1     | out | inside the sampling period Ps (key off) |
//! | `smp`    | 1     | out | sampling strobe: comparator outputs are latched at this edge |
//!
//! | register | width | reset | meaning |
//! |----------|-------|-------|---------|
//! | `tmr`    | 16    | 0     | ticks since the start of the current cycle (free-running timer) |

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Regs {
    pub tmr: u16,
}

pub const RESET: Regs = Regs { tmr: 0 };

#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct Inputs {
    pub sig: bool,
    pub kon: bool,
    pub koff: bool,
    pub si: u16,
    pub pw: u16,
    pub pi: u16,
    pub ps: u16,
    pub smp_on: u16,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct Outputs {
    pub st: bool,
    pub vs2_en: bool,
    pub ps_win: bool,
    pub smp: bool,
}

/// Outputs, decoded from the timer register and the registered inputs (`sig`, `si`, periods).
pub fn outputs(r: &Regs, i: &Inputs) -> Outputs {
    decode(r.tmr, i)
}

/// The decode of [`outputs`] for any timer value (the fast-forward query probes future values).
pub fn decode(tmr: u16, i: &Inputs) -> Outputs {
    let t = u32::from(tmr);
    let ps_start = u32::from(i.pw) + u32::from(i.pi);
    let wt = ps_start + u32::from(i.ps);
    if i.sig {
        Outputs {
            st: false,
            vs2_en: true,
            ps_win: false,
            smp: t + 1 == u32::from(i.smp_on),
        }
    } else {
        Outputs {
            st: t == 0,
            vs2_en: t < wt,
            ps_win: t >= ps_start && t < wt,
            smp: t + 1 == wt,
        }
    }
}

/// Cycle length in ticks in the current mode.
pub fn period(i: &Inputs) -> u16 {
    if i.sig {
        i.smp_on
    } else {
        i.si
    }
}

/// Pure next-state function (the block has no combinational outputs besides [`outputs`]).
pub fn eval(r: &Regs, i: &Inputs) -> Regs {
    // `>=` rather than `==`: if the interval register is ever below the timer (it cannot be
    // with legal parameters, see docs/spec.md), the cycle still ends instead of running 65536
    // ticks.
    let end_of_cycle = u32::from(r.tmr) + 1 >= u32::from(period(i));
    let tmr = if i.kon || i.koff || end_of_cycle {
        0
    } else {
        r.tmr + 1
    };
    Regs { tmr }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn off(si: u16) -> Inputs {
        Inputs {
            sig: false,
            si,
            pw: 5,
            pi: 12,
            ps: 5,
            smp_on: 10,
            ..Default::default()
        }
    }

    fn trace(i: &Inputs, n: usize) -> Vec<Outputs> {
        let mut r = RESET;
        (0..n)
            .map(|_| {
                let o = outputs(&r, i);
                r = eval(&r, i);
                o
            })
            .collect()
    }

    #[test]
    fn st_cycle_equals_the_drive_interval() {
        for si in [220u16, 330, 660] {
            let outs = trace(&off(si), 3 * usize::from(si));
            let st: Vec<usize> = outs
                .iter()
                .enumerate()
                .filter(|(_, o)| o.st)
                .map(|(k, _)| k)
                .collect();
            assert_eq!(st, vec![0, usize::from(si), 2 * usize::from(si)]);
        }
    }

    #[test]
    fn vs2_is_on_for_exactly_wt_and_samples_at_the_end_of_ps() {
        let outs = trace(&off(220), 220);
        assert_eq!(
            outs.iter().filter(|o| o.vs2_en).count(),
            22,
            "Wt = 220 us = 22 ticks [0229]"
        );
        assert!(outs[..22].iter().all(|o| o.vs2_en));
        let ps: Vec<usize> = outs
            .iter()
            .enumerate()
            .filter(|(_, o)| o.ps_win)
            .map(|(k, _)| k)
            .collect();
        assert_eq!(
            ps,
            (17..22).collect::<Vec<_>>(),
            "Ps starts after Pw + Pi [0323]"
        );
        let smp: Vec<usize> = outs
            .iter()
            .enumerate()
            .filter(|(_, o)| o.smp)
            .map(|(k, _)| k)
            .collect();
        assert_eq!(smp, vec![21], "one strobe, last tick of Ps");
    }

    #[test]
    fn key_on_samples_every_smp_on_with_vs2_continuous() {
        let i = Inputs {
            sig: true,
            ..off(220)
        };
        let outs = trace(&i, 40);
        assert!(outs.iter().all(|o| o.vs2_en && !o.st && !o.ps_win));
        let smp: Vec<usize> = outs
            .iter()
            .enumerate()
            .filter(|(_, o)| o.smp)
            .map(|(k, _)| k)
            .collect();
        assert_eq!(smp, vec![9, 19, 29, 39]);
    }

    #[test]
    fn key_edges_restart_the_timer() {
        let r = Regs { tmr: 100 };
        for i in [
            Inputs {
                koff: true,
                ..off(220)
            },
            Inputs {
                kon: true,
                ..off(220)
            },
        ] {
            assert_eq!(eval(&r, &i).tmr, 0);
        }
    }

    #[test]
    fn an_interval_below_the_timer_still_ends_the_cycle() {
        let r = Regs { tmr: 300 };
        assert_eq!(eval(&r, &off(220)).tmr, 0);
    }
}
