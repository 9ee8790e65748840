//! `pmu50 budget`: what the key-off logic costs the battery (docs/power.md).
//!
//! The scenario (a park profile, e.g. scenarios/park_*.toml) is run three ways:
//!
//! * **adaptive**: second embodiment, the drive interval adapts between x and min (FIG. 17/18);
//! * **fixed**: first embodiment, a fixed cycle T = x ([0083], `adaptive = false`);
//! * **always on**: the second sensor powered during the whole key-off time. The PMU cannot be
//!   told to do that, so this variant is not simulated: it is the adaptive run's key-off time
//!   with Vs2 on 100 % of it (the other rails as measured);
//! * and, for comparison, a **fixed cycle T = min**: what tracking as fast as the adaptive
//!   interval does at speed would cost without the adaptation.
//!
//! For each: average key-off current by rail (Vm: MPU 60, Vs1: first sensor 33, Vs2: second
//! sensor 34 and comparators 58a/58b, Vp: logic, regulator 51 quiescent current) and in total,
//! and the cumulative charge in mAh over the run. The rail on-times come from the dark-current
//! meter of the run ([`pmu50_env::DarkCurrentReport`]); the currents are the scenario's
//! `[env.dark_current]` (cited defaults: docs/power.md).
//!
//! The cumulative curve is rebuilt from the key-off samples (one Vs2 output each) and the key-off
//! time, so it needs no per-tick observer: the runs keep the testbench's fast-forward of idle
//! key-off gaps, and the curve's last point equals the meter's total (checked).

use super::{run_observed, AnalysisError};
use crate::plot::svg::{Anchor, Chart, Series, Style, Svg, PALETTE};
use crate::scenario::{Action, Scenario};
use crate::sim::RunResult;
use pmu50_env::DarkCurrentConfig;
use std::fmt::Write as _;
use std::time::Instant;

/// Microcoulombs per mAh.
const UC_PER_MAH: f64 = 3.6e6;

/// The three ways a park is run.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Variant {
    Adaptive,
    Fixed,
    AlwaysOn,
    /// Fixed cycle T = min: the speed limit of the adaptive interval at speed, all the time.
    FixedMin,
}

impl Variant {
    pub fn name(self) -> &'static str {
        match self {
            Variant::Adaptive => "adaptive",
            Variant::Fixed => "fixed_cycle_x",
            Variant::AlwaysOn => "sensor_always_on",
            Variant::FixedMin => "fixed_cycle_min",
        }
    }
    pub fn label(self) -> &'static str {
        match self {
            Variant::Adaptive => "adaptive interval (2nd embodiment)",
            Variant::Fixed => "fixed cycle T = x (1st embodiment)",
            Variant::AlwaysOn => "second sensor always on",
            Variant::FixedMin => "fixed cycle T = min (for comparison)",
        }
    }
}

/// Rails, in the order of the tables.
pub const RAILS: [&str; 5] = [
    "Vm (MPU)",
    "Vs1 (1st sensor)",
    "Vs2 (2nd sensor + comparators)",
    "Vp (logic)",
    "regulator Iq",
];

/// One variant's result.
#[derive(Clone, Debug, PartialEq)]
pub struct Row {
    pub variant: Variant,
    pub key_off_ns: u64,
    pub vs2_on_ns: u64,
    /// Average key-off current per rail (order of [`RAILS`]), uA.
    pub rail_ua: [f64; 5],
    /// Key-off charge per rail, uC.
    pub rail_uc: [f64; 5],
    pub total_ua: f64,
    pub total_uc: f64,
    /// Key-off samples (one Vs2 output each).
    pub outputs: u64,
    /// Cumulative charge: (time in s, mAh), the last point at the end of the run.
    pub curve: Vec<(f64, f64)>,
    /// Wall-clock time of the run, s (summary only, never in a file).
    pub run_time_s: f64,
}

impl Row {
    pub fn vs2_duty(&self) -> f64 {
        if self.key_off_ns == 0 {
            0.0
        } else {
            self.vs2_on_ns as f64 / self.key_off_ns as f64
        }
    }
}

/// The budget of one scenario.
#[derive(Clone, Debug)]
pub struct Budget {
    pub name: String,
    pub description: String,
    pub duration_s: f64,
    pub currents: DarkCurrentConfig,
    /// Wt = Pw + Pi + Ps, ms; x and min, ms.
    pub wt_ms: f64,
    pub x_ms: f64,
    pub min_ms: f64,
    pub rows: Vec<Row>,
}

/// Key-off time of the whole run in ns, from the timeline alone (compared with the meter's in
/// tests/plots.rs: the cumulative curve relies on it).
pub fn key_off_ns_from_timeline(sc: &Scenario) -> u64 {
    key_off_ticks_before(sc, sc.ticks) * sc.clock_ns()
}

/// Key-off time in [0, t) ticks, from the timeline (Sig follows IG through the synchronizer).
fn key_off_ticks_before(sc: &Scenario, t: u64) -> u64 {
    let d = u64::from(sc.params.sync_depth);
    let mut on = false;
    let mut since = 0u64;
    let mut off = 0u64;
    for e in &sc.events {
        if let Action::Ig(v) = e.action {
            let at = (e.tick + d).min(t);
            if v != on {
                if !on {
                    off += at.saturating_sub(since);
                }
                on = v;
                since = at;
            }
        }
    }
    if !on {
        off += t.saturating_sub(since);
    }
    off
}

fn row_from(sc: &Scenario, r: &RunResult, variant: Variant, run_time_s: f64) -> Row {
    let c = &sc.env.dark_current;
    let d = &r.dark;
    let vs2_on = if variant == Variant::AlwaysOn {
        d.key_off_ns
    } else {
        d.vs2_on_ns
    };
    let t = d.key_off_ns as f64;
    // uA x ns -> uC: 1e-9
    let rail_uc = [
        c.i_vm_ma * 1e3 * d.vm_on_ns as f64 * 1e-9,
        c.i_vs1_ma * 1e3 * d.vs1_on_ns as f64 * 1e-9,
        c.i_vs2_ma * 1e3 * vs2_on as f64 * 1e-9,
        c.i_vp_ua * d.vp_on_ns as f64 * 1e-9,
        c.i_q_ua * t * 1e-9,
    ];
    let rail_ua = rail_uc.map(|q| if t > 0.0 { q / (t * 1e-9) } else { 0.0 });
    let total_uc: f64 = rail_uc.iter().sum();
    let total_ua: f64 = rail_ua.iter().sum();
    let clk = sc.clock_ns();
    // Cumulative curve at 400 points: per key-off sample one Vs2 output of the measured average
    // width; the other rails in proportion to the key-off time so far.
    let outputs = r.pulses.len();
    let per_output_uc = if variant == Variant::AlwaysOn || outputs == 0 {
        0.0
    } else {
        rail_uc[2] / outputs as f64
    };
    let off_total = key_off_ticks_before(sc, sc.ticks).max(1) as f64;
    let steady_uc = if variant == Variant::AlwaysOn {
        total_uc
    } else {
        total_uc - rail_uc[2]
    };
    let n = 400u64;
    let mut curve = Vec::with_capacity(n as usize + 1);
    for k in 0..=n {
        let tick = sc.ticks * k / n;
        let i = r.pulses.count_until(tick);
        let q = per_output_uc * i as f64
            + steady_uc * key_off_ticks_before(sc, tick) as f64 / off_total;
        curve.push(((tick * clk) as f64 / 1e9, q / UC_PER_MAH));
    }
    Row {
        variant,
        key_off_ns: d.key_off_ns,
        vs2_on_ns: vs2_on,
        rail_ua,
        rail_uc,
        total_ua,
        total_uc,
        outputs,
        curve,
        run_time_s,
    }
}

/// Run the budget of `base` three ways.
/// Simulations [`budget`] makes of its scenario: adaptive, fixed cycle x, fixed cycle min (the
/// always-on row reuses the adaptive run); what `pmu50 budget --max-ticks` counts.
pub const RUNS: u64 = 3;

pub fn budget(base: &Scenario) -> Result<Budget, AnalysisError> {
    let clk = base.clock_ns() as f64;
    let p = &base.params;
    let mut rows = Vec::new();
    let mut adaptive_run: Option<(RunResult, f64)> = None;
    // on a terminal only, after a second (crate::limits::progress_bar)
    let bar = crate::limits::progress_bar(RUNS * base.ticks, "budget");
    let mut k = 0;
    let mut run = |sc: &Scenario| {
        let r = run_observed(sc, &mut crate::limits::TickBar::new(&bar, k * base.ticks));
        k += 1;
        r
    };
    for v in [Variant::Adaptive, Variant::Fixed] {
        let mut sc = base.clone();
        sc.core.adaptive = v == Variant::Adaptive;
        sc.params.adaptive = v == Variant::Adaptive;
        sc.expect = Default::default();
        let t = Instant::now();
        let r = run(&sc)?;
        let secs = t.elapsed().as_secs_f64();
        rows.push(row_from(&sc, &r, v, secs));
        if v == Variant::Adaptive {
            adaptive_run = Some((r, secs));
        }
    }
    if let Some((r, secs)) = adaptive_run {
        rows.push(row_from(base, &r, Variant::AlwaysOn, secs));
    }
    // The fair comparison for tracking: a fixed cycle as short as the adaptive interval gets.
    let mut sc = base.clone();
    sc.core.adaptive = false;
    sc.core.x = sc.core.min;
    if let Ok(params) = sc.core.to_params() {
        sc.params = params;
        sc.expect = Default::default();
        let t = Instant::now();
        let r = run(&sc)?;
        rows.push(row_from(
            &sc,
            &r,
            Variant::FixedMin,
            t.elapsed().as_secs_f64(),
        ));
    }
    bar.finish_and_clear();
    let x_ns = u64::from(p.si_max) * base.clock_ns();
    if rows.iter().all(|r| r.key_off_ns < x_ns) {
        let off = rows.first().map_or(0, |r| r.key_off_ns);
        return Err(AnalysisError::Input(format!(
            "{}: the key is never off for a whole interval x = {} (key off {} in all); a budget needs key-off time: add `ig = false` events",
            base.path.display(),
            pmu50_core::Dur(x_ns),
            pmu50_core::Dur(off)
        )));
    }
    Ok(Budget {
        name: base.name.clone(),
        description: base.description.clone(),
        duration_s: base.ticks as f64 * clk / 1e9,
        currents: base.env.dark_current,
        wt_ms: (f64::from(p.pw) + f64::from(p.pi) + f64::from(p.ps)) * clk / 1e6,
        x_ms: f64::from(p.si_max) * clk / 1e6,
        min_ms: f64::from(p.si_min) * clk / 1e6,
        rows,
    })
}

/// budget.csv: one line per variant and rail, then the totals.
pub fn csv(b: &Budget) -> String {
    let mut s = String::from(
        "variant,rail,current_while_on,unit,avg_key_off_current_ua,key_off_charge_mah\n",
    );
    let c = &b.currents;
    let on = [
        (c.i_vm_ma, "mA"),
        (c.i_vs1_ma, "mA"),
        (c.i_vs2_ma, "mA"),
        (c.i_vp_ua, "uA"),
        (c.i_q_ua, "uA"),
    ];
    for r in &b.rows {
        for (k, rail) in RAILS.iter().enumerate() {
            let _ = writeln!(
                s,
                "{},{rail},{},{},{:.6},{:.9}",
                r.variant.name(),
                on[k].0,
                on[k].1,
                r.rail_ua[k],
                r.rail_uc[k] / UC_PER_MAH
            );
        }
        let _ = writeln!(
            s,
            "{},total,,,{:.6},{:.9}",
            r.variant.name(),
            r.total_ua,
            r.total_uc / UC_PER_MAH
        );
    }
    for r in &b.rows {
        let _ = writeln!(
            s,
            "# {}: key off {:.3} s, Vs2 duty {:.4} %, {} Vs2 outputs",
            r.variant.name(),
            r.key_off_ns as f64 / 1e9,
            r.vs2_duty() * 100.0,
            r.outputs
        );
    }
    s
}

/// budget_cumulative.csv: the cumulative charge of the three variants over the run.
pub fn curve_csv(b: &Budget) -> String {
    let mut s = String::from("time_s");
    for r in &b.rows {
        s += &format!(",{}_mah", r.variant.name());
    }
    s.push('\n');
    let n = b.rows.first().map_or(0, |r| r.curve.len());
    for i in 0..n {
        let _ = write!(s, "{:.6}", b.rows[0].curve[i].0);
        for r in &b.rows {
            let _ = write!(s, ",{:.9}", r.curve[i].1);
        }
        s.push('\n');
    }
    s
}

/// Terminal summary: the table, the patent's duty claim, the chips that do the same job.
pub fn summary(b: &Budget) -> String {
    let mut s = format!(
        "== budget {}: {}\n   run of {:.1} s; Wt = {:.3} ms, x = {:.1} ms, min = {:.1} ms\n",
        b.name, b.description, b.duration_s, b.wt_ms, b.x_ms, b.min_ms
    );
    s += &format!(
        "   {:<36} {:>10} {:>10} {:>12} {:>12} {:>12} {:>12} {:>10}\n",
        "average key-off current (uA)", "Vm", "Vs1", "Vs2", "Vp", "reg. Iq", "total", "Vs2 duty"
    );
    for r in &b.rows {
        s += &format!(
            "   {:<36} {:>10.3} {:>10.3} {:>12.3} {:>12.3} {:>12.3} {:>12.3} {:>9.3}%\n",
            r.variant.label(),
            r.rail_ua[0],
            r.rail_ua[1],
            r.rail_ua[2],
            r.rail_ua[3],
            r.rail_ua[4],
            r.total_ua,
            r.vs2_duty() * 100.0
        );
    }
    for r in &b.rows {
        s += &format!("   {}: {:.6} mAh over the run, {:.1} mAh per 30 days at this average; ran in {:.2} s{}\n", r.variant.label(), r.total_uc / UC_PER_MAH, r.total_ua * 720.0 / 1e3, r.run_time_s, if r.variant == Variant::AlwaysOn { " (computed from the adaptive run)" } else { "" });
    }
    if let (Some(a), Some(f)) = (
        b.rows.iter().find(|r| r.variant == Variant::Adaptive),
        b.rows.iter().find(|r| r.variant == Variant::Fixed),
    ) {
        s += &format!("   patent: duty 10 % at 2.2 ms and a third of that at 6.6 ms with w = 220 us ([0229]-[0231]); here Wt/min = {:.2} %, Wt/x = {:.2} %, fixed cycle measured {:.2} %, adaptive {:.2} %\n", b.wt_ms / b.min_ms * 100.0, b.wt_ms / b.x_ms * 100.0, f.vs2_duty() * 100.0, a.vs2_duty() * 100.0);
    }
    s += "   chips that do the same job (docs/power.md): TI TMAG6181-Q1 counts turns itself at 1.6 ms / 0.2 ms wake-up periods; its low-power-mode current and iC-Haus iC-PV's current could not be confirmed from their datasheets here\n";
    s
}

/// budget.svg: average key-off current by rail (stacked bars), cumulative charge over the run.
pub fn svg(b: &Budget) -> String {
    let mut svg = Svg::new(1000.0, 900.0);
    svg.text(
        500.0,
        22.0,
        15.0,
        Anchor::Middle,
        "#000",
        &format!("{}: average key-off current by rail (log scale)", b.name),
    );
    // grouped horizontal bars on a log axis (the rails span five decades)
    let left = 230.0;
    let right = 880.0;
    let top = 44.0;
    let bar_h = 14.0;
    let group_h = RAILS.len() as f64 * (bar_h + 3.0) + 22.0;
    let vals: Vec<f64> = b
        .rows
        .iter()
        .flat_map(|r| r.rail_ua.iter().copied().chain([r.total_ua]))
        .filter(|v| *v > 0.0)
        .collect();
    let lo = vals
        .iter()
        .copied()
        .fold(f64::INFINITY, f64::min)
        .max(1e-3)
        .log10()
        .floor();
    let hi = vals
        .iter()
        .copied()
        .fold(1.0f64, f64::max)
        .log10()
        .ceil()
        .max(lo + 1.0);
    let sx = |v: f64| left + (v.max(10f64.powf(lo)).log10() - lo) / (hi - lo) * (right - left);
    let bottom = top + group_h * b.rows.len() as f64;
    let mut d = lo;
    while d <= hi + 1e-9 {
        let x = sx(10f64.powf(d));
        // grid lines only beside the bars, never through a group's title
        for g in 0..b.rows.len() {
            let gy = top + g as f64 * group_h;
            svg.line(x, gy + 16.0, x, gy + group_h - 4.0, "#e0e0e0", 1.0, None);
        }
        let label = if d >= 3.0 {
            format!("{} mA", 10f64.powf(d - 3.0))
        } else {
            format!("{} uA", 10f64.powf(d))
        };
        svg.text(x, bottom + 16.0, 11.0, Anchor::Middle, "#000", &label);
        d += 1.0;
    }
    for (g, r) in b.rows.iter().enumerate() {
        let gy = top + g as f64 * group_h;
        svg.text(
            20.0,
            gy + 12.0,
            12.5,
            Anchor::Start,
            "#000",
            &format!(
                "{}: total {:.2} uA, Vs2 duty {:.2} %",
                r.variant.label(),
                r.total_ua,
                r.vs2_duty() * 100.0
            ),
        );
        for (k, rail) in RAILS.iter().enumerate() {
            let y = gy + 18.0 + k as f64 * (bar_h + 3.0);
            svg.text(left - 8.0, y + 11.0, 11.0, Anchor::End, "#404040", rail);
            if r.rail_ua[k] > 0.0 {
                svg.rect(left, y, sx(r.rail_ua[k]) - left, bar_h, PALETTE[k], None);
                let v = format!("{:.3} uA", r.rail_ua[k]);
                svg.text(
                    sx(r.rail_ua[k]) + 4.0,
                    y + 11.0,
                    10.0,
                    Anchor::Start,
                    "#000",
                    &v,
                );
            } else {
                svg.text(
                    left + 4.0,
                    y + 11.0,
                    10.0,
                    Anchor::Start,
                    "#707070",
                    "0 (rail off)",
                );
            }
        }
    }
    for g in 0..b.rows.len() {
        let gy = top + g as f64 * group_h;
        svg.line(left, gy + 16.0, left, gy + group_h - 4.0, "#000", 1.0, None);
    }

    let mut c = Chart::new(
        &format!(
            "cumulative key-off charge over the run ({:.0} s)",
            b.duration_s
        ),
        "time (s)",
        "charge (mAh)",
    );
    for (k, r) in b.rows.iter().enumerate() {
        c.series.push(Series {
            name: format!("{}: {:.5} mAh", r.variant.label(), r.total_uc / UC_PER_MAH),
            color: [PALETTE[0], PALETTE[1], PALETTE[6], PALETTE[3]][k % 4].into(),
            style: Style::Line,
            points: r.curve.clone(),
        });
    }
    c.auto_range();
    let ctop = bottom + 40.0;
    c.draw(&mut svg, 0.0, ctop, 1000.0, 900.0 - ctop);
    svg.finish()
}

/// `pmu50 budget`: run, write budget.csv, budget_cumulative.csv and budget.svg into `dir`, and
/// return the summary.
pub fn run_cli(sc: &Scenario, dir: &std::path::Path) -> Result<String, AnalysisError> {
    let b = budget(sc)?;
    let w = |name: &str, text: String| {
        crate::plot::write_atomic(&dir.join(name), text.as_bytes()).map_err(AnalysisError::Write)
    };
    w("budget.csv", csv(&b))?;
    w("budget_cumulative.csv", curve_csv(&b))?;
    w("budget.svg", svg(&b))?;
    Ok(summary(&b)
        + &format!(
            "   wrote {0}/budget.csv, {0}/budget_cumulative.csv and {0}/budget.svg\n",
            dir.display()
        ))
}
