//! One seed: its scenario run on the model with the regression's checks and coverage, then its
//! recording handed to the DUT ([`crate::dut::Dut`]); the verdict. Shared by the seeds of a run
//! ([`crate::pool`]), the shrinking of a failure ([`crate::triage`]) and `--repro`
//! ([`check_scenario`]).

use crate::check::{Failure, SeedChecks};
use crate::dut;
use crate::gen::{Bias, Stimulus};
use crate::lockstep;
use crate::spec::sparse;
use crate::spec::Place;
use crate::spec::RunSpec;
use crate::spec::SeedResult;
use crate::spec::Verdict;
use pmu50_coverage::layout;
use pmu50_testbench::scenario::Scenario;
use pmu50_testbench::sim::{self, SimOptions};
use std::path::PathBuf;
use std::time::{Duration, Instant};

/// A seed after its model run: its result, or its recording for the RTL, which
/// [`Pending::send`] hands to the DUT.
pub(crate) enum Stage<'a> {
    /// Boxed: a seed's result is large beside a seed in flight.
    Done(Box<SeedResult>, Vec<u64>),
    Pending(Pending<'a>),
}

/// A seed whose model run passed and whose RTL check is to run or running.
pub(crate) struct Pending<'a> {
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
    pub(crate) fn send(&mut self, d: &'a dyn dut::Dut) -> Result<(), dut::DutError> {
        if let Some(rec) = self.rec.take() {
            self.flight = Some(d.send(&self.sc, rec)?);
        }
        Ok(())
    }

    /// The seed's result, with the verdict of the DUT (sent or not yet).
    pub(crate) fn finish(self, d: &'a dyn dut::Dut, timeout: Duration) -> (SeedResult, Vec<u64>) {
        let (seed, start) = (self.seed, self.start);
        let name = self.sc.name.clone();
        let (mut r, hits) = seed_result(seed, start, self.verdict(d, timeout));
        r.code = d.take_code_coverage(&name);
        (r, hits)
    }

    /// The seed's result when its recording could not be handed to the DUT: `error`.
    pub(crate) fn failed(self, e: dut::DutError) -> (SeedResult, Vec<u64>) {
        seed_result(
            self.seed,
            self.start,
            (
                Verdict::Error,
                Some(*error_failure(0, e.to_string())),
                self.ticks,
                self.evaluated,
                self.readouts_checked,
                self.hits,
            ),
        )
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
            Ok(None) => (Verdict::Pass, None),
            Ok(Some(f)) => (Verdict::Fail, Some(f)),
            Err(e) => (Verdict::Error, Some(*error_failure(0, e.to_string()))),
        };
        (
            verdict,
            failure,
            self.ticks,
            self.evaluated,
            self.readouts_checked,
            self.hits,
        )
    }
}

pub(crate) fn seed_result(seed: u64, start: Instant, e: Evaluated) -> (SeedResult, Vec<u64>) {
    let (verdict, failure, ticks, evaluated, readouts_checked, hits) = e;
    let r = SeedResult {
        seed,
        verdict,
        ticks,
        evaluated,
        readouts_checked,
        wall_ms: (start.elapsed().as_secs_f64() * 1e4).round() / 10.0,
        view: None,
        failure,
        place: Place::default(),
        cov: sparse(&hits),
        code: None,
    };
    (r, hits)
}

/// The model's part of a seed.
pub(crate) fn start_seed<'a>(
    spec: &RunSpec,
    seed: u64,
    bias: &Bias,
    d: &'a dyn dut::Dut,
) -> Stage<'a> {
    let start = Instant::now();
    let stim = Stimulus::generate(seed, bias);
    match evaluate_model(spec, &stim, d) {
        Ok(Phase::Final(e)) => {
            let (r, hits) = seed_result(seed, start, e);
            Stage::Done(Box::new(r), hits)
        }
        Ok(Phase::Dut {
            sc,
            rec,
            ticks,
            evaluated,
            readouts_checked,
            hits,
        }) => Stage::Pending(Pending {
            seed,
            start,
            sc,
            rec: Some(rec),
            flight: None,
            ticks,
            evaluated,
            readouts_checked,
            hits,
        }),
        Err(f) => {
            let (r, hits) = seed_result(
                seed,
                start,
                (
                    Verdict::Error,
                    Some(*f),
                    0,
                    0,
                    0,
                    vec![0; layout().bins.len()],
                ),
            );
            Stage::Done(Box::new(r), hits)
        }
    }
}

pub type Evaluated = (Verdict, Option<Failure>, u64, u64, u64, Vec<u64>);

pub(crate) fn error_failure(tick: u64, detail: String) -> Box<Failure> {
    Box::new(Failure {
        kind: "error".into(),
        tick,
        signal: "-".into(),
        expected: "-".into(),
        got: "-".into(),
        block: "-".into(),
        fig: "-".into(),
        diverging: Vec::new(),
        detail,
    })
}

/// What the model's run of a seed leaves to do.
pub(crate) enum Phase {
    /// The verdict (the model failed, or the DUT is the model).
    Final(Evaluated),
    /// The model passed; the RTL is to run on this recording.
    Dut {
        sc: Box<Scenario>,
        rec: dut::Recorded,
        ticks: u64,
        evaluated: u64,
        readouts_checked: u64,
        hits: Vec<u64>,
    },
}

/// The verdict of one stimulus: the model's checks, then the DUT (shared by the seeds, the
/// shrinking of a failure and `--repro`).
pub fn evaluate(
    spec: &RunSpec,
    stim: &Stimulus,
    d: &dyn dut::Dut,
    timeout: Duration,
) -> Result<Evaluated, Box<Failure>> {
    match evaluate_model(spec, stim, d)? {
        Phase::Final(e) => Ok(e),
        Phase::Dut {
            sc,
            rec,
            ticks,
            evaluated,
            readouts_checked,
            hits,
        } => {
            let p = Pending {
                seed: stim.seed,
                start: Instant::now(),
                sc,
                rec: Some(rec),
                flight: None,
                ticks,
                evaluated,
                readouts_checked,
                hits,
            };
            let name = p.sc.name.clone();
            let e = p.verdict(d, timeout);
            // a shrink try's code coverage is not a seed's
            let _ = d.take_code_coverage(&name);
            Ok(e)
        }
    }
}

/// The model's run of a stimulus with its checks, recording what the DUT needs: the inputs of
/// every tick in memory (verilator) or a vector file (icarus).
pub(crate) fn evaluate_model(
    spec: &RunSpec,
    stim: &Stimulus,
    d: &dyn dut::Dut,
) -> Result<Phase, Box<Failure>> {
    let name = format!("regress_{}", stim.seed);
    let text = stim.to_toml(&name);
    let path = PathBuf::from(format!("{name}.toml"));
    let sc = Scenario::parse(&text, &path.display().to_string(), &name, &path).map_err(|e| {
        error_failure(
            0,
            format!("the generator made a scenario the parser refuses: {e}"),
        )
    })?;
    let needs = d.needs();
    let vec = match needs {
        dut::Needs::Vectors => Some(
            d.vector_file(&sc)
                .map_err(|e| error_failure(0, e.to_string()))?,
        ),
        _ => None,
    };
    let mut writer = match &vec {
        Some(f) => Some(
            pmu50_testbench::observers::vectors::VectorWriter::new(
                std::io::BufWriter::new(f.as_file()),
                &sc,
            )
            .map_err(|e| error_failure(0, e.to_string()))?,
        ),
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
        w.into_inner()
            .flush()
            .map_err(|e| error_failure(0, format!("vector file: {e}")))?;
    }
    drop(writer);
    let hits = checks.coverage.hits().to_vec();
    let failure = model_failure(&checks, &res);
    if failure.is_none() {
        let rec = match (recorder, vec) {
            (Some(r), _) => Some(dut::Recorded::Inputs(r.inputs)),
            (None, Some(v)) => Some(dut::Recorded::Vectors(v)),
            (None, None) => None,
        };
        if let Some(rec) = rec {
            return Ok(Phase::Dut {
                sc: Box::new(sc),
                rec,
                ticks: res.ticks,
                evaluated: res.evaluated_ticks,
                readouts_checked: checks.readouts_checked,
                hits,
            });
        }
    }
    let verdict = if failure.is_some() {
        Verdict::Fail
    } else {
        Verdict::Pass
    };
    Ok(Phase::Final((
        verdict,
        failure,
        res.ticks,
        res.evaluated_ticks,
        checks.readouts_checked,
        hits,
    )))
}

/// Check one scenario (a repro) as a seed is checked: `Ok(None)` it passes.
pub fn check_scenario(
    spec: &RunSpec,
    sc: &Scenario,
    d: &dyn dut::Dut,
    timeout: Duration,
) -> Result<Option<Failure>, dut::DutError> {
    let (checks, res) =
        run_model(sc, spec.check_spec, &mut []).map_err(|e| dut::DutError::Tool(e.to_string()))?;
    if let Some(f) = model_failure(&checks, &res) {
        return Ok(Some(f));
    }
    dut::check(d, sc, timeout)
}

/// The model's verdict on a run: the first failure of its checks and invariants, else the first
/// `[expect]` of the scenario that does not hold (the same for a seed, a shrink try and a repro).
fn model_failure(checks: &SeedChecks, res: &sim::RunResult) -> Option<Failure> {
    if let Some(f) = &checks.failure {
        return Some(f.clone());
    }
    res.checks.iter().find(|c| !c.ok).map(|c| Failure {
        kind: "expect".into(),
        tick: res.ticks,
        signal: c.name.clone(),
        expected: "-".into(),
        got: "-".into(),
        block: "-".into(),
        fig: "-".into(),
        diverging: Vec::new(),
        detail: c.detail.clone(),
    })
}

/// The model's run of a scenario with the regression's checks and coverage.
pub fn run_model(
    sc: &Scenario,
    check_spec: bool,
    extra: &mut [&mut dyn sim::Observer],
) -> Result<(SeedChecks, sim::RunResult), sim::SimError> {
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
