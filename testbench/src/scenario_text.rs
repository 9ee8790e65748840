//! The one writer of scenario files (the TOML that [`crate::scenario::Scenario`] reads): the
//! seeded random scenarios of `pmu50 random` and the regression's generated seeds write their
//! text with it, so the two agree on every table and field. A test reads back what it writes.

use pmu50_core::Params;
use std::fmt::Write;

/// A motor segment (`[motor] segments`), in ticks of the scenario's clock.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Segment {
    Hold { ticks: u64 },
    Move { ticks: u64, delta_deg: f64 },
}

/// An event's action (`[[events]]`).
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum EventText {
    Ig(bool),
    Vs2Fault(bool),
    Write {
        reg: String,
        value: u64,
    },
    Read {
        addr: u64,
    },
    /// A raw cycle of the register bus: any address, any 16-bit word.
    BusWrite {
        addr: u64,
        data: u64,
    },
    Vs2PgLeak(bool),
}

/// A scenario file being written, table by table in the order the format documents.
pub struct ScenarioText {
    s: String,
    clock_us: u64,
}

impl ScenarioText {
    /// The head: a comment line, `name`, `description` and the duration of `ticks` ticks of
    /// `clock_us` microseconds.
    pub fn new(comment: &str, name: &str, description: &str, ticks: u64, clock_us: u64) -> Self {
        let mut t = ScenarioText {
            s: String::new(),
            clock_us,
        };
        let _ = writeln!(t.s, "# {comment}");
        let _ = writeln!(t.s, "name = \"{name}\"");
        let _ = writeln!(t.s, "description = \"{description}\"");
        let d = t.us(ticks);
        let _ = writeln!(t.s, "duration = {d}\n");
        t
    }

    /// `ticks` ticks as a quoted duration in microseconds.
    fn us(&self, ticks: u64) -> String {
        format!("\"{} us\"", ticks * self.clock_us)
    }

    /// `[core]`: the clock and every parameter (durations in microseconds).
    pub fn core(&mut self, p: &Params) {
        let _ = writeln!(self.s, "[core]\nclock = \"{} us\"", self.clock_us);
        let _ = writeln!(
            self.s,
            "sync_depth = {}\ncnt_width = {}\nadaptive = {}",
            p.sync_depth, p.cnt_width, p.adaptive
        );
        for (n, v) in [
            ("pw", p.pw),
            ("pi", p.pi),
            ("ps", p.ps),
            ("x", p.si_max),
            ("min", p.si_min),
            ("t1", p.t1),
            ("t2", p.t2),
            ("smp_on", p.smp_on),
        ] {
            let d = self.us(u64::from(v));
            let _ = writeln!(self.s, "{n} = {d}");
        }
        let _ = writeln!(self.s, "cth = {}\n", p.cth);
    }

    /// `[env.comparator]`: the threshold errors of the two comparators, in volts.
    pub fn comparator(&mut self, vr_err_s: f64, vr_err_c: f64) {
        let _ = writeln!(
            self.s,
            "[env.comparator]\nvr_err_s = {vr_err_s:.3}\nvr_err_c = {vr_err_c:.3}\n"
        );
    }

    /// `[motor]`: the start angle and the segments.
    pub fn motor(&mut self, start_deg: f64, segments: &[Segment]) {
        let _ = writeln!(self.s, "[motor]\nstart_deg = {start_deg:.1}\nsegments = [");
        for seg in segments {
            match *seg {
                Segment::Hold { ticks } => {
                    let d = self.us(ticks);
                    let _ = writeln!(self.s, "  {{ kind = \"hold\", duration = {d} }},");
                }
                Segment::Move { ticks, delta_deg } => {
                    let d = self.us(ticks);
                    let _ = writeln!(
                        self.s,
                        "  {{ kind = \"move\", duration = {d}, delta_deg = {delta_deg:.3} }},"
                    );
                }
            }
        }
        let _ = writeln!(self.s, "]");
    }

    /// One `[[events]]` entry at tick `at`.
    pub fn event(&mut self, at: u64, e: &EventText) {
        let d = self.us(at);
        let _ = write!(self.s, "\n[[events]]\nat = {d}\n");
        let _ = match e {
            EventText::Ig(v) => writeln!(self.s, "ig = {v}"),
            EventText::Vs2Fault(v) => writeln!(self.s, "vs2_fault = {v}"),
            EventText::Write { reg, value } => {
                writeln!(self.s, "write = {{ reg = \"{reg}\", value = {value} }}")
            }
            EventText::Read { addr } => writeln!(self.s, "read = {addr}"),
            EventText::BusWrite { addr, data } => {
                writeln!(self.s, "bus_write = {{ addr = {addr}, data = {data} }}")
            }
            EventText::Vs2PgLeak(v) => writeln!(self.s, "vs2_pg_leak = {v}"),
        };
    }

    /// The text.
    pub fn finish(self) -> String {
        self.s
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scenario::{Action, Scenario};
    use std::path::Path;

    #[test]
    fn what_it_writes_reads_back_as_written() {
        let p = Params::default();
        let mut t = ScenarioText::new("test", "t", "a test", 5000, 10);
        t.core(&p);
        t.comparator(0.012, -0.034);
        t.motor(
            12.5,
            &[
                Segment::Hold { ticks: 100 },
                Segment::Move {
                    ticks: 200,
                    delta_deg: -45.25,
                },
            ],
        );
        t.event(0, &EventText::Ig(true));
        t.event(
            300,
            &EventText::Write {
                reg: "CTH".into(),
                value: 5,
            },
        );
        t.event(400, &EventText::Read { addr: 0x40 });
        t.event(500, &EventText::Vs2Fault(true));
        let text = t.finish();
        let sc = Scenario::parse(&text, "t.toml", "t", Path::new("t.toml")).unwrap();
        assert_eq!(sc.name, "t");
        assert_eq!(sc.ticks, 5000);
        assert_eq!(sc.params, p);
        assert_eq!(sc.events.len(), 4);
        assert!(
            matches!(sc.events[1].action, Action::Write { .. }),
            "{:?}",
            sc.events[1]
        );
    }
}
