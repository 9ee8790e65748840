//! `pmu50`: run PMU 50 scenarios, write GTKWave-ready waveforms, export HDL vectors, diff VCDs.
//!
//! Exit codes: 0 ok, 1 a check failed (or the waveforms differ), 2 bad input.

use clap::{Parser, Subcommand};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use pmu50::output::{run_to_files, run_to_files_svg, summary, FileOptions};
use pmu50::scenario::Scenario;
use pmu50::sim::{self, Observer, SimError, SimOptions, TickView};
use pmu50::vectors::VectorWriter;
use pmu50_core::Dur;
use pmu50_waves::diff::{diff_files, DiffOptions, Outcome, Sample, XPolicy};
use std::io::{BufWriter, IsTerminal, Write};
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::{Duration, Instant};

/// `println!` that does not panic when stdout is a closed pipe (`pmu50 diff a b | head`): the
/// reader has gone, so the rest of the output is dropped.
macro_rules! out {
    ($($t:tt)*) => {{
        let _ = writeln!(std::io::stdout().lock(), $($t)*);
    }};
}

#[derive(Parser)]
#[command(name = "pmu50", version, about = "Cycle-accurate reference model of PMU 50 (US 2022/0041215 A1)")]
struct Cli {
    #[command(subcommand)]
    cmd: Cmd,
}

#[derive(Subcommand)]
enum Cmd {
    /// Run scenarios: writes <out-dir>/<name>.vcd and .gtkw, prints a summary.
    Run {
        scenarios: Vec<PathBuf>,
        /// Output folder.
        #[arg(long, default_value = "vcd_out")]
        out_dir: PathBuf,
        /// Also write <name>.log: one line per register change.
        #[arg(long)]
        log: bool,
        /// Dump only this time window, e.g. `--window "10 ms" "60 ms"`.
        #[arg(long, num_args = 2, value_names = ["START", "END"])]
        window: Option<Vec<String>>,
        /// Also write <name>.svg, a timing diagram in the style of FIG. 15/16 (and <name>_timing.csv).
        #[arg(long)]
        svg: bool,
    },
    /// Validate scenarios without running them.
    Check { scenarios: Vec<PathBuf> },
    /// List the scenarios in a folder.
    List {
        #[arg(default_value = "scenarios")]
        dir: PathBuf,
    },
    /// Export per-tick inputs and expected outputs for HDL testbenches (docs/spec.md 6.2).
    Vectors {
        scenario: PathBuf,
        #[arg(short, long)]
        output: PathBuf,
        /// Also write the model's VCD into this folder (same run).
        #[arg(long)]
        vcd_dir: Option<PathBuf>,
    },
    /// Write a seeded random scenario (for co-simulation).
    Random {
        #[arg(long)]
        seed: u64,
        #[arg(short, long)]
        output: PathBuf,
    },
    /// Sweep motor speeds and accelerations with the key off: highest speed tracked without a
    /// quadrant skip, against the analytic bound (docs/analysis.md). Writes speed_limit.csv/.svg
    /// and speed_limit_grid.csv/.svg (a grid of x, min, Cth).
    SpeedLimit {
        /// Scenario whose [core] and [env] are used (defaults when omitted).
        scenario: Option<PathBuf>,
        #[arg(long, default_value = "vcd_out")]
        out_dir: PathBuf,
        /// Speed sweep step, deg/s (default: 1.5 x the steady-state bound / 60, rounded).
        #[arg(long)]
        step: Option<f64>,
        /// First speed of the sweep, deg/s (default: one step).
        #[arg(long)]
        from: Option<f64>,
        /// Last speed of the sweep, deg/s (default: 1.5 x 90 deg / min).
        #[arg(long)]
        to: Option<f64>,
        /// Skip the grid of configurations (x, min, Cth).
        #[arg(long)]
        no_grid: bool,
    },
    /// Key-off battery budget of a park: adaptive, fixed cycle T = x, sensor always on.
    /// Writes budget.csv, budget_cumulative.csv and budget.svg (docs/power.md).
    Budget {
        scenario: PathBuf,
        #[arg(long, default_value = "vcd_out")]
        out_dir: PathBuf,
    },
    /// Compare two VCD files; exit 0 equal, 1 different, 2 bad input.
    Diff {
        left: PathBuf,
        right: PathBuf,
        /// Scope mapping LEFT=RIGHT, e.g. `pmu50=tb_vectors.dut` (repeatable).
        #[arg(long = "map")]
        map: Vec<String>,
        /// Compare only at rising edges of this one-bit signal (full path).
        #[arg(long, conflicts_with = "every")]
        clock: Option<String>,
        /// Compare only every N time units of the left file.
        #[arg(long)]
        every: Option<u64>,
        /// x handling: strict, left (x on the left matches anything), either.
        #[arg(long, default_value = "strict")]
        x: String,
        /// Report at most this many mismatches.
        #[arg(long, default_value_t = 20)]
        max: usize,
        /// Signals present on one side only do not count as a difference.
        #[arg(long)]
        allow_unmatched: bool,
        /// Absolute tolerance for real values.
        #[arg(long, default_value_t = 0.0)]
        real_tol: f64,
    },
}

/// Progress bar on stderr, shown only when stderr is a terminal and the run has taken a second.
struct Progress {
    bar: ProgressBar,
    start: Instant,
    shown: bool,
    tty: bool,
}

impl Progress {
    fn new(ticks: u64, name: &str) -> Progress {
        let bar = ProgressBar::with_draw_target(Some(ticks), ProgressDrawTarget::hidden());
        if let Ok(style) = ProgressStyle::with_template("{msg} [{bar:40}] {percent}% eta {eta}") {
            bar.set_style(style.progress_chars("=> "));
        }
        bar.set_message(name.to_string());
        Progress { bar, start: Instant::now(), shown: false, tty: std::io::stderr().is_terminal() }
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
    fn finish(&mut self, _: &TickView<'_>) -> Result<(), SimError> {
        self.bar.finish_and_clear();
        Ok(())
    }
}

fn load(p: &Path) -> Result<Scenario, ExitCode> {
    Scenario::load(p).map_err(|e| {
        eprintln!("error: {e}");
        ExitCode::from(2)
    })
}

fn window_ticks(sc: &Scenario, w: &Option<Vec<String>>) -> Result<Option<(u64, u64)>, String> {
    let Some(w) = w else { return Ok(None) };
    let clk = sc.clock_ns();
    let mut t = [0u64; 2];
    for (i, s) in w.iter().enumerate() {
        let d = Dur::parse(s).map_err(|e| format!("--window: {e}"))?;
        if d.0 % clk != 0 {
            return Err(format!("--window: {d} is not a whole number of ticks of {}", Dur(clk)));
        }
        t[i] = d.0 / clk;
    }
    if t[1] <= t[0] {
        return Err("--window: END must be after START".into());
    }
    Ok(Some((t[0], t[1])))
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    match cli.cmd {
        Cmd::Run { scenarios, out_dir, log, window, svg } => {
            if scenarios.is_empty() {
                eprintln!("error: run needs at least one scenario file (see `pmu50 list`)");
                return ExitCode::from(2);
            }
            let mut code = 0u8;
            for p in &scenarios {
                let sc = match load(p) {
                    Ok(s) => s,
                    Err(c) => return c,
                };
                let window = match window_ticks(&sc, &window) {
                    Ok(w) => w,
                    Err(e) => {
                        eprintln!("error: {e}");
                        return ExitCode::from(2);
                    }
                };
                let mut prog = Progress::new(sc.ticks, &sc.name);
                let fo = FileOptions { log, window };
                let ran = if svg {
                    run_to_files_svg(&sc, &out_dir, fo, &mut [&mut prog]).map(|(r, w, s)| (r, w, Some(s)))
                } else {
                    run_to_files(&sc, &out_dir, fo, &mut [&mut prog]).map(|(r, w)| (r, w, None))
                };
                match ran {
                    Ok((res, w, s)) => {
                        out!("{}", summary(&sc, &res).trim_end());
                        out!("   wrote {} and {}{}", w.vcd.display(), w.gtkw.display(), w.log.map(|l| format!(" and {}", l.display())).unwrap_or_default());
                        if let Some(s) = s {
                            out!("   wrote {} and {}", s.svg.display(), s.csv.display());
                        }
                        if !res.passed() {
                            code = code.max(1);
                        }
                    }
                    Err(e) => {
                        eprintln!("error: {e}");
                        return ExitCode::from(2);
                    }
                }
            }
            ExitCode::from(code)
        }
        Cmd::Check { scenarios } => {
            let mut bad = false;
            for p in &scenarios {
                match Scenario::load(p) {
                    Ok(sc) => out!("ok   {} ({}, {} ticks)", p.display(), sc.name, sc.ticks),
                    Err(e) => {
                        eprintln!("error: {e}");
                        bad = true;
                    }
                }
            }
            ExitCode::from(if bad { 2 } else { 0 })
        }
        Cmd::List { dir } => {
            let mut files: Vec<PathBuf> = match std::fs::read_dir(&dir) {
                Ok(rd) => rd.filter_map(|e| e.ok().map(|e| e.path())).filter(|p| p.extension().is_some_and(|x| x == "toml")).collect(),
                Err(e) => {
                    eprintln!("error: {}: {e}", dir.display());
                    return ExitCode::from(2);
                }
            };
            files.sort();
            for p in files {
                match Scenario::load(&p) {
                    Ok(sc) => out!("{:<18} {:>10}  {}", sc.name, Dur(sc.ticks * sc.clock_ns()).to_string(), sc.description),
                    Err(e) => out!("{:<18} INVALID: {e}", p.display()),
                }
            }
            ExitCode::SUCCESS
        }
        Cmd::Vectors { scenario, output, vcd_dir } => {
            let mut sc = match load(&scenario) {
                Ok(s) => s,
                Err(c) => return c,
            };
            // The model VCD written beside the vectors is compared tick by tick with the RTL's:
            // it must cover the whole run, whatever window the scenario asks for.
            sc.vcd_window = None;
            let f = match std::fs::File::create(&output) {
                Ok(f) => f,
                Err(e) => {
                    eprintln!("error: {}: {e}", output.display());
                    return ExitCode::from(2);
                }
            };
            let result = VectorWriter::new(BufWriter::new(f), &sc).and_then(|mut vw| match &vcd_dir {
                Some(d) => run_to_files(&sc, d, FileOptions::default(), &mut [&mut vw]).map(|r| r.0),
                None => sim::run(&sc, SimOptions { fast_forward: false }, &mut [&mut vw]),
            });
            match result {
                Ok(r) => {
                    out!("wrote {} ({} ticks)", output.display(), r.ticks);
                    ExitCode::SUCCESS
                }
                Err(e) => {
                    eprintln!("error: {e}");
                    ExitCode::from(2)
                }
            }
        }
        Cmd::Random { seed, output } => match std::fs::write(&output, pmu50::random::random_scenario(seed)) {
            Ok(()) => ExitCode::SUCCESS,
            Err(e) => {
                eprintln!("error: {}: {e}", output.display());
                ExitCode::from(2)
            }
        },
        Cmd::SpeedLimit { scenario, out_dir, step, from, to, no_grid } => {
            let sc = match &scenario {
                Some(p) => match load(p) {
                    Ok(s) => s,
                    Err(c) => return c,
                },
                None => match Scenario::parse("duration = \"1 ms\"\n", "<defaults>", "defaults", Path::new("")) {
                    Ok(s) => s,
                    Err(e) => {
                        eprintln!("error: {e}");
                        return ExitCode::from(2);
                    }
                },
            };
            match pmu50::analysis::speed::run_cli(&sc, &out_dir, step, from, to, !no_grid) {
                Ok(text) => {
                    out!("{}", text.trim_end());
                    ExitCode::SUCCESS
                }
                Err(e) => {
                    eprintln!("error: {e}");
                    ExitCode::from(2)
                }
            }
        }
        Cmd::Budget { scenario, out_dir } => {
            let sc = match load(&scenario) {
                Ok(s) => s,
                Err(c) => return c,
            };
            match pmu50::analysis::budget::run_cli(&sc, &out_dir) {
                Ok(text) => {
                    out!("{}", text.trim_end());
                    ExitCode::SUCCESS
                }
                Err(e) => {
                    eprintln!("error: {e}");
                    ExitCode::from(2)
                }
            }
        }
        Cmd::Diff { left, right, map, clock, every, x, max, allow_unmatched, real_tol } => {
            let mut prefix_map = Vec::new();
            for m in &map {
                match m.split_once('=') {
                    Some((a, b)) if !a.is_empty() && !b.is_empty() => prefix_map.push((a.to_string(), b.to_string())),
                    _ => {
                        eprintln!("error: --map {m}: expected LEFT=RIGHT, e.g. pmu50=tb_vectors.dut");
                        return ExitCode::from(2);
                    }
                }
            }
            let x_policy = match x.as_str() {
                "strict" => XPolicy::Strict,
                "left" => XPolicy::LeftXIsWildcard,
                "either" => XPolicy::EitherXIsWildcard,
                other => {
                    eprintln!("error: --x {other}: valid are strict, left, either");
                    return ExitCode::from(2);
                }
            };
            let sample = match (clock, every) {
                (Some(c), _) => Sample::RisingEdge(c),
                (None, Some(0)) => {
                    eprintln!("error: --every must be at least 1");
                    return ExitCode::from(2);
                }
                (None, Some(n)) => Sample::Every(n),
                (None, None) => Sample::Changes,
            };
            let opts = DiffOptions { prefix_map, sample, x_policy, max_reported: max, real_tolerance: real_tol, allow_unmatched };
            match diff_files(&left, &right, &opts) {
                Ok(rep) => {
                    out!("{}", rep.to_string().trim_end());
                    ExitCode::from(if rep.outcome == Outcome::Equal { 0 } else { 1 })
                }
                Err(e) => {
                    eprintln!("error: {e}");
                    ExitCode::from(2)
                }
            }
        }
    }
}
