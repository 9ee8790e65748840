//! `pmu50`: run PMU 50 scenarios, write GTKWave-ready waveforms, export HDL vectors, diff VCDs.
//!
//! Exit codes: 0 ok, 1 a check failed (or the waveforms differ), 2 bad input.

use clap::{Parser, Subcommand};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use pmu50::atomic_file::{self, Batch};
use pmu50::observers::refusals::RefusalWatch;
use pmu50::observers::vectors::VectorWriter;
use pmu50::observers::waveform::{Level, WaveFormat};
use pmu50::output::{
    choose_trace, dumped_ticks, estimate_run_bytes, human_bytes as human, output_paths,
    run_to_batch, run_to_batch_as, summary, FileOptions, RunError, TraceChoice,
};
use pmu50::scenario::{Scenario, Trace};
use pmu50::sim::{self, Observer, SimError, SimOptions, TickView};
use pmu50_core::Dur;
use pmu50_waves::diff::{diff_files, DiffOptions, Sample, XPolicy};
use pmu50_waves::reader::{ReadLimits, DEFAULT_MAX_FILE_BYTES};
use std::collections::BTreeMap;
use std::io::{BufWriter, IsTerminal, Write};
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

/// Set when stdout or stderr could not be written (closed pipe, full disk): the exit code is
/// then 2, and nothing panics.
static STREAM_FAILED: AtomicBool = AtomicBool::new(false);

/// `println!` that never panics: on a closed or full stdout the rest of the output is dropped
/// and the exit code becomes 2.
macro_rules! out {
    ($($t:tt)*) => {{
        if writeln!(std::io::stdout().lock(), $($t)*).is_err() {
            STREAM_FAILED.store(true, Ordering::Relaxed);
        }
    }};
}

/// `eprintln!` that never panics (see [`out!`]).
macro_rules! err {
    ($($t:tt)*) => {{
        if writeln!(std::io::stderr().lock(), $($t)*).is_err() {
            STREAM_FAILED.store(true, Ordering::Relaxed);
        }
    }};
}

// Default limit of one VCD (`--max-vcd-bytes`), with the other limits in pmu50::limits.
use pmu50::limits::DEFAULT_MAX_VCD_BYTES;

/// Bad command-line values.
#[derive(Debug, thiserror::Error)]
enum CliError {
    #[error("--window {which}: {source}")]
    WindowDur {
        which: &'static str,
        #[source]
        source: pmu50_core::config::DurParseError,
    },
    #[error(
        "--window {which}: {value} is not a whole number of ticks of {clock} (scenario {file})"
    )]
    WindowTicks {
        which: &'static str,
        value: Dur,
        clock: Dur,
        file: String,
    },
    #[error("--window: END ({end}) must be after START ({start})")]
    WindowOrder { start: Dur, end: Dur },
    #[error("--window {start} {end} is outside the run of {file} (0 to {duration}); valid is 0 <= START < END <= {duration}")]
    WindowOutside {
        start: Dur,
        end: Dur,
        duration: Dur,
        file: String,
    },
    #[error("{file}: the {} at trace = {} would be about {} ({ticks} dumped ticks), above the limit of {}; {}", format.ext().to_uppercase(), level.name(), human(*estimate), human(*limit), too_large_hint(*level, *format))]
    VcdTooLarge {
        file: String,
        ticks: u64,
        estimate: u64,
        limit: u64,
        level: Level,
        format: WaveFormat,
    },
    #[error("{} would be written by two scenarios: {first} and {second} (both are named `{name}`); give one of them another `name`", path.display())]
    SameOutput {
        path: PathBuf,
        first: String,
        second: String,
        name: String,
    },
}

/// What to do about a waveform over the limit: the smaller choices the run has not taken.
fn too_large_hint(level: Level, format: WaveFormat) -> String {
    let mut ways = vec!["dump part of the run with --window START END".to_string()];
    if level > Level::Ports {
        ways.push("trace fewer signals with --trace ports (or none)".into());
    } else {
        ways.push("write the summary only with --trace none".into());
    }
    if format == WaveFormat::Vcd {
        ways.push("write the compressed --format fst".into());
    }
    format!(
        "{}, or raise the limit with --max-vcd-bytes",
        ways.join(", ")
    )
}

#[derive(Parser)]
#[command(
    name = "pmu50",
    version,
    about = "Cycle-accurate reference model of PMU 50 (US 2022/0041215 A1)"
)]
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
        /// Refuse a scenario whose waveform would be larger than this (bytes; default 2 GB;
        /// estimated for its trace level and format).
        #[arg(long, value_name = "BYTES")]
        max_vcd_bytes: Option<u64>,
        /// Refuse a scenario with more than this many simulated key-on ticks (default 1e9;
        /// parked ticks, which the exact skip removes, do not count).
        #[arg(long, value_name = "TICKS")]
        max_ticks: Option<u64>,
        /// Also write <name>.svg, a timing diagram in the style of FIG. 15/16 (and <name>_timing.csv).
        #[arg(long)]
        svg: bool,
        /// What to write besides the summary: ports (the core's inputs and outputs and the
        /// analog env values), registers (ports and every register), all (registers and the
        /// internals), each with its save file and --log/--svg on request, or none (summary
        /// only; repeated key-off periods are then skipped, docs/spec.md 5.1).
        /// Default: the scenario's `[vcd] trace`, else all when a waveform of every signal
        /// is estimated within 256 MiB, else ports.
        #[arg(long, value_parser = pmu50::scenario::TRACE_WORDS)]
        trace: Option<String>,
        /// Waveform format: vcd (text) or fst (compressed, for long runs; GTKWave and Surfer
        /// read it, and so does `pmu50 diff`). The .gtkw save file points at the file written.
        #[arg(long, value_parser = ["vcd", "fst"], default_value = "vcd")]
        format: String,
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
        /// Vector file to write (`-`: standard output).
        #[arg(short, long)]
        output: PathBuf,
        /// Also write the model's VCD into this folder (same run).
        #[arg(long)]
        vcd_dir: Option<PathBuf>,
        /// Refuse a vector file larger than this (bytes; default 2 GB; one line per tick).
        #[arg(long, value_name = "BYTES")]
        max_vector_bytes: Option<u64>,
    },
    /// Write a seeded random scenario (for co-simulation).
    Random {
        #[arg(long)]
        seed: u64,
        /// The scenario `pmu50 regress` runs for this seed (uniform random; a directed seed
        /// also depends on the coverage before it: its repro is in failures/ of its run).
        #[arg(long)]
        regress: bool,
        /// Scenario file to write (`-`: standard output).
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
        /// Refuse a sweep of more speeds than this (default 2000).
        #[arg(long, value_name = "N")]
        max_points: Option<u64>,
        /// Refuse a sweep that would simulate more ticks than this (default 1e9).
        #[arg(long, value_name = "TICKS")]
        max_ticks: Option<u64>,
    },
    /// Key-off battery budget of a park: adaptive, fixed cycle T = x, sensor always on.
    /// Writes budget.csv, budget_cumulative.csv and budget.svg (docs/power.md).
    Budget {
        scenario: PathBuf,
        #[arg(long, default_value = "vcd_out")]
        out_dir: PathBuf,
        /// Refuse a scenario whose simulations (adaptive, fixed, fixed at min) would take more
        /// than this many key-on ticks together (default 1e9; parked ticks do not count).
        #[arg(long, value_name = "TICKS")]
        max_ticks: Option<u64>,
    },
    /// Random regression: seeds of generated scenarios checked on the model (and an RTL),
    /// measured by functional coverage, failures shrunk to a repro (docs/verification.md).
    /// Exit 0 every seed passed, 1 a seed failed (or seeds are missing), 2 bad input.
    Regress {
        /// First seed [default: 1].
        #[arg(long)]
        start_seed: Option<u64>,
        /// Number of seeds (the whole regression; a shard runs its part of it), at most 10^7.
        #[arg(long)]
        iterations: Option<u64>,
        /// Parallel jobs (default: every core).
        #[arg(long)]
        jobs: Option<usize>,
        /// Bias the generator towards coverage bins not hit yet (deterministic per seed range).
        #[arg(long)]
        directed: bool,
        /// Also step the readable per-block model beside the kernel and compare every register
        /// after every edge.
        #[arg(long)]
        check_spec: bool,
        /// Design under test: the model alone, or an RTL on verilator (lockstep) or icarus
        /// (vector replay), compared with the model on every seed.
        /// [default: model]
        #[arg(long, value_parser = ["model", "verilator", "icarus"])]
        dut: Option<String>,
        /// The RTL's Verilog file list (paths relative to the list's folder; top `pmu50` with the
        /// ports and parameters of docs/signals.md). Default: the twin, hdl/pmu50.f.
        #[arg(long, value_name = "FILELIST")]
        rtl: Option<PathBuf>,
        /// Also compare the RTL's registers and internals that this TOML map names (model name
        /// = hierarchical RTL name; `pmu50 rtl-map` proposes one). Default: the ports only.
        #[arg(long, value_name = "FILE.toml")]
        map: Option<PathBuf>,
        /// Hold SYNC_DEPTH (1-4) for every seed, e.g. for an RTL built for one configuration.
        #[arg(long, value_parser = clap::value_parser!(u8).range(1..=4))]
        sync_depth: Option<u8>,
        /// Hold CNT_W (2-16) for every seed.
        #[arg(long, value_parser = clap::value_parser!(u8).range(2..=16))]
        cnt_width: Option<u8>,
        /// Run part I of N of the seed range (job arrays). Inside a Slurm array or a Kubernetes
        /// Indexed Job the part comes from SLURM_ARRAY_TASK_ID / JOB_COMPLETION_INDEX.
        #[arg(long, value_name = "I/N")]
        shard: Option<String>,
        /// The number of shards, where the scheduler gives only the index (JOB_COMPLETION_INDEX).
        #[arg(long, value_name = "N")]
        shard_count: Option<u64>,
        /// Continue the regression in DIR: run only the seeds its results.jsonl does not have.
        /// Its seed range, DUT and options are those of DIR/regress.json.
        #[arg(long, value_name = "DIR", conflicts_with_all = ["start_seed", "iterations", "shard", "shard_count", "directed", "check_spec", "dut", "rtl", "map", "repro", "sync_depth", "cnt_width", "out", "code_coverage", "waivers"])]
        resume: Option<PathBuf>,
        /// Measure the RTL's code coverage (Verilator line and toggle coverage; --dut verilator):
        /// code/coverage.dat, code/lcov.info, code/summary.json and a section of report.html.
        #[arg(long, conflicts_with = "repro")]
        code_coverage: bool,
        /// The waivers of the code coverage (TOML, docs/verification.md). Default: the twin's
        /// hdl/coverage-waivers.toml for the twin, none for another RTL.
        #[arg(long, value_name = "FILE.toml", requires = "code_coverage")]
        waivers: Option<PathBuf>,
        /// Output folder [default: regress_out].
        #[arg(long)]
        out: Option<PathBuf>,
        /// Per-seed time limit for the DUT, seconds.
        #[arg(long, default_value_t = 120.0)]
        timeout: f64,
        /// Do not shrink failures into failures/<signature>/.
        #[arg(long)]
        no_triage: bool,
        /// Check one scenario file (a shrunk repro) the way a seed is checked; prints the failure.
        #[arg(long, value_name = "FILE.toml", conflicts_with_all = ["iterations", "shard", "shard_count", "directed"])]
        repro: Option<PathBuf>,
    },
    /// Mutation score of the directed regression: for each mutant of hdl/mutants.txt, the
    /// directed seeds (`regress --directed --dut verilator --map hdl/pmu50.map.toml`) checked in
    /// order on the twin built with the mutant's define, up to the first failure
    /// (docs/verification.md). Writes DIR/mutation.json and mutation.txt. Exit 0 every mutant
    /// caught or proven equivalent, 1 one escaped (or could not be checked), 2 bad input.
    Mutation {
        /// Directed seeds per mutant.
        #[arg(long, default_value_t = 400)]
        iterations: u64,
        /// First seed.
        #[arg(long, default_value_t = 1)]
        start_seed: u64,
        /// Mutants checked at once (default: every core).
        #[arg(long)]
        jobs: Option<usize>,
        /// Only these mutants (comma-separated names).
        #[arg(long, value_delimiter = ',')]
        only: Vec<String>,
        /// The mutants' list [default: the kit's hdl/mutants.txt].
        #[arg(long, value_name = "FILE")]
        mutants: Option<PathBuf>,
        /// Output folder.
        #[arg(long, default_value = "regress_out/mutation")]
        out: PathBuf,
        /// Per-seed time limit for the DUT, seconds.
        #[arg(long, default_value_t = 120.0)]
        timeout: f64,
    },
    /// Propose a map (`regress --map`) for an RTL: its signals matched to the model's registers
    /// and internals by name and width, from Verilator's elaboration. Review and edit it.
    RtlMap {
        /// The RTL's Verilog file list (top `pmu50` with the contract ports).
        #[arg(long, value_name = "FILELIST")]
        rtl: PathBuf,
        /// Write the map here (default: standard output).
        #[arg(short, long)]
        output: Option<PathBuf>,
    },
    /// Verification method 2 on one vector file: the RTL (default the twin) built by Verilator
    /// and stepped in lockstep with the model on the file's inputs; every output port compared
    /// after every edge, and what a --map names. Prints the MISMATCH lines of the first
    /// divergent tick. Exit 0 equal, 1 a divergence, 2 bad input.
    Lockstep {
        /// The vector file (`pmu50 vectors`, docs/spec.md 6.2).
        file: PathBuf,
        /// The RTL's Verilog file list (default: the twin, hdl/pmu50.f).
        #[arg(long, value_name = "FILELIST")]
        rtl: Option<PathBuf>,
        /// Also compare the registers and internals this map names.
        #[arg(long, value_name = "FILE.toml")]
        map: Option<PathBuf>,
        /// A Verilog `define for the RTL (a mutant of hdl/mutants.txt), repeatable.
        #[arg(long = "define", value_name = "NAME")]
        defines: Vec<String>,
        /// Time limit, seconds.
        #[arg(long, default_value_t = 600.0)]
        timeout: f64,
        /// On a pass, also write the functional coverage of the run (the model sampled at
        /// every edge of the file's inputs) as a coverage.json, mergeable with `pmu50 merge`:
        /// a formal witness replayed through the RTL closes its bin.
        #[arg(long, value_name = "FILE.json")]
        coverage: Option<PathBuf>,
    },
    /// The HDL kit this binary carries (the twin, its file list and map, the mutants, the FuseSoC
    /// core, the testbenches, the scripts, the formal kit).
    Hdl {
        #[command(subcommand)]
        cmd: HdlCmd,
    },
    /// What the regression reads of an RTL, as JSON: the top's parameters, the values it fixes
    /// (read back through the bus after reset) and the contract check. Exit 2 on a bad RTL.
    RtlInfo {
        /// The RTL's Verilog file list (top `pmu50` with the contract ports).
        #[arg(long, value_name = "FILELIST")]
        rtl: PathBuf,
    },
    /// The DUT worker of `regress --dut verilator` (started by the regression itself): steps a
    /// Verilator library and the core in lockstep for each request on stdin.
    #[command(hide = true)]
    DutWorker,
    /// Merge regression folders (shards, resumed parts, adjacent seed ranges) and coverage.json
    /// files into one folder.
    /// Exit 0 complete and passing, 1 a seed failed or seeds are missing, 2 bad input.
    Merge {
        /// Output folder: a new folder, neither an input nor holding one.
        #[arg(long, default_value = "regress_out/merged")]
        out: PathBuf,
        /// Replace the files of an output folder that holds a regression already.
        #[arg(long)]
        force: bool,
        inputs: Vec<PathBuf>,
    },
    /// The sign-off table of a regression folder (docs/verification.md "Sign-off"): functional
    /// coverage of the reachable bins, bins proven unreachable and undecided, code line and
    /// toggle coverage, formal properties proven, seeds passing, each against its threshold
    /// (default 100 %, OpenTitan V3). Printed, written to DIR/signoff.json and at the top of
    /// DIR/report.html.
    /// Exit 0 every threshold met, 1 one missed, 2 bad input.
    Signoff {
        /// The regression folder.
        dir: PathBuf,
        /// TOML file with a table [thresholds]: functional, unreachable_proven, code_line,
        /// code_toggle, properties, seeds (percent) and undecided (a count); any subset.
        #[arg(long, value_name = "FILE.toml")]
        thresholds: Option<PathBuf>,
    },
    /// Draw the closure curves (coverage against seeds) of regression folders into one SVG.
    Closure {
        #[arg(short, long)]
        output: PathBuf,
        dirs: Vec<PathBuf>,
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
        #[arg(long = "x", value_name = "X", default_value = "strict")]
        x_policy: String,
        /// Report at most this many mismatches.
        #[arg(long, default_value_t = 20)]
        max: usize,
        /// Signals present on one side only do not count as a difference.
        #[arg(long)]
        allow_unmatched: bool,
        /// Absolute tolerance for real values.
        #[arg(long, default_value_t = 0.0)]
        real_tol: f64,
        /// Refuse (exit 2) a file larger than this many bytes (default 2 GiB).
        #[arg(long, default_value_t = DEFAULT_MAX_FILE_BYTES)]
        max_bytes: u64,
    },
}

#[derive(Subcommand)]
enum HdlCmd {
    /// Write the kit into DIR, for an HDL team to take into its own repository. Refuses a DIR
    /// that holds files unless --force.
    Export {
        dir: PathBuf,
        #[arg(long)]
        force: bool,
    },
    /// Write the coverage model as a Verilog monitor: DIR/pmu50_cov.sv (module pmu50_cov, one
    /// hit_<bin> wire per bin), DIR/pmu50_cov_top.sv (the twin with the monitor bound to it) and
    /// DIR/pmu50_cov.json (the bins and their wires); and the top's contract
    /// DIR/pmu50_contract.json (its ports and parameters). The repository keeps them in
    /// hdl/formal.
    CoverageMonitor {
        /// Folder to write into (made if missing).
        #[arg(long, default_value = "hdl/formal")]
        dir: PathBuf,
        /// Write nothing: exit 1 if a file in DIR differs from what would be written.
        #[arg(long)]
        check: bool,
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

fn load(p: &Path) -> Result<Scenario, ExitCode> {
    Scenario::load(p).map_err(|e| {
        err!("error: {e}");
        ExitCode::from(2)
    })
}

/// `--window START END` in ticks of `sc`, within the run.
fn window_ticks(sc: &Scenario, w: &Option<Vec<String>>) -> Result<Option<(u64, u64)>, CliError> {
    let Some(w) = w else { return Ok(None) };
    let clk = sc.clock_ns();
    let mut t = [0u64; 2];
    for (i, s) in w.iter().enumerate().take(2) {
        let which = if i == 0 { "START" } else { "END" };
        let d = Dur::parse(s).map_err(|source| CliError::WindowDur { which, source })?;
        if d.0 % clk != 0 {
            return Err(CliError::WindowTicks {
                which,
                value: d,
                clock: Dur(clk),
                file: sc.path.display().to_string(),
            });
        }
        t[i] = d.0 / clk;
    }
    if t[1] <= t[0] {
        return Err(CliError::WindowOrder {
            start: Dur(t[0] * clk),
            end: Dur(t[1] * clk),
        });
    }
    if t[1] > sc.ticks {
        return Err(CliError::WindowOutside {
            start: Dur(t[0] * clk),
            end: Dur(t[1] * clk),
            duration: Dur(sc.ticks * clk),
            file: sc.path.display().to_string(),
        });
    }
    Ok(Some((t[0], t[1])))
}

/// Refuse a run whose waveform (of `level`, in `format`) would exceed the limit.
fn check_vcd_size(
    sc: &Scenario,
    window: Option<(u64, u64)>,
    level: Level,
    format: WaveFormat,
    max: Option<u64>,
) -> Result<(), CliError> {
    let ticks = dumped_ticks(sc, window);
    let estimate = estimate_run_bytes(sc, window, level, format);
    let limit = max.unwrap_or(DEFAULT_MAX_VCD_BYTES);
    if estimate > limit {
        return Err(CliError::VcdTooLarge {
            file: sc.path.display().to_string(),
            ticks,
            estimate,
            limit,
            level,
            format,
        });
    }
    Ok(())
}

fn with_streams(code: u8) -> ExitCode {
    if STREAM_FAILED.load(Ordering::Relaxed) {
        ExitCode::from(code.max(2))
    } else {
        ExitCode::from(code)
    }
}

fn main() -> ExitCode {
    // clap's own printing ignores a full or closed stream; print its help and errors ourselves.
    let cli = match Cli::try_parse() {
        Ok(c) => c,
        Err(e) => {
            use clap::error::ErrorKind;
            let text = e.render().to_string();
            return match e.kind() {
                ErrorKind::DisplayHelp | ErrorKind::DisplayVersion => {
                    out!("{}", text.trim_end());
                    with_streams(0)
                }
                _ => {
                    err!("{}", text.trim_end());
                    with_streams(2)
                }
            };
        }
    };
    if let Err(e) = atomic_file::sync_to_disk() {
        err!("error: {e}");
        return with_streams(2);
    }
    if let Err(e) = atomic_file::install_signal_cleanup() {
        err!("error: cannot install the SIGINT/SIGTERM handler that removes temporary files: {e}");
        return with_streams(2);
    }
    let code = match cli.cmd {
        Cmd::Run {
            scenarios,
            out_dir,
            log,
            window,
            max_vcd_bytes,
            max_ticks,
            svg,
            trace,
            format,
        } => {
            let trace = trace.as_deref().and_then(Trace::parse);
            let format = WaveFormat::parse(&format).unwrap_or_default();
            cmd_run(
                &scenarios,
                &out_dir,
                RunFlags {
                    log,
                    svg,
                    trace,
                    format,
                    max_ticks,
                },
                &window,
                max_vcd_bytes,
            )
        }
        Cmd::Check { scenarios } => {
            let mut bad = false;
            if scenarios.is_empty() {
                err!("error: check needs at least one scenario file");
                bad = true;
            }
            for p in &scenarios {
                match Scenario::load(p) {
                    Ok(sc) => out!("ok   {} ({}, {} ticks)", p.display(), sc.name, sc.ticks),
                    Err(e) => {
                        err!("error: {e}");
                        bad = true;
                    }
                }
            }
            if bad {
                2
            } else {
                0
            }
        }
        Cmd::List { dir } => {
            let mut files: Vec<PathBuf> = match std::fs::read_dir(&dir) {
                Ok(rd) => rd
                    .filter_map(|e| e.ok().map(|e| e.path()))
                    .filter(|p| p.extension().is_some_and(|x| x == "toml"))
                    .collect(),
                Err(e) => {
                    err!("error: {}: {e}", dir.display());
                    return with_streams(2);
                }
            };
            files.sort();
            for p in files {
                // Scenario::load refuses FIFOs, devices and folders before opening them.
                match Scenario::load(&p) {
                    Ok(sc) => out!(
                        "{:<18} {:>10}  {}",
                        sc.name,
                        Dur(sc.ticks * sc.clock_ns()).to_string(),
                        sc.description
                    ),
                    Err(e) => out!("{:<18} INVALID: {e}", p.display()),
                }
            }
            0
        }
        Cmd::Vectors {
            scenario,
            output,
            vcd_dir,
            max_vector_bytes,
        } => cmd_vectors(&scenario, &output, vcd_dir.as_deref(), max_vector_bytes),
        Cmd::Random {
            seed,
            regress,
            output,
        } => {
            let text = if regress {
                pmu50::regress::gen::Stimulus::generate(seed, &pmu50::regress::gen::Bias::uniform())
                    .to_toml(&format!("regress_{seed}"))
            } else {
                pmu50::random::random_scenario(seed)
            };
            // `-o -`: standard output (atomic_file::Sink); a device or a FIFO is refused.
            let r = atomic_file::Sink::open(&output).and_then(|mut f| {
                f.write_all(text.as_bytes())
                    .map_err(|source| atomic_file::OutputError::Write {
                        path: output.clone(),
                        source,
                    })?;
                let mut b = Batch::new();
                f.finish(&mut b)?;
                b.commit()
            });
            match r {
                Ok(()) => 0,
                Err(e) => {
                    err!("error: {e}");
                    2
                }
            }
        }
        Cmd::SpeedLimit {
            scenario,
            out_dir,
            step,
            from,
            to,
            no_grid,
            max_points,
            max_ticks,
        } => {
            let sc = match &scenario {
                Some(p) => Scenario::load(p),
                None => Scenario::parse(
                    "duration = \"1 ms\"\n",
                    "<defaults>",
                    "defaults",
                    Path::new(""),
                ),
            };
            match sc {
                Ok(sc) => report(pmu50::analysis::speed::run_cli(
                    &sc, &out_dir, step, from, to, !no_grid, max_points, max_ticks,
                )),
                Err(e) => {
                    err!("error: {e}");
                    2
                }
            }
        }
        Cmd::Budget {
            scenario,
            out_dir,
            max_ticks,
        } => match Scenario::load(&scenario) {
            Ok(sc) => {
                match pmu50::limits::check_ticks(&sc, pmu50::analysis::budget::RUNS, max_ticks) {
                    Ok(()) => report(pmu50::analysis::budget::run_cli(&sc, &out_dir)),
                    Err(e) => {
                        err!("error: {e}");
                        2
                    }
                }
            }
            Err(e) => {
                err!("error: {e}");
                2
            }
        },
        Cmd::Regress {
            start_seed,
            iterations,
            jobs,
            directed,
            check_spec,
            dut,
            rtl,
            map,
            sync_depth,
            cnt_width,
            shard,
            shard_count,
            resume,
            code_coverage,
            waivers,
            out,
            timeout,
            no_triage,
            repro,
        } => {
            let pins = pmu50::regress::gen::Pins {
                sync_depth,
                cnt_width,
            };
            cmd_regress(RegressArgs {
                start_seed,
                iterations,
                jobs,
                directed,
                check_spec,
                dut,
                rtl,
                map,
                pins,
                shard,
                shard_count,
                resume,
                code_coverage,
                waivers,
                out,
                timeout,
                no_triage,
                repro,
            })
        }
        Cmd::Closure { output, dirs } => {
            match pmu50::regress::report::closure_cli(&dirs, &output) {
                Ok(text) => {
                    out!("{}", text.trim_end());
                    0
                }
                Err(e) => {
                    err!("error: {e}");
                    2
                }
            }
        }
        Cmd::DutWorker => pmu50::regress::lockstep::worker_main() as u8,
        Cmd::RtlMap { rtl, output } => cmd_rtl_map(&rtl, output.as_deref()),
        Cmd::Mutation {
            iterations,
            start_seed,
            jobs,
            only,
            mutants,
            out,
            timeout,
        } => cmd_mutation(iterations, start_seed, jobs, only, mutants, out, timeout),
        Cmd::Hdl {
            cmd: HdlCmd::Export { dir, force },
        } => {
            if let Some(kind) = pmu50::atomic_file::special_kind(&dir) {
                err!("error: {}: is {kind}, not a folder", dir.display());
                2
            } else if dir.exists() && !dir.is_dir() {
                err!("error: {}: is a file, not a folder", dir.display());
                2
            } else if !force
                && std::fs::read_dir(&dir)
                    .map(|mut d| d.next().is_some())
                    .unwrap_or(false)
            {
                err!("error: {}: the folder holds files; give --force to write the kit into it (files of the kit are replaced, others kept)", dir.display());
                2
            } else {
                match pmu50::hdl_kit::write(&dir) {
                    Ok(n) => {
                        out!("wrote the HDL kit ({n} files) into {}: the twin (pmu50.f), its map, the testbenches, the FuseSoC core pmu50.core, the formal kit", dir.display());
                        0
                    }
                    Err(e) => {
                        err!("error: {e}");
                        2
                    }
                }
            }
        }
        Cmd::Hdl {
            cmd: HdlCmd::CoverageMonitor { dir, check },
        } => cmd_coverage_monitor(&dir, check),
        Cmd::Lockstep {
            file,
            rtl,
            map,
            defines,
            timeout,
            coverage,
        } => cmd_lockstep(
            &file,
            rtl.as_deref(),
            map.as_deref(),
            &defines,
            timeout,
            coverage.as_deref(),
        ),
        Cmd::RtlInfo { rtl } => match pmu50::regress::dut::verilator::VerilatorDut::prepare(
            &rtl,
            None,
            Default::default(),
        ) {
            Ok(d) => {
                use pmu50::regress::dut::Dut;
                let fixed: serde_json::Map<String, serde_json::Value> = d
                    .fixed()
                    .values
                    .iter()
                    .map(|(n, v)| (n.clone(), serde_json::Value::from(*v)))
                    .collect();
                let info = serde_json::json!({ "rtl": rtl.display().to_string(), "parameters": d.top_param_names(), "fixed": fixed, "contract": "ok" });
                out!(
                    "{}",
                    serde_json::to_string_pretty(&info).unwrap_or_default()
                );
                0
            }
            Err(e) => {
                err!("error: {e}");
                2
            }
        },
        Cmd::Signoff { dir, thresholds } => {
            match pmu50::regress::signoff::run(&dir, thresholds.as_deref()) {
                Ok(so) => {
                    out!("{}", so.text().trim_end());
                    u8::from(!so.met())
                }
                Err(e) => {
                    err!("error: {e}");
                    2
                }
            }
        }
        Cmd::Merge { out, force, inputs } => {
            match pmu50::regress::merge::merge(&inputs, &out, force) {
                Ok(m) => {
                    out!(
                        "merged {} regression folder(s) and {} coverage file(s) into {}",
                        m.folders,
                        m.coverage_files,
                        out.display()
                    );
                    out!("{}", m.summary.text().trim_end());
                    if let Some(code) = &m.summary.code {
                        err!("{}", code.text().trim_end());
                    }
                    u8::from(m.summary.failed() > 0 || !m.summary.missing.is_empty())
                }
                Err(e) => {
                    err!("error: {e}");
                    2
                }
            }
        }
        Cmd::Diff {
            left,
            right,
            map,
            clock,
            every,
            x_policy,
            max,
            allow_unmatched,
            real_tol,
            max_bytes,
        } => cmd_diff(
            left,
            right,
            map,
            clock,
            every,
            x_policy,
            max,
            allow_unmatched,
            real_tol,
            max_bytes,
        ),
    };
    with_streams(code)
}

/// Print an analysis' text (exit 0) or its error (exit 2).
struct RegressArgs {
    start_seed: Option<u64>,
    iterations: Option<u64>,
    jobs: Option<usize>,
    directed: bool,
    check_spec: bool,
    dut: Option<String>,
    rtl: Option<PathBuf>,
    map: Option<PathBuf>,
    pins: pmu50::regress::gen::Pins,
    shard: Option<String>,
    shard_count: Option<u64>,
    resume: Option<PathBuf>,
    code_coverage: bool,
    waivers: Option<PathBuf>,
    out: Option<PathBuf>,
    timeout: f64,
    no_triage: bool,
    repro: Option<PathBuf>,
}

/// A regression's progress line, on a terminal.
fn progress_line(line: &str) {
    err!("{line}");
}

/// `pmu50 regress`.
fn cmd_regress(a: RegressArgs) -> u8 {
    use pmu50::regress::{self, DutKind, RunSpec};
    let fail = |m: String| {
        err!("error: {m}");
        2
    };
    if !(a.timeout.is_finite() && a.timeout > 0.0 && a.timeout <= 86_400.0) {
        return fail(format!(
            "--timeout {}: give the per-seed time limit in seconds, 0 < T <= 86400",
            a.timeout
        ));
    }
    let jobs = match a.jobs {
        Some(0) => return fail("--jobs 0: give at least 1 job".into()),
        Some(j) => j,
        None => std::thread::available_parallelism()
            .map(|n| n.get())
            .unwrap_or(1),
    };
    let dut_name = a.dut.clone().unwrap_or_else(|| "model".into());
    let dut = match dut_name.as_str() {
        "verilator" => DutKind::Verilator,
        "icarus" => DutKind::Icarus,
        _ => DutKind::Model,
    };
    if a.rtl.is_some() && dut == DutKind::Model {
        return fail("--rtl needs an RTL simulator: add --dut verilator (or --dut icarus)".into());
    }
    if a.code_coverage && dut != DutKind::Verilator {
        return fail(format!("--code-coverage measures the RTL's code with Verilator's line and toggle coverage: use --dut verilator (not {dut_name})"));
    }
    // the waivers of the code coverage: --waivers, or the twin's own
    let waivers = if a.code_coverage {
        let list = a
            .rtl
            .clone()
            .unwrap_or_else(|| pmu50::regress::dut::hdl_dir().join("pmu50.f"));
        let file = match (&a.waivers, &a.rtl) {
            (Some(w), _) => Some(w.clone()),
            (None, None) => Some(pmu50::regress::dut::hdl_dir().join("coverage-waivers.toml")),
            (None, Some(_)) => None,
        };
        match file {
            None => Some(regress::code_cov::Waivers::default()),
            Some(f) => {
                let files = match regress::rtl::FileList::read(&list) {
                    Ok(fl) => fl.files,
                    Err(e) => return fail(e.to_string()),
                };
                match regress::code_cov::Waivers::read(&f, Some(&files)) {
                    Ok(w) => Some(w),
                    Err(e) => return fail(e.to_string()),
                }
            }
        }
    } else {
        None
    };
    let rtl = match &a.rtl {
        Some(r) => match regress::rtl::FileList::read(r) {
            Ok(fl) => Some(fl.list.display().to_string()),
            Err(e) => return fail(e.to_string()),
        },
        None => None,
    };
    let map = match &a.map {
        Some(m) => match regress::map::RtlMap::read(m) {
            Ok(_) => Some(
                m.canonicalize()
                    .unwrap_or_else(|_| m.clone())
                    .display()
                    .to_string(),
            ),
            Err(e) => return fail(e.to_string()),
        },
        None => None,
    };
    let timeout = Duration::from_secs_f64(a.timeout);
    let model = pmu50_coverage::model_id(pmu50_coverage::layout());
    let tool = format!("pmu50 {}", env!("CARGO_PKG_VERSION"));

    if let Some(file) = &a.repro {
        let sc = match load(file) {
            Ok(sc) => sc,
            Err(_) => return 2,
        };
        let spec = RunSpec {
            tool,
            model,
            start_seed: 0,
            iterations: 0,
            directed: false,
            check_spec: a.check_spec,
            dut: dut.clone(),
            rtl,
            map,
            fixed: Default::default(),
            pins: a.pins,
            shard: None,
            code_coverage: false,
        };
        let d = match regress::dut::prepare(&spec) {
            Ok(d) => d,
            Err(e) => return fail(e.to_string()),
        };
        if !d.fixed().holds(&sc.params) {
            return fail(format!("{}: the RTL fixes {} (its top lacks these parameters), the scenario has other values", file.display(), d.fixed().text()));
        }
        return match regress::check_scenario(&spec, &sc, d.as_ref(), timeout) {
            Ok(None) => {
                out!(
                    "PASS {}: the model's checks{} hold",
                    file.display(),
                    if dut == DutKind::Model {
                        String::new()
                    } else {
                        format!(" and the {dut_name} DUT")
                    }
                );
                0
            }
            Ok(Some(f)) => {
                out!(
                    "FAIL {}: tick {} {} expected {} got {} (block {}, FIG. path {})\n  {}",
                    file.display(),
                    f.tick,
                    f.signal,
                    f.expected,
                    f.got,
                    f.block,
                    f.fig,
                    f.detail
                );
                1
            }
            Err(e) => fail(format!("{}: {e}", file.display())),
        };
    }

    let (spec, resume) = match &a.resume {
        Some(dir) => match regress::read_spec(dir) {
            Ok(s) => (s, true),
            Err(e) => return fail(e.to_string()),
        },
        None => {
            let Some(iterations) = a.iterations else {
                return fail(
                    "regress needs --iterations N (or --resume DIR, or --repro FILE)".into(),
                );
            };
            let start_seed = a.start_seed.unwrap_or(1);
            if iterations == 0 {
                return fail("--iterations 0: give at least one seed".into());
            }
            if iterations > regress::folder::MAX_SEEDS {
                return fail(format!("--iterations {iterations}: at most {} seeds make one regression; split a larger range into regressions of adjacent seed ranges (--start-seed), which pmu50 merge joins", regress::folder::MAX_SEEDS));
            }
            if start_seed.checked_add(iterations).is_none() {
                return fail(format!("--start-seed {start_seed} --iterations {iterations}: the seed range passes 2^64"));
            }
            let shard =
                match regress::shard::Shard::resolve(a.shard.as_deref(), a.shard_count, |k| {
                    std::env::var(k).ok()
                }) {
                    Ok(s) => s,
                    Err(e) => return fail(e),
                };
            if a.directed && shard.is_some() {
                return fail("--directed steers each batch by the coverage of the seeds before it, which another shard runs: run a directed regression in one process, or shard a random one".into());
            }
            (
                RunSpec {
                    tool,
                    model,
                    start_seed,
                    iterations,
                    directed: a.directed,
                    check_spec: a.check_spec,
                    dut,
                    rtl,
                    map,
                    fixed: Default::default(),
                    pins: a.pins,
                    shard,
                    code_coverage: a.code_coverage,
                },
                false,
            )
        }
    };
    let out_dir = a
        .resume
        .clone()
        .or(a.out.clone())
        .unwrap_or_else(|| PathBuf::from("regress_out"));
    // The DUT before any seed: an RTL that does not elaborate, lacks a contract port or does not
    // build is bad input (exit 2), and what it fixes goes into the run's record.
    let t0 = Instant::now();
    let mut spec = spec;
    let d = match regress::dut::prepare(&spec) {
        Ok(d) => d,
        Err(e) => return fail(e.to_string()),
    };
    if resume && spec.fixed != *d.fixed() {
        return fail(format!("--resume {}: the regression was run on an RTL that fixes {}, this RTL fixes {}: the RTL changed", out_dir.display(), if spec.fixed.is_empty() { "nothing".into() } else { spec.fixed.text() }, if d.fixed().is_empty() { "nothing".into() } else { d.fixed().text() }));
    }
    spec.fixed = d.fixed().clone();
    for n in d.notes() {
        err!("regress: {n}");
    }
    let o = regress::Options {
        spec,
        jobs,
        out: out_dir.clone(),
        timeout,
        triage: !a.no_triage,
        progress: std::io::stderr()
            .is_terminal()
            .then_some(progress_line as fn(&str)),
        waivers,
    };
    let stop = AtomicBool::new(false);
    match regress::run(&o, resume, &stop, d.as_ref()) {
        Ok(s) => {
            out!("{}", s.text().trim_end());
            if let Some(code) = &s.code {
                err!("{}", code.text().trim_end());
            }
            out!(
                "wrote {}/results.jsonl, coverage.json, report.html{} ({:.1} s, {} jobs)",
                out_dir.display(),
                if s.code.is_some() {
                    ", code/coverage.dat, code/lcov.info, code/summary.json"
                } else {
                    ""
                },
                t0.elapsed().as_secs_f64(),
                jobs
            );
            u8::from(s.failed() > 0 || !s.missing.is_empty())
        }
        Err(e) => fail(e.to_string()),
    }
}

/// `pmu50 mutation`: the mutation table of the directed regression.
fn cmd_mutation(
    iterations: u64,
    start_seed: u64,
    jobs: Option<usize>,
    only: Vec<String>,
    mutants: Option<PathBuf>,
    out: PathBuf,
    timeout: f64,
) -> u8 {
    use pmu50::regress::mutation;
    if !(timeout.is_finite() && timeout > 0.0 && timeout <= 86_400.0) {
        err!("error: --timeout {timeout}: give the per-seed time limit in seconds, 0 < T <= 86400");
        return 2;
    }
    if jobs == Some(0) {
        err!("error: --jobs 0: give at least 1 job");
        return 2;
    }
    let hdl = pmu50::regress::dut::hdl_dir();
    let o = mutation::Options {
        mutants: mutants.unwrap_or_else(|| hdl.join("mutants.txt")),
        twin: hdl.join("pmu50.f"),
        map: Some(hdl.join("pmu50.map.toml")),
        start_seed,
        iterations,
        jobs: jobs.unwrap_or_else(|| {
            std::thread::available_parallelism()
                .map(|n| n.get())
                .unwrap_or(1)
        }),
        timeout: Duration::from_secs_f64(timeout),
        only,
        out: out.clone(),
    };
    let stop = AtomicBool::new(false);
    match mutation::run(&o, &stop, progress_line) {
        Ok(r) => {
            out!("{}", r.text().trim_end());
            out!("wrote {}/mutation.json, mutation.txt", out.display());
            u8::from(!r.ok())
        }
        Err(e) => {
            err!("error: {e}");
            2
        }
    }
}

/// `pmu50 lockstep`: method 2 on one vector file.
fn cmd_lockstep(
    file: &Path,
    rtl: Option<&Path>,
    map: Option<&Path>,
    defines: &[String],
    timeout: f64,
    coverage: Option<&Path>,
) -> u8 {
    use pmu50::regress::{dut::verilator::VerilatorDut, lockstep, map as m, rtl as r};
    let fail = |e: String| {
        err!("LOCKSTEP ERROR: {e}");
        2
    };
    if !(timeout.is_finite() && timeout > 0.0 && timeout <= 86_400.0) {
        return fail(format!("--timeout {timeout}: give seconds, 0 < T <= 86400"));
    }
    let v = match lockstep::read_vector_inputs(file) {
        Ok(v) => v,
        Err(e) => return fail(e),
    };
    let list = rtl
        .map(Path::to_path_buf)
        .unwrap_or_else(|| pmu50::regress::dut::hdl_dir().join("pmu50.f"));
    // defines: a file list with a file of `define lines first
    let scratch = match tempfile::tempdir() {
        Ok(d) => d,
        Err(e) => return fail(format!("a scratch folder: {e}")),
    };
    let list = if defines.is_empty() {
        list
    } else {
        if let Some(bad) = defines
            .iter()
            .find(|d| d.is_empty() || !d.chars().all(|c| c.is_ascii_alphanumeric() || c == '_'))
        {
            return fail(format!(
                "--define `{bad}`: a Verilog macro name (letters, digits, _)"
            ));
        }
        let fl = match r::FileList::read(&list) {
            Ok(fl) => fl,
            Err(e) => return fail(e.to_string()),
        };
        let defs: String = defines.iter().map(|d| format!("`define {d}\n")).collect();
        let body: String = std::iter::once(scratch.path().join("defines.vh"))
            .chain(fl.files.iter().cloned())
            .map(|f| format!("{}\n", f.display()))
            .collect();
        let mut batch = pmu50::atomic_file::Batch::new();
        let written =
            pmu50::atomic_file::write_atomic(&scratch.path().join("defines.vh"), defs.as_bytes())
                .map(|f| batch.add(f))
                .and_then(|()| {
                    pmu50::atomic_file::write_atomic(&scratch.path().join("rtl.f"), body.as_bytes())
                })
                .map(|f| batch.add(f))
                .and_then(|()| batch.commit());
        if written.is_err() {
            return fail("cannot write the file list with the defines".into());
        }
        scratch.path().join("rtl.f")
    };
    let map = match map.map(m::RtlMap::read).transpose() {
        Ok(m) => m,
        Err(e) => return fail(e.to_string()),
    };
    let d = match VerilatorDut::prepare(&list, map, Default::default()) {
        Ok(d) => d,
        Err(e) => return fail(e.to_string()),
    };
    let (nr, nx) = d.mapped_counts();
    match d.lockstep_inputs(&v.params, &v.inputs, Duration::from_secs_f64(timeout)) {
        Ok(lockstep::Answer::Reply(lockstep::Reply::Pass { ticks })) => {
            out!(
                "PASS ticks={ticks} outputs={} registers={nr} internals={nx} (scenario {})",
                pmu50_core::signals::N_OUTPUTS,
                v.scenario
            );
            if let Some(path) = coverage {
                let id = format!(
                    "lockstep/{}",
                    file.file_stem().unwrap_or_default().to_string_lossy()
                );
                let written = lockstep::model_coverage(&v)
                    .map_err(|e| format!("{}: {e}", file.display()))
                    .and_then(|c| {
                        let text = pmu50_coverage::db::of_run(&c, &id, "pass").to_text();
                        pmu50::atomic_file::write_atomic(path, text.as_bytes())
                            .and_then(|f| {
                                let mut b = pmu50::atomic_file::Batch::new();
                                b.add(f);
                                b.commit()
                            })
                            .map_err(|e| e.to_string())
                    });
                match written {
                    Ok(()) => out!("coverage: {} (run {id})", path.display()),
                    Err(e) => return fail(e),
                }
            }
            0
        }
        Ok(lockstep::Answer::Reply(lockstep::Reply::Diverged {
            tick,
            combinational,
            mismatches,
        })) => {
            for x in &mismatches {
                out!(
                    "MISMATCH tick={tick} signal={} expected={:x} got={:x}",
                    x.signal,
                    x.expected,
                    x.got
                );
            }
            let when = if combinational {
                format!("combinational, before rising edge {}", tick + 1)
            } else {
                format!("after rising edge {tick}")
            };
            out!("LOCKSTEP FAIL {} (scenario {}): first divergence at tick {tick} ({when}), time {} ns", file.display(), v.scenario, tick * v.clock_ns);
            1
        }
        Ok(lockstep::Answer::Reply(lockstep::Reply::Error { reason })) => fail(reason),
        Ok(lockstep::Answer::Reply(
            lockstep::Reply::Probe { .. } | lockstep::Reply::Trace { .. },
        )) => fail("the DUT worker answered another request".into()),
        Ok(lockstep::Answer::TimedOut) => {
            out!(
                "LOCKSTEP FAIL {} (scenario {}): the DUT did not finish within {timeout} s",
                file.display(),
                v.scenario
            );
            1
        }
        Ok(lockstep::Answer::Died(how)) => {
            out!(
                "LOCKSTEP FAIL {} (scenario {}): {how}",
                file.display(),
                v.scenario
            );
            1
        }
        Err(e) => fail(e.to_string()),
    }
}

/// `pmu50 rtl-map`: a proposed map for an RTL.
fn cmd_rtl_map(rtl: &Path, output: Option<&Path>) -> u8 {
    use pmu50::regress::{map, rtl as r};
    let go = || -> Result<String, String> {
        let fl = r::FileList::read(rtl).map_err(|e| e.to_string())?;
        let work = tempfile::tempdir().map_err(|e| format!("a scratch folder: {e}"))?;
        let d = r::elaborate(&fl, &[], work.path()).map_err(|e| e.to_string())?;
        let p = pmu50_core::Params::default();
        let s = pmu50_core::pmu50::Structural {
            sync_depth: d.param("SYNC_DEPTH").map_or(p.sync_depth, |v| v as u8),
            cnt_width: d.param("CNT_W").map_or_else(
                || d.port_width("cnt_s").map_or(p.cnt_width, |w| w as u8),
                |v| v as u8,
            ),
        };
        d.check_contract(&s).map_err(|e| e.to_string())?;
        let (m, props) = map::propose(&d, &s);
        Ok(map::proposal_toml(&m, &props))
    };
    match go() {
        Ok(text) => match output {
            Some(path) => {
                match pmu50::atomic_file::write_atomic(path, text.as_bytes()).and_then(|f| {
                    let mut b = pmu50::atomic_file::Batch::new();
                    b.add(f);
                    b.commit()
                }) {
                    Ok(()) => {
                        out!("wrote {}", path.display());
                        0
                    }
                    Err(e) => {
                        err!("error: {e}");
                        2
                    }
                }
            }
            None => {
                out!("{}", text.trim_end());
                0
            }
        },
        Err(e) => {
            err!("error: {e}");
            2
        }
    }
}

fn report(r: Result<String, pmu50::analysis::AnalysisError>) -> u8 {
    match r {
        Ok(text) => {
            out!("{}", text.trim_end());
            0
        }
        Err(e) => {
            err!("error: {e}");
            2
        }
    }
}

/// `pmu50 run`: load every file first; report every bad one; refuse two scenarios writing the
/// same file before anything runs; run the good ones; exit with the worst code.
/// The output flags of `pmu50 run`.
#[derive(Clone, Copy)]
struct RunFlags {
    log: bool,
    svg: bool,
    /// `--trace`, overriding each scenario's `[vcd] trace`.
    trace: Option<Trace>,
    /// `--format`: the waveform file's format.
    format: WaveFormat,
    /// `--max-ticks`: simulated key-on ticks (pmu50::limits).
    max_ticks: Option<u64>,
}

/// A scenario `run` will run: its dump window of `--window` (in ticks) and its trace level.
struct Planned {
    sc: Scenario,
    window: Option<(u64, u64)>,
    choice: TraceChoice,
}

fn cmd_run(
    scenarios: &[PathBuf],
    out_dir: &Path,
    flags: RunFlags,
    window: &Option<Vec<String>>,
    max_vcd_bytes: Option<u64>,
) -> u8 {
    let RunFlags { log, svg, .. } = flags;
    if scenarios.is_empty() {
        err!("error: run needs at least one scenario file (see `pmu50 list`)");
        return 2;
    }
    let mut code = 0u8;
    let mut good: Vec<Planned> = Vec::new();
    for p in scenarios {
        let sc = match Scenario::load(p) {
            Ok(s) => s,
            Err(e) => {
                err!("error: {e}");
                code = 2;
                continue;
            }
        };
        let window_flag = match window_ticks(&sc, window) {
            Ok(w) => w,
            Err(e) => {
                err!("error: {e}");
                code = 2;
                continue;
            }
        };
        if let Err(e) = pmu50::limits::check_ticks(&sc, 1, flags.max_ticks) {
            err!("error: {e}");
            code = 2;
            continue;
        }
        let choice = choose_trace(&sc, flags.trace, window_flag, flags.format);
        let Some(level) = choice.trace.level() else {
            if window.is_some() {
                err!("error: --window: {} is run with trace = none, which writes no waveform; drop --window or run it with --trace ports, registers or all", sc.path.display());
                code = 2;
            } else {
                good.push(Planned {
                    sc,
                    window: None,
                    choice,
                });
            }
            continue;
        };
        if let Err(e) = check_vcd_size(&sc, window_flag, level, flags.format, max_vcd_bytes) {
            err!("error: {e}");
            code = 2;
            continue;
        }
        good.push(Planned {
            sc,
            window: window_flag,
            choice,
        });
    }
    let mut owner: BTreeMap<PathBuf, usize> = BTreeMap::new();
    let mut clash = false;
    for (k, Planned { sc, .. }) in good
        .iter()
        .enumerate()
        .filter(|(_, p)| p.choice.trace.level().is_some())
    {
        for path in output_paths(out_dir, &sc.name, true) {
            if let Some(&j) = owner.get(&path) {
                let e = CliError::SameOutput {
                    path,
                    first: good[j].sc.path.display().to_string(),
                    second: sc.path.display().to_string(),
                    name: sc.name.clone(),
                };
                err!("error: {e}");
                clash = true;
                break;
            }
            owner.insert(path, k);
        }
    }
    if clash {
        err!("error: nothing was run");
        return 2;
    }
    for Planned { sc, window, choice } in &good {
        let mut prog = Progress::new(sc.ticks, &sc.name);
        let mut watch = RefusalWatch::new(sc);
        let Some(level) = choice.trace.level() else {
            match sim::run(sc, SimOptions::default(), &mut [&mut prog, &mut watch]) {
                Ok(res) => {
                    out!("{}", summary(sc, &res).trim_end());
                    for rw in &watch.refused {
                        out!("   refused write {rw}");
                    }
                    out!("   trace = none: no waveform, log or timing diagram written; {} of {} ticks evaluated, the rest skipped exactly (docs/spec.md 5.1)", res.evaluated_ticks, res.ticks);
                    if !res.passed() || !watch.refused.is_empty() {
                        code = code.max(1);
                    }
                }
                Err(e) => {
                    err!("error: {e}");
                    code = 2;
                }
            }
            continue;
        };
        let r = run_to_batch_as(
            sc,
            out_dir,
            FileOptions {
                log,
                window: *window,
                svg,
                level,
            },
            flags.format,
            &mut [&mut prog, &mut watch],
        )
        .and_then(|(res, w, batch)| {
            batch.commit()?;
            Ok((res, w))
        });
        match r {
            Ok((res, w)) => {
                out!("{}", summary(sc, &res).trim_end());
                for rw in &watch.refused {
                    out!("   refused write {rw}");
                }
                out!("   {}", choice.describe(flags.format));
                out!(
                    "   wrote {} and {}{}",
                    w.vcd.display(),
                    w.gtkw.display(),
                    w.log
                        .map(|l| format!(" and {}", l.display()))
                        .unwrap_or_default()
                );
                if let Some(s) = &w.svg {
                    out!("   wrote {} and {}", s.svg.display(), s.csv.display());
                }
                if !res.passed() || !watch.refused.is_empty() {
                    code = code.max(1);
                }
            }
            Err(e) => {
                err!("error: {e}");
                code = 2;
            }
        }
    }
    code
}

/// `pmu50 hdl coverage-monitor`: the monitor generated from the coverage model.
fn cmd_coverage_monitor(dir: &Path, check: bool) -> u8 {
    let files = pmu50_coverage::monitor::files();
    if check {
        let stale: Vec<String> = files
            .iter()
            .filter(|(n, text)| std::fs::read_to_string(dir.join(n)).ok().as_deref() != Some(text))
            .map(|(n, _)| dir.join(n).display().to_string())
            .collect();
        if stale.is_empty() {
            out!("the coverage monitor in {} is up to date", dir.display());
            return 0;
        }
        err!(
            "the coverage monitor is stale: {} (run `pmu50 hdl coverage-monitor --dir {}`)",
            stale.join(", "),
            dir.display()
        );
        return 1;
    }
    if let Err(e) = std::fs::create_dir_all(dir) {
        err!("error: {}: cannot make the folder: {e}", dir.display());
        return 2;
    }
    // the three files renamed into place together
    let mut batch = pmu50::atomic_file::Batch::default();
    for (name, text) in &files {
        match pmu50::atomic_file::write_atomic(&dir.join(name), text.as_bytes()) {
            Ok(f) => batch.add(f),
            Err(e) => {
                err!("error: {e}");
                return 2;
            }
        }
    }
    if let Err(e) = batch.commit() {
        err!("error: {e}");
        return 2;
    }
    out!(
        "wrote the coverage monitor ({} bins) into {}: {}",
        pmu50_coverage::layout().bins.len(),
        dir.display(),
        files.map(|(n, _)| n).join(", ")
    );
    0
}

fn cmd_vectors(
    scenario: &Path,
    output: &Path,
    vcd_dir: Option<&Path>,
    max_vector_bytes: Option<u64>,
) -> u8 {
    let mut sc = match load(scenario) {
        Ok(s) => s,
        Err(_) => return 2,
    };
    if let Err(e) = pmu50::limits::check_vector_bytes(&sc, max_vector_bytes) {
        err!("error: {e}");
        return 2;
    }
    // The model VCD written beside the vectors is compared tick by tick with the RTL's:
    // it must cover the whole run, whatever window the scenario asks for.
    sc.vcd_window = None;
    if let Some(d) = vcd_dir {
        // Same folder and name (the folders compared once they exist).
        let same = |a: &Path, b: &Path| {
            a == b
                || (a.file_name() == b.file_name()
                    && matches!((a.parent().map(std::fs::canonicalize), b.parent().map(std::fs::canonicalize)), (Some(Ok(x)), Some(Ok(y))) if x == y))
        };
        if let Some(p) = output_paths(d, &sc.name, false)
            .into_iter()
            .find(|p| same(p, output))
        {
            err!("error: -o {} is also the model's {} written into --vcd-dir; choose another name for the vectors", output.display(), p.display());
            return 2;
        }
    }
    if atomic_file::same_file(scenario, output) {
        err!("error: -o {} is the scenario file itself; the vectors would overwrite it; choose another name", output.display());
        return 2;
    }
    let result = (|| -> Result<u64, RunError> {
        // `-o -`: standard output (atomic_file::Sink); a device or a FIFO is refused.
        let f = atomic_file::Sink::open(output)?;
        let mut vw = VectorWriter::new(BufWriter::new(f), &sc)?;
        let mut prog = Progress::new(sc.ticks, &sc.name);
        let (ticks, mut batch) = match vcd_dir {
            Some(d) => {
                let (r, _, b) =
                    run_to_batch(&sc, d, FileOptions::default(), &mut [&mut vw, &mut prog])?;
                (r.ticks, b)
            }
            None => (
                sim::run(
                    &sc,
                    SimOptions {
                        fast_forward: false,
                    },
                    &mut [&mut vw, &mut prog],
                )?
                .ticks,
                Batch::new(),
            ),
        };
        let f = vw
            .into_inner()
            .into_inner()
            .map_err(|e| atomic_file::OutputError::Write {
                path: output.to_path_buf(),
                source: e.into_error(),
            })?;
        f.finish(&mut batch)?;
        batch.commit()?;
        Ok(ticks)
    })();
    match result {
        Ok(ticks) if output.as_os_str() == "-" => {
            err!("wrote the vectors to standard output ({ticks} ticks)");
            0
        }
        Ok(ticks) => {
            out!("wrote {} ({} ticks)", output.display(), ticks);
            0
        }
        Err(e) => {
            err!("error: {e}");
            2
        }
    }
}

#[allow(clippy::too_many_arguments)]
fn cmd_diff(
    left: PathBuf,
    right: PathBuf,
    map: Vec<String>,
    clock: Option<String>,
    every: Option<u64>,
    x: String,
    max: usize,
    allow_unmatched: bool,
    real_tol: f64,
    max_bytes: u64,
) -> u8 {
    let mut prefix_map = Vec::new();
    for m in &map {
        match m.split_once('=') {
            Some((a, b)) if !a.is_empty() && !b.is_empty() => {
                prefix_map.push((a.to_string(), b.to_string()))
            }
            _ => {
                err!("error: --map {m}: expected LEFT=RIGHT, e.g. pmu50=tb_vectors.dut");
                return 2;
            }
        }
    }
    let x_policy = match x.as_str() {
        "strict" => XPolicy::Strict,
        "left" => XPolicy::LeftXIsWildcard,
        "either" => XPolicy::EitherXIsWildcard,
        other => {
            err!("error: --x {other}: valid are strict, left, either");
            return 2;
        }
    };
    let sample = match (clock, every) {
        (Some(c), _) => Sample::RisingEdge(c),
        (None, Some(0)) => {
            err!("error: --every must be at least 1");
            return 2;
        }
        (None, Some(n)) => Sample::Every(n),
        (None, None) => Sample::Changes,
    };
    let read_limits = ReadLimits {
        max_file_bytes: max_bytes,
        ..ReadLimits::default()
    };
    let opts = DiffOptions {
        prefix_map,
        sample,
        x_policy,
        max_reported: max,
        real_tolerance: real_tol,
        allow_unmatched,
        read_limits,
    };
    // The exit codes are the diff API's own (0 equal, 1 different, 2 bad input).
    match diff_files(&left, &right, &opts) {
        Ok(rep) => {
            out!("{}", rep.to_string().trim_end());
            rep.exit_code()
        }
        Err(e) => {
            err!("error: {e}");
            e.exit_code()
        }
    }
}
