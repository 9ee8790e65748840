//! Bounded work: what a command would do is estimated before it starts, and refused above a
//! default limit with the option that raises it, the way `run` bounds a waveform's size
//! ([`crate::output::estimate_run_bytes`], `--max-vcd-bytes`).
//!
//! | command | estimate | default limit | option |
//! |---|---|---|---|
//! | `run`, `vectors`, `budget` | simulated key-on ticks: every tick the exact skip of parked periods cannot remove ([`active_ticks`]), times the runs the command makes | 1 000 000 000 ticks | `--max-ticks` |
//! | `run` | waveform bytes ([`crate::output::estimate_run_bytes`]) | 2 GB | `--max-vcd-bytes` |
//! | `vectors` | vector file bytes ([`estimate_vector_bytes`]) | 2 GB | `--max-vector-bytes` |
//! | `speed-limit` | sweep points, counted without building them ([`crate::analysis::speed::SweepSpec::point_count`]) | 2000 | `--max-points` |
//!
//! Parked ticks (key off, shaft still) are skipped exactly with `--trace none`, and replayed in
//! a waveform: they do not count as key-on ticks, so a month of parking (`park_30d`) stays
//! allowed. A long run shows a progress bar on a terminal (stderr; never in captured output).

use crate::output::{human_bytes, parked_ticks};
use crate::scenario::Scenario;
use std::fmt;

/// Default of `--max-ticks`: 1e9 simulated key-on ticks (2.8 hours of key-on at the default
/// 10 us clock), about 90 s of CPU: `run --trace none` of 12 minutes of key-on (72 M ticks)
/// takes 6.2 s in the release build, 86 ns a tick. `budget` of an hour of key-on (three
/// simulations, 1.08e9 ticks, 170 s) is above it.
pub const DEFAULT_MAX_TICKS: u64 = 1_000_000_000;
/// Default of `run --max-vcd-bytes`: 2 GB (a waveform, [`crate::output::estimate_run_bytes`]).
pub const DEFAULT_MAX_VCD_BYTES: u64 = 2_000_000_000;
/// Default of `--max-vector-bytes`: 2 GB, as `--max-vcd-bytes`.
pub const DEFAULT_MAX_VECTOR_BYTES: u64 = 2_000_000_000;
/// Default of `speed-limit --max-points`: 2000 speeds (each one a simulation, from rest and steady).
pub const DEFAULT_MAX_POINTS: u64 = 2000;

/// What a limit counts.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Unit {
    Bytes,
    Ticks,
    Points,
}

/// Work above its limit: refused before it starts.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub struct TooMuch {
    /// what would be too large (`fig15a.toml: the vector file`)
    pub what: String,
    pub estimate: u64,
    pub limit: u64,
    pub unit: Unit,
    /// the option that raises the limit (`--max-ticks`)
    pub option: &'static str,
    /// smaller choices, if any (`dump part of the run with --window START END`)
    pub hint: String,
}

fn amount(n: u64, unit: Unit) -> String {
    match unit {
        Unit::Bytes => human_bytes(n),
        Unit::Ticks => format!("{n} ticks"),
        Unit::Points if n == u64::MAX => "more points than can be counted".to_string(),
        Unit::Points => format!("{n} points"),
    }
}

impl fmt::Display for TooMuch {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{} would be about {}, above the limit of {}; ",
            self.what,
            amount(self.estimate, self.unit),
            amount(self.limit, self.unit)
        )?;
        if !self.hint.is_empty() {
            write!(f, "{}, or ", self.hint)?;
        }
        write!(f, "raise the limit with {} N", self.option)
    }
}

/// `Err(TooMuch)` when `estimate` is above `limit` (default `default`).
pub fn check(
    what: impl Into<String>,
    estimate: u64,
    limit: Option<u64>,
    default: u64,
    unit: Unit,
    option: &'static str,
    hint: &str,
) -> Result<(), TooMuch> {
    let limit = limit.unwrap_or(default);
    if estimate > limit {
        return Err(TooMuch {
            what: what.into(),
            estimate,
            limit,
            unit,
            option,
            hint: hint.to_string(),
        });
    }
    Ok(())
}

/// Ticks of `sc` that are simulated one by one: every tick but the parked ones
/// ([`crate::output::parked_ticks`]), which the exact skip removes (`--trace none`) or replays.
pub fn active_ticks(sc: &Scenario) -> u64 {
    sc.ticks - parked_ticks(sc, 0, sc.ticks)
}

/// Refuse `runs` simulations of `sc` above `max` (`--max-ticks`) key-on ticks.
pub fn check_ticks(sc: &Scenario, runs: u64, max: Option<u64>) -> Result<(), TooMuch> {
    let est = active_ticks(sc).saturating_mul(runs);
    let what = if runs > 1 {
        format!(
            "{}: {runs} simulations of its key-on ticks",
            sc.path.display()
        )
    } else {
        format!("{}: the simulation of its key-on ticks", sc.path.display())
    };
    check(
        what,
        est,
        max,
        DEFAULT_MAX_TICKS,
        Unit::Ticks,
        "--max-ticks",
        "shorten the scenario's key-on time",
    )
}

/// Size of the vector file of `sc`: its header (at most 4 kB) and one line of
/// [`crate::observers::vectors::line_bytes`] per tick (the vectors skip nothing).
pub fn estimate_vector_bytes(sc: &Scenario) -> u64 {
    4096 + sc
        .ticks
        .saturating_mul(crate::observers::vectors::line_bytes(sc))
}

/// Refuse the vector file of `sc` above `max` (`--max-vector-bytes`).
pub fn check_vector_bytes(sc: &Scenario, max: Option<u64>) -> Result<(), TooMuch> {
    let what = format!(
        "{}: the vector file ({} lines)",
        sc.path.display(),
        sc.ticks
    );
    check(
        what,
        estimate_vector_bytes(sc),
        max,
        DEFAULT_MAX_VECTOR_BYTES,
        Unit::Bytes,
        "--max-vector-bytes",
        "export a shorter scenario",
    )
}

/// A progress bar on stderr for `total` steps, drawn only when stderr is a terminal and only
/// after the work has taken a second (so a short run never shows one and a captured output
/// never holds one).
pub fn progress_bar(total: u64, name: &str) -> indicatif::ProgressBar {
    use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
    use std::io::IsTerminal;
    let bar = ProgressBar::with_draw_target(Some(total), ProgressDrawTarget::hidden());
    if let Ok(style) = ProgressStyle::with_template("{msg} [{bar:40}] {percent}% eta {eta}") {
        bar.set_style(style.progress_chars("=> "));
    }
    bar.set_message(name.to_string());
    if std::io::stderr().is_terminal() {
        let b = bar.clone();
        // drawn from the first update after a second
        std::thread::spawn(move || {
            std::thread::sleep(std::time::Duration::from_secs(1));
            if !b.is_finished() {
                b.set_draw_target(ProgressDrawTarget::stderr());
            }
        });
    }
    bar
}

/// An observer moving `bar` to `offset` plus the tick of the run, every 8192 evaluated ticks
/// (a bar over several runs gives each its offset).
pub struct TickBar {
    bar: indicatif::ProgressBar,
    offset: u64,
    seen: u64,
}

impl TickBar {
    pub fn new(bar: &indicatif::ProgressBar, offset: u64) -> TickBar {
        TickBar {
            bar: bar.clone(),
            offset,
            seen: 0,
        }
    }
}

impl crate::sim::Observer for TickBar {
    fn tick(&mut self, v: &crate::sim::TickView<'_>) -> Result<(), crate::sim::SimError> {
        self.seen += 1;
        if self.seen.is_multiple_of(8192) {
            self.bar.set_position(self.offset + v.tick);
        }
        Ok(())
    }
    /// A progress bar is content with the ticks the bench evaluates (the skip stays exact).
    fn needs_every_tick(&self) -> bool {
        false
    }
    fn finish(&mut self, v: &crate::sim::TickView<'_>) -> Result<(), crate::sim::SimError> {
        self.bar.set_position(self.offset + v.tick);
        Ok(())
    }
}
