//! SplitMix64, the one seeded generator of stimuli: `pmu50 random`, the regression generator,
//! the stress vectors of the HDL co-simulation and the randomised tests all draw from it, so that
//! a seed means the same draws everywhere. It drives the core's ports from outside; no block
//! uses it.

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

#[cfg(test)]
mod tests {
    use super::SplitMix64;

    /// The first outputs of SplitMix64 from state 0 (the published reference sequence), so
    /// that every seed keeps meaning the same stimuli.
    #[test]
    fn reference_sequence() {
        let mut r = SplitMix64(0);
        assert_eq!([r.next(), r.next(), r.next()], [0xE220_A839_7B1D_CDAF, 0x6E78_9E6A_A1B9_65F4, 0x06C4_5D18_8009_454F]);
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
