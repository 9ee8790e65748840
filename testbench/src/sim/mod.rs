//! Testbench: the digital core in its environment, one clock edge per iteration.
//!
//! The bench is a loop over named parts, evaluated in this order per tick *k* (time k·T,
//! docs/spec.md 6.1):
//! 1. the core's outputs of this tick (all Moore: the `after` of the previous edge);
//! 2. the MPU sees key edges on `sig` (boot scheduled, tracking ends) ([`mpu::Mpu::key_edges`]);
//! 3. the timeline applies the events of this tick: key, MPU register writes, rail faults
//!    ([`Timeline::apply`]); the MPU polls the register map while it is powered;
//! 4. the analog front: Vs2 rail from `vs2_en`/`rail_hi`, second sensor settling towards the
//!    shaft angle at the end of the tick ([0326]), comparators against Vr = Vs2/2 ([0351])
//!    ([`front::AnalogFront::sample`]);
//! 5. the MPU: read-out Vm-boot time after key-on (FIG. 12-13), then tracking of θm ([0115]);
//! 6. one edge of the core with those inputs; observers see the tick;
//! 7. the dark-current meter accounts the tick while the key is off ([0324]);
//! 8. the recorder adds a row to the pulse table at each key-off decision (FIG. 17/18).
//!
//! Observers (VCD writer, change log) get [`Observer::begin`] with the reset state, then every
//! tick, then [`Observer::finish`]. When no observer needs every tick the bench may skip what it
//! can account exactly ([`Stepping`]): idle key-off gaps with [`Pmu50::fast_forward`], and whole
//! repeated key-off periods ([`skip`], docs/spec.md 5.1). Observers that need every tick but can replay a
//! repeated period (the waveform writer, the change log, the markers: [`Observer::replay`],
//! [`replay`]) still let the bench skip whole periods, and emit the skipped copies themselves.
//! Results, and the files written, are identical to stepping every tick (tests/properties.rs,
//! tests/skip_ahead.rs).

pub mod front;
pub mod mpu;
pub mod recorder;
pub mod replay;
pub mod rows;
pub mod skip;

use crate::scenario::{Action, Event, Scenario};
use front::AnalogFront;
use mpu::Mpu;
use pmu50_core::unit::FastForwardError;
use pmu50_core::{Inputs, Internals, Outputs, ParamError, Pmu50, Regs};
use pmu50_env::{DarkCurrentMeter, DarkCurrentReport, EnvError, RailStates};
use recorder::Recorder;
pub use recorder::{PulseLog, PulseRun};
pub use rows::{KeyOffRow, KeyOnRow, PulseRow};
use skip::{At, PeriodSkip, Snapshot};

#[derive(Debug, thiserror::Error)]
pub enum SimError {
    #[error("scenario {scenario}: the core's parameters are not legal: {source}")]
    Core {
        scenario: String,
        #[source]
        source: ParamError,
    },
    #[error("scenario {scenario}: environment model configuration: {source}")]
    EnvSetup {
        scenario: String,
        #[source]
        source: EnvError,
    },
    #[error("scenario {scenario}: environment model failed at t = {time_us} us: {source}")]
    Env {
        scenario: String,
        time_us: f64,
        #[source]
        source: EnvError,
    },
    #[error("scenario {scenario}: fast-forward at t = {time_us} us: {source}")]
    FastForward {
        scenario: String,
        time_us: f64,
        #[source]
        source: FastForwardError,
    },
    #[error("observer used before the bench called `begin`")]
    NotBegun,
    /// An observer (waveform, log, vectors) could not do its work: what it was doing, and why.
    #[error("{what}: {source}")]
    Observer {
        what: String,
        #[source]
        source: Box<dyn std::error::Error + Send + Sync + 'static>,
    },
}

impl SimError {
    /// An observer's error: `what` it was writing (a file, "change log"), and the cause.
    pub fn observer(
        what: impl Into<String>,
        source: impl Into<Box<dyn std::error::Error + Send + Sync + 'static>>,
    ) -> SimError {
        SimError::Observer {
            what: what.into(),
            source: source.into(),
        }
    }
}

/// Analog values of one tick.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct EnvSample {
    pub theta_deg: f64,
    pub sin2_v: f64,
    pub cos2_v: f64,
    pub vs2_v: f64,
    pub vp_v: f64,
    pub vr_v: f64,
    /// θ1 while the first sensor is powered (key on).
    pub theta1_deg: Option<f64>,
    /// The MPU's multi-turn angle while it tracks (key on, after the read-out).
    pub theta_m_deg: Option<f64>,
}

/// Everything visible in one tick, for observers.
pub struct TickView<'a> {
    pub tick: u64,
    pub time_ns: u64,
    /// Registers during this tick (after edge `tick`).
    pub regs: &'a Regs,
    /// Registers after the edge at the end of this tick (at `begin` and `finish`: `regs`).
    pub after: &'a Regs,
    pub ports: &'a Outputs,
    /// Inputs applied during this tick (they act at edge `tick + 1`).
    pub inputs: &'a Inputs,
    pub internals: &'a Internals,
    pub env: &'a EnvSample,
}

pub trait Observer {
    /// Called once before the first tick with the reset state at time 0 (default inputs,
    /// internals and analog values).
    fn begin(&mut self, _v: &TickView<'_>) -> Result<(), SimError> {
        Ok(())
    }
    fn tick(&mut self, v: &TickView<'_>) -> Result<(), SimError>;
    /// Called once after the last tick with the final state at time `ticks`·T. Default:
    /// nothing to flush.
    fn finish(&mut self, _v: &TickView<'_>) -> Result<(), SimError> {
        Ok(())
    }
    /// Whether this observer must see every tick (a waveform must). While one does, the bench
    /// evaluates every tick, except whole repeated periods when it can replay them
    /// ([`Observer::replays_periods`]); otherwise it may skip stretches it accounts exactly.
    fn needs_every_tick(&self) -> bool {
        true
    }
    /// Whether this observer, although it needs every tick, can replay whole repeated key-off
    /// periods ([`Observer::replay`]): when every observer that needs every tick can, the bench
    /// still skips repeated periods (docs/spec.md 5.1), but no idle gaps. Default: no, so the
    /// bench evaluates every tick.
    fn replays_periods(&self) -> bool {
        false
    }
    /// A key-off period may start at tick `k` (called before tick `k` is evaluated, only while
    /// the bench may skip periods): an observer that replays keeps what it saw since the
    /// previous call, the last whole period.
    fn period_boundary(&mut self, _k: u64) -> Result<(), SimError> {
        Ok(())
    }
    /// A key-off or key-on period boundary at tick `k` after which the shaft moves before the
    /// period could be seen twice: the period that starts here is never replayed (the bench
    /// skips a period only while the angle stays constant from its start through one more copy,
    /// [`skip::PeriodSkip::at_boundary`]), so an observer need not record it. The period that
    /// ends here may still be replayed at `k`. Default: [`Observer::period_boundary`].
    fn moving_boundary(&mut self, k: u64) -> Result<(), SimError> {
        self.period_boundary(k)
    }
    /// Whether the observer can now replay the period `[k - len, k)` it has seen.
    fn can_replay(&self, _k: u64, _len: u64) -> bool {
        false
    }
    /// The bench skips `periods` copies of the period `[k - len, k)` (it evaluates tick
    /// `k + periods·len` next): do what `periods·len` more ticks would have done, copy `j` of
    /// that period shifted by `(j + 1)·len` ticks. Called only after [`Observer::can_replay`]
    /// said yes.
    fn replay(&mut self, _k: u64, _periods: u64, _len: u64) -> Result<(), SimError> {
        Ok(())
    }
}

/// An observer built from the reset state at [`Observer::begin`] (a waveform writer declares
/// its signals with their initial values), so that nobody rebuilds the reset state by hand.
pub struct OnBegin<O, F> {
    make: Option<F>,
    inner: Option<O>,
}

impl<O, F> OnBegin<O, F>
where
    O: Observer,
    F: FnOnce(&TickView<'_>) -> Result<O, SimError>,
{
    pub fn new(make: F) -> Self {
        OnBegin {
            make: Some(make),
            inner: None,
        }
    }

    /// The observer, once begun.
    pub fn get(&self) -> Option<&O> {
        self.inner.as_ref()
    }

    /// The observer, once begun (to finish its files after the run).
    pub fn into_inner(self) -> Option<O> {
        self.inner
    }
}

impl<O, F> Observer for OnBegin<O, F>
where
    O: Observer,
    F: FnOnce(&TickView<'_>) -> Result<O, SimError>,
{
    fn begin(&mut self, v: &TickView<'_>) -> Result<(), SimError> {
        let make = self.make.take().ok_or(SimError::NotBegun)?;
        let mut o = make(v)?;
        o.begin(v)?;
        self.inner = Some(o);
        Ok(())
    }
    fn tick(&mut self, v: &TickView<'_>) -> Result<(), SimError> {
        self.inner.as_mut().ok_or(SimError::NotBegun)?.tick(v)
    }
    fn finish(&mut self, v: &TickView<'_>) -> Result<(), SimError> {
        self.inner.as_mut().ok_or(SimError::NotBegun)?.finish(v)
    }
    fn needs_every_tick(&self) -> bool {
        self.inner.as_ref().is_none_or(|o| o.needs_every_tick())
    }
    fn replays_periods(&self) -> bool {
        self.inner.as_ref().is_some_and(|o| o.replays_periods())
    }
    fn period_boundary(&mut self, k: u64) -> Result<(), SimError> {
        self.inner
            .as_mut()
            .ok_or(SimError::NotBegun)?
            .period_boundary(k)
    }
    fn moving_boundary(&mut self, k: u64) -> Result<(), SimError> {
        self.inner
            .as_mut()
            .ok_or(SimError::NotBegun)?
            .moving_boundary(k)
    }
    fn can_replay(&self, k: u64, len: u64) -> bool {
        self.inner.as_ref().is_some_and(|o| o.can_replay(k, len))
    }
    fn replay(&mut self, k: u64, periods: u64, len: u64) -> Result<(), SimError> {
        self.inner
            .as_mut()
            .ok_or(SimError::NotBegun)?
            .replay(k, periods, len)
    }
}

#[derive(Clone, Debug, PartialEq)]
pub struct Check {
    pub name: String,
    pub ok: bool,
    pub detail: String,
}

#[derive(Clone, Debug)]
pub struct RunResult {
    pub name: String,
    pub ticks: u64,
    pub clock_ns: u64,
    /// Ticks evaluated one by one (the rest were fast-forwarded or skipped).
    pub evaluated_ticks: u64,
    /// Ticks skipped as whole repeated key-off periods.
    pub skipped_ticks: u64,
    /// The per-pulse table (run-length aggregated; [`PulseLog::iter`] gives every row).
    pub pulses: PulseLog,
    pub keyons: Vec<KeyOnRow>,
    pub keyoffs: Vec<KeyOffRow>,
    pub final_ports: Outputs,
    pub final_regs: Regs,
    pub dark: DarkCurrentReport,
    pub checks: Vec<Check>,
    pub cnt_width: u8,
}

impl RunResult {
    pub fn passed(&self) -> bool {
        self.checks.iter().all(|c| c.ok)
    }

    /// Successive distinct drive intervals (ms) in force after each key-off pulse, starting with
    /// the interval at the first pulse.
    pub fn si_sequence_ms(&self) -> Vec<f64> {
        let mut out: Vec<f64> = Vec::new();
        // Every row of a run has the run's interval.
        for r in self.pulses.runs() {
            let ms = f64::from(r.first.si) * self.clock_ns as f64 / 1e6;
            if out.last().is_none_or(|&l| (l - ms).abs() > 1e-9) {
                out.push(ms);
            }
        }
        out
    }

    /// The per-pulse event table, as text (golden snapshots, CLI): one line per pulse.
    pub fn pulse_table(&self) -> String {
        self.pulses.table()
    }
}

/// Options of a run.
#[derive(Clone, Copy, Debug)]
pub struct SimOptions {
    /// Skip what can be skipped exactly ([`Stepping::Periods`]): everything when no observer
    /// needs every tick, whole repeated periods when those that do can replay them; `false`:
    /// evaluate every tick ([`Stepping::EveryTick`]).
    pub fast_forward: bool,
}

impl Default for SimOptions {
    fn default() -> Self {
        SimOptions { fast_forward: true }
    }
}

/// How the bench advances time when no observer needs every tick.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stepping {
    /// Every tick evaluated: the reference.
    EveryTick,
    /// Idle key-off gaps (Vs2 off, nothing due) advanced in O(1) with [`Pmu50::fast_forward`].
    IdleGaps,
    /// Idle gaps, and whole key-off periods once they repeat (docs/spec.md 5.1).
    Periods,
}

impl From<SimOptions> for Stepping {
    fn from(o: SimOptions) -> Stepping {
        if o.fast_forward {
            Stepping::Periods
        } else {
            Stepping::EveryTick
        }
    }
}

/// The scenario's timeline: the key level and the events not yet applied.
struct Timeline<'a> {
    events: &'a [Event],
    next: usize,
    ig: bool,
}

impl Timeline<'_> {
    /// Apply the events of tick `k`; returns this tick's inputs with the key level and any
    /// register write or read (the analog inputs are filled in by the front), and whether the
    /// timeline drives the bus this tick (a write or a read: the MPU does not poll then).
    fn apply(&mut self, k: u64, front: &mut AnalogFront) -> (Inputs, bool) {
        let mut inputs = Inputs::default();
        let mut bus = false;
        while let Some(e) = self.events.get(self.next).filter(|e| e.tick == k) {
            match &e.action {
                Action::Ig(v) => self.ig = *v,
                Action::Vs2Fault(v) => front.set_fault(*v),
                Action::Vs2PgLeak(v) => front.set_pg_leak(*v),
                Action::Write { addr, value, .. } => {
                    inputs.bus_we = true;
                    inputs.bus_addr = *addr;
                    inputs.bus_wdata = *value;
                    bus = true;
                }
                Action::Read { addr } => {
                    inputs.bus_addr = *addr;
                    bus = true;
                }
            }
            self.next += 1;
        }
        inputs.ig = self.ig;
        (inputs, bus)
    }

    fn next_tick(&self) -> Option<u64> {
        self.events.get(self.next).map(|e| e.tick)
    }
}

/// Run a scenario.
pub fn run(
    sc: &Scenario,
    opts: SimOptions,
    observers: &mut [&mut dyn Observer],
) -> Result<RunResult, SimError> {
    run_with(sc, opts.into(), observers)
}

/// Run a scenario with the given stepping: as given while no observer needs every tick; whole
/// periods only (no idle gaps) while those that do all replay periods; else every tick.
pub fn run_with(
    sc: &Scenario,
    stepping: Stepping,
    observers: &mut [&mut dyn Observer],
) -> Result<RunResult, SimError> {
    let setup = |source: EnvError| SimError::EnvSetup {
        scenario: sc.name.clone(),
        source,
    };
    let mut core = Pmu50::new(sc.params).map_err(|source| SimError::Core {
        scenario: sc.name.clone(),
        source,
    })?;
    let w = sc.params.cnt_width;
    let clk = sc.clock_ns();
    let env_err = |k: u64, source: EnvError| SimError::Env {
        scenario: sc.name.clone(),
        time_us: (k * clk) as f64 / 1e3,
        source,
    };

    // The parts.
    let mut timeline = Timeline {
        events: &sc.events,
        next: 0,
        ig: false,
    };
    let mut front = AnalogFront::new(&sc.env).map_err(setup)?;
    let mut mpu = Mpu::new(&sc.env).map_err(setup)?;
    let mut meter = DarkCurrentMeter::new(sc.env.dark_current).map_err(|e| setup(e.into()))?;
    let mut rec = Recorder::new(clk, w);

    let mut stepping = stepping;
    let wt = u64::from(sc.params.pw) + u64::from(sc.params.pi) + u64::from(sc.params.ps);
    let mut evaluated = 0u64;
    let mut skipped = 0u64;
    let mut env = EnvSample::default();
    // Outputs of the current tick: from reset, then the `after` of each edge (Moore outputs).
    let mut out = core.peek();

    let reset = *core.regs();
    for o in observers.iter_mut() {
        o.begin(&TickView {
            tick: 0,
            time_ns: 0,
            regs: &reset,
            after: &reset,
            ports: &out,
            inputs: &Inputs::default(),
            internals: &Internals::default(),
            env: &env,
        })?;
    }
    // Observers that need every tick: if one of them cannot replay a skipped period, every tick
    // is evaluated; if all can, whole repeated periods are still skipped (and replayed to them),
    // but no idle gap (nobody could replay the timer counting through it).
    let replaying = observers.iter().any(|o| o.needs_every_tick());
    if observers
        .iter()
        .any(|o| o.needs_every_tick() && !o.replays_periods())
    {
        stepping = Stepping::EveryTick;
    }
    let idle_gaps = stepping != Stepping::EveryTick && !replaying;
    let mut periods = (stepping == Stepping::Periods).then(PeriodSkip::new);

    let mut k = 0u64;
    while k < sc.ticks {
        let t_ns = k * clk;
        mpu.key_edges(k, t_ns, &out, &sc.motor);

        // Whole repeated periods, checked at each period start: with the key off, each drive
        // interval (timer at 0, Vs2 off); with the key on, every on-key sampling period that
        // also starts a round of the MPU's polling of the register map (the bench then repeats
        // once the sensor has settled and the MPU's tracking holds still).
        if let Some(ps) = periods.as_mut() {
            let tmr0 = core.regs().timing_generator.tmr == 0;
            // (A pending MPU boot is due at a tick of its own, so no key-on period repeats
            // before the read-out.)
            let boundary = if out.sig {
                tmr0 && k.is_multiple_of(mpu::POLL_CYCLE) && mpu.idle()
            } else {
                tmr0 && front.quiet_while_off()
            };
            if boundary {
                let at = At {
                    tick: k,
                    snap: Snapshot {
                        regs: *core.regs(),
                        front: front.state(),
                        mpu: mpu.state().clone(),
                        ig: timeline.ig,
                    },
                    next_event: timeline.next,
                    next_event_tick: timeline.next_tick(),
                    meter: meter.on_times(),
                    rows: rec.take_period_count(),
                    motor: &sc.motor,
                    clock_ns: clk,
                    end_tick: sc.ticks,
                };
                if replaying {
                    // The period starting here can be replayed at the next boundary only if the
                    // angle stays constant from tick k + 1 through at least one more tick
                    // (`PeriodSkip::at_boundary` asks for a whole period and its copy).
                    let until = sc.motor.constant_until_ns((k + 1) * clk);
                    let still = until == u64::MAX || until / clk >= k + 2;
                    for o in observers.iter_mut() {
                        if still {
                            o.period_boundary(k)?;
                        } else {
                            o.moving_boundary(k)?;
                        }
                    }
                }
                let skip = ps.at_boundary(at).filter(|s| {
                    observers
                        .iter()
                        .all(|o| !o.needs_every_tick() || o.can_replay(k, s.len))
                });
                if let Some(s) = skip {
                    for o in observers.iter_mut().filter(|o| o.needs_every_tick()) {
                        o.replay(k, s.periods, s.len)?;
                    }
                    meter.repeat(s.meter, s.periods);
                    if s.rows == 1 {
                        rec.log.repeat_last(s.periods, s.len);
                    }
                    k += s.periods * s.len;
                    skipped += s.periods * s.len;
                    continue;
                }
            }
        }

        let (mut inputs, bus) = timeline.apply(k, &mut front);
        if !bus {
            mpu.poll_bus(k, &out, &mut inputs);
        }

        // Fast-forward an idle key-off gap: Vs2 off, nothing scheduled, nobody watching.
        if idle_gaps && !out.sig && !out.vs2_en && !out.sr && !bus && mpu.idle() {
            let tmr = u64::from(core.regs().timing_generator.tmr);
            let si = u64::from(core.regs().drive_interval.si);
            if tmr >= wt && tmr < si {
                let until_event = timeline.next_tick().map_or(u64::MAX, |e| e - k);
                let n = (si - tmr).min(until_event).min(sc.ticks - k);
                let idle = Inputs {
                    ig: timeline.ig,
                    ..Inputs::default()
                };
                if n > 1 && !front.pg_leak() && core.quiet_ticks(&idle) >= n {
                    front.unpowered(clk).map_err(|e| env_err(k, e))?;
                    meter.tick(
                        out.sig,
                        RailStates {
                            vm: out.vm_en,
                            vs1: out.vs1_en,
                            vs2: false,
                            vp: out.vp_en,
                        },
                        n * clk,
                    );
                    core.fast_forward(n, &idle)
                        .map_err(|source| SimError::FastForward {
                            scenario: sc.name.clone(),
                            time_us: t_ns as f64 / 1e3,
                            source,
                        })?;
                    k += n;
                    out = core.peek();
                    continue;
                }
            }
        }

        // Analog front of this tick; the shaft angle is the one at the end of the tick.
        let theta = sc.motor.angle_at(t_ns + clk);
        let f = front.sample(&out, theta, clk).map_err(|e| env_err(k, e))?;
        inputs.vs2_ok = front.power_good(&f, &out);
        inputs.cmp_s = f.bits.cs;
        inputs.cmp_c = f.bits.cc;

        // MPU: read-out at boot, then tracking ([0108]-[0116]).
        let (theta1, theta_m) = mpu
            .read_and_track(k, t_ns, &core, &out, theta, &f)
            .map_err(|e| env_err(k, e))?;

        env = EnvSample {
            theta_deg: theta,
            sin2_v: f.sin2_v,
            cos2_v: f.cos2_v,
            vs2_v: f.vs2_v,
            vp_v: f.vp_v,
            vr_v: f.vs2_v / 2.0,
            theta1_deg: theta1,
            theta_m_deg: theta_m,
        };

        // One clock edge.
        let regs_before = *core.regs();
        let pmu50_core::TracedStep {
            internals, after, ..
        } = core.step_traced(&inputs);
        evaluated += 1;
        let regs_after = *core.regs();
        for o in observers.iter_mut() {
            o.tick(&TickView {
                tick: k,
                time_ns: t_ns,
                regs: &regs_before,
                after: &regs_after,
                ports: &out,
                inputs: &inputs,
                internals: &internals,
                env: &env,
            })?;
        }

        // Dark-current meter and recorder.
        meter.tick(
            out.sig,
            RailStates {
                vm: out.vm_en,
                vs1: out.vs1_en,
                vs2: f.vs2_v > 0.0,
                vp: out.vp_en,
            },
            clk,
        );
        if internals.first {
            mpu.first_sample(&after, theta);
        }
        rec.edge(k, clk, &internals, &after);
        out = after;
        k += 1;
    }

    let final_ports = core.peek();
    let final_regs = *core.regs();
    let idle = Internals::default();
    let last_in = Inputs {
        ig: timeline.ig,
        ..Inputs::default()
    };
    for o in observers.iter_mut() {
        o.finish(&TickView {
            tick: sc.ticks,
            time_ns: sc.ticks * clk,
            regs: &final_regs,
            after: &final_regs,
            ports: &final_ports,
            inputs: &last_in,
            internals: &idle,
            env: &env,
        })?;
    }

    let mut res = RunResult {
        name: sc.name.clone(),
        ticks: sc.ticks,
        clock_ns: clk,
        evaluated_ticks: evaluated,
        skipped_ticks: skipped,
        pulses: rec.log,
        keyons: mpu.keyons,
        keyoffs: mpu.keyoffs,
        final_ports,
        final_regs,
        dark: meter.report(),
        checks: Vec::new(),
        cnt_width: w,
    };
    res.checks = checks(sc, &res);
    Ok(res)
}

fn checks(sc: &Scenario, r: &RunResult) -> Vec<Check> {
    let x = &sc.expect;
    let mut out = Vec::new();
    if let Some(want) = &x.si_sequence_ms {
        let got = r.si_sequence_ms();
        let ok = got.len() == want.len() && got.iter().zip(want).all(|(a, b)| (a - b).abs() < 1e-6);
        out.push(Check {
            name: "si_sequence_ms".into(),
            ok,
            detail: format!("expected {want:?}, got {got:?}"),
        });
    }
    if let Some(tol) = x.readout_within_deg {
        let worst = r
            .keyons
            .iter()
            .map(|k| k.error_deg.abs())
            .fold(0.0, f64::max);
        let ok = !r.keyons.is_empty() && worst <= tol;
        out.push(Check {
            name: "readout_within_deg".into(),
            ok,
            detail: if r.keyons.is_empty() {
                "no key-on read-out happened".into()
            } else {
                format!(
                    "worst |theta_m - true| = {worst:.4} deg over {} read-outs, limit {tol}",
                    r.keyons.len()
                )
            },
        });
    }
    if let Some(want) = x.diag {
        out.push(Check {
            name: "diag".into(),
            ok: r.final_ports.diag == want,
            detail: format!("expected {want}, got {}", r.final_ports.diag),
        });
    }
    if let Some(want) = x.quadrant_skip {
        out.push(Check {
            name: "quadrant_skip".into(),
            ok: r.final_ports.quadrant_skip == want,
            detail: format!("expected {want}, got {}", r.final_ports.quadrant_skip),
        });
    }
    out
}
