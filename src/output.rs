//! Running a scenario to files (VCD, GTKWave save file, change log) and the text summary.

use crate::changelog::ChangeLog;
use crate::scenario::Scenario;
use crate::sim::{self, Observer, RunResult, SimError, SimOptions, TickView};
use crate::waveform::VcdObserver;
use pmu50_core::pmu50::Structural;
use std::fs::File;
use std::io::BufWriter;
use std::path::{Path, PathBuf};

/// What to write besides the VCD and its save file.
#[derive(Clone, Copy, Debug, Default)]
pub struct FileOptions {
    /// Also write `<name>.log`, one line per register change.
    pub log: bool,
    /// Dump window in ticks (overrides the scenario's `[vcd] window`).
    pub window: Option<(u64, u64)>,
}

/// Paths written by [`run_to_files`].
#[derive(Clone, Debug)]
pub struct Written {
    pub vcd: PathBuf,
    pub gtkw: PathBuf,
    pub log: Option<PathBuf>,
}

/// Run `sc`, writing `<dir>/<name>.vcd`, `.gtkw` and optionally `.log`; `extra` observers (a
/// progress bar, a vector writer) see every tick as well.
pub fn run_to_files(sc: &Scenario, dir: &Path, fo: FileOptions, extra: &mut [&mut dyn Observer]) -> Result<(RunResult, Written), SimError> {
    std::fs::create_dir_all(dir).map_err(|e| SimError::Observer(format!("{}: {e}", dir.display())))?;
    let s = Structural { sync_depth: sc.params.sync_depth, cnt_width: sc.params.cnt_width };
    let window = fo.window.or(sc.vcd_window);
    // The VCD declares every signal with its reset value: built when the bench begins.
    let mut vcd = sim::OnBegin::new(|init: &TickView<'_>| VcdObserver::create(dir, &sc.name, s, sc.clock_ns(), window, init));
    let log_path = dir.join(format!("{}.log", sc.name));
    let mut log = if fo.log {
        let f = File::create(&log_path).map_err(|e| SimError::Observer(format!("{}: {e}", log_path.display())))?;
        Some(ChangeLog::new(BufWriter::new(f), s, sc.clock_ns())?)
    } else {
        None
    };
    let mut obs: Vec<&mut dyn Observer> = vec![&mut vcd];
    if let Some(l) = log.as_mut() {
        obs.push(l);
    }
    for e in extra.iter_mut() {
        obs.push(&mut **e);
    }
    let res = sim::run(sc, SimOptions::default(), &mut obs)?;
    Ok((res, Written { vcd: dir.join(format!("{}.vcd", sc.name)), gtkw: dir.join(format!("{}.gtkw", sc.name)), log: fo.log.then_some(log_path) }))
}

/// Human summary of a run: counts, read-outs against the true angle, diagnosis, Vs2 duty,
/// average key-off current, checks.
pub fn summary(sc: &Scenario, r: &RunResult) -> String {
    let mut s = String::new();
    let ms = |ticks: u64| ticks as f64 * r.clock_ns as f64 / 1e6;
    let w = r.cnt_width;
    let sx = |v: u16| pmu50_core::updown_counter_58cd::sext(v, w);
    s += &format!("== {}: {}\n", sc.name, sc.description);
    s += &format!("   simulated {:.3} ms ({} ticks of {} ns), {} key-off pulses\n", ms(r.ticks), r.ticks, r.clock_ns, r.pulses.len());
    let p = &r.final_ports;
    s += &format!(
        "   final: cnt_s={} cnt_c={} (CNT={}) si={:.1} ms cnt_r={} hist_s={} hist_c={} diag={} quadrant_skip={}\n",
        sx(p.cnt_s),
        sx(p.cnt_c),
        sx(p.cnt_s) + sx(p.cnt_c),
        f64::from(p.si) * r.clock_ns as f64 / 1e6,
        p.cnt_r,
        u8::from(p.hist_s),
        u8::from(p.hist_c),
        u8::from(p.diag),
        u8::from(p.quadrant_skip)
    );
    let seq: Vec<String> = r.si_sequence_ms().iter().map(|v| format!("{v:.1}")).collect();
    if !seq.is_empty() {
        s += &format!("   drive interval at key-off pulses (ms): {}\n", seq.join(" -> "));
    }
    for k in &r.keyons {
        let ro = &k.readout;
        s += &format!(
            "   key-on read-out at {:.3} ms: CNTs={} CNTc={} CNT={} Q1={} Q2={} diff={} ({:?}) CNTa={} Nr={} theta1={:.2} -> theta_m={:.2} deg, true {:.2} deg, error {:+.3} deg; theta_o={:.3} theta_i={:.3} deg; diag={} theta1/theta2 abnormal={}\n",
            k.time_ns as f64 / 1e6, ro.cnt_s, ro.cnt_c, ro.cnt, ro.q1, ro.q2, ro.quadrant_diff, ro.equation, ro.cnt_a, ro.nr, ro.theta1_deg, ro.theta_m_deg, k.true_deg, k.error_deg, k.angles.theta_o_deg, k.angles.theta_i_deg, u8::from(k.diag), u8::from(k.theta_abnormal)
        );
    }
    for k in &r.keyoffs {
        s += &format!("   key-off at {:.3} ms: tracked theta_m={:.2} deg (theta_o={:.3}, theta_i={:.3}), true {:.2} deg\n", ms(k.tick), k.theta_m_deg, k.angles.theta_o_deg, k.angles.theta_i_deg, k.true_deg);
    }
    let d = &r.dark;
    if d.key_off_ns > 0 {
        let duty = d.vs2_duty.map_or("-".into(), |v| format!("{:.2} %", v * 100.0));
        let cur = d.avg_current_ua.map_or("-".into(), |v| format!("{v:.1} uA"));
        s += &format!("   key off for {:.3} ms: Vs2 duty {duty}, average key-off current {cur}\n", d.key_off_ns as f64 / 1e6);
    }
    for c in &r.checks {
        s += &format!("   check {:<20} {}  {}\n", c.name, if c.ok { "PASS" } else { "FAIL" }, c.detail);
    }
    s
}
