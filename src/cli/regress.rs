//! `pmu50 regress`: a random or directed regression on the model and a DUT backend, measured by
//! functional (and code) coverage, failures shrunk to a repro; or one repro checked.

use super::common::{jobs, progress_line, timeout};
use super::error::{CliError, CmdResult, Outcome};
use super::io::{err, out};
use pmu50_testbench::scenario::Scenario;
use pmu50_verif::dut::Backend;
use pmu50_verif::{self as regress, DutKind, RunSpec};
use std::io::IsTerminal;
use std::path::PathBuf;
use std::sync::atomic::AtomicBool;
use std::time::{Duration, Instant};

/// The options of `pmu50 regress`.
#[derive(clap::Args)]
pub struct Args {
    /// First seed [default: 1].
    #[arg(long)]
    pub start_seed: Option<u64>,
    /// Number of seeds (the whole regression; a shard runs its part of it), at most 10^7.
    #[arg(long)]
    pub iterations: Option<u64>,
    /// Parallel jobs (default: every core).
    #[arg(long)]
    pub jobs: Option<usize>,
    /// Bias the generator towards coverage bins not hit yet (deterministic per seed range).
    #[arg(long)]
    pub directed: bool,
    /// Also step the readable per-block model beside the kernel and compare every register
    /// after every edge.
    #[arg(long)]
    pub check_spec: bool,
    /// Design under test: the model alone, or an RTL on verilator (lockstep) or icarus
    /// (vector replay), compared with the model on every seed (the backends of the
    /// registry, docs/architecture.md). [default: model]
    #[arg(long, value_parser = dut_names())]
    pub dut: Option<String>,
    /// The RTL's Verilog file list (paths relative to the list's folder; top `pmu50` with the
    /// ports and parameters of docs/signals.md). Default: the twin, hdl/pmu50.f.
    #[arg(long, value_name = "FILELIST")]
    pub rtl: Option<PathBuf>,
    /// Also compare the RTL's registers and internals that this TOML map names (model name
    /// = hierarchical RTL name; `pmu50 rtl-map` proposes one). Default: the ports only.
    #[arg(long, value_name = "FILE.toml")]
    pub map: Option<PathBuf>,
    /// Hold SYNC_DEPTH (1-4) for every seed, e.g. for an RTL built for one configuration.
    #[arg(long, value_parser = clap::value_parser!(u8).range(1..=4))]
    pub sync_depth: Option<u8>,
    /// Hold CNT_W (2-16) for every seed.
    #[arg(long, value_parser = clap::value_parser!(u8).range(2..=16))]
    pub cnt_width: Option<u8>,
    /// Run part I of N of the seed range (job arrays). Inside a Slurm array or a Kubernetes
    /// Indexed Job the part comes from SLURM_ARRAY_TASK_ID / JOB_COMPLETION_INDEX.
    #[arg(long, value_name = "I/N")]
    pub shard: Option<String>,
    /// The number of shards, where the scheduler gives only the index (JOB_COMPLETION_INDEX).
    #[arg(long, value_name = "N")]
    pub shard_count: Option<u64>,
    /// Continue the regression in DIR: run only the seeds its results.jsonl does not have.
    /// Its seed range, DUT and options are those of DIR/regress.json.
    #[arg(long, value_name = "DIR", conflicts_with_all = ["start_seed", "iterations", "shard", "shard_count", "directed", "check_spec", "dut", "rtl", "map", "repro", "sync_depth", "cnt_width", "out", "code_coverage", "waivers", "param_sets"])]
    pub resume: Option<PathBuf>,
    /// Measure the RTL's code coverage (Verilator line and toggle coverage; --dut verilator):
    /// code/coverage.dat, code/lcov.info, code/summary.json, code/summary.md and a section of report.html.
    #[arg(long, conflicts_with = "repro")]
    pub code_coverage: bool,
    /// The waivers of the code coverage (TOML, docs/verification.md). Default: the twin's
    /// hdl/coverage-waivers.toml for the twin, none for another RTL.
    #[arg(long, value_name = "FILE.toml", requires = "code_coverage")]
    pub waivers: Option<PathBuf>,
    /// Build modes: the seeds draw their reset values, structure and clock from a pool of at
    /// most P parameter sets, fixed from the seed range by a greedy cover of the configuration
    /// bins and built once each; 0 gives each seed its own set (a build per seed on an RTL).
    /// [default: 10 with an RTL (--dut verilator or icarus), 0 with the model]
    #[arg(long, value_name = "P")]
    pub param_sets: Option<u32>,
    /// Output folder [default: regress_out].
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Per-seed time limit for the DUT, seconds.
    #[arg(long, default_value_t = 120.0)]
    pub timeout: f64,
    /// Do not shrink failures into failures/<signature>/.
    #[arg(long)]
    pub no_triage: bool,
    /// Check one scenario file (a shrunk repro) the way a seed is checked; prints the failure.
    #[arg(long, value_name = "FILE.toml", conflicts_with_all = ["iterations", "shard", "shard_count", "directed"])]
    pub repro: Option<PathBuf>,
    /// Rerun only the seeds of a graded list (`pmu50 grade DIR`'s DIR/graded.json), each with
    /// the stimulus it had in DIR's regression, into --out: results.jsonl and coverage.json;
    /// exit 0 when every seed passes and every bin DIR hit is hit again.
    #[arg(long, value_name = "GRADED.json", conflicts_with_all = ["iterations", "shard", "shard_count", "directed", "resume", "repro", "start_seed", "dut", "rtl", "map", "code_coverage"])]
    pub seeds_from: Option<PathBuf>,
    /// The history database this regression is appended to: a SQLite file or
    /// postgres://USER[:PASSWORD]@HOST[:PORT]/DB [default: $PMU50_HISTORY, else history.sqlite
    /// beside --out; `off`: none].
    #[arg(long, value_name = "FILE|URL")]
    pub history: Option<String>,
}

/// `--dut`: the names of the registry's backends.
fn dut_names() -> clap::builder::PossibleValuesParser {
    clap::builder::PossibleValuesParser::new(pmu50_verif::dut::BACKENDS.iter().map(|b| b.name))
}

pub fn run(a: Args) -> CmdResult {
    let timeout = timeout(a.timeout)?;
    let jobs = jobs(a.jobs)?;
    let dut_name = a.dut.clone().unwrap_or_else(|| "model".into());
    let backend =
        regress::dut::find(&dut_name).map_err(|e| CliError::Usage(format!("--dut: {e}")))?;
    backend
        .check(a.rtl.is_some(), a.map.is_some(), a.code_coverage)
        .map_err(|e| CliError::Usage(e.to_string()))?;
    let dut = DutKind::new(backend.name);
    // the waivers of the code coverage: --waivers, or the twin's own
    let waivers = if a.code_coverage {
        let list = a
            .rtl
            .clone()
            .unwrap_or_else(|| pmu50_verif::hdl_kit::hdl_dir().join("pmu50.f"));
        let file = match (&a.waivers, &a.rtl) {
            (Some(w), _) => Some(w.clone()),
            (None, None) => Some(pmu50_verif::hdl_kit::hdl_dir().join("coverage-waivers.toml")),
            (None, Some(_)) => None,
        };
        match file {
            None => Some(regress::code_cov::Waivers::default()),
            Some(f) => {
                let files = regress::rtl::FileList::read(&list)?.files;
                Some(regress::code_cov::Waivers::read(&f, Some(&files))?)
            }
        }
    } else {
        None
    };
    let rtl = match &a.rtl {
        Some(r) => Some(regress::rtl::FileList::read(r)?.list.display().to_string()),
        None => None,
    };
    let map = match &a.map {
        Some(m) => {
            regress::map::RtlMap::read(m)?;
            Some(
                m.canonicalize()
                    .unwrap_or_else(|_| m.clone())
                    .display()
                    .to_string(),
            )
        }
        None => None,
    };
    let pins = pmu50_verif::gen::Pins {
        sync_depth: a.sync_depth,
        cnt_width: a.cnt_width,
    };
    let model = pmu50_coverage::model_id(pmu50_coverage::layout());
    let tool = format!("pmu50 {}", env!("CARGO_PKG_VERSION"));
    if let Some(list) = &a.seeds_from {
        return seeds_from(list, a.out.as_deref(), jobs, timeout);
    }
    if let Some(file) = &a.repro {
        let spec = RunSpec {
            tool,
            model,
            start_seed: 0,
            iterations: 0,
            directed: false,
            check_spec: a.check_spec,
            dut,
            rtl,
            map,
            fixed: Default::default(),
            pins,
            shard: None,
            code_coverage: false,
            param_sets: 0,
            pool: Vec::new(),
        };
        return repro(file, &spec, backend, timeout);
    }
    let (spec, resume) = match &a.resume {
        Some(dir) => (regress::read_spec(dir)?, true),
        None => {
            let Some(iterations) = a.iterations else {
                return Err(CliError::Usage(
                    "regress needs --iterations N (or --resume DIR, or --repro FILE)".into(),
                ));
            };
            let start_seed = a.start_seed.unwrap_or(1);
            if iterations == 0 {
                return Err(CliError::Usage(
                    "--iterations 0: give at least one seed".into(),
                ));
            }
            if iterations > regress::folder::MAX_SEEDS {
                return Err(CliError::Usage(format!("--iterations {iterations}: at most {} seeds make one regression; split a larger range into regressions of adjacent seed ranges (--start-seed), which pmu50 merge joins", regress::folder::MAX_SEEDS)));
            }
            if start_seed.checked_add(iterations).is_none() {
                return Err(CliError::Usage(format!("--start-seed {start_seed} --iterations {iterations}: the seed range passes 2^64")));
            }
            let shard = regress::shard::Shard::resolve(a.shard.as_deref(), a.shard_count, |k| {
                std::env::var(k).ok()
            })
            .map_err(CliError::Usage)?;
            if a.directed && shard.is_some() {
                return Err(CliError::Usage("--directed steers each batch by the coverage of the seeds before it, which another shard runs: run a directed regression in one process, or shard a random one".into()));
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
                    pins,
                    shard,
                    code_coverage: a.code_coverage,
                    param_sets: 0,
                    pool: Vec::new(),
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
    let d = regress::dut::prepare_for_pool(&spec)?;
    if resume && spec.fixed != *d.fixed() {
        return Err(CliError::Usage(format!("--resume {}: the regression was run on an RTL that fixes {}, this RTL fixes {}: the RTL changed", out_dir.display(), if spec.fixed.is_empty() { "nothing".into() } else { spec.fixed.text() }, if d.fixed().is_empty() { "nothing".into() } else { d.fixed().text() })));
    }
    spec.fixed = d.fixed().clone();
    if !resume {
        // the pool of parameter sets, fixed from the seed range (and what the RTL fixes)
        spec.param_sets = a.param_sets.unwrap_or(if backend.caps.rtl {
            pmu50_verif::param_pool::DEFAULT_SETS
        } else {
            0
        });
        spec.pool = pmu50_verif::param_pool::choose(
            spec.start_seed,
            spec.iterations,
            spec.param_sets,
            spec.pins,
            &spec.fixed,
        )
        .map_err(|e| CliError::Usage(e.to_string()))?;
        if !spec.pool.is_empty() {
            let builds: std::collections::BTreeSet<String> = spec
                .pool
                .iter()
                .map(|s| format!("{:?}", s.params))
                .collect();
            err!(
                "regress: {} parameter set(s) of at most {} ({} build(s) of the RTL), the seeds spread over them",
                spec.pool.len(),
                spec.param_sets,
                builds.len()
            );
        }
    }
    // Build modes: every parameter set of the pool built now, as many at once as the jobs
    // allow; an RTL that builds for none of them is bad input (exit 2)
    d.prebuild(&spec.pool, jobs)?;
    // what makes the folder: the RTL's content hash and every file's, the tools, the command
    let evidence = if resume {
        None
    } else {
        Some(regress::evidence::for_run(
            &spec,
            "pmu50 regress",
            regress::evidence::command_line(),
        )?)
    };
    for n in d.notes() {
        err!("regress: {n}");
    }
    let o = regress::regress::Options {
        spec,
        jobs,
        out: out_dir.clone(),
        timeout,
        triage: !a.no_triage,
        progress: std::io::stderr()
            .is_terminal()
            .then_some(progress_line as fn(&str)),
        waivers,
        evidence,
    };
    let stop = AtomicBool::new(false);
    let s = regress::regress::run(&o, resume, &stop, d.as_ref())?;
    out!("{}", s.text().trim_end());
    if let Some(code) = &s.code {
        err!("{}", code.text().trim_end());
    }
    super::common::record_history(
        a.history.as_deref(),
        &out_dir,
        &regress::history::record_of(&s, "regress", &out_dir),
    );
    out!(
        "wrote {}/results.jsonl, coverage.json, report.html{} ({:.1} s, {} jobs)",
        out_dir.display(),
        if s.code.is_some() {
            ", code/coverage.dat, code/lcov.info, code/summary.json, code/summary.md"
        } else {
            ""
        },
        t0.elapsed().as_secs_f64(),
        jobs
    );
    Ok(Outcome::of(s.failed() == 0 && s.missing.is_empty()))
}

/// `--repro FILE`: one scenario checked the way a seed is.
fn repro(
    file: &std::path::Path,
    spec: &RunSpec,
    backend: &Backend,
    timeout: Duration,
) -> CmdResult {
    let sc = Scenario::load(file)?;
    // the RTL of the failure, when the repro lies in its regression folder
    // (DIR/failures/<signature>/repro.toml): an RTL changed since is said before the run
    if let Some(note) = regress::evidence::repro_rtl_note(file, spec)? {
        err!("regress: {note}");
    }
    let d = regress::dut::prepare(spec)?;
    if !d.fixed().holds(&sc.params) {
        return Err(CliError::Usage(format!(
            "{}: the RTL fixes {} (its top lacks these parameters), the scenario has other values",
            file.display(),
            d.fixed().text()
        )));
    }
    match regress::check_scenario(spec, &sc, d.as_ref(), timeout)
        .map_err(|e| CliError::Usage(format!("{}: {e}", file.display())))?
    {
        None => {
            out!(
                "PASS {}: the model's checks{} hold",
                file.display(),
                if !backend.caps.rtl {
                    String::new()
                } else {
                    format!(" and the {} DUT", backend.name)
                }
            );
            Ok(Outcome::Pass)
        }
        Some(f) => {
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
            Ok(Outcome::Fail)
        }
    }
}

/// `--seeds-from GRADED.json`: the graded seeds rerun on their regression's DUT and stimulus.
fn seeds_from(
    list: &std::path::Path,
    out_dir: Option<&std::path::Path>,
    jobs: usize,
    timeout: Duration,
) -> CmdResult {
    let Some(out_dir) = out_dir else {
        return Err(CliError::Usage(
            "--seeds-from needs --out DIR for the rerun's results".into(),
        ));
    };
    let g = regress::grade::Graded::read(list)?;
    let spec = regress::read_spec(std::path::Path::new(&g.folder))?;
    let d = regress::dut::prepare(&spec)?;
    let stop = AtomicBool::new(false);
    let r = regress::grade::rerun(list, out_dir, d.as_ref(), jobs, timeout, &stop)?;
    out!(
        "rerun: {} graded seeds of {}, {} failing; coverage {} bins, the regression's {} seeds hit {}{}",
        r.seeds,
        g.folder,
        r.failed,
        r.bins_hit,
        g.seeds,
        r.original_hit,
        if r.lost.is_empty() {
            String::new()
        } else {
            format!("; not hit again: {}", r.lost.join(", "))
        }
    );
    out!("wrote {}/results.jsonl, coverage.json", out_dir.display());
    Ok(Outcome::of(r.failed == 0 && r.lost.is_empty()))
}
