//! `pmu50 speed-limit`: how fast may the shaft turn with the key off before the key-off logic
//! skips a quadrant and the multi-turn angle is lost? Derivation of the bounds: docs/analysis.md.
//!
//! Three sweeps over the configuration of the scenario's `[core]` (defaults otherwise), key off
//! throughout, key on at the end for the MPU's read-out ([0108]-[0116]):
//!
//! * **from rest**: the interval is at x when the shaft jumps from rest to speed w, right after
//!   a sample, 0.5 deg before a quadrant boundary (the worst phase). Bound: w < 90 deg / x.
//! * **steady state**: the shaft first turns at 0.8 * 90 deg / x until the interval has been
//!   shortened to min ([0228]), then jumps to w and keeps it long enough for every phase to occur
//!   (90 deg / step of the sweep). Bound: w < 90 deg / min.
//! * **acceleration from rest**: constant acceleration a from rest (the angle is a parabola,
//!   drawn as 1 ms pieces of constant speed) up to 90 % of the steady-state bound, then that
//!   speed for 50 ms. No closed form: the sweep is the answer.
//!
//! For each point: quadrant skips (both signs changed in one sample), `diag`, and the key-on
//! read-out error against the true angle. A point is tracked when there was no skip, no diag
//! and the read-out is within 0.5 deg. The limit of a sweep is the highest value below which
//! every point of the sweep was tracked.

use super::{ig, run, skip_count, variant, AnalysisError};
use crate::plot::svg::{Chart, Series, Style, Svg, PALETTE};
use crate::scenario::Scenario;
use pmu50_core::Dur;
use pmu50_env::Segment;
use std::fmt::Write as _;

/// Read-out error above which a point counts as lost even without a diagnosis.
pub const READOUT_TOL_DEG: f64 = 0.5;

/// deg/s to rpm.
pub fn rpm(dps: f64) -> f64 {
    dps / 6.0
}

/// Which sweep a point belongs to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Sweep {
    FromRest,
    SteadyState,
    Acceleration,
}

impl Sweep {
    pub fn name(self) -> &'static str {
        match self {
            Sweep::FromRest => "from_rest",
            Sweep::SteadyState => "steady_state",
            Sweep::Acceleration => "acceleration",
        }
    }
}

/// One simulated point.
#[derive(Clone, Debug, PartialEq)]
pub struct Point {
    pub sweep: Sweep,
    /// deg/s, or deg/s^2 for the acceleration sweep.
    pub value: f64,
    pub skips: usize,
    pub quadrant_skip: bool,
    pub diag: bool,
    pub readout_error_deg: Option<f64>,
    /// Drive interval when the test speed started (ms).
    pub si_at_start_ms: f64,
}

impl Point {
    pub fn tracked(&self) -> bool {
        self.skips == 0
            && !self.quadrant_skip
            && !self.diag
            && self
                .readout_error_deg
                .is_some_and(|e| e.abs() <= READOUT_TOL_DEG)
    }
}

/// What to sweep.
#[derive(Clone, Copy, Debug)]
pub struct SweepSpec {
    /// Speeds from `from` to `to` (inclusive) in steps of `step`, deg/s.
    pub from_dps: f64,
    pub to_dps: f64,
    pub step_dps: f64,
    /// Accelerations: `accel_points` values from `accel_from` multiplied by `accel_ratio` each.
    pub accel_from: f64,
    pub accel_ratio: f64,
    pub accel_points: usize,
}

impl SweepSpec {
    /// Speeds from step to 1.5 x the steady-state bound, 60 steps; accelerations 1e4..1e7 deg/s^2.
    pub fn default_for(b: &Bounds) -> SweepSpec {
        let to = 1.5 * b.steady_dps;
        let step = nice_step(to / 60.0);
        SweepSpec {
            from_dps: step,
            to_dps: to,
            step_dps: step,
            accel_from: 1e4,
            accel_ratio: 10f64.powf(0.125),
            accel_points: 25,
        }
    }

    /// How many speeds [`SweepSpec::speeds`] lists, computed without listing them (a tiny step
    /// or a huge `to` would ask for more memory than there is): `f64::INFINITY` when not finite.
    pub fn point_count(&self) -> f64 {
        let n = ((self.to_dps - self.from_dps) / self.step_dps + 1e-9).floor() + 1.0;
        if n.is_finite() {
            n
        } else {
            f64::INFINITY
        }
    }

    /// Simulated ticks of the two speed sweeps, estimated: each point runs 90 deg / step (every
    /// phase offset) plus ten intervals after its lead-in, from rest and at steady state.
    pub fn estimated_ticks(&self, clock_ns: u64, min_ns: u64) -> f64 {
        let run_ns = (90.0 / self.step_dps) * 1e9 + 10.0 * min_ns as f64;
        2.0 * self.point_count() * run_ns / clock_ns.max(1) as f64
    }

    pub fn speeds(&self) -> Vec<f64> {
        let n = ((self.to_dps - self.from_dps) / self.step_dps + 1e-9).floor() as usize;
        (0..=n)
            .map(|k| self.from_dps + k as f64 * self.step_dps)
            .collect()
    }

    pub fn accels(&self) -> Vec<f64> {
        (0..self.accel_points)
            .map(|k| self.accel_from * self.accel_ratio.powi(k as i32))
            .map(|a| (a * 1e3).round() / 1e3)
            .collect()
    }
}

/// 1, 2 or 5 times a power of ten, at least `v`.
pub fn nice_step(v: f64) -> f64 {
    let mag = 10f64.powf(v.log10().floor());
    [1.0, 2.0, 5.0, 10.0]
        .iter()
        .map(|m| m * mag)
        .find(|s| *s >= v * (1.0 - 1e-12))
        .unwrap_or(10.0 * mag)
}

/// The analytic bounds of docs/analysis.md.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bounds {
    pub x_ms: f64,
    pub min_ms: f64,
    /// 90 deg / x: a speed step from rest while the interval is x.
    pub rest_dps: f64,
    /// 90 deg / min: at the shortest interval.
    pub steady_dps: f64,
}

impl Bounds {
    pub fn of(sc: &Scenario) -> Bounds {
        let clk = sc.clock_ns() as f64;
        let x_ms = f64::from(sc.params.si_max) * clk / 1e6;
        let min_ms = f64::from(sc.params.si_min) * clk / 1e6;
        Bounds {
            x_ms,
            min_ms,
            rest_dps: 90.0 / (x_ms / 1e3),
            steady_dps: 90.0 / (min_ms / 1e3),
        }
    }
}

/// The sweeps' results.
#[derive(Clone, Debug)]
pub struct Report {
    pub name: String,
    pub bounds: Bounds,
    pub spec: SweepSpec,
    pub points: Vec<Point>,
}

/// Highest value below which every point of the sweep was tracked (None: the first failed).
pub fn limit(points: &[Point], sweep: Sweep) -> Option<f64> {
    let mut best = None;
    for p in points.iter().filter(|p| p.sweep == sweep) {
        if !p.tracked() {
            break;
        }
        best = Some(p.value);
    }
    best
}

impl Report {
    pub fn limit(&self, sweep: Sweep) -> Option<f64> {
        limit(&self.points, sweep)
    }
}

fn ms_ticks(sc: &Scenario, ns: u64) -> u64 {
    ns.div_ceil(sc.clock_ns())
}

/// Time of the last key-off sample at or before `t_ns` with the shaft at rest from reset.
fn sample_before(base: &Scenario, t_ns: u64) -> Result<u64, AnalysisError> {
    let ticks = ms_ticks(base, t_ns) + 1;
    let sc = variant(base, "probe", 0.0, vec![], vec![], ticks)?;
    let r = run(&sc)?;
    r.pulses
        .iter()
        .map(|p| p.time_ns)
        .filter(|t| *t <= t_ns)
        .last()
        .ok_or_else(|| {
            AnalysisError::Input(format!("no key-off sample in the first {}", Dur(t_ns)))
        })
}

fn mv(duration_ns: u64, delta_deg: f64) -> Segment {
    Segment::Move {
        duration_ns,
        delta_deg,
    }
}

/// Finish a profile: hold 3 x, key on, MPU read-out, 2 ms.
/// What a finished run is reported as.
struct Tag {
    sweep: Sweep,
    value: f64,
    si_at_start_ms: f64,
}

fn finish(
    base: &Scenario,
    name: &str,
    start_deg: f64,
    mut segs: Vec<Segment>,
    t_ns: u64,
    tag: Tag,
) -> Result<Point, AnalysisError> {
    let Tag {
        sweep,
        value,
        si_at_start_ms,
    } = tag;
    let clk = base.clock_ns();
    let x_ns = u64::from(base.params.si_max) * clk;
    segs.push(Segment::Hold {
        duration_ns: 3 * x_ns,
    });
    let key_on = ms_ticks(base, t_ns + 3 * x_ns);
    let ticks = key_on + base.env.mpu_boot_ticks + ms_ticks(base, 2_000_000);
    let sc = variant(base, name, start_deg, segs, vec![ig(key_on, true)], ticks)?;
    let r = run(&sc)?;
    let k = r.keyons.first();
    Ok(Point {
        sweep,
        value,
        skips: skip_count(&r),
        quadrant_skip: k.map_or(r.final_ports.quadrant_skip, |k| k.quadrant_skip),
        diag: k.map_or(r.final_ports.diag, |k| k.diag),
        readout_error_deg: k.map(|k| k.error_deg),
        si_at_start_ms,
    })
}

/// Interval in force at time `t_ns` of a run of `base` with the given motion (for the report).
fn si_at(
    base: &Scenario,
    start_deg: f64,
    segs: &[Segment],
    t_ns: u64,
) -> Result<f64, AnalysisError> {
    let sc = variant(
        base,
        "probe",
        start_deg,
        segs.to_vec(),
        vec![],
        ms_ticks(base, t_ns) + 1,
    )?;
    let r = run(&sc)?;
    Ok(f64::from(r.final_ports.si) * base.clock_ns() as f64 / 1e6)
}

/// Worst start angle: 0.5 deg before a quadrant boundary (turning forwards).
const START_DEG: f64 = 89.5;
/// The shaft rests until the first key-off sample after this time.
const REST_NS: u64 = 20_000_000;

/// One point of the from-rest sweep.
pub fn from_rest(base: &Scenario, t_s: u64, w: f64, run_ns: u64) -> Result<Point, AnalysisError> {
    let segs = vec![
        Segment::Hold { duration_ns: t_s },
        mv(run_ns, w * run_ns as f64 / 1e9),
    ];
    let si = f64::from(base.params.si_max) * base.clock_ns() as f64 / 1e6;
    finish(
        base,
        "speed_from_rest",
        START_DEG,
        segs,
        t_s + run_ns,
        Tag {
            sweep: Sweep::FromRest,
            value: w,
            si_at_start_ms: si,
        },
    )
}

/// One point of the steady-state sweep.
pub fn steady(base: &Scenario, t_s: u64, w: f64, run_ns: u64) -> Result<Point, AnalysisError> {
    let b = Bounds::of(base);
    let w0 = 0.8 * b.rest_dps;
    // enough boundaries to shorten x down to min, plus one and a half
    let t1 = f64::from(base.params.t1.max(1));
    let n = ((f64::from(base.params.si_max) - f64::from(base.params.si_min)) / t1).ceil() + 2.5;
    let spin_ns = (n * 90.0 / w0 * 1e9).round() as u64;
    let mut segs = vec![
        Segment::Hold { duration_ns: t_s },
        mv(spin_ns, w0 * spin_ns as f64 / 1e9),
    ];
    let si = si_at(base, START_DEG, &segs, t_s + spin_ns)?;
    segs.push(mv(run_ns, w * run_ns as f64 / 1e9));
    finish(
        base,
        "speed_steady",
        START_DEG,
        segs,
        t_s + spin_ns + run_ns,
        Tag {
            sweep: Sweep::SteadyState,
            value: w,
            si_at_start_ms: si,
        },
    )
}

/// One point of the acceleration sweep: a from rest up to `w_end`, then `w_end` for 50 ms.
pub fn accel(base: &Scenario, t_s: u64, a: f64, w_end: f64) -> Result<Point, AnalysisError> {
    let piece = 1_000_000u64;
    let t_acc = w_end / a;
    let pieces = (t_acc * 1e3).ceil() as u64;
    let mut segs = vec![Segment::Hold { duration_ns: t_s }];
    let mut t = 0.0;
    for _ in 0..pieces {
        let t_next = (t + 1e-3f64).min(t_acc);
        let d = 0.5 * a * (t_next * t_next - t * t);
        segs.push(mv(piece, d));
        t = t_next;
    }
    let hold_ns = 50_000_000u64;
    segs.push(mv(hold_ns, w_end * 0.05));
    let si = f64::from(base.params.si_max) * base.clock_ns() as f64 / 1e6;
    finish(
        base,
        "accel_from_rest",
        START_DEG,
        segs,
        t_s + pieces * piece + hold_ns,
        Tag {
            sweep: Sweep::Acceleration,
            value: a,
            si_at_start_ms: si,
        },
    )
}

/// Run all three sweeps. `progress` is called after every point.
pub fn sweep(
    base: &Scenario,
    spec: SweepSpec,
    progress: &mut dyn FnMut(&Point),
) -> Result<Report, AnalysisError> {
    sweep_within(base, spec, None, None, progress)
}

/// A number for a message: plain when it reads well, else in scientific notation.
fn short(v: f64) -> String {
    if v == 0.0 || (1e-3..1e9).contains(&v.abs()) {
        format!("{}", (v * 1e6).round() / 1e6)
    } else {
        format!("{v:e}")
    }
}

/// [`sweep`], refused before anything runs when it has more than `max_points` speeds
/// (`--max-points`, default [`crate::limits::DEFAULT_MAX_POINTS`]) or would simulate more than
/// `max_ticks` ticks (`--max-ticks`, default [`crate::limits::DEFAULT_MAX_TICKS`]).
pub fn sweep_within(
    base: &Scenario,
    spec: SweepSpec,
    max_points: Option<u64>,
    max_ticks: Option<u64>,
    progress: &mut dyn FnMut(&Point),
) -> Result<Report, AnalysisError> {
    use crate::limits::{check, Unit, DEFAULT_MAX_POINTS, DEFAULT_MAX_TICKS};
    if !(spec.step_dps > 0.0
        && spec.from_dps > 0.0
        && spec.to_dps >= spec.from_dps
        && spec.to_dps.is_finite())
    {
        return Err(AnalysisError::Input(format!(
            "speed sweep {}..{} step {} deg/s: need 0 < from <= to and step > 0",
            spec.from_dps, spec.to_dps, spec.step_dps
        )));
    }
    let what = format!(
        "speed sweep {}..{} step {} deg/s",
        short(spec.from_dps),
        short(spec.to_dps),
        short(spec.step_dps)
    );
    // saturating float-to-int casts: an infinite count is u64::MAX
    let points = spec.point_count() as u64;
    check(
        what.clone(),
        points,
        max_points,
        DEFAULT_MAX_POINTS,
        Unit::Points,
        "--max-points",
        "use a larger --step or a shorter --from..--to",
    )
    .map_err(|e| AnalysisError::Input(e.to_string()))?;
    let ticks = spec.estimated_ticks(
        base.clock_ns(),
        u64::from(base.params.si_min) * base.clock_ns(),
    ) as u64;
    check(
        what,
        ticks,
        max_ticks,
        DEFAULT_MAX_TICKS,
        Unit::Ticks,
        "--max-ticks",
        "use a larger --step (each point runs 90 deg / step)",
    )
    .map_err(|e| AnalysisError::Input(e.to_string()))?;
    let b = Bounds::of(base);
    let t_s = sample_before(base, REST_NS)?;
    let min_ns = u64::from(base.params.si_min) * base.clock_ns();
    // every phase offset occurs within 90 deg / (step * interval) samples; 10 samples more
    let run_ns = ((90.0 / spec.step_dps) * 1e9) as u64 + 10 * min_ns;
    let mut points = Vec::new();
    for w in spec.speeds() {
        let p = from_rest(base, t_s, w, run_ns)?;
        progress(&p);
        points.push(p);
    }
    for w in spec.speeds() {
        let p = steady(base, t_s, w, run_ns)?;
        progress(&p);
        points.push(p);
    }
    for a in spec.accels() {
        let p = accel(base, t_s, a, 0.9 * b.steady_dps)?;
        progress(&p);
        points.push(p);
    }
    Ok(Report {
        name: base.name.clone(),
        bounds: b,
        spec,
        points,
    })
}

/// The points as CSV.
pub fn csv(r: &Report) -> String {
    let mut s = String::from(
        "sweep,value,unit,rpm,skips,quadrant_skip,diag,readout_error_deg,tracked,si_at_start_ms\n",
    );
    for p in &r.points {
        let (unit, rpm_s) = match p.sweep {
            Sweep::Acceleration => ("deg/s^2", String::new()),
            _ => ("deg/s", format!("{:.1}", rpm(p.value))),
        };
        let _ = writeln!(
            s,
            "{},{},{unit},{rpm_s},{},{},{},{},{},{:.3}",
            p.sweep.name(),
            p.value,
            p.skips,
            u8::from(p.quadrant_skip),
            u8::from(p.diag),
            p.readout_error_deg
                .map_or(String::new(), |e| format!("{e:.4}")),
            u8::from(p.tracked()),
            p.si_at_start_ms
        );
    }
    let b = &r.bounds;
    let lim = |s| {
        r.limit(s)
            .map_or("none".to_string(), |v: f64| format!("{v}"))
    };
    let _ = writeln!(
        s,
        "# bound from_rest = 90 deg / x = {:.1} deg/s ({:.1} rpm); found {}",
        b.rest_dps,
        rpm(b.rest_dps),
        lim(Sweep::FromRest)
    );
    let _ = writeln!(
        s,
        "# bound steady_state = 90 deg / min = {:.1} deg/s ({:.1} rpm); found {}",
        b.steady_dps,
        rpm(b.steady_dps),
        lim(Sweep::SteadyState)
    );
    let _ = writeln!(
        s,
        "# acceleration limit found {} deg/s^2",
        lim(Sweep::Acceleration)
    );
    s
}

/// Text summary for the terminal.
pub fn summary(r: &Report) -> String {
    let b = &r.bounds;
    let f = |v: Option<f64>| {
        v.map_or("none (the first point failed)".to_string(), |v| {
            format!("{v:.0} deg/s = {:.0} rpm", rpm(v))
        })
    };
    let mut s = format!(
        "== speed-limit {} (x = {:.1} ms, min = {:.1} ms, sweep step {} deg/s)\n",
        r.name, b.x_ms, b.min_ms, r.spec.step_dps
    );
    s += &format!("   from rest (interval x):   tracked up to {}; bound 90 deg / x = {:.0} deg/s = {:.0} rpm\n", f(r.limit(Sweep::FromRest)), b.rest_dps, rpm(b.rest_dps));
    s += &format!("   steady state (interval min): tracked up to {}; bound 90 deg / min = {:.0} deg/s = {:.0} rpm\n", f(r.limit(Sweep::SteadyState)), b.steady_dps, rpm(b.steady_dps));
    s += &format!(
        "   constant acceleration from rest: tracked up to {}\n",
        r.limit(Sweep::Acceleration)
            .map_or("none".to_string(), |a| format!("{a:.0} deg/s^2"))
    );
    s += "   for comparison (the same one-quadrant-per-sample rule applied to its periods): TMAG6181-Q1 samples every 1.6 ms at rest and 0.2 ms on rotation: 9 375 / 75 000 rpm; iC-PV: 12 000 rpm as quoted, not confirmed from its datasheet (docs/analysis.md)\n";
    s
}

fn clip_err(p: &Point) -> f64 {
    p.readout_error_deg.map_or(400.0, |e| e.abs().min(400.0))
}

/// speed_limit.svg: read-out error against speed (both speed sweeps) and against acceleration.
pub fn svg(r: &Report) -> String {
    let b = &r.bounds;
    let mut s = Svg::new(1000.0, 860.0);
    let mut c = Chart::new(&format!("{}: key-on read-out error after a key-off run at constant speed (x = {:.1} ms, min = {:.1} ms)", r.name, b.x_ms, b.min_ms), "motor speed (rpm)", "|read-out error| (deg, lost = 400)");
    let pts = |sw: Sweep, tracked: Option<bool>| -> Vec<(f64, f64)> {
        r.points
            .iter()
            .filter(|p| p.sweep == sw && tracked.is_none_or(|t| p.tracked() == t))
            .map(|p| (rpm(p.value), clip_err(p)))
            .collect()
    };
    c.series.push(Series {
        name: "jump from rest (interval x)".into(),
        color: PALETTE[0].into(),
        style: Style::Line,
        points: pts(Sweep::FromRest, None),
    });
    c.series.push(Series {
        name: "steady state (interval min)".into(),
        color: PALETTE[1].into(),
        style: Style::Line,
        points: pts(Sweep::SteadyState, None),
    });
    c.series.push(Series {
        name: "quadrant skip / diag / error > 0.5 deg".into(),
        color: "#C00000".into(),
        style: Style::Points,
        points: [
            pts(Sweep::FromRest, Some(false)),
            pts(Sweep::SteadyState, Some(false)),
        ]
        .concat(),
    });
    c.vlines.push((
        rpm(b.rest_dps),
        format!("90 deg / x = {:.0} rpm", rpm(b.rest_dps)),
        PALETTE[0].into(),
    ));
    c.vlines.push((
        rpm(b.steady_dps),
        format!("90 deg / min = {:.0} rpm", rpm(b.steady_dps)),
        PALETTE[1].into(),
    ));
    if 12_000.0 <= rpm(r.spec.to_dps) {
        c.vlines.push((
            12_000.0,
            "iC-PV 12000 rpm (quoted, unconfirmed)".into(),
            "#009E73".into(),
        ));
    }
    if 9_375.0 <= rpm(r.spec.to_dps) {
        c.vlines.push((
            9_375.0,
            "90 deg / 1.6 ms (TMAG6181 at rest) = 9375 rpm".into(),
            "#CC79A7".into(),
        ));
    }
    c.x_range = (0.0, rpm(r.spec.to_dps));
    c.y_range = (0.0, 420.0);
    c.draw(&mut s, 0.0, 0.0, 1000.0, 440.0);

    let mut a = Chart::new(
        "constant acceleration from rest (interval x), up to 90 % of 90 deg / min",
        "acceleration (log10 of deg/s^2)",
        "|read-out error| (deg, lost = 400)",
    );
    let apts = |tracked: Option<bool>| -> Vec<(f64, f64)> {
        r.points
            .iter()
            .filter(|p| p.sweep == Sweep::Acceleration && tracked.is_none_or(|t| p.tracked() == t))
            .map(|p| (p.value.log10(), clip_err(p)))
            .collect()
    };
    a.series.push(Series {
        name: "acceleration from rest".into(),
        color: PALETTE[2].into(),
        style: Style::LinePoints,
        points: apts(None),
    });
    a.series.push(Series {
        name: "quadrant skip / diag / error > 0.5 deg".into(),
        color: "#C00000".into(),
        style: Style::Points,
        points: apts(Some(false)),
    });
    if let Some(l) = r.limit(Sweep::Acceleration) {
        a.vlines.push((
            l.log10(),
            format!("tracked up to {l:.0} deg/s^2"),
            PALETTE[2].into(),
        ));
    }
    let acc = r.spec.accels();
    a.x_range = (
        acc.first().copied().unwrap_or(1.0).log10(),
        acc.last().copied().unwrap_or(10.0).log10(),
    );
    a.y_range = (0.0, 420.0);
    a.draw(&mut s, 0.0, 440.0, 1000.0, 420.0);
    s.finish()
}

/// One configuration of the grid figure.
#[derive(Clone, Debug)]
pub struct GridRow {
    pub x_ms: f64,
    pub min_ms: f64,
    pub cth: u8,
    pub bounds: Bounds,
    pub rest: Option<f64>,
    pub steady: Option<f64>,
    pub accel: Option<f64>,
    /// Vs2 duty at rest, Wt / x.
    pub duty_rest: f64,
    pub step_dps: f64,
}

/// The grid of configurations (x, min, Cth), each swept coarsely (about 40 speed steps up to the
/// steady-state bound).
pub fn grid(
    base: &Scenario,
    xs_us: &[u64],
    mins_us: &[u64],
    cths: &[u8],
    progress: &mut dyn FnMut(&str),
) -> Result<Vec<GridRow>, AnalysisError> {
    let mut out = Vec::new();
    for &x in xs_us {
        for &m in mins_us {
            for &cth in cths {
                let mut core = base.core.clone();
                core.x = Dur::us(x);
                core.min = Dur::us(m);
                core.cth = u32::from(cth);
                let Ok(params) = core.to_params() else {
                    progress(&format!(
                        "skipped x = {} us, min = {} us, Cth = {cth}: not a valid configuration",
                        x, m
                    ));
                    continue;
                };
                let mut sc = base.clone();
                sc.core = core;
                sc.params = params;
                let b = Bounds::of(&sc);
                let step = nice_step(b.steady_dps / 40.0);
                let spec = SweepSpec {
                    from_dps: step,
                    to_dps: 1.3 * b.steady_dps,
                    step_dps: step,
                    accel_from: 1e4,
                    accel_ratio: 10f64.powf(0.25),
                    accel_points: 13,
                };
                let r = sweep(&sc, spec, &mut |_| {})?;
                let wt =
                    f64::from(sc.params.pw) + f64::from(sc.params.pi) + f64::from(sc.params.ps);
                let row = GridRow {
                    x_ms: b.x_ms,
                    min_ms: b.min_ms,
                    cth,
                    bounds: b,
                    rest: r.limit(Sweep::FromRest),
                    steady: r.limit(Sweep::SteadyState),
                    accel: r.limit(Sweep::Acceleration),
                    duty_rest: wt / f64::from(sc.params.si_max),
                    step_dps: step,
                };
                progress(&format!("x = {:.1} ms, min = {:.1} ms, Cth = {cth}: from rest {:?}, steady {:?}, accel {:?}", row.x_ms, row.min_ms, row.rest, row.steady, row.accel));
                out.push(row);
            }
        }
    }
    Ok(out)
}

pub fn grid_csv(rows: &[GridRow]) -> String {
    let mut s = String::from("x_ms,min_ms,cth,bound_rest_rpm,found_rest_rpm,bound_steady_rpm,found_steady_rpm,sweep_step_rpm,accel_limit_dps2,vs2_duty_at_rest\n");
    let o = |v: Option<f64>| v.map_or(String::new(), |v| format!("{:.1}", rpm(v)));
    for r in rows {
        let _ = writeln!(
            s,
            "{:.1},{:.1},{},{:.1},{},{:.1},{},{:.1},{},{:.4}",
            r.x_ms,
            r.min_ms,
            r.cth,
            rpm(r.bounds.rest_dps),
            o(r.rest),
            rpm(r.bounds.steady_dps),
            o(r.steady),
            rpm(r.step_dps),
            r.accel.map_or(String::new(), |a| format!("{a:.0}")),
            r.duty_rest
        );
    }
    s
}

/// speed_limit_grid.svg: speed limits and the acceleration limit per configuration.
pub fn grid_svg(rows: &[GridRow]) -> String {
    let mut s = Svg::new(1000.0, 820.0);
    let cats: Vec<(f64, String)> = rows
        .iter()
        .enumerate()
        .map(|(i, r)| {
            (
                i as f64,
                format!("{:.1} / {:.1} / {}", r.x_ms, r.min_ms, r.cth),
            )
        })
        .collect();
    let xr = (-0.5, rows.len() as f64 - 0.5);
    let mut c = Chart::new(
        "speed limits by configuration (sweep: points; analytic bound: dashed bars)",
        "x (ms) / min (ms) / Cth",
        "motor speed (rpm)",
    );
    let ser = |f: &dyn Fn(&GridRow) -> Option<f64>| -> Vec<(f64, f64)> {
        rows.iter()
            .enumerate()
            .filter_map(|(i, r)| f(r).map(|v| (i as f64, rpm(v))))
            .collect()
    };
    c.series.push(Series {
        name: "steady state, sweep".into(),
        color: PALETTE[1].into(),
        style: Style::Points,
        points: ser(&|r| r.steady),
    });
    c.series.push(Series {
        name: "steady state, 90 deg / min".into(),
        color: PALETTE[1].into(),
        style: Style::Level,
        points: ser(&|r| Some(r.bounds.steady_dps)),
    });
    c.series.push(Series {
        name: "from rest, sweep".into(),
        color: PALETTE[0].into(),
        style: Style::Points,
        points: ser(&|r| r.rest),
    });
    c.series.push(Series {
        name: "from rest, 90 deg / x".into(),
        color: PALETTE[0].into(),
        style: Style::Level,
        points: ser(&|r| Some(r.bounds.rest_dps)),
    });
    c.x_categories = cats.clone();
    c.x_range = xr;
    let ymax = rows
        .iter()
        .map(|r| rpm(r.bounds.steady_dps))
        .fold(1.0, f64::max)
        * 1.1;
    c.y_range = (0.0, ymax);
    c.draw(&mut s, 0.0, 0.0, 1000.0, 440.0);
    let mut a = Chart::new("highest constant acceleration from rest tracked (x sets it: the first samples come x apart)", "x (ms) / min (ms) / Cth", "acceleration (1000 deg/s^2)");
    a.series.push(Series {
        name: "highest acceleration tracked".into(),
        color: PALETTE[2].into(),
        style: Style::Points,
        points: rows
            .iter()
            .enumerate()
            .filter_map(|(i, r)| r.accel.map(|v| (i as f64, v / 1e3)))
            .collect(),
    });
    a.x_categories = cats;
    a.x_range = xr;
    let amax = rows.iter().filter_map(|r| r.accel).fold(1.0, f64::max) / 1e3 * 1.15;
    a.y_range = (0.0, amax);
    a.draw(&mut s, 0.0, 440.0, 1000.0, 380.0);
    s.finish()
}

/// The grid of the second figure: x in {6.6, 13.2} ms, min in {2.2, 1.1} ms, Cth in {1, 4}.
pub const GRID_X_US: [u64; 2] = [6_600, 13_200];
pub const GRID_MIN_US: [u64; 2] = [2_200, 1_100];
pub const GRID_CTH: [u8; 2] = [1, 4];

/// `pmu50 speed-limit`: sweep, write speed_limit.csv/.svg (and the grid) into `dir`, return the
/// summary.
#[allow(clippy::too_many_arguments)]
pub fn run_cli(
    sc: &Scenario,
    dir: &std::path::Path,
    step: Option<f64>,
    from: Option<f64>,
    to: Option<f64>,
    with_grid: bool,
    max_points: Option<u64>,
    max_ticks: Option<u64>,
) -> Result<String, AnalysisError> {
    let b = Bounds::of(sc);
    let mut spec = SweepSpec::default_for(&b);
    if let Some(s) = step {
        spec.step_dps = s;
        spec.from_dps = s;
    }
    if let Some(f) = from {
        spec.from_dps = f;
    }
    if let Some(t) = to {
        spec.to_dps = t;
    }
    // A progress bar on a terminal only (stderr), for long sweeps.
    let total = spec.point_count().min(1e9) as u64 * 2 + spec.accel_points as u64;
    let bar = crate::limits::progress_bar(total, "speed-limit");
    let r = sweep_within(sc, spec, max_points, max_ticks, &mut |_| bar.inc(1));
    bar.finish_and_clear();
    let r = r?;
    let w = |name: &str, text: String| {
        crate::plot::write_atomic(&dir.join(name), text.as_bytes()).map_err(AnalysisError::Write)
    };
    w("speed_limit.csv", csv(&r))?;
    w("speed_limit.svg", svg(&r))?;
    let mut text = summary(&r);
    text += &format!(
        "   wrote {0}/speed_limit.csv and {0}/speed_limit.svg\n",
        dir.display()
    );
    if with_grid {
        let rows = grid(sc, &GRID_X_US, &GRID_MIN_US, &GRID_CTH, &mut |_| {})?;
        w("speed_limit_grid.csv", grid_csv(&rows))?;
        w("speed_limit_grid.svg", grid_svg(&rows))?;
        text += &format!(
            "   wrote {0}/speed_limit_grid.csv and {0}/speed_limit_grid.svg ({1} configurations)\n",
            dir.display(),
            rows.len()
        );
    }
    Ok(text)
}
