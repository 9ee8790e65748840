//! Period skip-ahead (docs/spec.md 5.1): with the key off and nothing outside changing,
//! the whole bench repeats from one key-off period to the next once the drive interval has
//! settled ([0226]-[0231]: the intermittent Vs2 output every interval). This part detects the
//! repeat and says how many whole periods may be skipped.
//!
//! The argument for exactness: the bench is deterministic. What happens during a period that
//! starts at edge `b` (timer at 0, key off) is a function of
//! - the state at `b`: every core register, the analog front (second sensor, Vs2 fault), the MPU
//!   (boot, tracker, origin, last key level) and the key level of the timeline ([`Snapshot`]);
//! - the inputs from outside during the period: timeline events and the shaft angle.
//!
//! If the state at a boundary equals the state one period earlier, no event fell in that period
//! and the shaft angle has been constant since ("no change before t",
//! [`pmu50_env::MotorProfile::constant_until_ns`]), then every later period with no event and the
//! same angle is an exact copy: same end state, same rail on-times, same table rows shifted by
//! the period. The accumulators are then advanced by `n` times the last period's increments.

use super::front::FrontState;
use super::mpu::MpuState;
use pmu50_core::Regs;
use pmu50_env::{MotorProfile, OnTimes};

/// The state of the whole bench at a key-off period boundary (accumulators excluded).
#[derive(Clone, Debug, PartialEq)]
pub struct Snapshot {
    pub regs: Regs,
    pub front: FrontState,
    pub mpu: MpuState,
    pub ig: bool,
}

struct Boundary {
    tick: u64,
    snap: Snapshot,
    /// Index of the next timeline event not yet applied.
    next_event: usize,
    meter: OnTimes,
}

/// A skip the bench may take now.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Skip {
    /// Whole periods to skip.
    pub periods: u64,
    /// Period length in edges.
    pub len: u64,
    /// Rail on-times one period adds.
    pub meter: OnTimes,
    /// Table rows one period adds (0 or 1).
    pub rows: u64,
}

/// What the bench knows at a boundary.
pub struct At<'a> {
    pub tick: u64,
    pub snap: Snapshot,
    pub next_event: usize,
    pub next_event_tick: Option<u64>,
    pub meter: OnTimes,
    /// Table rows since the previous boundary.
    pub rows: u64,
    pub motor: &'a MotorProfile,
    pub clock_ns: u64,
    pub end_tick: u64,
}

#[derive(Default)]
pub struct PeriodSkip {
    prev: Option<Boundary>,
}

impl PeriodSkip {
    pub fn new() -> PeriodSkip {
        PeriodSkip::default()
    }

    /// Called at every key-off period boundary (key off, timer at 0) before the events of the
    /// tick; returns the skip to take, if the last period repeats and at least one whole period
    /// fits before the next event, motion or the end of the run.
    pub fn at_boundary(&mut self, a: At<'_>) -> Option<Skip> {
        let cur = Boundary {
            tick: a.tick,
            snap: a.snap,
            next_event: a.next_event,
            meter: a.meter,
        };
        let p = self.prev.replace(cur)?;
        let cur = self.prev.as_ref()?;
        // A period with more than one table row cannot happen with the key off (one sampling
        // strobe per period); not skipping keeps the table exact if it ever did.
        if a.rows > 1 || cur.next_event != p.next_event || cur.snap != p.snap || cur.tick <= p.tick
        {
            return None;
        }
        let len = cur.tick - p.tick;
        let mut n = a.end_tick.saturating_sub(a.tick) / len;
        if let Some(te) = a.next_event_tick {
            n = n.min(te.saturating_sub(a.tick) / len);
        }
        // Angle queries of the previous period start at (p.tick + 1)·T; the last skipped tick
        // queries (k + n·len)·T.
        let until = a.motor.constant_until_ns((p.tick + 1) * a.clock_ns);
        if until != u64::MAX {
            let last = until / a.clock_ns;
            n = n.min(last.saturating_sub(a.tick) / len);
        }
        if n == 0 {
            return None;
        }
        let meter = cur.meter.since(&p.meter);
        // After the skip the next period is stepped again and compared afresh.
        self.prev = None;
        Some(Skip {
            periods: n,
            len,
            meter,
            rows: a.rows,
        })
    }
}
