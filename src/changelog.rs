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
//! is left out. Counters are printed as signed decimals, everything else unsigned.

use crate::sim::{Observer, SimError, TickView};
use pmu50_core::pmu50::{RegValue, Structural};
use pmu50_core::updown_counter_58cd::sext;
use std::io::Write;

pub struct ChangeLog<W: Write> {
    out: W,
    s: Structural,
    clock_ns: u64,
    prev: Option<Vec<RegValue>>,
}

impl<W: Write> ChangeLog<W> {
    pub fn new(mut out: W, s: Structural, clock_ns: u64) -> Result<Self, SimError> {
        writeln!(out, "# tick      time_us  register                                      old -> new").map_err(|e| SimError::Observer(format!("change log: {e}")))?;
        Ok(ChangeLog { out, s, clock_ns, prev: None })
    }

    fn show(&self, r: &RegValue, v: u64) -> String {
        if r.name == "cnt_s" || r.name == "cnt_c" {
            sext(v as u16, self.s.cnt_width).to_string()
        } else {
            v.to_string()
        }
    }

    fn record(&mut self, v: &TickView<'_>) -> Result<(), SimError> {
        let now = v.regs.values(&self.s);
        if let Some(prev) = &self.prev {
            let time_us = (v.tick * self.clock_ns) as f64 / 1e3;
            let mut lines = String::new();
            for (a, b) in prev.iter().zip(&now) {
                if a.value != b.value && b.name != "tmr" {
                    let path = format!("pmu50.{}.{}", b.block, b.name);
                    lines += &format!("{:>6} {:>12.1}  {:<44} {} -> {}\n", v.tick, time_us, path, self.show(a, a.value), self.show(b, b.value));
                }
            }
            self.out.write_all(lines.as_bytes()).map_err(|e| SimError::Observer(format!("change log: {e}")))?;
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
        self.out.flush().map_err(|e| SimError::Observer(format!("change log: {e}")))
    }
}
