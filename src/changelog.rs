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

use crate::sim::{Observer, SimError, TickView};
use pmu50_core::pmu50::Structural;
use pmu50_core::signals::{self, N_REGISTERS};
use std::io::Write;

pub struct ChangeLog<W: Write> {
    out: W,
    s: Structural,
    clock_ns: u64,
    prev: Option<[u64; N_REGISTERS]>,
}

impl<W: Write> ChangeLog<W> {
    pub fn new(mut out: W, s: Structural, clock_ns: u64) -> Result<Self, SimError> {
        writeln!(out, "# tick      time_us  register                                      old -> new").map_err(|e| SimError::observer("change log", e))?;
        Ok(ChangeLog { out, s, clock_ns, prev: None })
    }

    fn record(&mut self, v: &TickView<'_>) -> Result<(), SimError> {
        let now: [u64; N_REGISTERS] = signals::values(signals::REGISTERS, v.regs);
        if let Some(prev) = &self.prev {
            let time_us = (v.tick * self.clock_ns) as f64 / 1e3;
            let mut lines = String::new();
            for ((a, b), r) in prev.iter().zip(&now).zip(signals::REGISTERS) {
                if a != b && !r.free_running {
                    let path = format!("pmu50.{}", r.path());
                    lines += &format!("{:>6} {:>12.1}  {:<44} {} -> {}\n", v.tick, time_us, path, r.show(*a, &self.s), r.show(*b, &self.s));
                }
            }
            self.out.write_all(lines.as_bytes()).map_err(|e| SimError::observer("change log", e))?;
        }
        self.prev = Some(now);
        Ok(())
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
        self.out.flush().map_err(|e| SimError::observer("change log", e))
    }
}
