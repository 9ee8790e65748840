//! The patent's numbers, asserted directly on full-system runs (core + environment), so that a
//! golden snapshot accepted by mistake cannot hide a regression.

use pmu50_core::drive_interval_changing_56b::{Fig17, Fig18};
use pmu50_testbench::scenario::Scenario;
use pmu50_testbench::sim::{run, PulseRow, RunResult, SimOptions};
use std::path::Path;

fn load(name: &str) -> Scenario {
    Scenario::load(
        &Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("scenarios")
            .join(format!("{name}.toml")),
    )
    .unwrap()
}

fn parse(text: &str) -> Scenario {
    Scenario::parse(text, "inline.toml", "inline", Path::new("inline.toml"))
        .unwrap_or_else(|e| panic!("{e}"))
}

fn sim(sc: &Scenario) -> RunResult {
    run(sc, SimOptions::default(), &mut []).unwrap()
}

/// Pulses at which the interval changed, as (si in ms, the row).
fn changes(r: &RunResult) -> Vec<(f64, PulseRow)> {
    let mut out = Vec::new();
    let mut si = None;
    for p in r.pulses.iter() {
        if si != Some(p.si) {
            si = Some(p.si);
            out.push((f64::from(p.si) * r.clock_ns as f64 / 1e6, p));
        }
    }
    out
}

fn ms(v: f64) -> f64 {
    (v * 10.0).round() / 10.0
}

#[test]
fn fig15a_cs_then_cc_shortens_6_6_to_4_4_to_2_2() {
    let r = sim(&load("fig15a"));
    let ch = changes(&r);
    let seq: Vec<f64> = ch.iter().map(|c| ms(c.0)).collect();
    assert_eq!(seq, vec![6.6, 4.4, 2.2], "{}", r.pulse_table());
    // Reference sign 100: Cs 0 -> 1, stored in hist_s, shortened by T1.
    let p = &ch[1].1;
    assert!(p.cs && !p.cc && p.hist_s && !p.hist_c, "{p:?}");
    assert_eq!((p.fig17, p.fig18), (Fig17::S6Shorten, Fig18::S23DetectedCs));
    // Reference sign 101: Cc 0 -> 1, history moves to Cc, shortened again to the minimum.
    let p = &ch[2].1;
    assert!(p.cs && p.cc && !p.hist_s && p.hist_c, "{p:?}");
    assert_eq!((p.fig17, p.fig18), (Fig17::S6Shorten, Fig18::S28DetectedCc));
    // Cycle from st to st equals the interval decided at that pulse: the next pulse comes
    // exactly si ticks after this one.
    let rows = r.pulses.rows();
    let i = rows.iter().position(|q| q == p).unwrap();
    assert_eq!(rows[i + 1].tick - p.tick, u64::from(p.si));
}

#[test]
fn fig15b_15c_a_second_change_of_the_same_sign_does_not_shorten_again() {
    let r = sim(&load("fig15b"));
    let rows = r.pulses.rows();
    let first = rows
        .iter()
        .position(|p| p.fig18 == Fig18::S23DetectedCs)
        .expect("Cs change");
    let again = rows
        .iter()
        .position(|p| p.fig18 == Fig18::S21CsRepeat)
        .expect("Cs changes back");
    assert!(again > first);
    assert_eq!(rows[first].si, 440, "6.6 -> 4.4 ms at the first change");
    let p = &rows[again];
    assert_eq!(
        p.si,
        440,
        "no second shortening [0236]: {}",
        r.pulse_table()
    );
    assert!(!p.cs && p.hist_s, "Cs is back at 0, history still stored");
    assert_eq!(
        p.fig17,
        Fig17::S9Count,
        "not a rotation: counts as a quiet pulse"
    );
    assert!(
        r.pulses.iter().all(|p| p.si >= 440),
        "never below 4.4 ms in FIG. 15B"
    );
}

#[test]
fn fig16_expands_2_2_3_3_4_4_5_5_6_6_and_stops_at_x() {
    let r = sim(&load("fig16"));
    let rows = r.pulses.rows();
    let at_min = rows
        .iter()
        .position(|p| p.si == 220)
        .expect("reaches 2.2 ms");
    let after = &rows[at_min + 1..];
    // Cth = 4: four quiet pulses count 1..4, the fifth expands by T2 = 1.1 ms, and every later
    // quiet pulse expands again until x.
    let got: Vec<(Fig17, u8, u16)> = after
        .iter()
        .take(10)
        .map(|p| (p.fig17, p.cnt_r, p.si))
        .collect();
    let want = vec![
        (Fig17::S9Count, 1, 220),
        (Fig17::S9Count, 2, 220),
        (Fig17::S9Count, 3, 220),
        (Fig17::S9Count, 4, 220),
        (Fig17::S10Expand, 5, 330),
        (Fig17::S10Expand, 6, 440),
        (Fig17::S10Expand, 7, 550),
        (Fig17::S10Expand, 8, 660),
        (Fig17::S7AtMax, 8, 660),
        (Fig17::S7AtMax, 8, 660),
    ];
    assert_eq!(got, want, "{}", r.pulse_table());
    assert!(
        after
            .iter()
            .filter(|p| p.fig17 == Fig17::S10Expand)
            .all(|p| !p.hist_s && !p.hist_c),
        "S11 clears the history"
    );
    // The interval between consecutive pulses is the interval decided at the earlier one.
    for w in after.windows(2) {
        assert_eq!(w[1].tick - w[0].tick, u64::from(w[0].si));
    }
}

#[test]
fn change_at_3_3_ms_goes_to_2_2_not_below_0261_0262() {
    // FIG. 16 run, then a new quarter-turn crossing right after the first expansion to 3.3 ms.
    let base = sim(&load("fig16"));
    let expand = base
        .pulses
        .iter()
        .find(|p| p.fig17 == Fig17::S10Expand)
        .expect("expansion");
    assert_eq!(expand.si, 330);
    let t_ms = expand.time_ns as f64 / 1e6;
    let hold = t_ms - 38.0 + 0.3; // the fig16 motion ends at 38 ms
    let text = format!(
        r#"duration = "{end} ms"
[motor]
start_deg = 190.0
segments = [
  {{ kind = "hold", duration = "20 ms" }},
  {{ kind = "move", duration = "18 ms", delta_deg = -110.0 }},
  {{ kind = "hold", duration = "{hold:.2} ms" }},
  {{ kind = "move", duration = "1 ms", delta_deg = 15.0 }},
]
"#,
        end = (t_ms + 8.0).round(),
    );
    let r = sim(&parse(&text));
    let rows = r.pulses.rows();
    let i = rows
        .iter()
        .position(|p| p.fig17 == Fig17::S10Expand)
        .unwrap();
    let p = &rows[i + 1];
    assert_eq!(rows[i].si, 330);
    assert_eq!(
        (p.fig17, p.si),
        (Fig17::S6Shorten, 220),
        "3.3 ms - T1 clamps at the 2.2 ms minimum: {}",
        r.pulse_table()
    );
}

#[test]
fn first_embodiment_keeps_the_fixed_cycle() {
    let r = sim(&load("first_embodiment"));
    assert!(!r.pulses.is_empty());
    assert!(
        r.pulses
            .iter()
            .all(|p| p.si == 660 && p.fig17 == Fig17::Fixed),
        "{}",
        r.pulse_table()
    );
    assert!(
        r.final_ports.cnt_s != 0 || r.final_ports.cnt_c != 0,
        "the counters still count"
    );
    assert!(r.passed(), "{:?}", r.checks);
}

fn parked(x: &str, cycles: u64) -> RunResult {
    let x_ms: f64 = x.trim_end_matches(" ms").parse().unwrap();
    let dur_us = (x_ms * 1000.0).round() as u64 * cycles;
    sim(&parse(&format!(
        "duration = \"{dur_us} us\"\n[core]\nadaptive = false\nx = \"{x}\"\n"
    )))
}

#[test]
fn vs2_duty_is_10_percent_at_2_2_ms_and_a_third_of_that_at_6_6_ms_0230_0231() {
    let fast = parked("2.2 ms", 30);
    let (on, total) = fast.dark.vs2_duty_fraction();
    assert_eq!(on * 10, total, "220 us every 2.2 ms is exactly 10 %");
    let slow = parked("6.6 ms", 10);
    let (on6, total6) = slow.dark.vs2_duty_fraction();
    assert_eq!(on6 * 30, total6, "220 us every 6.6 ms is a third of 10 %");
    assert!(slow.dark.avg_current_ua.unwrap() < fast.dark.avg_current_ua.unwrap());
}

#[test]
fn s1_no_rise_of_vs2_means_no_sample_and_no_change_0264() {
    let r = sim(&parse(
        r#"duration = "60 ms"
[motor]
start_deg = 190.0
segments = [ { kind = "hold", duration = "10 ms" }, { kind = "move", duration = "20 ms", delta_deg = -110.0 } ]
[[events]]
at = "5 ms"
vs2_fault = true
"#,
    ));
    let faulted: Vec<PulseRow> = r.pulses.iter().filter(|p| p.time_ns > 5_000_000).collect();
    assert!(!faulted.is_empty());
    assert!(
        faulted
            .iter()
            .all(|p| p.fig17 == Fig17::S1NoRise && p.si == 660 && p.cnt_r == 0),
        "{}",
        r.pulse_table()
    );
    assert!(
        !r.final_ports.cs && !r.final_ports.cc,
        "Cs/Cc keep the last sampled values (third quadrant)"
    );
}

#[test]
fn keyoff_turns_read_out_gives_the_true_angle() {
    let r = sim(&load("keyoff_turns"));
    assert_eq!(r.keyons.len(), 2);
    let k = &r.keyons[1];
    assert_eq!(
        k.readout.nr, 1,
        "two turns forward and one back: one turn on"
    );
    assert!(k.error_deg.abs() <= 0.05, "{k:?}");
    assert!(!k.diag && !k.theta_abnormal);
    assert!(r.passed(), "{:?}", r.checks);
}

#[test]
fn threshold_error_is_corrected_by_equations_1_and_2() {
    use pmu50_env::QuadrantEquation;
    let r = sim(&load("threshold_error"));
    assert_eq!(r.keyons.len(), 3);
    let (a, b) = (&r.keyons[1].readout, &r.keyons[2].readout);
    assert_eq!(
        (a.quadrant_diff, a.equation),
        (-1, QuadrantEquation::Eq1),
        "Cs falls late after 180 deg: CNT one short"
    );
    assert_eq!(
        (b.quadrant_diff, b.equation),
        (1, QuadrantEquation::Eq2),
        "Cs rises early before 360 deg: Q1 fourth, Q2 first"
    );
    assert!(
        r.keyons.iter().all(|k| k.error_deg.abs() <= 0.05),
        "{:?}",
        r.keyons
    );
}

#[test]
fn too_fast_rotation_sets_quadrant_skip_and_diag() {
    let r = sim(&load("too_fast"));
    assert!(r.final_ports.quadrant_skip && r.final_ports.diag);
    let k = &r.keyons[0];
    assert!(
        k.diag && k.quadrant_skip,
        "the MPU sees the diagnosis in STATUS"
    );
    assert!(
        k.error_deg.abs() > 90.0,
        "the read-out is wrong, which is why the flag exists"
    );
}

#[test]
fn every_shipped_scenario_passes_its_own_checks() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenarios");
    let mut n = 0;
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.extension().is_some_and(|x| x == "toml") {
            let r = sim(&Scenario::load(&p).unwrap());
            assert!(r.passed(), "{}: {:?}", p.display(), r.checks);
            n += 1;
        }
    }
    assert!(n >= 7);
}
