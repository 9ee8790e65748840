//! `pmu50 regress`: random regressions measured by functional coverage, failures triaged to a
//! repro (docs/verification.md).
//!
//! A regression is a seed range. Each seed is one generated scenario ([`gen`]) run on the full
//! bench (environment, MPU, core) with the checks and coverage of [`check`]; with a DUT other
//! than the model, the same stimulus also drives the RTL in lockstep ([`dut`]). A seed's result
//! is one line of `results.jsonl`, carrying its sparse coverage, so results and coverage of any
//! set of seeds merge exactly ([`merge`]): the files of a regression depend on its seed range
//! and options only, never on `--jobs`, on sharding or on interruptions.
//!
//! Folder layout (`--out DIR`): `regress.json` (the run), `results.jsonl` (one line per seed,
//! sorted by seed when the run completes), `coverage.json` (merge format), `coverage.ucis.xml`
//! (the same coverage as UCIS 1.0 XML, which pyucis reads and merges), `report.html`,
//! `failures/<signature>/` (shrunk repro, command, waveform).

pub mod check;
pub mod dut;
pub mod folder;
pub mod gen;
pub mod lockstep;
pub mod map;
pub mod merge;
pub mod picture;
pub mod report;
pub mod rtl;
pub mod shard;
pub mod triage;
pub mod wave;

use crate::scenario::Scenario;
use crate::sim::{self, SimOptions};
use check::{Failure, SeedChecks};
use gen::{Bias, Stimulus};
use pmu50_coverage::{layout, CoverageFile, RunRecord};
use serde::{Deserialize, Serialize};
use shard::Shard;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

use std::time::{Duration, Instant};

/// Seeds generated between two updates of the directed bias (and written to results.jsonl at once).
pub const BATCH: u64 = 32;

/// Where the regression's verdicts come from.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum DutKind {
    /// The model alone: its checks and invariants.
    Model,
    /// An RTL on Verilator, in lockstep with the model (the twin unless `--rtl`).
    Verilator,
    /// An RTL on Icarus Verilog, replaying the model's vectors.
    Icarus,
}

/// The run as recorded in `regress.json`: everything its results depend on.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RunSpec {
    pub tool: String,
    pub model: String,
    pub start_seed: u64,
    pub iterations: u64,
    pub directed: bool,
    pub check_spec: bool,
    pub dut: DutKind,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rtl: Option<String>,
    /// `--map`: model registers and internals compared beside the ports.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub map: Option<String>,
    /// What the RTL fixes itself (its top lacks these parameters): every seed keeps them.
    #[serde(default, skip_serializing_if = "rtl::Fixed::is_empty")]
    pub fixed: rtl::Fixed,
    /// Structural parameters held fixed (absent: drawn per seed).
    #[serde(default, skip_serializing_if = "is_default")]
    pub pins: gen::Pins,
    /// This folder's part of the range (absent: the whole range).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shard: Option<Shard>,
}

impl RunSpec {
    /// The same regression (seed range and options), whatever the shard.
    pub fn same_regression(&self, o: &RunSpec) -> bool {
        RunSpec { shard: None, ..self.clone() } == RunSpec { shard: None, ..o.clone() }
    }

    /// The seeds of this folder.
    pub fn seeds(&self) -> std::ops::Range<u64> {
        match &self.shard {
            Some(s) => s.seeds(self.start_seed, self.iterations),
            None => self.start_seed..self.start_seed.saturating_add(self.iterations),
        }
    }

    /// The id of a seed's run in coverage.json: the same seed of the same regression is the
    /// same run, and is refused when merged twice.
    pub fn run_id(&self, seed: u64) -> String {
        if self.directed {
            format!("directed:{}+{}/{seed}", self.start_seed, self.iterations)
        } else {
            format!("random/{seed}")
        }
    }
}

fn is_default(p: &gen::Pins) -> bool {
    *p == gen::Pins::default()
}

/// Where a seed ran.
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Place {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shard: Option<String>,
    pub host: String,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub slurm_job_id: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub slurm_array_task_id: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub k8s_job: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub k8s_index: Option<String>,
}

impl Place {
    pub fn here(shard: Option<&Shard>) -> Place {
        let env = |k: &str| std::env::var(k).ok().filter(|v| !v.is_empty());
        Place {
            shard: shard.map(|s| format!("{}/{}", s.index, s.count)),
            host: hostname(),
            slurm_job_id: env("SLURM_ARRAY_JOB_ID").or_else(|| env("SLURM_JOB_ID")),
            slurm_array_task_id: env("SLURM_ARRAY_TASK_ID"),
            k8s_job: env("JOB_NAME").or_else(|| env("HOSTNAME").filter(|_| env("JOB_COMPLETION_INDEX").is_some())),
            k8s_index: env("JOB_COMPLETION_INDEX"),
        }
    }
}

fn hostname() -> String {
    std::fs::read_to_string("/proc/sys/kernel/hostname").map(|s| s.trim().to_string()).ok().filter(|s| !s.is_empty()).or_else(|| std::env::var("HOSTNAME").ok()).unwrap_or_else(|| "unknown".into())
}

/// One line of results.jsonl.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SeedResult {
    pub seed: u64,
    /// `pass`, `fail` or `error`.
    pub verdict: String,
    /// Simulated ticks, and those evaluated one by one.
    pub ticks: u64,
    pub evaluated: u64,
    /// Key-on read-outs the tracking invariant checked.
    pub readouts_checked: u64,
    pub wall_ms: f64,
    #[serde(default)]
    pub failure: Option<Failure>,
    #[serde(rename = "where")]
    pub place: Place,
    /// The seed's coverage, sparse: `bin:hits,bin:hits,...` (bin = index in the model).
    pub cov: String,
}

impl SeedResult {
    pub fn hits(&self, out: &mut [u64]) -> Result<(), String> {
        if self.cov.is_empty() {
            return Ok(());
        }
        for pair in self.cov.split(',') {
            let (k, v) = pair.split_once(':').ok_or_else(|| format!("coverage entry `{pair}` is not bin:hits"))?;
            let k: usize = k.parse().map_err(|_| format!("coverage bin `{k}` is not a number"))?;
            let v: u64 = v.parse().map_err(|_| format!("coverage hits `{v}` are not a number"))?;
            let slot = out.get_mut(k).ok_or_else(|| format!("coverage bin {k} is outside the model's {} bins", layout().bins.len()))?;
            if let Some(why) = layout().bins[k].unreachable {
                if v > 0 {
                    return Err(format!("coverage bin {k} ({}) is declared unreachable ({why}) but has {v} hits", layout().bins[k].name));
                }
            }
            *slot = slot.checked_add(v).ok_or("coverage hits overflow 64 bits")?;
        }
        Ok(())
    }
}

fn sparse(hits: &[u64]) -> String {
    let mut s = String::new();
    for (k, &h) in hits.iter().enumerate().filter(|(_, h)| **h > 0) {
        if !s.is_empty() {
            s.push(',');
        }
        s.push_str(&format!("{k}:{h}"));
    }
    s
}

/// Options of `pmu50 regress`.
#[derive(Clone, Debug)]
pub struct Options {
    pub spec: RunSpec,
    pub jobs: usize,
    pub out: PathBuf,
    pub timeout: Duration,
    /// Shrink failures and write their repro folders.
    pub triage: bool,
    /// Print a line per batch on stderr.
    pub progress: bool,
}

#[derive(Debug, thiserror::Error)]
pub enum RegressError {
    #[error("{0}")]
    Usage(String),
    #[error("{}: {reason}", path.display())]
    File { path: PathBuf, reason: String },
    #[error("{}: line {line}: {reason}", path.display())]
    Line { path: PathBuf, line: u64, reason: String },
    #[error(transparent)]
    Output(#[from] crate::atomic_file::OutputError),
    #[error("{0}")]
    Dut(String),
}

fn file_err(path: &Path, reason: impl std::fmt::Display) -> RegressError {
    RegressError::File { path: path.to_path_buf(), reason: reason.to_string() }
}

/// A seed after its model run: its result, or its recording for the RTL, which
/// [`Pending::send`] hands to the DUT.
enum Stage<'a> {
    /// Boxed: a seed's result is large beside a seed in flight.
    Done(Box<SeedResult>, Vec<u64>),
    Pending(Pending<'a>),
}

/// A seed whose model run passed and whose RTL check is to run or running.
struct Pending<'a> {
    seed: u64,
    start: Instant,
    /// Boxed: a scenario is large beside a finished seed's result.
    sc: Box<Scenario>,
    rec: Option<dut::Recorded>,
    flight: Option<Box<dyn dut::InFlight + 'a>>,
    ticks: u64,
    evaluated: u64,
    readouts_checked: u64,
    hits: Vec<u64>,
}

impl<'a> Pending<'a> {
    /// Hand the recording to the DUT; the seed's verdict waits in [`Pending::finish`].
    fn send(&mut self, d: &'a dyn dut::Dut) -> Result<(), dut::DutError> {
        if let Some(rec) = self.rec.take() {
            self.flight = Some(d.send(&self.sc, rec)?);
        }
        Ok(())
    }

    /// The seed's result, with the verdict of the DUT (sent or not yet).
    fn finish(self, d: &'a dyn dut::Dut, timeout: Duration) -> (SeedResult, Vec<u64>) {
        let (seed, start) = (self.seed, self.start);
        seed_result(seed, start, self.verdict(d, timeout))
    }

    /// The verdict of the DUT (sent or not yet).
    fn verdict(mut self, d: &'a dyn dut::Dut, timeout: Duration) -> Evaluated {
        let verdict = match self.flight.take() {
            Some(f) => f.wait(&self.sc, timeout),
            None => self.send(d).and_then(|()| match self.flight.take() {
                Some(f) => f.wait(&self.sc, timeout),
                None => Ok(None),
            }),
        };
        let (verdict, failure) = match verdict {
            Ok(None) => ("pass", None),
            Ok(Some(f)) => ("fail", Some(f)),
            Err(e) => ("error", Some(*error_failure(0, e.to_string()))),
        };
        (verdict, failure, self.ticks, self.evaluated, self.readouts_checked, self.hits)
    }
}

fn seed_result(seed: u64, start: Instant, e: Evaluated) -> (SeedResult, Vec<u64>) {
    let (verdict, failure, ticks, evaluated, readouts_checked, hits) = e;
    let r = SeedResult {
        seed,
        verdict: verdict.into(),
        ticks,
        evaluated,
        readouts_checked,
        wall_ms: (start.elapsed().as_secs_f64() * 1e4).round() / 10.0,
        failure,
        place: Place::default(),
        cov: sparse(&hits),
    };
    (r, hits)
}

/// The model's part of a seed.
fn start_seed<'a>(spec: &RunSpec, seed: u64, bias: &Bias, d: &'a dyn dut::Dut) -> Stage<'a> {
    let start = Instant::now();
    let stim = Stimulus::generate(seed, bias);
    match evaluate_model(spec, &stim, d) {
        Ok(Phase::Final(e)) => {
            let (r, hits) = seed_result(seed, start, e);
            Stage::Done(Box::new(r), hits)
        }
        Ok(Phase::Dut { sc, rec, ticks, evaluated, readouts_checked, hits }) => Stage::Pending(Pending { seed, start, sc, rec: Some(rec), flight: None, ticks, evaluated, readouts_checked, hits }),
        Err(f) => {
            let (r, hits) = seed_result(seed, start, ("error", Some(*f), 0, 0, 0, vec![0; layout().bins.len()]));
            Stage::Done(Box::new(r), hits)
        }
    }
}

type Evaluated = (&'static str, Option<Failure>, u64, u64, u64, Vec<u64>);

fn error_failure(tick: u64, detail: String) -> Box<Failure> {
    Box::new(Failure { kind: "error".into(), tick, signal: "-".into(), expected: "-".into(), got: "-".into(), block: "-".into(), fig: "-".into(), detail })
}

/// What the model's run of a seed leaves to do.
enum Phase {
    /// The verdict (the model failed, or the DUT is the model).
    Final(Evaluated),
    /// The model passed; the RTL is to run on this recording.
    Dut { sc: Box<Scenario>, rec: dut::Recorded, ticks: u64, evaluated: u64, readouts_checked: u64, hits: Vec<u64> },
}

/// The verdict of one stimulus: the model's checks, then the DUT (shared by the seeds, the
/// shrinking of a failure and `--repro`).
pub fn evaluate(spec: &RunSpec, stim: &Stimulus, d: &dyn dut::Dut, timeout: Duration) -> Result<Evaluated, Box<Failure>> {
    match evaluate_model(spec, stim, d)? {
        Phase::Final(e) => Ok(e),
        Phase::Dut { sc, rec, ticks, evaluated, readouts_checked, hits } => {
            let p = Pending { seed: stim.seed, start: Instant::now(), sc, rec: Some(rec), flight: None, ticks, evaluated, readouts_checked, hits };
            Ok(p.verdict(d, timeout))
        }
    }
}

/// The model's run of a stimulus with its checks, recording what the DUT needs: the inputs of
/// every tick in memory (verilator) or a vector file (icarus).
fn evaluate_model(spec: &RunSpec, stim: &Stimulus, d: &dyn dut::Dut) -> Result<Phase, Box<Failure>> {
    let name = format!("regress_{}", stim.seed);
    let text = stim.to_toml(&name);
    let path = PathBuf::from(format!("{name}.toml"));
    let sc = Scenario::parse(&text, &path.display().to_string(), &name, &path).map_err(|e| error_failure(0, format!("the generator made a scenario the parser refuses: {e}")))?;
    let needs = d.needs();
    let vec = match needs {
        dut::Needs::Vectors => Some(d.vector_file(&sc).map_err(|e| error_failure(0, e.to_string()))?),
        _ => None,
    };
    let mut writer = match &vec {
        Some(f) => Some(crate::observers::vectors::VectorWriter::new(std::io::BufWriter::new(f.as_file()), &sc).map_err(|e| error_failure(0, e.to_string()))?),
        None => None,
    };
    let mut recorder = (needs == dut::Needs::Inputs).then(lockstep::InputRecorder::default);
    let run = match (writer.as_mut(), recorder.as_mut()) {
        (Some(w), _) => run_model(&sc, spec.check_spec, &mut [w]),
        (None, Some(r)) => run_model(&sc, spec.check_spec, &mut [r]),
        (None, None) => run_model(&sc, spec.check_spec, &mut []),
    };
    let (checks, res) = run.map_err(|e| error_failure(0, e.to_string()))?;
    if let Some(w) = writer.take() {
        use std::io::Write;
        w.into_inner().flush().map_err(|e| error_failure(0, format!("vector file: {e}")))?;
    }
    drop(writer);
    let hits = checks.coverage.hits().to_vec();
    let mut failure = checks.failure.clone();
    if failure.is_none() {
        if let Some(c) = res.checks.iter().find(|c| !c.ok) {
            failure = Some(Failure { kind: "expect".into(), tick: res.ticks, signal: c.name.clone(), expected: "-".into(), got: "-".into(), block: "-".into(), fig: "-".into(), detail: c.detail.clone() });
        }
    }
    if failure.is_none() {
        let rec = match (recorder, vec) {
            (Some(r), _) => Some(dut::Recorded::Inputs(r.inputs)),
            (None, Some(v)) => Some(dut::Recorded::Vectors(v)),
            (None, None) => None,
        };
        if let Some(rec) = rec {
            return Ok(Phase::Dut { sc: Box::new(sc), rec, ticks: res.ticks, evaluated: res.evaluated_ticks, readouts_checked: checks.readouts_checked, hits });
        }
    }
    let verdict = if failure.is_some() { "fail" } else { "pass" };
    Ok(Phase::Final((verdict, failure, res.ticks, res.evaluated_ticks, checks.readouts_checked, hits)))
}

/// Check one scenario (a repro) as a seed is checked: `Ok(None)` it passes.
pub fn check_scenario(spec: &RunSpec, sc: &Scenario, d: &dyn dut::Dut, timeout: Duration) -> Result<Option<Failure>, dut::DutError> {
    let (checks, res) = run_model(sc, spec.check_spec, &mut []).map_err(|e| dut::DutError::Tool(e.to_string()))?;
    if let Some(f) = checks.failure {
        return Ok(Some(f));
    }
    if let Some(c) = res.checks.iter().find(|c| !c.ok) {
        return Ok(Some(Failure { kind: "expect".into(), tick: res.ticks, signal: c.name.clone(), expected: "-".into(), got: "-".into(), block: "-".into(), fig: "-".into(), detail: c.detail.clone() }));
    }
    dut::check(d, sc, timeout)
}

/// The model's run of a scenario with the regression's checks and coverage.
pub fn run_model(sc: &Scenario, check_spec: bool, extra: &mut [&mut dyn sim::Observer]) -> Result<(SeedChecks, sim::RunResult), sim::SimError> {
    let mut checks = SeedChecks::new(&sc.params, sc.clock_ns(), check_spec);
    let mut obs: Vec<&mut dyn sim::Observer> = vec![&mut checks];
    for e in extra.iter_mut() {
        obs.push(&mut **e);
    }
    let res = sim::run(sc, SimOptions::default(), &mut obs)?;
    drop(obs);
    checks.finish_checks(&res, sc);
    Ok((checks, res))
}

/// A `fmt::Write` into an `io::Write`, keeping the first I/O error.
struct IoText<W: std::io::Write> {
    out: W,
    err: Option<std::io::Error>,
}

impl<W: std::io::Write> std::fmt::Write for IoText<W> {
    fn write_str(&mut self, s: &str) -> std::fmt::Result {
        if self.err.is_some() {
            return Err(std::fmt::Error);
        }
        self.out.write_all(s.as_bytes()).map_err(|e| {
            self.err = Some(e);
            std::fmt::Error
        })
    }
}

/// Read regress.json of `dir`, checked as strictly as the command line ([`folder::parse_spec`]).
pub fn read_spec(dir: &Path) -> Result<RunSpec, RegressError> {
    folder::read_spec(dir)
}

/// A results file summed into a [`Summary`], and the seeds it may hold (its folder's range).
#[derive(Clone, Debug)]
pub struct Source {
    pub results: PathBuf,
    pub range: std::ops::Range<u64>,
}

impl Source {
    /// The results file of the regression folder `dir` of `spec`.
    pub fn of(dir: &Path, spec: &RunSpec) -> Source {
        Source { results: dir.join("results.jsonl"), range: spec.seeds() }
    }
}

/// What a regression folder holds, summed: the counts, the coverage and the failures by
/// signature in memory; the results themselves stay in their files ([`folder::Store`]).
pub struct Summary {
    pub spec: RunSpec,
    pub store: folder::Store,
    pub pass: u64,
    pub fail: u64,
    pub error: u64,
    /// Failing seeds by signature.
    pub groups: std::collections::BTreeMap<String, folder::Group>,
    pub coverage: CoverageFile,
    /// Seeds of the range with no result, as ranges.
    pub missing: Vec<std::ops::Range<u64>>,
    /// The closure curve: (seeds, % of the bins scenario stimuli reach), where it changes.
    pub curve: Vec<(u64, f64)>,
}

impl Summary {
    /// Read and check every results file of `sources`, in one pass each, and sum them.
    pub fn build(spec: RunSpec, sources: &[Source]) -> Result<Summary, RegressError> {
        if sources.len() > usize::from(u16::MAX) {
            return Err(RegressError::Usage(format!("{} results files: at most {} merge at once", sources.len(), u16::MAX)));
        }
        let mut hits = vec![0u64; layout().bins.len()];
        let (mut pass, mut fail, mut error) = (0u64, 0u64, 0u64);
        let mut groups: std::collections::BTreeMap<String, folder::Group> = std::collections::BTreeMap::new();
        let mut entries = Vec::new();
        for (k, s) in sources.iter().enumerate() {
            let scanned = folder::scan(&s.results, k as u16, &s.range, &mut hits, |r, e| {
                match e.verdict {
                    folder::Verdict::Pass => pass += 1,
                    folder::Verdict::Fail => fail += 1,
                    folder::Verdict::Error => error += 1,
                }
                if let Some(f) = &r.failure {
                    let g = groups.entry(f.signature()).or_insert_with(|| folder::Group { count: 0, smallest: r.seed, failure: f.clone(), file: e.file });
                    g.count += 1;
                    if r.seed < g.smallest {
                        g.smallest = r.seed;
                        g.failure = f.clone();
                        g.file = e.file;
                    }
                }
            })?;
            entries.extend(scanned.entries);
        }
        let store = folder::Store::new(sources.iter().map(|s| s.results.clone()).collect(), entries)?;
        let runs = store.entries.iter().map(|e| RunRecord { id: spec.run_id(e.seed), verdict: e.verdict.name().into() }).collect();
        let mut missing = Vec::new();
        let range = spec.seeds();
        let mut next = range.start;
        for e in &store.entries {
            if e.seed > next {
                missing.push(next..e.seed);
            }
            next = e.seed + 1;
        }
        if next < range.end {
            missing.push(next..range.end);
        }
        let mut curve = report::Curve::new();
        let mut reader = store.reader()?;
        let mut scratch = vec![0u64; hits.len()];
        for e in &store.entries {
            scratch.iter_mut().for_each(|h| *h = 0);
            reader.result(e)?.hits(&mut scratch).map_err(RegressError::Usage)?;
            curve.push(&scratch);
        }
        drop(reader);
        Ok(Summary { coverage: CoverageFile::from_coverage(&hits, runs), spec, store, pass, fail, error, groups, missing, curve: curve.finish() })
    }

    /// Seeds with a result.
    pub fn seeds(&self) -> u64 {
        self.store.len() as u64
    }

    /// Seeds that did not pass.
    pub fn failed(&self) -> u64 {
        self.fail + self.error
    }

    /// Seeds of the range with no result.
    pub fn missing_count(&self) -> u64 {
        self.missing.iter().map(|r| r.end - r.start).sum()
    }

    /// The coverage of the seeds before `seed` (a directed batch's bias), read back in order.
    pub fn hits_before(&self, seed: u64) -> Result<Vec<u64>, RegressError> {
        let mut before = vec![0u64; layout().bins.len()];
        let mut reader = self.store.reader()?;
        for e in self.store.entries.iter().take_while(|e| e.seed < seed) {
            reader.result(e)?.hits(&mut before).map_err(RegressError::Usage)?;
        }
        Ok(before)
    }

    /// Write regress.json, results.jsonl (sorted by seed), coverage.json, coverage.ucis.xml,
    /// report.html (and missing.txt when seeds are missing) into `dir`, each atomically; the
    /// folders of `failures/` whose signature no seed has any more are removed.
    pub fn write(&self, dir: &Path, extra: Option<&str>) -> Result<(), RegressError> {
        use crate::atomic_file::{write_atomic, AtomicFile, OutputError};
        let mut batch = crate::atomic_file::Batch::new();
        let spec = serde_json::to_string_pretty(&self.spec).map_err(|e| RegressError::Usage(e.to_string()))? + "\n";
        batch.add(write_atomic(&dir.join("regress.json"), spec.as_bytes())?);
        let results = dir.join("results.jsonl");
        let werr = |path: &Path| {
            let path = path.to_path_buf();
            move |source: std::io::Error| RegressError::Output(OutputError::Write { path: path.clone(), source })
        };
        {
            let mut w = std::io::BufWriter::with_capacity(1 << 16, AtomicFile::stage(&results)?);
            let mut reader = self.store.reader()?;
            for e in &self.store.entries {
                let line = reader.line(e)?;
                w.write_all(line).and_then(|_| w.write_all(b"\n")).map_err(werr(&results))?;
            }
            batch.add(w.into_inner().map_err(|e| werr(&results)(e.into_error()))?);
        }
        // Written a line at a time: the run list of a million seeds is 330 MB of UCIS text.
        type Text = fn(&CoverageFile, &mut dyn std::fmt::Write) -> std::fmt::Result;
        let texts: [(&str, Text); 2] = [("coverage.json", |c, w| c.write_text(w)), ("coverage.ucis.xml", |c, w| pmu50_coverage::write_ucis_xml(c, w))];
        for (name, text) in texts {
            let path = dir.join(name);
            let mut w = IoText { out: std::io::BufWriter::with_capacity(1 << 16, AtomicFile::stage(&path)?), err: None };
            if text(&self.coverage, &mut w).is_err() || w.err.is_some() {
                return Err(werr(&path)(w.err.unwrap_or_else(|| std::io::Error::other("formatting failed"))));
            }
            batch.add(w.out.into_inner().map_err(|e| werr(&path)(e.into_error()))?);
        }
        let repros = self.repro_folders(dir)?;
        batch.add(write_atomic(&dir.join("report.html"), report::html(self, extra, &repros).as_bytes())?);
        let missing = dir.join("missing.txt");
        if self.missing.is_empty() {
            batch.remove_stale(missing);
        } else {
            let mut w = std::io::BufWriter::with_capacity(1 << 16, AtomicFile::stage(&missing)?);
            for s in self.missing.iter().flat_map(|r| r.clone()) {
                writeln!(w, "{s}").map_err(werr(&missing))?;
            }
            batch.add(w.into_inner().map_err(|e| werr(&missing)(e.into_error()))?);
        }
        batch.commit()?;
        Ok(())
    }

    /// The signatures whose repro folder `dir/failures/<signature>/` holds a repro; the folders
    /// of signatures no seed fails with are removed (a rerun into the same folder).
    pub fn repro_folders(&self, dir: &Path) -> Result<std::collections::BTreeMap<String, Option<String>>, RegressError> {
        let mut have = std::collections::BTreeMap::new();
        let failures = dir.join("failures");
        match std::fs::symlink_metadata(&failures) {
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(have),
            Err(e) => return Err(file_err(&failures, e)),
            Ok(m) if !m.is_dir() => return Err(file_err(&failures, "is not a folder; the repros of a regression go into the folder failures/")),
            Ok(_) => {}
        }
        let rd = std::fs::read_dir(&failures).map_err(|e| file_err(&failures, e))?;
        for d in rd {
            let d = d.map_err(|e| file_err(&failures, e))?;
            let name = d.file_name().to_string_lossy().into_owned();
            let path = d.path();
            if self.groups.contains_key(&name) {
                if std::fs::symlink_metadata(path.join("repro.toml")).is_ok_and(|m| m.is_file()) {
                    // the picture, when it is a regular file of a sane size
                    let svg = path.join("divergence.svg");
                    let pic = std::fs::symlink_metadata(&svg).ok().filter(|m| m.is_file() && m.len() < 4 << 20).and_then(|_| std::fs::read_to_string(&svg).ok()).and_then(|t| t.find("<svg").map(|i| t[i..].to_string()));
                    have.insert(name, pic);
                }
            } else if std::fs::symlink_metadata(&path).is_ok_and(|m| m.is_dir()) {
                // A signature of an earlier run into this folder: no seed fails with it now.
                std::fs::remove_dir_all(&path).map_err(|e| file_err(&path, format!("cannot remove the stale repro folder: {e}")))?;
            }
        }
        Ok(have)
    }

    /// The summary printed on stdout.
    pub fn text(&self) -> String {
        let (hit, reachable) = self.coverage.closure();
        let scen = scenario_closure(&self.coverage);
        let mut s = format!(
            "regress: {} seeds, {} pass, {} fail, {} error; coverage {hit}/{reachable} bins ({:.1} %), {}/{} of those scenario stimuli can reach ({:.1} %)\n",
            self.seeds(),
            self.pass,
            self.fail,
            self.error,
            pct(hit, reachable),
            scen.0,
            scen.1,
            pct(scen.0, scen.1),
        );
        if let Some(first) = self.missing.first() {
            s.push_str(&format!("missing seeds: {} (first {}); run them with --resume\n", self.missing_count(), first.start));
        }
        for (sig, g) in &self.groups {
            s.push_str(&format!("  fail {sig}: {} seed(s), smallest {}\n", g.count, g.smallest));
        }
        s
    }
}

pub fn pct(a: usize, b: usize) -> f64 {
    if b == 0 {
        100.0
    } else {
        100.0 * a as f64 / b as f64
    }
}

/// Bins that scenario stimuli can reach (not unreachable, not port-level only): hit and total.
pub fn scenario_closure(c: &CoverageFile) -> (usize, usize) {
    let l = layout();
    let mut hit = 0;
    let mut total = 0;
    for (b, info) in c.bins.iter().zip(&l.bins) {
        if info.unreachable.is_none() && !info.port_only {
            total += 1;
            hit += usize::from(b.hits > 0);
        }
    }
    (hit, total)
}

/// Seeds of a random regression handed to the pool at once: what the pool holds in memory (a
/// seed's result with its coverage is about 7 kB) stays bounded whatever the seed range.
const CHUNK: u64 = 4096;

/// Run a regression into `o.out`: the seeds of the spec not yet in the folder (all of them
/// unless resuming), in batches, on `o.jobs` threads. Finished results go to results.jsonl at
/// once; only their index stays in memory.
pub fn run(o: &Options, resume: bool, stop: &AtomicBool, d: &dyn dut::Dut) -> Result<Summary, RegressError> {
    let dir = &o.out;
    crate::atomic_file::create_dir(dir)?;
    let results_path = dir.join("results.jsonl");
    let range = o.spec.seeds();
    let mut total = vec![0u64; layout().bins.len()];
    let (done, complete_len) = if resume {
        let s = folder::scan(&results_path, 0, &range, &mut total, |_, _| {})?;
        (folder::Store::new(vec![results_path.clone()], s.entries)?, s.complete_len)
    } else {
        (folder::Store::new(vec![results_path.clone()], Vec::new())?, 0)
    };
    if !resume {
        // A new run: the folder's previous results are replaced when this run writes them.
        let spec = serde_json::to_string_pretty(&o.spec).map_err(|e| RegressError::Usage(e.to_string()))? + "\n";
        let mut b = crate::atomic_file::Batch::new();
        b.add(crate::atomic_file::write_atomic(&dir.join("regress.json"), spec.as_bytes())?);
        b.add(crate::atomic_file::write_atomic(&results_path, b"")?);
        b.commit()?;
    }
    // A last line torn by an interruption is cut before anything is appended after it.
    let mut appender = folder::open_regular(&results_path, true)?.ok_or_else(|| file_err(&results_path, "cannot be created"))?;
    appender.set_len(complete_len).map_err(|e| file_err(&results_path, e))?;
    let total_seeds = range.end - range.start;
    let mut n_done = done.len() as u64;
    let mut fails = done.entries.iter().filter(|e| e.verdict != folder::Verdict::Pass).count() as u64;
    let mut write = |out: Vec<(SeedResult, Vec<u64>)>, total: &mut Vec<u64>| -> Result<(), RegressError> {
        let mut text = String::new();
        for (r, hits) in &out {
            for (t, h) in total.iter_mut().zip(hits) {
                *t = t.saturating_add(*h);
            }
            text.push_str(&serde_json::to_string(r).map_err(|e| RegressError::Usage(e.to_string()))?);
            text.push('\n');
        }
        appender.write_all(text.as_bytes()).and_then(|_| appender.flush()).map_err(|e| file_err(&results_path, e))?;
        n_done += out.len() as u64;
        fails += out.iter().filter(|(r, _)| r.verdict != "pass").count() as u64;
        if o.progress {
            let l = layout();
            let hit = l.bins.iter().zip(total.iter()).filter(|(b, h)| **h > 0 && b.unreachable.is_none()).count();
            let all = l.bins.iter().filter(|b| b.unreachable.is_none()).count();
            eprintln!("regress: {n_done}/{total_seeds} seeds, {fails} failing, coverage {hit}/{all}");
        }
        Ok(())
    };
    if o.spec.directed {
        // Batch by batch: each batch's bias is the coverage of every seed before it (the
        // folder's, read back in seed order, and this run's).
        let mut before = vec![0u64; total.len()];
        let mut reader = done.reader()?;
        let mut cursor = 0;
        let mut lo = range.start;
        while lo < range.end && !stop.load(Ordering::Relaxed) {
            let hi = (lo + BATCH).min(range.end);
            while let Some(e) = done.entries.get(cursor).filter(|e| e.seed < lo) {
                reader.result(e)?.hits(&mut before).map_err(RegressError::Usage)?;
                cursor += 1;
            }
            let bias = Bias::directed(&before, o.spec.pins).fixing(&o.spec.fixed);
            let todo: Vec<u64> = (lo..hi).filter(|s| !done.contains(*s)).collect();
            let out = run_pool(&o.spec, &todo, &bias, d, o.jobs, o.timeout, stop, |_| Ok(()))?;
            for (_, hits) in &out {
                for (b, h) in before.iter_mut().zip(hits) {
                    *b = b.saturating_add(*h);
                }
            }
            write(out, &mut total)?;
            lo = hi;
        }
    } else {
        // One queue over each chunk of the range: no core waits for the slowest seed of a
        // batch; the results are written in seed order as soon as every seed before them has
        // finished.
        let bias = Bias::uniform().pinned(o.spec.pins).fixing(&o.spec.fixed);
        let mut pending: Vec<(SeedResult, Vec<u64>)> = Vec::new();
        let mut last = std::time::Instant::now();
        let mut lo = range.start;
        while lo < range.end && !stop.load(Ordering::Relaxed) {
            let hi = lo.saturating_add(CHUNK).min(range.end);
            let todo: Vec<u64> = (lo..hi).filter(|s| !done.contains(*s)).collect();
            run_pool(&o.spec, &todo, &bias, d, o.jobs, o.timeout, stop, |ready| {
                pending.extend(ready);
                if pending.len() as u64 >= BATCH || last.elapsed() > Duration::from_secs(2) {
                    last = std::time::Instant::now();
                    write(std::mem::take(&mut pending), &mut total)?;
                }
                Ok(())
            })?;
            lo = hi;
        }
        write(pending, &mut total)?;
    }
    drop(appender);
    drop(done);
    let summary = Summary::build(o.spec.clone(), &[Source::of(dir, &o.spec)])?;
    if o.triage && !stop.load(Ordering::Relaxed) {
        triage::write_repros(&summary, dir, d, o.timeout)?;
    }
    summary.write(dir, None)?;
    Ok(summary)
}

/// Run seeds on `jobs` threads. `ready` is given the results in seed order, each as soon as
/// every seed before it has finished; all of them are also returned, in seed order.
#[allow(clippy::too_many_arguments)]
fn run_pool(
    spec: &RunSpec,
    seeds: &[u64],
    bias: &Bias,
    dut: &dyn dut::Dut,
    jobs: usize,
    timeout: Duration,
    stop: &AtomicBool,
    mut ready: impl FnMut(Vec<(SeedResult, Vec<u64>)>) -> Result<(), RegressError>,
) -> Result<Vec<(SeedResult, Vec<u64>)>, RegressError> {
    let next = AtomicUsize::new(0);
    let place = Place::here(spec.shard.as_ref());
    let (tx, rx) = std::sync::mpsc::channel::<(usize, SeedResult, Vec<u64>)>();
    let mut all: Vec<Option<(SeedResult, Vec<u64>)>> = vec![None; seeds.len()];
    let mut err = None;
    std::thread::scope(|s| {
        for _ in 0..jobs.max(1).min(seeds.len().max(1)) {
            let tx = tx.clone();
            let (next, place) = (&next, &place);
            // A job pipelines its seeds: while the RTL of seed n runs in this job's DUT worker,
            // the model runs seed n+1 here; then n's verdict is taken and n+1 is sent. So the
            // regression waits for the model only where it is slower than the RTL.
            s.spawn(move || {
                let mut running: Option<(usize, Pending)> = None;
                let emit = |k: usize, (mut r, hits): (SeedResult, Vec<u64>)| {
                    r.place = place.clone();
                    tx.send((k, r, hits)).is_ok()
                };
                loop {
                    let k = if stop.load(Ordering::Relaxed) { None } else { Some(next.fetch_add(1, Ordering::Relaxed)) };
                    let stage = k.and_then(|k| seeds.get(k).map(|&seed| (k, start_seed(spec, seed, bias, dut))));
                    if let Some((j, p)) = running.take() {
                        if !emit(j, p.finish(dut, timeout)) {
                            break;
                        }
                    }
                    match stage {
                        None => break,
                        Some((k, Stage::Done(r, hits))) => {
                            if !emit(k, (*r, hits)) {
                                break;
                            }
                        }
                        Some((k, Stage::Pending(mut p))) => match p.send(dut) {
                            Err(e) => {
                                let (r, hits) = seed_result(p.seed, p.start, ("error", Some(*error_failure(0, e.to_string())), p.ticks, p.evaluated, p.readouts_checked, p.hits));
                                if !emit(k, (r, hits)) {
                                    break;
                                }
                            }
                            Ok(()) => running = Some((k, p)),
                        },
                    }
                }
            });
        }
        drop(tx);
        let mut flushed = 0;
        for (k, r, hits) in rx {
            all[k] = Some((r, hits));
            let start = flushed;
            while flushed < all.len() && all[flushed].is_some() {
                flushed += 1;
            }
            if flushed > start && err.is_none() {
                let out = all[start..flushed].iter().flatten().cloned().collect();
                if let Err(e) = ready(out) {
                    err = Some(e);
                    stop.store(true, Ordering::Relaxed);
                }
            }
        }
    });
    if let Some(e) = err {
        return Err(e);
    }
    Ok(all.into_iter().flatten().collect())
}
