//! SplitMix64, the one seeded generator of stimuli: `pmu50 random`, the regression generator,
//! the stress vectors of the HDL co-simulation and the randomised tests all draw from it, so that
//! a seed means the same draws everywhere; and the random legal parameter sets of `pmu50 random`
//! and the stress vectors. It drives the core from outside; no block uses it.

use crate::params::Params;

/// SplitMix64 (Steele, Lea and Flood): tiny, deterministic, good enough to spread stimuli.
/// The field is the state; [`SplitMix64::new`] mixes a seed into it.
#[derive(Clone, Debug)]
pub struct SplitMix64(pub u64);

impl SplitMix64 {
    /// The generator for `seed` (the seed mixed with the golden-ratio increment).
    pub fn new(seed: u64) -> SplitMix64 {
        SplitMix64(seed ^ 0x9E37_79B9_7F4A_7C15)
    }

    /// The next 64 random bits.
    #[allow(clippy::should_implement_trait)]
    pub fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in `lo..=hi` (up to the modulo bias, which stimuli do not mind).
    pub fn range(&mut self, lo: u64, hi: u64) -> u64 {
        lo + self.next() % (hi - lo + 1)
    }

    /// One random bit.
    pub fn bit(&mut self) -> bool {
        self.next() & 1 == 1
    }

    /// True with probability `num / den`.
    pub fn chance(&mut self, num: u64, den: u64) -> bool {
        self.next() % den < num
    }

    /// True with probability `p` percent.
    pub fn percent(&mut self, p: u64) -> bool {
        self.chance(p, 100)
    }
}

/// The ranges of [`SplitMix64::legal_params`], in clock ticks: the highest value drawn for
/// `pw` and `pi` (from 0), `ps`, `t1`, `t2` and `cth` (from 1) and `smp_on` (from 2); `si_min`
/// at most `si_min_over_wt` above Wt (`pw + pi + ps`), `si_max` at most `si_max_over_min` above
/// `si_min`; the chance (num, den) of a counter narrower than 16 bits (then 2 to
/// `narrow_cnt_max` bits) and of the adaptive interval.
#[derive(Clone, Copy, Debug)]
pub struct ParamRanges {
    pub pw: u64,
    pub pi: u64,
    pub ps: u64,
    pub si_min_over_wt: u64,
    pub si_max_over_min: u64,
    pub narrow_cnt: (u64, u64),
    pub narrow_cnt_max: u64,
    pub adaptive: (u64, u64),
    pub t1: u64,
    pub t2: u64,
    pub cth: u64,
    pub smp_on: u64,
}

impl SplitMix64 {
    /// A legal parameter set within `r` (drawn again until [`Params::validate`] accepts it),
    /// SYNC_DEPTH 1 to 4.
    pub fn legal_params(&mut self, r: &ParamRanges) -> Params {
        loop {
            let pw = self.range(0, r.pw) as u16;
            let pi = self.range(0, r.pi) as u16;
            let ps = self.range(1, r.ps) as u16;
            let wt = u64::from(pw + pi + ps);
            let si_min = self.range(wt + 1, wt + r.si_min_over_wt) as u16;
            let si_max =
                self.range(u64::from(si_min), u64::from(si_min) + r.si_max_over_min) as u16;
            let p = Params {
                sync_depth: self.range(1, 4) as u8,
                cnt_width: if self.chance(r.narrow_cnt.0, r.narrow_cnt.1) {
                    self.range(2, r.narrow_cnt_max) as u8
                } else {
                    16
                },
                adaptive: self.chance(r.adaptive.0, r.adaptive.1),
                pw,
                pi,
                ps,
                si_max,
                si_min,
                t1: self.range(1, r.t1) as u16,
                t2: self.range(1, r.t2) as u16,
                cth: self.range(1, r.cth) as u8,
                smp_on: self.range(2, r.smp_on) as u16,
            };
            if p.validate().is_ok() {
                return p;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::SplitMix64;

    /// The first outputs of SplitMix64 from state 0 (the published reference sequence), so
    /// that every seed keeps meaning the same stimuli.
    #[test]
    fn reference_sequence() {
        let mut r = SplitMix64(0);
        assert_eq!(
            [r.next(), r.next(), r.next()],
            [
                0xE220_A839_7B1D_CDAF,
                0x6E78_9E6A_A1B9_65F4,
                0x06C4_5D18_8009_454F
            ]
        );
        assert_eq!(SplitMix64::new(5).0, 5 ^ 0x9E37_79B9_7F4A_7C15);
    }

    #[test]
    fn range_chance_and_percent_stay_in_bounds() {
        let mut r = SplitMix64::new(1);
        let mut hits = 0;
        for _ in 0..10_000 {
            let v = r.range(3, 9);
            assert!((3..=9).contains(&v));
            assert!(!r.chance(0, 7));
            assert!(r.chance(7, 7));
            hits += u32::from(r.percent(25));
        }
        assert!((2_000..3_000).contains(&hits), "{hits}");
    }
}
