//! Action switching unit 56a, with the mode switch of regulator 51 and the rail enables of power
//! supply units 52, 53, 54 and internal power generation unit 55.
//!
//! Paragraphs: [0196]-[0208] (Sig from IG; rails per Sig), [0213] (56a generates Sig from IG),
//! [0310]-[0348] (third embodiment: Vs2 and Vp from unit 54, regulator 6 V / 4 V [0340]).
//!
//! The ignition key signal `ig` is asynchronous to the clock, so it passes through a
//! `sync_depth`-stage synchronizer; the last stage is the operation switching signal `sig`
//! ([0198]: 1 = key on, 0 = key off). Everything downstream sees only `sig`.
//!
//! Structural parameter (Verilog `parameter`), fixed when the block is built
//! ([`ActionSwitching::new`]): `sync_depth` (`SYNC_DEPTH`, 1..=4).
//!
//! Registered outputs ([`ActionSwitching::outputs`], decoded from `sync` only):
//!
//! | port      | width | dir | meaning |
//! |-----------|-------|-----|---------|
//! | `sig`     | 1     | out | operation switching signal Sig = last synchronizer stage |
//! | `vr_hi`   | 1     | out | regulator 51 in the high mode: VR = 6 V when 1, 4 V when 0 [0340] |
//! | `vm_en`   | 1     | out | power supply unit 52 on: Vm to the MPU [0341] |
//! | `vs1_en`  | 1     | out | power supply unit 53 on: Vs1 to the first sensor [0341] |
//! | `vp_en`   | 1     | out | internal power Vp on: always 1 [0330] |
//! | `rail_hi` | 1     | out | Vs2 and Vp at Vcc1 (5 V) when 1, at Vcc2 (3.3 V) when 0 [0343], [0345], [0348] |
//!
//! Next state and combinational outputs of the cycle ([`ActionSwitching::eval`]):
//!
//! | port      | width | dir | meaning |
//! |-----------|-------|-----|---------|
//! | `ig`      | 1     | in  | ignition key signal IG (asynchronous) |
//! | `sig_nxt` | 1     | out | value `sig` takes at this edge |
//! | `kon`     | 1     | out | `sig` rises at this edge (key on; internal strobe) |
//! | `koff`    | 1     | out | `sig` falls at this edge (key off; internal strobe) |
//!
//! | register | width | reset | meaning |
//! |----------|-------|-------|---------|
//! | `sync`   | `sync_depth` | 0 | synchronizer stages, bit 0 first; bit `sync_depth-1` is `sig` |
//!
//! Reset 0 = key off: at power-on the chip assumes the key is off until `ig` has crossed the
//! synchronizer.

/// Registers of the block.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Regs {
    /// Synchronizer stages (4 bit, bit 0 = first stage).
    pub sync: u8,
}

pub const RESET: Regs = Regs { sync: 0 };

#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct Inputs {
    pub ig: bool,
}

/// Registered outputs (functions of `sync` only).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct Outputs {
    pub sig: bool,
    pub vr_hi: bool,
    pub vm_en: bool,
    pub vs1_en: bool,
    pub vp_en: bool,
    pub rail_hi: bool,
}

/// Combinational outputs of the cycle (they depend on `ig`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct Comb {
    pub sig_nxt: bool,
    pub kon: bool,
    pub koff: bool,
}

/// The block with its structural parameter, fixed at construction.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct ActionSwitching {
    sync_depth: u8,
}

impl ActionSwitching {
    /// `sync_depth` stages (legal 1..=4, checked by `Params::validate`; clamped here so that the
    /// shifts below stay defined).
    pub const fn new(sync_depth: u8) -> Self {
        let d = if sync_depth < 1 {
            1
        } else if sync_depth > 4 {
            4
        } else {
            sync_depth
        };
        ActionSwitching { sync_depth: d }
    }

    pub const fn sync_depth(&self) -> u8 {
        self.sync_depth
    }

    fn last_stage(&self, sync: u8) -> bool {
        (sync >> (self.sync_depth - 1)) & 1 == 1
    }

    /// Registered outputs, decoded from the registers.
    pub fn outputs(&self, r: &Regs) -> Outputs {
        let sig = self.last_stage(r.sync);
        Outputs {
            sig,
            vr_hi: sig,
            vm_en: sig,
            vs1_en: sig,
            vp_en: true,
            rail_hi: sig,
        }
    }

    /// Pure next-state function, with the combinational outputs of the cycle.
    pub fn eval(&self, r: &Regs, i: &Inputs) -> (Comb, Regs) {
        let mask = (1u8 << self.sync_depth) - 1;
        let sync_nxt = ((r.sync << 1) | u8::from(i.ig)) & mask;
        let sig = self.last_stage(r.sync);
        let sig_nxt = self.last_stage(sync_nxt);
        (
            Comb {
                sig_nxt,
                kon: !sig && sig_nxt,
                koff: sig && !sig_nxt,
            },
            Regs { sync: sync_nxt },
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Registered outputs and strobes of each cycle.
    fn run(depth: u8, ig: &[bool]) -> Vec<(Outputs, Comb)> {
        let b = ActionSwitching::new(depth);
        let mut r = RESET;
        ig.iter()
            .map(|&ig| {
                let o = b.outputs(&r);
                let (c, n) = b.eval(&r, &Inputs { ig });
                r = n;
                (o, c)
            })
            .collect()
    }

    #[test]
    fn sig_follows_ig_after_depth_edges() {
        for depth in 1..=4u8 {
            let outs = run(depth, &[true; 8]);
            let first_on = outs.iter().position(|(o, _)| o.sig).unwrap();
            assert_eq!(first_on, usize::from(depth), "depth {depth}");
            // kon strobes exactly at the edge where sig rises (the cycle before sig = 1).
            assert!(outs[first_on - 1].1.kon && outs.iter().filter(|(_, c)| c.kon).count() == 1);
        }
    }

    #[test]
    fn koff_strobes_once_and_rails_follow_sig() {
        let ig: Vec<bool> = [true; 5].into_iter().chain([false; 5]).collect();
        let outs = run(2, &ig);
        assert_eq!(outs.iter().filter(|(_, c)| c.koff).count(), 1);
        for (o, _) in &outs {
            assert_eq!(
                (o.vm_en, o.vs1_en, o.vr_hi, o.rail_hi),
                (o.sig, o.sig, o.sig, o.sig)
            );
            assert!(o.vp_en, "Vp is always present [0330]");
        }
        let fall = outs.iter().position(|(_, c)| c.koff).unwrap();
        assert!(outs[fall].0.sig && !outs[fall + 1].0.sig);
    }

    #[test]
    fn a_one_tick_glitch_shorter_than_the_chain_still_passes_a_stage_at_a_time() {
        // A synchronizer is not a filter: a 1-tick pulse propagates as a 1-tick pulse.
        let outs = run(2, &[false, true, false, false, false]);
        assert_eq!(outs.iter().filter(|(o, _)| o.sig).count(), 1);
    }
}
