//! `pmu50`: run PMU 50 scenarios, write GTKWave-ready waveforms, export HDL vectors, diff
//! waveforms, and verify an RTL against the model (regressions, coverage, sign-off). One file per
//! command in `cli/`; each returns an [`cli::error::Outcome`] or a typed [`cli::error::CliError`],
//! and the exit code is decided here, once: 0 ok, 1 a check failed (or the waveforms differ),
//! 2 bad input.

mod cli;

use clap::{Parser, Subcommand};
use cli::error::Outcome;
use cli::io::{err, exit_code, out};
use pmu50_testbench::atomic_file;
use std::process::ExitCode;

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
    Run(cli::run::Args),
    /// Validate scenarios without running them.
    Check(cli::check::Args),
    /// List the scenarios in a folder.
    List(cli::list::Args),
    /// Export per-tick inputs and expected outputs for HDL testbenches (docs/spec.md 6.2).
    Vectors(cli::vectors::Args),
    /// Write a seeded random scenario (for co-simulation).
    Random(cli::random::Args),
    /// Sweep motor speeds and accelerations with the key off: highest speed tracked without a
    /// quadrant skip, against the analytic bound (docs/analysis.md). Writes speed_limit.csv/.svg
    /// and speed_limit_grid.csv/.svg (a grid of x, min, Cth).
    SpeedLimit(cli::speed_limit::Args),
    /// Key-off battery budget of a park: adaptive, fixed cycle T = x, sensor always on.
    /// Writes budget.csv, budget_cumulative.csv and budget.svg (docs/power.md).
    Budget(cli::budget::Args),
    /// Random regression: seeds of generated scenarios checked on the model (and an RTL),
    /// measured by functional coverage, failures shrunk to a repro (docs/verification.md).
    /// Exit 0 every seed passed, 1 a seed failed (or seeds are missing), 2 bad input.
    Regress(cli::regress::Args),
    /// Mutation score of the directed regression: for each mutant of hdl/mutants.txt, the
    /// directed seeds (`regress --directed --dut verilator --map hdl/pmu50.map.toml`) checked in
    /// order on the twin built with the mutant's define, up to the first failure
    /// (docs/verification.md). Writes DIR/mutation.json and mutation.txt. Exit 0 every mutant
    /// caught or proven equivalent, 1 one escaped (or could not be checked), 2 bad input.
    Mutation(cli::mutation::Args),
    /// Propose a map (`regress --map`) for an RTL: its signals matched to the model's registers
    /// and internals by name and width, from Verilator's elaboration. Review and edit it.
    RtlMap(cli::rtl_map::Args),
    /// Verification method 2 on one vector file: the RTL (default the twin) built by Verilator
    /// and stepped in lockstep with the model on the file's inputs; every output port compared
    /// after every edge, and what a --map names. Prints the MISMATCH lines of the first
    /// divergent tick. Exit 0 equal, 1 a divergence, 2 bad input.
    Lockstep(cli::lockstep::Args),
    /// The HDL kit this binary carries (the twin, its file list and map, the mutants, the FuseSoC
    /// core, the testbenches, the scripts, the formal kit).
    Hdl(cli::hdl::Args),
    /// An RTL's file list as the kit reads it (`+incdir+`, `+define+`, nested `-f`, libraries),
    /// resolved to absolute paths, with the RTL's content hash (`--json`): for the scripts that
    /// build the RTL with another tool.
    RtlFiles(cli::rtl_files::Args),
    /// Write the provenance and digest of a JSON file of evidence (for the scripts that make
    /// them), or verify one (`--check`).
    Seal(cli::seal::Args),
    /// Lint of an RTL (Verilator -Wall --lint-only and yosys check), each warning waived with a
    /// reviewed reason or counted; a sealed report for the sign-off. Exit 0 clean, 1 warnings
    /// not waived (or a check could not run), 2 bad input
    Lint(cli::lint::Args),
    /// X-propagation of an RTL: a 4-state simulation (Icarus) of regression seeds with inputs X
    /// while they may float, no output X after reset; and every flip-flop reset (yosys). A
    /// sealed report for the sign-off. Exit 0 clean, 1 findings (or a check could not run), 2
    /// bad input
    Xprop(cli::xprop::Args),
    /// Waivers (code coverage, lint, X): `refresh` writes the checksums of those checked again
    Waivers(cli::waivers::Args),
    /// What the regression reads of an RTL, as JSON: the top's parameters, the values it fixes
    /// (read back through the bus after reset) and the contract check. Exit 2 on a bad RTL.
    RtlInfo(cli::rtl_info::Args),
    /// The build cache of RTL under test: its size against its cap (PMU50_CACHE_MAX), its
    /// builds per RTL and their last use; `cache clean` empties it or (`--to-cap`) trims it.
    Cache(cli::cache::Args),
    /// The DUT worker of `regress --dut verilator` (started by the regression itself): steps a
    /// Verilator library and the core in lockstep for each request on stdin.
    #[command(hide = true)]
    DutWorker,
    /// Merge regression folders (shards, resumed parts, adjacent seed ranges) and coverage.json
    /// files into one folder.
    /// Exit 0 complete and passing, 1 a seed failed or seeds are missing, 2 bad input.
    Merge(cli::merge::Args),
    /// The sign-off table of a regression folder (docs/verification.md "Sign-off"): functional
    /// coverage of the reachable bins, bins proven unreachable and undecided, code line and
    /// toggle coverage, formal properties proven, seeds passing, each against its threshold
    /// (default 100 %, OpenTitan V3). Printed, written to DIR/signoff.json and at the top of
    /// DIR/report.html.
    /// Exit 0 every threshold met, 1 one missed, 2 bad input.
    Signoff(cli::signoff::Args),
    /// The history of regressions, merges and sign-offs (a SQLite file or a PostgreSQL
    /// database): the runs, and a static HTML dashboard (`--html`).
    History(cli::history::Args),
    /// Rank a regression's seeds by the coverage each adds (greedy set cover): the shortest
    /// list that keeps every bin hit, DIR/graded.json; rerun it with `regress --seeds-from`.
    Grade(cli::grade::Args),
    /// Draw the closure curves (coverage against seeds) of regression folders into one SVG.
    Closure(cli::closure::Args),
    /// Compare two VCD files; exit 0 equal, 1 different, 2 bad input.
    Diff(cli::diff::Args),
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
                    exit_code(0)
                }
                _ => {
                    err!("{}", text.trim_end());
                    exit_code(2)
                }
            };
        }
    };
    if let Err(e) = atomic_file::sync_to_disk() {
        err!("error: {e}");
        return exit_code(2);
    }
    if let Err(e) = atomic_file::install_signal_cleanup() {
        err!("error: cannot install the SIGINT/SIGTERM handler that removes temporary files: {e}");
        return exit_code(2);
    }
    let result = match cli.cmd {
        Cmd::Run(a) => cli::run::run(a),
        Cmd::Check(a) => cli::check::run(a),
        Cmd::List(a) => cli::list::run(a),
        Cmd::Vectors(a) => cli::vectors::run(a),
        Cmd::Random(a) => cli::random::run(a),
        Cmd::SpeedLimit(a) => cli::speed_limit::run(a),
        Cmd::Budget(a) => cli::budget::run(a),
        Cmd::Regress(a) => cli::regress::run(a),
        Cmd::Mutation(a) => cli::mutation::run(a),
        Cmd::RtlMap(a) => cli::rtl_map::run(a),
        Cmd::Lockstep(a) => cli::lockstep::run(a),
        Cmd::Hdl(a) => cli::hdl::run(a),
        Cmd::RtlFiles(a) => cli::rtl_files::run(a),
        Cmd::RtlInfo(a) => cli::rtl_info::run(a),
        Cmd::Cache(a) => cli::cache::run(a),
        Cmd::Seal(a) => cli::seal::run(a),
        Cmd::Lint(a) => cli::lint::run(a),
        Cmd::Xprop(a) => cli::xprop::run(a),
        Cmd::Waivers(a) => cli::waivers::run(a),
        Cmd::Merge(a) => cli::merge::run(a),
        Cmd::Signoff(a) => cli::signoff::run(a),
        Cmd::Closure(a) => cli::closure::run(a),
        Cmd::History(a) => cli::history::run(a),
        Cmd::Grade(a) => cli::grade::run(a),
        Cmd::Diff(a) => cli::diff::run(a),
        Cmd::DutWorker => return exit_code(pmu50_verif::lockstep::worker_main() as u8),
    };
    exit_code(match result {
        Ok(Outcome::Pass) => 0,
        Ok(Outcome::Fail) => 1,
        Err(e) => {
            e.print();
            2
        }
    })
}
