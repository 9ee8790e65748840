//! The closure curve of a regression: the share of the reachable bins hit, seed by seed.

use pmu50_coverage::layout;

/// The closure curve, built seed by seed in seed order: the share of the bins scenario stimuli
/// reach hit so far. Only the points where it changes are kept (each with the point just before
/// it, so the line stays a staircase), with the first and the last: at most two points a bin,
/// whatever the number of seeds.
pub struct Curve {
    reachable: Vec<bool>,
    total: usize,
    seen: Vec<bool>,
    hit: usize,
    n: u64,
    out: Vec<(u64, f64)>,
}

impl Default for Curve {
    fn default() -> Curve {
        Curve::new()
    }
}

impl Curve {
    pub fn new() -> Curve {
        let l = layout();
        let reachable: Vec<bool> = l
            .bins
            .iter()
            .map(|b| b.unreachable.is_none() && !b.port_only)
            .collect();
        let total = reachable.iter().filter(|r| **r).count();
        Curve {
            seen: vec![false; reachable.len()],
            reachable,
            total,
            hit: 0,
            n: 0,
            out: Vec::new(),
        }
    }

    /// The next seed's hits.
    pub fn push(&mut self, hits: &[u64]) {
        let before = self.hit;
        for (i, h) in hits.iter().enumerate() {
            if *h > 0 && self.reachable.get(i).copied().unwrap_or(false) && !self.seen[i] {
                self.seen[i] = true;
                self.hit += 1;
            }
        }
        if self.n == 0 || self.hit != before {
            if self.n > 0 && self.out.last().is_some_and(|p| p.0 != self.n) {
                self.out.push((self.n, pct(before, self.total)));
            }
            self.out.push((self.n + 1, pct(self.hit, self.total)));
        }
        self.n += 1;
    }

    pub fn finish(mut self) -> Vec<(u64, f64)> {
        if self.out.last().is_some_and(|p| p.0 != self.n) {
            self.out.push((self.n, pct(self.hit, self.total)));
        }
        self.out
    }
}

/// `a` of `b` in percent (100 when `b` is 0).
pub fn pct(a: usize, b: usize) -> f64 {
    if b == 0 {
        100.0
    } else {
        100.0 * a as f64 / b as f64
    }
}
