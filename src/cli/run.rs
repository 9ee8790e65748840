//! `pmu50 run`: scenarios run to their waveforms, save files, logs and timing diagrams, with a
//! summary each. Every file is loaded first and every bad one reported; two scenarios that
//! would write the same file are refused before anything runs; the good ones run; the exit code
//! is the worst.

use super::common::Progress;
use super::error::{CliError, CmdResult, Outcome};
use super::io::{err, out};
use pmu50_core::Dur;
use pmu50_testbench::limits::DEFAULT_MAX_VCD_BYTES;
use pmu50_testbench::observers::refusals::RefusalWatch;
use pmu50_testbench::observers::waveform::{Level, WaveFormat};
use pmu50_testbench::output::{
    choose_trace, dumped_ticks, estimate_run_bytes, output_paths, run_to_batch_as, summary,
    FileOptions, TraceChoice,
};
use pmu50_testbench::scenario::{Scenario, Trace};
use pmu50_testbench::sim::{self, SimOptions};
use std::collections::BTreeMap;
use std::path::PathBuf;

/// The options of `pmu50 run`.
#[derive(clap::Args)]
pub struct Args {
    pub scenarios: Vec<PathBuf>,
    /// Output folder.
    #[arg(long, default_value = "vcd_out")]
    pub out_dir: PathBuf,
    /// Also write <name>.log: one line per register change.
    #[arg(long)]
    pub log: bool,
    /// Dump only this time window, e.g. `--window "10 ms" "60 ms"`.
    #[arg(long, num_args = 2, value_names = ["START", "END"])]
    pub window: Option<Vec<String>>,
    /// Refuse a scenario whose waveform would be larger than this (bytes; default 2 GB;
    /// estimated for its trace level and format).
    #[arg(long, value_name = "BYTES")]
    pub max_vcd_bytes: Option<u64>,
    /// Refuse a scenario with more than this many simulated key-on ticks (default 1e9;
    /// parked ticks, which the exact skip removes, do not count).
    #[arg(long, value_name = "TICKS")]
    pub max_ticks: Option<u64>,
    /// Also write <name>.svg, a timing diagram in the style of FIG. 15/16 (and <name>_timing.csv).
    #[arg(long)]
    pub svg: bool,
    /// What to write besides the summary: ports (the core's inputs and outputs and the
    /// analog env values), registers (ports and every register), all (registers and the
    /// internals), each with its save file and --log/--svg on request, or none (summary
    /// only; repeated key-off periods are then skipped, docs/spec.md 5.1).
    /// Default: the scenario's `[vcd] trace`, else all when a waveform of every signal
    /// is estimated within 256 MiB, else ports.
    #[arg(long, value_parser = pmu50_testbench::scenario::TRACE_WORDS)]
    pub trace: Option<String>,
    /// Waveform format: vcd (text) or fst (compressed, for long runs; GTKWave and Surfer
    /// read it, and so does `pmu50 diff`). The .gtkw save file points at the file written.
    #[arg(long, value_parser = ["vcd", "fst"], default_value = "vcd")]
    pub format: String,
}

/// A scenario `run` will run: its dump window of `--window` (in ticks) and its trace level.
struct Planned {
    sc: Scenario,
    window: Option<(u64, u64)>,
    choice: TraceChoice,
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

/// The plan of one scenario file: loaded, its window and trace level chosen, its size checked.
fn plan(
    p: &std::path::Path,
    a: &Args,
    trace: Option<Trace>,
    format: WaveFormat,
) -> Result<Planned, CliError> {
    let sc = Scenario::load(p)?;
    let window = window_ticks(&sc, &a.window)?;
    pmu50_testbench::limits::check_ticks(&sc, 1, a.max_ticks)?;
    let choice = choose_trace(&sc, trace, window, format);
    let Some(level) = choice.trace.level() else {
        if a.window.is_some() {
            return Err(CliError::Usage(format!("--window: {} is run with trace = none, which writes no waveform; drop --window or run it with --trace ports, registers or all", sc.path.display())));
        }
        return Ok(Planned {
            sc,
            window: None,
            choice,
        });
    };
    check_vcd_size(&sc, window, level, format, a.max_vcd_bytes)?;
    Ok(Planned { sc, window, choice })
}

pub fn run(a: Args) -> CmdResult {
    if a.scenarios.is_empty() {
        return Err(CliError::Usage(
            "run needs at least one scenario file (see `pmu50 list`)".into(),
        ));
    }
    let trace = a.trace.as_deref().and_then(Trace::parse);
    let format = WaveFormat::parse(&a.format).unwrap_or_default();
    let mut bad = false;
    let mut failed = false;
    let mut good: Vec<Planned> = Vec::new();
    for p in &a.scenarios {
        match plan(p, &a, trace, format) {
            Ok(planned) => good.push(planned),
            Err(e) => {
                e.print();
                bad = true;
            }
        }
    }
    let mut owner: BTreeMap<PathBuf, usize> = BTreeMap::new();
    let mut clash = false;
    for (k, Planned { sc, .. }) in good
        .iter()
        .enumerate()
        .filter(|(_, p)| p.choice.trace.level().is_some())
    {
        for path in output_paths(&a.out_dir, &sc.name, true) {
            if let Some(&j) = owner.get(&path) {
                CliError::SameOutput {
                    path,
                    first: good[j].sc.path.display().to_string(),
                    second: sc.path.display().to_string(),
                    name: sc.name.clone(),
                }
                .print();
                clash = true;
                break;
            }
            owner.insert(path, k);
        }
    }
    if clash {
        return Err(CliError::Reported {
            what: "nothing was run".into(),
        });
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
                    failed |= !res.passed() || !watch.refused.is_empty();
                }
                Err(e) => {
                    err!("error: {e}");
                    bad = true;
                }
            }
            continue;
        };
        let r = run_to_batch_as(
            sc,
            &a.out_dir,
            FileOptions {
                log: a.log,
                window: *window,
                svg: a.svg,
                level,
            },
            format,
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
                out!("   {}", choice.describe(format));
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
                failed |= !res.passed() || !watch.refused.is_empty();
            }
            Err(e) => {
                err!("error: {e}");
                bad = true;
            }
        }
    }
    if bad {
        return Err(CliError::Reported {
            what: String::new(),
        });
    }
    Ok(Outcome::of(!failed))
}
