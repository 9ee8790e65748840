//! The functional coverage model (`pmu50-coverage`) as an observer of the bench: sampled at
//! every edge, and replayed over skipped key-off periods as a stepped run would sample them.

use crate::sim::{Observer, SimError, TickView};
use pmu50_coverage::{Coverage, Edge};

/// The coverage alone as an observer: sampled at every edge and replayed over skipped periods
/// as a regression seed does it (the verification kit's seed checks delegate to it; the
/// regression bench measures it on its own).
impl Observer for Coverage {
    fn tick(&mut self, v: &TickView<'_>) -> Result<(), SimError> {
        self.sample(&Edge {
            before: v.regs,
            after: v.after,
            out: v.ports,
            inputs: v.inputs,
            internals: v.internals,
        });
        Ok(())
    }

    fn replays_periods(&self) -> bool {
        true
    }

    fn period_boundary(&mut self, k: u64) -> Result<(), SimError> {
        Coverage::period_boundary(self, k);
        Ok(())
    }

    fn can_replay(&self, k: u64, len: u64) -> bool {
        Coverage::can_replay(self, k, len)
    }

    fn replay(&mut self, _k: u64, periods: u64, _len: u64) -> Result<(), SimError> {
        Coverage::replay(self, periods);
        Ok(())
    }
}
