//! Testbench: the digital core in its environment, one clock edge per iteration.
//!
//! Per tick *k* (time k·T, see docs/spec.md 6.1):
//! 1. read the core's outputs of this tick (`peek`; all outputs are Moore);
//! 2. apply the timeline events of this tick (ignition, MPU register writes, rail faults);
//! 3. environment: Vs2 rail voltage from `vs2_en`/`rail_hi`, motor angle at the end of the tick,
//!    second sensor settling ([0326]), comparators against Vr = Vs2/2 ([0351]);
//! 4. one edge of the core with those inputs;
//! 5. MPU: read-out Vm-boot time after key-on (FIG. 12-13), then tracking of θm ([0115]);
//!    dark-current accounting while the key is off.
//!
//! While the key is on and the timeline has no write for the tick, the MPU model polls the
//! register map over the bus, one address per tick in map order, so the register file's
//! registered read path (`bus_addr` -> `bus_rdata`) is exercised in every waveform and vector
//! file. Its read-out uses the read mux of the same cycle (`Pmu50::read`), which is what the
//! polled `bus_rdata` shows one tick later.
//!
//! Observers (VCD writer, change log) see every tick. Without observers the bench fast-forwards
//! idle key-off gaps with [`Pmu50::fast_forward`]; results are identical (tested).

use crate::scenario::{Action, Scenario};
use pmu50_core::drive_interval_changing_56b::{Fig17, Fig18};
use pmu50_core::register_file::{addr, MAP};
use pmu50_core::{Inputs, Internals, Outputs, Pmu50, Regs};
use pmu50_env::{
    theta2_deg, wrap_360, AngleTracker, ComparatorPair, DarkCurrentMeter, DarkCurrentReport, KeyOnReadout,
    RailStates, Readout, RotationAngles, Sensor1, Sensor2,
};

#[derive(Debug, thiserror::Error)]
pub enum SimError {
    #[error("scenario {scenario}: environment model failed at t = {time_us} us: {msg}")]
    Env { scenario: String, time_us: f64, msg: String },
    #[error("scenario {scenario}: {msg}")]
    Setup { scenario: String, msg: String },
    #[error("{0}")]
    Observer(String),
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
    pub ports: &'a Outputs,
    /// Inputs applied during this tick (they act at edge `tick + 1`).
    pub inputs: &'a Inputs,
    pub internals: &'a Internals,
    pub env: &'a EnvSample,
}

pub trait Observer {
    fn tick(&mut self, v: &TickView<'_>) -> Result<(), SimError>;
    /// Called once after the last tick with the final state at time `ticks`·T.
    fn finish(&mut self, v: &TickView<'_>) -> Result<(), SimError>;
}

/// One row of the per-pulse event table: the state after a key-off sampling edge.
#[derive(Clone, Debug, PartialEq)]
pub struct PulseRow {
    /// Edge number (the sample was taken at the end of tick `tick - 1`).
    pub tick: u64,
    pub time_ns: u64,
    pub cs: bool,
    pub cc: bool,
    pub hist_s: bool,
    pub hist_c: bool,
    pub cnt_r: u8,
    pub si: u16,
    pub cnt_s: i32,
    pub cnt_c: i32,
    pub fig17: Fig17,
    pub fig18: Fig18,
}

/// One key-on read-out by the MPU.
#[derive(Clone, Debug, PartialEq)]
pub struct KeyOnRow {
    pub tick: u64,
    pub time_ns: u64,
    /// True multi-turn angle relative to the turn the counters started in.
    pub true_deg: f64,
    pub readout: KeyOnReadout,
    /// θm, θo = θm·Rg, θi = θo + θt at the read-out ([0116]).
    pub angles: RotationAngles,
    pub error_deg: f64,
    /// STATUS.diag and STATUS.quadrant_skip as read by the MPU.
    pub diag: bool,
    pub quadrant_skip: bool,
    /// θ1 against θ2 diagnosis ([0118]).
    pub theta_abnormal: bool,
}

/// θm at the moment the key goes off (end of tracking), against the true angle.
#[derive(Clone, Debug, PartialEq)]
pub struct KeyOffRow {
    pub tick: u64,
    pub true_deg: f64,
    pub theta_m_deg: f64,
    /// θm, θo, θi as tracked up to key-off ([0115]-[0116]).
    pub angles: RotationAngles,
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
    /// Ticks evaluated one by one (the rest were fast-forwarded).
    pub evaluated_ticks: u64,
    pub pulses: Vec<PulseRow>,
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
        for p in &self.pulses {
            let ms = f64::from(p.si) * self.clock_ns as f64 / 1e6;
            if out.last().is_none_or(|&l| (l - ms).abs() > 1e-9) {
                out.push(ms);
            }
        }
        out
    }

    /// The per-pulse event table, as text (golden snapshots, CLI).
    pub fn pulse_table(&self) -> String {
        let mut s = String::from("    time_us  cs cc hist_s hist_c cnt_r  si_ms  cnt_s  cnt_c  fig17       fig18\n");
        for p in &self.pulses {
            s += &format!(
                "{:>11} {:>3} {:>2} {:>6} {:>6} {:>5} {:>6} {:>6} {:>6}  {:<11} {:?}\n",
                p.time_ns / 1_000,
                u8::from(p.cs),
                u8::from(p.cc),
                u8::from(p.hist_s),
                u8::from(p.hist_c),
                p.cnt_r,
                format!("{:.1}", f64::from(p.si) * self.clock_ns as f64 / 1e6),
                p.cnt_s,
                p.cnt_c,
                format!("{:?}", p.fig17),
                p.fig18
            );
        }
        s
    }
}

/// Options of a run.
#[derive(Clone, Copy, Debug)]
pub struct SimOptions {
    /// Skip idle key-off gaps when no observer is attached.
    pub fast_forward: bool,
}

impl Default for SimOptions {
    fn default() -> Self {
        SimOptions { fast_forward: true }
    }
}

fn sext(v: u16, w: u8) -> i32 {
    pmu50_core::updown_counter_58cd::sext(v, w)
}

/// Run a scenario.
pub fn run(sc: &Scenario, opts: SimOptions, observers: &mut [&mut dyn Observer]) -> Result<RunResult, SimError> {
    let setup = |m: String| SimError::Setup { scenario: sc.name.clone(), msg: m };
    let mut core = Pmu50::new(sc.params).map_err(|e| setup(e.to_string()))?;
    let w = sc.params.cnt_width;
    let clk = sc.clock_ns();
    let mut sensor2 = Sensor2::new(sc.env.sensor2).map_err(|e| setup(e.to_string()))?;
    let cmp = ComparatorPair::new(sc.env.comparator).map_err(|e| setup(e.to_string()))?;
    let sensor1 = Sensor1::new(sc.env.sensor1).map_err(|e| setup(e.to_string()))?;
    let readout = Readout::new(sc.env.readout).map_err(|e| setup(e.to_string()))?;
    let mut meter = DarkCurrentMeter::new(sc.env.dark_current).map_err(|e| setup(e.to_string()))?;
    let env_err = |k: u64, m: String| SimError::Env { scenario: sc.name.clone(), time_us: (k * clk) as f64 / 1e3, msg: m };

    let ff = opts.fast_forward && observers.is_empty();
    let wt = u64::from(sc.params.pw) + u64::from(sc.params.pi) + u64::from(sc.params.ps);

    let mut ig = false;
    let mut fault = false;
    let mut next_event = 0usize;
    let mut pulses = Vec::new();
    let mut keyons = Vec::new();
    let mut keyoffs = Vec::new();
    let mut boot_at: Option<u64> = None;
    let mut tracker: Option<AngleTracker> = None;
    let mut turn0: Option<f64> = None;
    let mut prev_sig = false;
    let mut evaluated = 0u64;
    let mut env = EnvSample::default();
    let mut k = 0u64;
    // Outputs of the current tick: from reset, then the `after` of each edge (Moore outputs).
    let mut out = core.peek();

    while k < sc.ticks {
        let t_ns = k * clk;

        // Key edges seen by the MPU model.
        if out.sig && !prev_sig {
            boot_at = Some(k + sc.env.mpu_boot_ticks);
        }
        if !out.sig && prev_sig {
            boot_at = None;
            if let Some(tr) = tracker.take() {
                let true_deg = motor_rel(sc, t_ns, turn0);
                keyoffs.push(KeyOffRow { tick: k, true_deg, theta_m_deg: tr.theta_m_deg(), angles: tr.angles(sc.env.theta_t_deg) });
            }
        }
        prev_sig = out.sig;

        // Timeline events of this tick.
        let mut inputs = Inputs::default();
        while next_event < sc.events.len() && sc.events[next_event].tick == k {
            match &sc.events[next_event].action {
                Action::Ig(v) => ig = *v,
                Action::Vs2Fault(v) => fault = *v,
                Action::Write { addr, value, .. } => {
                    inputs.bus_we = true;
                    inputs.bus_addr = *addr;
                    inputs.bus_wdata = *value;
                }
            }
            next_event += 1;
        }
        inputs.ig = ig;
        if out.sig && !inputs.bus_we {
            inputs.bus_addr = MAP[(k % MAP.len() as u64) as usize].1;
        }

        // Fast-forward an idle key-off gap: Vs2 off, nothing scheduled, nobody watching.
        if ff && !out.sig && !out.vs2_en && !out.sr && !inputs.bus_we && boot_at.is_none() {
            let tmr = u64::from(core.regs().timing_generator.tmr);
            let si = u64::from(core.regs().drive_interval.si);
            if tmr >= wt && tmr < si {
                let until_event = sc.events.get(next_event).map_or(u64::MAX, |e| e.tick - k);
                let n = (si - tmr).min(until_event).min(sc.ticks - k);
                let idle = Inputs { ig, ..Inputs::default() };
                if n > 1 && core.quiet_ticks(&idle) >= n {
                    sensor2.step(0.0, 0.0, clk).map_err(|e| env_err(k, e.to_string()))?;
                    let rails = RailStates { vm: out.vm_en, vs1: out.vs1_en, vs2: false, vp: out.vp_en };
                    meter.tick(out.sig, rails, n * clk);
                    core.fast_forward(n, &idle).map_err(|e| env_err(k, e.to_string()))?;
                    k += n;
                    out = core.peek();
                    continue;
                }
            }
        }

        // Environment of this tick.
        let vs2_nominal = if out.rail_hi { sc.env.vcc1_v } else { sc.env.vcc2_v };
        let vs2_v = if out.vs2_en && !fault { vs2_nominal } else { 0.0 };
        let theta = sc.motor.angle_at(t_ns + clk);
        let (sin2, cos2) = sensor2.step(vs2_v, theta, clk).map_err(|e| env_err(k, e.to_string()))?;
        let bits = cmp.compare(vs2_v, sin2, cos2);
        inputs.vs2_ok = vs2_v > 0.0;
        inputs.cmp_s = bits.cs;
        inputs.cmp_c = bits.cc;

        // MPU: read-out at boot, then tracking ([0108]-[0116]).
        let theta1 = if out.vs1_en { Some(sensor1.theta1_deg(wrap_360(theta)).map_err(|e| env_err(k, e.to_string()))?) } else { None };
        if let (Some(b), Some(t1)) = (boot_at, theta1) {
            if k == b {
                let cnt_s = core.read(addr::CNT_S) as i16;
                let cnt_c = core.read(addr::CNT_C) as i16;
                let status = core.read(addr::STATUS);
                let r = readout.key_on(cnt_s, cnt_c, t1).map_err(|e| env_err(k, e.to_string()))?;
                // θ1 is the angle at the end of this tick; compare at that same instant.
                let true_deg = theta - turn0.unwrap_or(0.0);
                let th2 = theta2_deg(vs2_v, sin2, cos2);
                keyons.push(KeyOnRow {
                    tick: k,
                    time_ns: t_ns,
                    true_deg,
                    error_deg: r.theta_m_deg - true_deg,
                    diag: status >> pmu50_core::register_file::status::DIAG & 1 == 1,
                    quadrant_skip: status >> pmu50_core::register_file::status::QUADRANT_SKIP & 1 == 1,
                    theta_abnormal: readout.theta_abnormal(t1, th2),
                    readout: r,
                    angles: readout.tracker(&r).angles(sc.env.theta_t_deg),
                });
                tracker = Some(readout.tracker(&r));
                boot_at = None;
            }
        }
        if let (Some(tr), Some(t1)) = (tracker.as_mut(), theta1) {
            tr.update(t1).map_err(|e| env_err(k, e.to_string()))?;
        }

        env = EnvSample {
            theta_deg: theta,
            sin2_v: sin2,
            cos2_v: cos2,
            vs2_v,
            vp_v: if out.rail_hi { sc.env.vcc1_v } else { sc.env.vcc2_v },
            vr_v: vs2_v / 2.0,
            theta1_deg: theta1,
            theta_m_deg: tracker.as_ref().map(|t| t.theta_m_deg()),
        };

        // One clock edge.
        let regs_before = *core.regs();
        let (_, internals, after) = core.step_traced(&inputs);
        evaluated += 1;
        for o in observers.iter_mut() {
            o.tick(&TickView { tick: k, time_ns: t_ns, regs: &regs_before, ports: &out, inputs: &inputs, internals: &internals, env: &env })?;
        }
        meter.tick(out.sig, RailStates { vm: out.vm_en, vs1: out.vs1_en, vs2: vs2_v > 0.0, vp: out.vp_en }, clk);

        if internals.first {
            // The counters' origin is the turn in which the chip's first sample put the shaft:
            // the turn that brings this angle nearest the middle of the sampled quadrant (at a
            // boundary the chip may see either side, e.g. a settling sine exactly at 0 deg).
            let q0 = match (after.cs, after.cc) {
                (true, true) => 0.0,
                (true, false) => 1.0,
                (false, false) => 2.0,
                (false, true) => 3.0,
            };
            turn0 = Some(((theta - (q0 * 90.0 + 45.0)) / 360.0).round() * 360.0);
        }
        if internals.fig17 != Fig17::Idle {
            pulses.push(PulseRow {
                tick: k + 1,
                time_ns: (k + 1) * clk,
                cs: after.cs,
                cc: after.cc,
                hist_s: after.hist_s,
                hist_c: after.hist_c,
                cnt_r: after.cnt_r,
                si: after.si,
                cnt_s: sext(after.cnt_s, w),
                cnt_c: sext(after.cnt_c, w),
                fig17: internals.fig17,
                fig18: internals.fig18,
            });
        }
        out = after;
        k += 1;
    }

    let final_ports = core.peek();
    let final_regs = *core.regs();
    let idle = Internals::default();
    let last_in = Inputs { ig, ..Inputs::default() };
    for o in observers.iter_mut() {
        o.finish(&TickView { tick: sc.ticks, time_ns: sc.ticks * clk, regs: &final_regs, ports: &final_ports, inputs: &last_in, internals: &idle, env: &env })?;
    }

    let mut res = RunResult {
        name: sc.name.clone(),
        ticks: sc.ticks,
        clock_ns: clk,
        evaluated_ticks: evaluated,
        pulses,
        keyons,
        keyoffs,
        final_ports,
        final_regs,
        dark: meter.report(),
        checks: Vec::new(),
        cnt_width: w,
    };
    res.checks = checks(sc, &res);
    Ok(res)
}

/// True angle relative to the turn in which the counters took their first sample.
fn motor_rel(sc: &Scenario, t_ns: u64, turn0: Option<f64>) -> f64 {
    sc.motor.angle_at(t_ns) - turn0.unwrap_or(0.0)
}

fn checks(sc: &Scenario, r: &RunResult) -> Vec<Check> {
    let x = &sc.expect;
    let mut out = Vec::new();
    if let Some(want) = &x.si_sequence_ms {
        let got = r.si_sequence_ms();
        let ok = got.len() == want.len() && got.iter().zip(want).all(|(a, b)| (a - b).abs() < 1e-6);
        out.push(Check { name: "si_sequence_ms".into(), ok, detail: format!("expected {want:?}, got {got:?}") });
    }
    if let Some(tol) = x.readout_within_deg {
        let worst = r.keyons.iter().map(|k| k.error_deg.abs()).fold(0.0, f64::max);
        let ok = !r.keyons.is_empty() && worst <= tol;
        out.push(Check {
            name: "readout_within_deg".into(),
            ok,
            detail: if r.keyons.is_empty() { "no key-on read-out happened".into() } else { format!("worst |theta_m - true| = {worst:.4} deg over {} read-outs, limit {tol}", r.keyons.len()) },
        });
    }
    if let Some(want) = x.diag {
        out.push(Check { name: "diag".into(), ok: r.final_ports.diag == want, detail: format!("expected {want}, got {}", r.final_ports.diag) });
    }
    if let Some(want) = x.quadrant_skip {
        out.push(Check { name: "quadrant_skip".into(), ok: r.final_ports.quadrant_skip == want, detail: format!("expected {want}, got {}", r.final_ports.quadrant_skip) });
    }
    out
}
