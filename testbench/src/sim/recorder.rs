//! The recorder: the per-pulse event table of the key-off sampling edges (FIG. 17/18 decisions),
//! run-length aggregated so that its memory does not grow with the run.
//!
//! A parked car produces one row per drive interval (about 13 million a day at 6.6 ms), and
//! every row after the interval has settled differs from the previous one only in its time. The
//! log keeps runs of rows that are identical but for the time and equally spaced: a run is its
//! first row, a count and a stride. Every row can still be read back ([`PulseLog::iter`]), so the
//! text table of [`PulseLog::table`] is the same as a table of every row.

use super::rows::PulseRow;
use pmu50_core::drive_interval_changing_56b::Fig17;
use pmu50_core::{Internals, Outputs};

/// `count` rows equal to `first` but for their time: row `i` is at edge `first.tick + i·stride`.
#[derive(Clone, Debug, PartialEq)]
pub struct PulseRun {
    pub first: PulseRow,
    pub count: u64,
    /// Edges between two rows of the run (0 while `count` is 1).
    pub stride: u64,
}

impl PulseRun {
    fn last_tick(&self) -> u64 {
        self.first.tick + (self.count - 1) * self.stride
    }

    /// Row `i` of the run (`i < count`).
    pub fn row(&self, i: u64, clock_ns: u64) -> PulseRow {
        let tick = self.first.tick + i * self.stride;
        PulseRow {
            tick,
            time_ns: tick * clock_ns,
            ..self.first.clone()
        }
    }
}

fn same_but_time(a: &PulseRow, b: &PulseRow) -> bool {
    PulseRow {
        tick: 0,
        time_ns: 0,
        ..a.clone()
    } == PulseRow {
        tick: 0,
        time_ns: 0,
        ..b.clone()
    }
}

/// The per-pulse table, run-length aggregated.
#[derive(Clone, Debug, PartialEq)]
pub struct PulseLog {
    clock_ns: u64,
    runs: Vec<PulseRun>,
    len: u64,
}

impl PulseLog {
    pub fn new(clock_ns: u64) -> PulseLog {
        PulseLog {
            clock_ns,
            runs: Vec::new(),
            len: 0,
        }
    }

    /// Number of rows (pulses).
    pub fn len(&self) -> u64 {
        self.len
    }

    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// The runs, in time order.
    pub fn runs(&self) -> &[PulseRun] {
        &self.runs
    }

    /// Every row, in time order.
    pub fn iter(&self) -> impl Iterator<Item = PulseRow> + '_ {
        self.runs
            .iter()
            .flat_map(move |r| (0..r.count).map(move |i| r.row(i, self.clock_ns)))
    }

    /// Every row as a vector (for short runs: tests, tables).
    pub fn rows(&self) -> Vec<PulseRow> {
        self.iter().collect()
    }

    /// Append one row.
    pub fn push(&mut self, row: PulseRow) {
        self.len += 1;
        if let Some(r) = self.runs.last_mut() {
            if same_but_time(&r.first, &row) && row.tick > r.last_tick() {
                let d = row.tick - r.last_tick();
                if r.count == 1 {
                    r.stride = d;
                    r.count = 2;
                    return;
                }
                if d == r.stride {
                    r.count += 1;
                    return;
                }
            }
        }
        self.runs.push(PulseRun {
            first: row,
            count: 1,
            stride: 0,
        });
    }

    /// Append `n` more copies of the last row, each `period` edges after the one before: what
    /// `n` repetitions of a period whose only pulse was that row add to the table.
    pub fn repeat_last(&mut self, n: u64, period: u64) {
        if n == 0 || period == 0 {
            return;
        }
        let Some(r) = self.runs.last_mut() else {
            return;
        };
        self.len += n;
        if r.count == 1 {
            r.stride = period;
            r.count = 1 + n;
        } else if r.stride == period {
            r.count += n;
        } else {
            let next = r.row(r.count - 1, self.clock_ns);
            let tick = next.tick + period;
            self.runs.push(PulseRun {
                first: PulseRow {
                    tick,
                    time_ns: tick * self.clock_ns,
                    ..next
                },
                count: n,
                stride: period,
            });
        }
    }

    /// Number of rows whose edge is at or before `tick` (without expanding the runs).
    pub fn count_until(&self, tick: u64) -> u64 {
        self.runs
            .iter()
            .take_while(|r| r.first.tick <= tick)
            .map(|r| {
                (tick - r.first.tick)
                    .checked_div(r.stride)
                    .map_or(r.count, |n| r.count.min(n + 1))
            })
            .sum()
    }

    /// Consecutive pairs of rows, as (last row of a run, first row of the next): rows inside a
    /// run are equal but for their time, so these are the only pairs at which anything changes.
    pub fn run_boundaries(&self) -> impl Iterator<Item = (PulseRow, PulseRow)> + '_ {
        self.runs
            .windows(2)
            .map(move |w| (w[0].row(w[0].count - 1, self.clock_ns), w[1].first.clone()))
    }

    /// The last row.
    pub fn last(&self) -> Option<PulseRow> {
        self.runs.last().map(|r| r.row(r.count - 1, self.clock_ns))
    }

    /// The table as text, one line per row (golden snapshots, CLI).
    pub fn table(&self) -> String {
        let mut s = String::from(
            "    time_us  cs cc hist_s hist_c cnt_r  si_ms  cnt_s  cnt_c  fig17       fig18\n",
        );
        for p in self.iter() {
            s += &format!(
                "{:>11} {:>3} {:>2} {:>6} {:>6} {:>5} {:>6} {:>6} {:>6}  {:<11} {:?}\n",
                p.time_ns / 1_000,
                u8::from(p.cs),
                u8::from(p.cc),
                u8::from(p.hist_s),
                u8::from(p.hist_c),
                p.cnt_r,
                format!("{:.1}", f64::from(p.si) * self.clock_ns as f64 / 1e6),
                p.cnt_s,
                p.cnt_c,
                format!("{:?}", p.fig17),
                p.fig18
            );
        }
        s
    }
}

/// The recorder part of the bench: turns the core's key-off decisions into table rows and keeps
/// the rows of the current key-off period (for the period skip).
#[derive(Clone, Debug)]
pub struct Recorder {
    cnt_width: u8,
    pub log: PulseLog,
    /// Rows recorded since the last period boundary.
    in_period: u64,
}

impl Recorder {
    pub fn new(clock_ns: u64, cnt_width: u8) -> Recorder {
        Recorder {
            cnt_width,
            log: PulseLog::new(clock_ns),
            in_period: 0,
        }
    }

    /// After edge `k + 1`: one row when the drive interval unit made a key-off decision.
    pub fn edge(&mut self, k: u64, clock_ns: u64, internals: &Internals, after: &Outputs) {
        if internals.fig17 == Fig17::Idle {
            return;
        }
        let sx = |v: u16| pmu50_core::updown_counter_58cd::sext(v, self.cnt_width);
        self.log.push(PulseRow {
            tick: k + 1,
            time_ns: (k + 1) * clock_ns,
            cs: after.cs,
            cc: after.cc,
            hist_s: after.hist_s,
            hist_c: after.hist_c,
            cnt_r: after.cnt_r,
            si: after.si,
            cnt_s: sx(after.cnt_s),
            cnt_c: sx(after.cnt_c),
            fig17: internals.fig17,
            fig18: internals.fig18,
        });
        self.in_period += 1;
    }

    /// Rows recorded since the last call (called at each period boundary).
    pub fn take_period_count(&mut self) -> u64 {
        std::mem::take(&mut self.in_period)
    }
}
