//! Register change log: one line per register change, like a processor model's commit log.
//!
//! ```text
//! # tick      time_us  register                              old -> new
//!     23        230.0  pmu50.comparator_latch.vld            0 -> 1
//!    682       6820.0  pmu50.drive_interval.si               660 -> 440
//! ```
//!
//! The line for edge *k* carries time k·T, the instant the register takes its new value
//! (docs/spec.md 6.1). The free-running timer `pmu50.timing_generator.tmr` changes every tick and
//! (`free_running` in the signal table) is left out. Signed registers of the table (the counters)
//! are printed as signed decimals, everything else unsigned.

use crate::sim::replay::PeriodRecorder;
use crate::sim::{Observer, SimError, TickView};
use pmu50_core::pmu50::Structural;
use pmu50_core::signals::{self, N_REGISTERS};
use std::io::Write;

pub struct ChangeLog<W: Write> {
    out: W,
    structural: Structural,
    clock_ns: u64,
    prev: Option<[u64; N_REGISTERS]>,
    /// Replay of skipped key-off periods (crate::sim::replay): the registers of every tick.
    rec: PeriodRecorder,
}

impl<W: Write> ChangeLog<W> {
    pub fn new(mut out: W, s: Structural, clock_ns: u64) -> Result<Self, SimError> {
        writeln!(
            out,
            "# tick      time_us  register                                      old -> new"
        )
        .map_err(|e| SimError::observer("change log", e))?;
        Ok(ChangeLog {
            out,
            structural: s,
            clock_ns,
            prev: None,
            rec: PeriodRecorder::new(),
        })
    }

    fn record(&mut self, v: &TickView<'_>) -> Result<(), SimError> {
        let now: [u64; N_REGISTERS] = signals::values(signals::REGISTERS, v.regs);
        if let Some(prev) = &self.prev {
            let mut lines = String::new();
            for (i, (a, b)) in prev.iter().zip(&now).enumerate() {
                if a != b {
                    self.line(&mut lines, v.tick, i, *a, *b);
                }
            }
            self.out
                .write_all(lines.as_bytes())
                .map_err(|e| SimError::observer("change log", e))?;
        }
        self.prev = Some(now);
        if self.rec.active() {
            self.rec.record(v.tick, &now);
        }
        Ok(())
    }

    /// The line of register `i` changing from `a` to `b` at edge `tick` (none for the
    /// free-running timer).
    fn line(&self, lines: &mut String, tick: u64, i: usize, a: u64, b: u64) {
        let r = &signals::REGISTERS[i];
        if !r.free_running {
            let time_us = (tick * self.clock_ns) as f64 / 1e3;
            let path = format!("pmu50.{}", r.path());
            *lines += &format!(
                "{:>6} {:>12.1}  {:<44} {} -> {}\n",
                tick,
                time_us,
                path,
                r.show(a, &self.structural),
                r.show(b, &self.structural)
            );
        }
    }
}

impl<W: Write> ChangeLog<W> {
    /// The writer, after `finish` (for the caller to rename the file into place).
    pub fn into_inner(self) -> W {
        self.out
    }
}

impl<W: Write> Observer for ChangeLog<W> {
    fn tick(&mut self, v: &TickView<'_>) -> Result<(), SimError> {
        self.record(v)
    }
    fn finish(&mut self, v: &TickView<'_>) -> Result<(), SimError> {
        self.record(v)?;
        self.out
            .flush()
            .map_err(|e| SimError::observer("change log", e))
    }

    /// A log replays skipped periods: the lines of each copy are those of the recorded period
    /// at the shifted ticks (crate::sim::replay).
    fn replays_periods(&self) -> bool {
        true
    }

    crate::sim::replay::recorder_boundaries!(rec);

    fn can_replay(&self, k: u64, len: u64) -> bool {
        self.prev.is_some() && self.rec.can_replay(k, len)
    }

    fn replay(&mut self, k: u64, periods: u64, len: u64) -> Result<(), SimError> {
        let Some(mut cur) = self.prev else {
            return Ok(());
        };
        let mut rec = std::mem::take(&mut self.rec);
        let mut lines = String::new();
        let r = rec.replay(k, periods, len, None, |tick, changes| {
            lines.clear();
            for &(i, b) in changes {
                let i = i as usize;
                self.line(&mut lines, tick, i, cur[i], b);
                cur[i] = b;
            }
            self.out.write_all(lines.as_bytes())
        });
        self.rec = rec;
        r.map_err(|e| SimError::observer("change log", e))
    }
}
