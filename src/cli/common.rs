//! What several commands share: a progress bar, a file written atomically, a regression's
//! progress line, the checks of `--timeout` and `--jobs`.

use super::error::CliError;
use super::io::err;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use pmu50_testbench::atomic_file::{self, Batch};
use pmu50_testbench::sim::{Observer, SimError, TickView};
use std::io::IsTerminal;
use std::path::Path;
use std::time::{Duration, Instant};

/// Progress bar on stderr, shown only when stderr is a terminal and the run has taken a second.
pub struct Progress {
    bar: ProgressBar,
    start: Instant,
    shown: bool,
    tty: bool,
}

impl Progress {
    pub fn new(ticks: u64, name: &str) -> Progress {
        let bar = ProgressBar::with_draw_target(Some(ticks), ProgressDrawTarget::hidden());
        if let Ok(style) = ProgressStyle::with_template("{msg} [{bar:40}] {percent}% eta {eta}") {
            bar.set_style(style.progress_chars("=> "));
        }
        bar.set_message(name.to_string());
        Progress {
            bar,
            start: Instant::now(),
            shown: false,
            tty: std::io::stderr().is_terminal(),
        }
    }
}

impl Observer for Progress {
    fn tick(&mut self, v: &TickView<'_>) -> Result<(), SimError> {
        if v.tick.is_multiple_of(8192) {
            if self.tty && !self.shown && self.start.elapsed() > Duration::from_secs(1) {
                self.bar.set_draw_target(ProgressDrawTarget::stderr());
                self.shown = true;
            }
            self.bar.set_position(v.tick);
        }
        Ok(())
    }
    /// A progress bar is content with the ticks the bench evaluates.
    fn needs_every_tick(&self) -> bool {
        false
    }
    fn finish(&mut self, _: &TickView<'_>) -> Result<(), SimError> {
        self.bar.finish_and_clear();
        Ok(())
    }
}

/// A regression's progress line, on a terminal.
pub fn progress_line(line: &str) {
    err!("{line}");
}

/// `text` written to `path` atomically (a temporary file renamed into place).
pub fn write_file(path: &Path, text: &str) -> Result<(), CliError> {
    let f = atomic_file::write_atomic(path, text.as_bytes())?;
    let mut b = Batch::new();
    b.add(f);
    b.commit()?;
    Ok(())
}

/// `--timeout SECONDS` of a DUT: finite, above 0, at most a day.
pub fn timeout(seconds: f64) -> Result<Duration, CliError> {
    if seconds.is_finite() && seconds > 0.0 && seconds <= 86_400.0 {
        Ok(Duration::from_secs_f64(seconds))
    } else {
        Err(CliError::Usage(format!(
            "--timeout {seconds}: give the per-seed time limit in seconds, 0 < T <= 86400"
        )))
    }
}

/// `--jobs N` (default: every core); 0 is refused.
pub fn jobs(jobs: Option<usize>) -> Result<usize, CliError> {
    match jobs {
        Some(0) => Err(CliError::Usage("--jobs 0: give at least 1 job".into())),
        Some(j) => Ok(j),
        None => Ok(std::thread::available_parallelism()
            .map(|n| n.get())
            .unwrap_or(1)),
    }
}

/// Append a run's record to the history (`--history`, `PMU50_HISTORY`, else history.sqlite
/// beside the folder): a line on stderr says where; a history that cannot be written is a
/// warning, the run's own result stands.
pub fn record_history(given: Option<&str>, folder: &Path, r: &pmu50_verif::history::Record) {
    let Some(loc) = pmu50_verif::history::Location::choose(given, folder) else {
        return;
    };
    match pmu50_verif::history::append(&loc, r) {
        Ok(()) => super::io::err!("history: {} record appended to {}", r.kind, loc.text()),
        Err(e) => super::io::err!("warning: {e}: this run is not in the history"),
    }
}
