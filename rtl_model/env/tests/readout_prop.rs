//! Property and end-to-end tests of the key-on read-out (US 2022/0041215 A1
//! [0108]-[0116], [0137]-[0153]).

use pmu50_env::{
    ComparatorBits, ComparatorConfig, ComparatorPair, MotorProfile, Readout, ReadoutConfig,
    Segment, Sensor1, Sensor1Config, Sensor2, Sensor2Config,
};
use proptest::prelude::*;

/// Count error consistent with a comparator threshold shift: near a
/// quadrant boundary the count may already have switched (just below the
/// boundary, +1) or not yet switched (just above it, -1). Elsewhere 0.
fn allowed_error(theta: f64, wanted: i32, window_deg: f64) -> i32 {
    let k = (theta / 90.0).floor();
    let below = theta - 90.0 * k; // distance above the lower boundary
    let above = 90.0 * (k + 1.0) - theta; // distance below the upper boundary
    match wanted {
        1 if above < window_deg => 1,
        -1 if below < window_deg => -1,
        _ => 0,
    }
}

fn split(cnt: i32, skew: i32) -> (i16, i16) {
    let s = cnt.div_euclid(2) + skew;
    (s as i16, (cnt - s) as i16)
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 4096, ..ProptestConfig::default() })]

    /// For any true multi-turn angle within ±20 turns and any count that is
    /// ideal or off by one quadrant near a boundary, θm equals the true angle
    /// within the θ1 resolution (rounding to nearest: half a step).
    #[test]
    fn key_on_theta_m_matches_true_angle(
        theta in -7200.0f64..7200.0,
        wanted in -1i32..=1,
        skew in -1i32..=1,
    ) {
        let s1 = Sensor1::new(Sensor1Config::default()).unwrap();
        let ro = Readout::new(ReadoutConfig::default()).unwrap();
        let ideal_cnt = (theta / 90.0).floor() as i32; // 4·floor(Θ/360) + quadrant
        let err = allowed_error(theta, wanted, 20.0);
        let (cs, cc) = split(ideal_cnt + err, skew);
        let th1 = s1.theta1_deg(theta).unwrap();
        let r = ro.key_on(cs, cc, th1).unwrap();
        prop_assert!(
            (r.theta_m_deg - theta).abs() <= 0.05 + 1e-9,
            "Θ = {theta}, err = {err}, readout = {r:?}"
        );
        prop_assert!(r.quadrant_diff.abs() <= 1);
        prop_assert!(!r.quadrant_mismatch);
    }

    /// Same with an ideal (unquantised) θ1: θm is exact up to float rounding.
    #[test]
    fn key_on_theta_m_exact_with_ideal_theta1(
        theta in -7200.0f64..7200.0,
        wanted in -1i32..=1,
    ) {
        let ro = Readout::new(ReadoutConfig::default()).unwrap();
        let ideal_cnt = (theta / 90.0).floor() as i32;
        let err = allowed_error(theta, wanted, 20.0);
        let (cs, cc) = split(ideal_cnt + err, 0);
        let th1 = Sensor1::ideal().theta1_deg(theta).unwrap();
        let r = ro.key_on(cs, cc, th1).unwrap();
        prop_assert!((r.theta_m_deg - theta).abs() < 1e-9, "Θ = {theta}, {r:?}");
        // Nr is the floor quotient of the true angle.
        prop_assert_eq!(r.nr, (theta / 360.0).floor() as i32);
    }

    /// Key-on tracking ([0115]) follows any walk with steps below 180 deg.
    #[test]
    fn tracking_follows_random_walk(
        start in -3600.0f64..3600.0,
        steps in proptest::collection::vec(-179.0f64..179.0, 1..200),
    ) {
        let s1 = Sensor1::new(Sensor1Config::default()).unwrap();
        let ro = Readout::new(ReadoutConfig::default()).unwrap();
        let (cs, cc) = split((start / 90.0).floor() as i32, 0);
        let r = ro.key_on(cs, cc, s1.theta1_deg(start).unwrap()).unwrap();
        let mut t = ro.tracker(&r);
        let mut theta = start;
        for d in steps {
            theta += d;
            let m = t.update(s1.theta1_deg(theta).unwrap()).unwrap();
            prop_assert!((m - theta).abs() <= 0.05 + 1e-6, "Θ = {theta}, θm = {m}");
        }
    }
}

/// Reference quadrant counter following [0096]-[0099] literally (the real
/// one lives in the digital core; this is only a test oracle).
struct RefCounter {
    cnt_s: i16,
    cnt_c: i16,
    prev: ComparatorBits,
}

impl RefCounter {
    fn update(&mut self, b: ComparatorBits) {
        let p = self.prev;
        if p.cs != b.cs {
            let rising = b.cs;
            // [0096]: Cc = 1: 0->1 is +1, 1->0 is -1. [0097]: Cc = 0: mirrored.
            let up = if b.cc { rising } else { !rising };
            self.cnt_s += if up { 1 } else { -1 };
        }
        if p.cc != b.cc {
            let rising = b.cc;
            // [0098]: Cs = 0: 0->1 is +1. [0099]: Cs = 1: 1->0 is +1.
            let up = if b.cs { !rising } else { rising };
            self.cnt_c += if up { 1 } else { -1 };
        }
        self.prev = b;
    }
}

/// Motor -> sensor 34 -> comparators (FIG. 10 threshold error) -> counter
/// oracle -> key-on read-out: the correction of FIG. 12 removes the count
/// timing errors (FIG. 13), and without it θm would be off by a turn
/// (FIG. 11B).
#[test]
fn end_to_end_fig10_threshold_error_is_corrected() {
    let motor = MotorProfile::new(
        10.0,
        vec![
            Segment::Move {
                duration_ns: 2_000_000_000,
                delta_deg: 5.0 * 360.0,
            },
            Segment::Hold {
                duration_ns: 10_000_000,
            },
            Segment::Move {
                duration_ns: 3_000_000_000,
                delta_deg: -9.0 * 360.0 - 45.0,
            },
        ],
    )
    .unwrap();
    let mut s2 = Sensor2::new(Sensor2Config::default()).unwrap();
    let cmp = ComparatorPair::new(ComparatorConfig {
        vr_err_s: -0.10,
        vr_err_c: 0.05,
    })
    .unwrap();
    let s1 = Sensor1::new(Sensor1Config::default()).unwrap();
    let ro = Readout::new(ReadoutConfig::default()).unwrap();

    let tick = 10_000u64;
    let vs2 = 5.0;
    // Settle the sensor at the start angle before counting.
    for _ in 0..100 {
        s2.step(vs2, motor.angle_at(0), tick).unwrap();
    }
    let (a, b) = s2.outputs();
    let mut ctr = RefCounter {
        cnt_s: 0,
        cnt_c: 0,
        prev: cmp.compare(vs2, a, b),
    };
    let mut uncorrected_wrong = 0u32;
    let mut samples = 0u32;
    let mut t = 0u64;
    let mut n_tick = 0u32;
    while t <= motor.end_ns() + 10 * tick {
        t += tick;
        let theta = motor.angle_at(t);
        let (a, b) = s2.step(vs2, theta, tick).unwrap();
        ctr.update(cmp.compare(vs2, a, b));
        n_tick += 1;
        if n_tick == 7 {
            n_tick = 0;
            samples += 1;
            let r = ro
                .key_on(ctr.cnt_s, ctr.cnt_c, s1.theta1_deg(theta).unwrap())
                .unwrap();
            assert!(
                (r.theta_m_deg - theta).abs() <= 0.05 + 1e-9,
                "t = {t} ns, Θ = {theta}, {r:?}"
            );
            assert!(!r.counts_abnormal, "t = {t}: {r:?}");
            let naive = 360.0 * r.cnt.div_euclid(4) as f64 + r.theta1_deg;
            if (naive - theta).abs() > 1.0 {
                uncorrected_wrong += 1;
            }
        }
    }
    assert!(samples > 50_000);
    // The threshold errors really did disturb the raw count (FIG. 11B).
    assert!(uncorrected_wrong > 100, "{uncorrected_wrong}");
    // Net 5 turns up then 9 turns + 45 deg down: ends at 10 - 4·360 - 45.
    assert_eq!(motor.end_deg(), 10.0 + 1800.0 - 3285.0);
    let r = ro
        .key_on(
            ctr.cnt_s,
            ctr.cnt_c,
            s1.theta1_deg(motor.end_deg()).unwrap(),
        )
        .unwrap();
    assert!((r.theta_m_deg - motor.end_deg()).abs() <= 0.05 + 1e-9);
}
