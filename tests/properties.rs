//! System-level properties, each against a simple reference: the true motor angle.
//!
//! - For any motion that crosses at most one quadrant boundary between two samples, across any
//!   number of key-off/key-on cycles, the read-out's θm at key-on equals the true multi-turn angle
//!   within the first sensor's resolution.
//! - With a comparator threshold error of up to ±10 % of the amplitude, the quadrant correction
//!   still gives the true rotation number.
//! - cnt_s and cnt_c differ by at most 1 unless a quadrant was skipped, and then diag is set.
//! - The drive interval stays within [minimum, x].
//! - Fast-forwarding idle gaps changes nothing.

use pmu50_testbench::scenario::Scenario;
use pmu50_testbench::sim::{run, RunResult, SimOptions};
use proptest::prelude::*;
use std::fmt::Write;
use std::path::Path;

/// One motion segment: (duration in 10 us ticks, angle change in degrees).
#[derive(Clone, Debug)]
struct Seg {
    ticks: u64,
    delta: f64,
}

/// A random stimulus: start angle, segments, key toggles (tick, level), threshold errors.
#[derive(Clone, Debug)]
struct Stim {
    start: f64,
    segs: Vec<Seg>,
    keys: Vec<(u64, bool)>,
    vr_err: (f64, f64),
    ticks: u64,
}

fn to_toml(s: &Stim) -> String {
    let mut t = String::new();
    let _ = writeln!(t, "duration = \"{} us\"", s.ticks * 10);
    let _ = writeln!(
        t,
        "[env.comparator]\nvr_err_s = {}\nvr_err_c = {}",
        s.vr_err.0, s.vr_err.1
    );
    let _ = writeln!(t, "[motor]\nstart_deg = {}\nsegments = [", s.start);
    for g in &s.segs {
        if g.delta == 0.0 {
            let _ = writeln!(
                t,
                "  {{ kind = \"hold\", duration = \"{} us\" }},",
                g.ticks * 10
            );
        } else {
            let _ = writeln!(
                t,
                "  {{ kind = \"move\", duration = \"{} us\", delta_deg = {} }},",
                g.ticks * 10,
                g.delta
            );
        }
    }
    t += "]\n";
    for (tick, ig) in &s.keys {
        let _ = writeln!(t, "[[events]]\nat = \"{} us\"\nig = {ig}", tick * 10);
    }
    t
}

fn sim(s: &Stim, ff: bool) -> RunResult {
    let text = to_toml(s);
    let sc = Scenario::parse(&text, "prop.toml", "prop", Path::new("prop.toml"))
        .unwrap_or_else(|e| panic!("{e}\n{text}"));
    run(&sc, SimOptions { fast_forward: ff }, &mut []).unwrap()
}

/// Motion no faster than `max_deg_per_ms`; key periods long enough for the MPU to boot (1 ms)
/// and read; always ends with the key on after a key-off period.
fn stim(max_deg_per_ms: f64, vr_err: f64) -> impl Strategy<Value = Stim> {
    let seg = (20u64..3_000, -1.0f64..1.0, any::<bool>()).prop_map(move |(ticks, f, hold)| Seg {
        ticks,
        delta: if hold {
            0.0
        } else {
            (f * max_deg_per_ms * ticks as f64 / 100.0 * 1000.0).round() / 1000.0
        },
    });
    let keys = prop::collection::vec(300u64..4_000, 1..4);
    (
        0.0f64..360.0,
        prop::collection::vec(seg, 1..8),
        keys,
        -vr_err..=vr_err,
        -vr_err..=vr_err,
    )
        .prop_map(|(start, segs, gaps, es, ec)| {
            // ig on at 0, then alternate off/on; the last toggle is on, followed by 500 ticks.
            let mut keys = vec![(0u64, true)];
            let mut t = 200u64;
            let mut level = false;
            for g in gaps.iter().chain(gaps.iter()) {
                keys.push((t, level));
                t += g;
                level = !level;
            }
            if !keys.last().is_some_and(|k| k.1) {
                keys.push((t, true));
                t += 300;
            }
            let ticks = t + 500;
            Stim {
                start: (start * 10.0).round() / 10.0,
                segs,
                keys,
                vr_err: (
                    (es * 1000.0).round() / 1000.0,
                    (ec * 1000.0).round() / 1000.0,
                ),
                ticks,
            }
        })
}

fn counts_and_interval_invariants(r: &RunResult) -> Result<(), TestCaseError> {
    for p in r.pulses.iter() {
        prop_assert!((220..=660).contains(&p.si), "si {} outside [min, x]", p.si);
    }
    let w = r.cnt_width;
    let d = pmu50_core::count_diagnosis::difference(r.final_ports.cnt_s, r.final_ports.cnt_c, w);
    if r.final_ports.quadrant_skip {
        prop_assert!(r.final_ports.diag, "a skipped quadrant sets diag");
    } else {
        prop_assert!(d.abs() <= 1, "|cnt_s - cnt_c| = {} without a skip", d.abs());
        for p in r.pulses.iter() {
            prop_assert!((p.cnt_s - p.cnt_c).abs() <= 1, "{p:?}");
        }
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 128, ..ProptestConfig::default() })]

    /// At most one quadrant per sample: 90 deg per 6.6 ms is 13.6 deg/ms; stay below 10.
    #[test]
    fn read_out_equals_the_true_multi_turn_angle(s in stim(10.0, 0.0)) {
        let r = sim(&s, true);
        prop_assert!(!r.keyons.is_empty());
        for k in &r.keyons {
            prop_assert!(k.error_deg.abs() <= 0.05 + 1e-9, "read-out {:?} off by {} deg\n{}", k.readout, k.error_deg, to_toml(&s));
            prop_assert!(!k.diag);
        }
        prop_assert!(!r.final_ports.quadrant_skip);
        counts_and_interval_invariants(&r)?;
    }

    /// Threshold errors up to +-10 % of the amplitude move a boundary by up to 5.7 deg, so the
    /// narrowest quadrant is 78.6 deg; motion stays below 78 deg per 6.6 ms.
    #[test]
    fn quadrant_correction_gives_the_true_rotation_number_with_threshold_errors(s in stim(10.0, 0.10)) {
        let r = sim(&s, true);
        for k in &r.keyons {
            // Within half a theta1 resolution step (0.05 deg) of a turn boundary the first sensor
            // may round to either side, and both turns are then right.
            let nr_lo = ((k.true_deg - 0.05) / 360.0).floor() as i32;
            let nr_hi = ((k.true_deg + 0.05) / 360.0).floor() as i32;
            prop_assert!((nr_lo..=nr_hi).contains(&k.readout.nr), "Nr {} not in {nr_lo}..={nr_hi}: {:?}\n{}", k.readout.nr, k, to_toml(&s));
            prop_assert!(k.error_deg.abs() <= 0.05 + 1e-9);
        }
        counts_and_interval_invariants(&r)?;
    }

    /// Any speed, including fast enough to skip quadrants: the counts invariant or the diagnosis.
    #[test]
    fn counts_differ_by_at_most_one_unless_a_quadrant_was_skipped(s in stim(120.0, 0.05)) {
        let r = sim(&s, true);
        counts_and_interval_invariants(&r)?;
    }

    /// Fast-forwarding idle key-off gaps is exact.
    #[test]
    fn fast_forward_gives_identical_results(s in stim(20.0, 0.05)) {
        let a = sim(&s, true);
        let b = sim(&s, false);
        prop_assert_eq!(&a.pulses, &b.pulses);
        prop_assert_eq!(&a.keyons, &b.keyons);
        prop_assert_eq!(a.final_regs, b.final_regs);
        prop_assert_eq!(a.dark.vs2_on_ns, b.dark.vs2_on_ns);
        prop_assert_eq!(a.dark.key_off_ns, b.dark.key_off_ns);
        prop_assert!(a.evaluated_ticks <= b.evaluated_ticks);
    }
}

#[test]
fn fast_forward_skips_most_of_a_parked_hour_fraction() {
    // 10 s parked at x = 6.6 ms: only the windows and a few ticks around them are evaluated.
    let s = Stim {
        start: 10.0,
        segs: vec![Seg {
            ticks: 10,
            delta: 0.0,
        }],
        keys: vec![],
        vr_err: (0.0, 0.0),
        ticks: 1_000_000,
    };
    let r = sim(&s, true);
    assert_eq!(r.pulses.len(), 1_000_000u64.div_ceil(660));
    assert!(
        r.evaluated_ticks * 10 < r.ticks,
        "evaluated {} of {}",
        r.evaluated_ticks,
        r.ticks
    );
}
