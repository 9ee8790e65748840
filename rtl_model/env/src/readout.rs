//! MPU 60 key-on read-out: count total unit 62, rotation number information
//! correction unit 63 (FIG. 12), rotation number calculation unit 64,
//! rotation angle information calculation unit 66 and diagnosis unit 67.
//!
//! Key-on sequence ([0108]-[0114], [0137]-[0153]):
//!
//! 1. `CNT = CNTs + CNTc` ([0108]); the 16-bit two's-complement counters are
//!    summed in `i32`, so the sum never wraps.
//! 2. `Q1` = quadrant of θ1 by threshold determination ([0138], [0141]):
//!    index 0 = [0,90), 1 = [90,180), 2 = [180,270), 3 = [270,360).
//! 3. `Q2 = CNT mod 4` (Euclidean remainder, 0..=3) ([0139], [0142]).
//!    Convention: the chip's counters are preset so that
//!    `CNT = 4·turns + quadrant index` when the count is correct.
//! 4. Quadrant difference ([0145]-[0147]): `Q2 - Q1` (eq. 1);
//!    `+ 4` when Q1 is the fourth quadrant (3) and Q2 the first (0) (eq. 2);
//!    `- 4` when Q1 is the first (0) and Q2 the fourth (3) (eq. 3).
//! 5. `CNTa = CNT - difference` ([0150]).
//! 6. `Nr = floor(CNTa / 4)` ([0111] "quotient", n = 4). Interpretation:
//!    the quotient must be the *floor* (Euclidean) quotient, not the
//!    truncating one: for negative multi-turn angles truncation would give
//!    e.g. CNTa = -1 (shaft at 270..360 deg of turn -1) -> Nr = 0 instead of
//!    -1, making θm jump by 360 deg across 0 deg. With floor,
//!    `θm = 360·Nr + θ1` is continuous for all angles.
//! 7. `θm = 360·Nr + θ1` ([0113]-[0114]).
//!
//! While the key stays on ([0115]) θm accumulates the change of θ1, each
//! change wrapped into (-180, 180] deg (so a 359 -> 1 step is +2 deg).
//! [`AngleTracker`] keeps θm as `360·turns + θ1` with an integer turn count,
//! which is exactly the same sum without floating-point drift.
//! [0116]: `θo = θm·Rg` (output shaft, reduction gear ratio Rg) and
//! `θi = θo + θt` (input shaft / steering angle, torsion angle θt).
//!
//! Diagnosis ([0118]-[0119]): abnormal when the circular difference
//! |θ1 - θ2| >= threshold (default 5 deg), and when |CNTs - CNTc| >= 2.

use serde::Deserialize;

use crate::angle::{circular_diff_deg, wrap_180};

/// Counts per rotation (natural number n of [0111]).
pub const COUNTS_PER_TURN: i32 = 4;

/// Read-out parameters (scenario file).
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct ReadoutConfig {
    /// Gear ratio Rg of the reduction gear 3 as a multiplier:
    /// θo = θm·Rg (default 1.0).
    pub gear_ratio: f64,
    /// θ1/θ2 diagnosis threshold, degrees (default 5.0): abnormal when the
    /// circular difference is >= this.
    pub diag_threshold_deg: f64,
    /// Counter diagnosis threshold (default 2): abnormal when
    /// |CNTs - CNTc| >= this ([0119]).
    pub count_diff_threshold: u32,
}

impl Default for ReadoutConfig {
    fn default() -> Self {
        Self {
            gear_ratio: 1.0,
            diag_threshold_deg: 5.0,
            count_diff_threshold: 2,
        }
    }
}

/// Invalid read-out configuration or input.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ReadoutError {
    #[error("readout config field `{field}` = {value} is invalid: must be {valid}")]
    InvalidConfig {
        field: &'static str,
        value: f64,
        valid: &'static str,
    },
    #[error("readout input `{field}` = {value} is invalid: must be {valid}")]
    InvalidInput {
        field: &'static str,
        value: f64,
        valid: &'static str,
    },
}

/// Which of the patent's equations produced the quadrant difference.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum QuadrantEquation {
    /// Eq. (1): Q2 - Q1.
    Eq1,
    /// Eq. (2): Q2 - Q1 + 4 (Q1 fourth quadrant, Q2 first quadrant).
    Eq2,
    /// Eq. (3): Q2 - Q1 - 4 (Q1 first quadrant, Q2 fourth quadrant).
    Eq3,
}

/// Every intermediate of the key-on read-out.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct KeyOnReadout {
    /// Sine count value CNTs as read from the chip.
    pub cnt_s: i16,
    /// Cosine count value CNTc as read from the chip.
    pub cnt_c: i16,
    /// Angular position θ1 at key-on, [0, 360) deg.
    pub theta1_deg: f64,
    /// Total count value CNT = CNTs + CNTc (no wrapping).
    pub cnt: i32,
    /// First quadrant information (from θ1), 0..=3.
    pub q1: u8,
    /// Second quadrant information CNT mod 4, 0..=3.
    pub q2: u8,
    /// Quadrant difference (eq. 1-3); -2..=2.
    pub quadrant_diff: i32,
    /// Equation used for the quadrant difference.
    pub equation: QuadrantEquation,
    /// Corrected total count value CNTa = CNT - quadrant_diff.
    pub cnt_a: i32,
    /// Rotation number Nr = floor(CNTa / 4).
    pub nr: i32,
    /// Rotation angle information θm = 360·Nr + θ1, degrees.
    pub theta_m_deg: f64,
    /// |quadrant_diff| == 2: Q1 and Q2 are opposite quadrants, the count
    /// error is outside what the correction of FIG. 12 can resolve (the
    /// patent expects only -1, 0, +1, [0148]); θm is then unreliable.
    pub quadrant_mismatch: bool,
    /// |CNTs - CNTc| >= count_diff_threshold ([0119]).
    pub counts_abnormal: bool,
}

/// θm and the derived shaft angles of [0116].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RotationAngles {
    /// Motor rotation angle information θm, degrees (multi-turn).
    pub theta_m_deg: f64,
    /// Output shaft angle θo = θm·Rg.
    pub theta_o_deg: f64,
    /// Input shaft (steering) angle θi = θo + θt.
    pub theta_i_deg: f64,
}

/// Quadrant index of an angular position by threshold determination
/// ([0141]); `theta_deg` must be in [0, 360).
fn quadrant_of(theta_deg: f64) -> u8 {
    if theta_deg < 90.0 {
        0
    } else if theta_deg < 180.0 {
        1
    } else if theta_deg < 270.0 {
        2
    } else {
        3
    }
}

fn check_theta1(theta1_deg: f64) -> Result<(), ReadoutError> {
    if theta1_deg.is_finite() && (0.0..360.0).contains(&theta1_deg) {
        Ok(())
    } else {
        Err(ReadoutError::InvalidInput {
            field: "theta1_deg",
            value: theta1_deg,
            valid: "finite and in [0, 360)",
        })
    }
}

/// Quadrant difference per equations (1)-(3) of [0145]-[0147].
pub fn quadrant_difference(q1: u8, q2: u8) -> (i32, QuadrantEquation) {
    let d = q2 as i32 - q1 as i32;
    match (q1, q2) {
        (3, 0) => (d + 4, QuadrantEquation::Eq2),
        (0, 3) => (d - 4, QuadrantEquation::Eq3),
        _ => (d, QuadrantEquation::Eq1),
    }
}

/// |CNTs - CNTc| >= `threshold` ([0119]; the patent's example threshold is 2).
pub fn counts_abnormal(cnt_s: i16, cnt_c: i16, threshold: u32) -> bool {
    (cnt_s as i32 - cnt_c as i32).unsigned_abs() >= threshold
}

/// The read-out logic of MPU 60 with its configuration.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Readout {
    cfg: ReadoutConfig,
}

impl Default for Readout {
    /// Default configuration (Rg = 1, 5 deg θ1/θ2 threshold, counts threshold 2).
    fn default() -> Self {
        Self {
            cfg: ReadoutConfig::default(),
        }
    }
}

impl Readout {
    pub fn new(cfg: ReadoutConfig) -> Result<Self, ReadoutError> {
        if !cfg.gear_ratio.is_finite() {
            return Err(ReadoutError::InvalidConfig {
                field: "gear_ratio",
                value: cfg.gear_ratio,
                valid: "finite",
            });
        }
        if !(cfg.diag_threshold_deg.is_finite()
            && cfg.diag_threshold_deg > 0.0
            && cfg.diag_threshold_deg <= 180.0)
        {
            return Err(ReadoutError::InvalidConfig {
                field: "diag_threshold_deg",
                value: cfg.diag_threshold_deg,
                valid: "finite, > 0 and <= 180 (degrees of circular difference)",
            });
        }
        if cfg.count_diff_threshold == 0 {
            return Err(ReadoutError::InvalidConfig {
                field: "count_diff_threshold",
                value: 0.0,
                valid: ">= 1",
            });
        }
        Ok(Self { cfg })
    }

    pub fn config(&self) -> &ReadoutConfig {
        &self.cfg
    }

    /// Key-on read-out from the chip's counters and θ1 (in [0, 360)).
    pub fn key_on(
        &self,
        cnt_s: i16,
        cnt_c: i16,
        theta1_deg: f64,
    ) -> Result<KeyOnReadout, ReadoutError> {
        check_theta1(theta1_deg)?;
        let cnt = cnt_s as i32 + cnt_c as i32;
        let q1 = quadrant_of(theta1_deg);
        let q2 = cnt.rem_euclid(COUNTS_PER_TURN) as u8;
        let (quadrant_diff, equation) = quadrant_difference(q1, q2);
        let cnt_a = cnt - quadrant_diff;
        let nr = cnt_a.div_euclid(COUNTS_PER_TURN);
        let theta_m_deg = 360.0 * nr as f64 + theta1_deg;
        Ok(KeyOnReadout {
            cnt_s,
            cnt_c,
            theta1_deg,
            cnt,
            q1,
            q2,
            quadrant_diff,
            equation,
            cnt_a,
            nr,
            theta_m_deg,
            quadrant_mismatch: quadrant_diff.abs() >= 2,
            counts_abnormal: counts_abnormal(cnt_s, cnt_c, self.cfg.count_diff_threshold),
        })
    }

    /// θ1/θ2 diagnosis ([0118]): true (abnormal) when the circular
    /// difference is >= `diag_threshold_deg`, or when θ2 is unavailable.
    pub fn theta_abnormal(&self, theta1_deg: f64, theta2_deg: Option<f64>) -> bool {
        match theta2_deg {
            Some(t2) if theta1_deg.is_finite() && t2.is_finite() => {
                circular_diff_deg(theta1_deg, t2) >= self.cfg.diag_threshold_deg
            }
            _ => true,
        }
    }

    /// Counter diagnosis ([0119]) with the configured threshold.
    pub fn counts_abnormal(&self, cnt_s: i16, cnt_c: i16) -> bool {
        counts_abnormal(cnt_s, cnt_c, self.cfg.count_diff_threshold)
    }

    /// Starts key-on tracking from a read-out.
    pub fn tracker(&self, r: &KeyOnReadout) -> AngleTracker {
        AngleTracker {
            turns: r.nr as i64,
            theta1_deg: r.theta1_deg,
            gear_ratio: self.cfg.gear_ratio,
        }
    }
}

/// Key-on tracking of θm ([0115]) and the derived angles ([0116]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AngleTracker {
    turns: i64,
    theta1_deg: f64,
    gear_ratio: f64,
}

impl AngleTracker {
    /// Adds the wrapped change of θ1 (into (-180, 180]) to θm; returns θm.
    pub fn update(&mut self, theta1_deg: f64) -> Result<f64, ReadoutError> {
        check_theta1(theta1_deg)?;
        let d = theta1_deg - self.theta1_deg;
        // θm_new = θm_old + wrap_180(d); with θm = 360·turns + θ1 this only
        // changes `turns` when the wrap adds or removes a full turn.
        let w = wrap_180(d);
        if w - d > 180.0 {
            self.turns += 1; // e.g. 359 -> 1: d = -358, w = +2
        } else if d - w > 180.0 {
            self.turns -= 1; // e.g. 1 -> 359: d = +358, w = -2
        }
        self.theta1_deg = theta1_deg;
        Ok(self.theta_m_deg())
    }

    /// Current θm = 360·turns + θ1.
    pub fn theta_m_deg(&self) -> f64 {
        360.0 * self.turns as f64 + self.theta1_deg
    }

    /// Whole turns part of θm (Nr while tracking).
    pub fn turns(&self) -> i64 {
        self.turns
    }

    /// Last θ1 seen.
    pub fn theta1_deg(&self) -> f64 {
        self.theta1_deg
    }

    /// θm, θo = θm·Rg and θi = θo + θt for torsion angle `theta_t_deg`.
    pub fn angles(&self, theta_t_deg: f64) -> RotationAngles {
        let theta_m_deg = self.theta_m_deg();
        let theta_o_deg = theta_m_deg * self.gear_ratio;
        RotationAngles {
            theta_m_deg,
            theta_o_deg,
            theta_i_deg: theta_o_deg + theta_t_deg,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ro() -> Readout {
        let r = Readout::new(ReadoutConfig::default()).unwrap();
        assert_eq!(r, Readout::default());
        r
    }

    #[test]
    fn ideal_readout() {
        // 2 turns + 100 deg: CNT = 4·2 + 1 = 9.
        let r = ro().key_on(5, 4, 100.0).unwrap();
        assert_eq!((r.cnt, r.q1, r.q2, r.quadrant_diff), (9, 1, 1, 0));
        assert_eq!((r.cnt_a, r.nr), (9, 2));
        assert_eq!(r.equation, QuadrantEquation::Eq1);
        assert_eq!(r.theta_m_deg, 820.0);
        assert!(!r.quadrant_mismatch && !r.counts_abnormal);
    }

    #[test]
    fn equation_2_count_ahead_in_fourth_quadrant() {
        // Shaft at 710 deg (turn 1, θ1 = 350, fourth quadrant), but the count
        // already switched to the next turn's first quadrant: CNT = 8.
        let r = ro().key_on(4, 4, 350.0).unwrap();
        assert_eq!((r.q1, r.q2), (3, 0));
        assert_eq!(r.equation, QuadrantEquation::Eq2);
        assert_eq!(r.quadrant_diff, 1); // 0 - 3 + 4
        assert_eq!(r.cnt_a, 7);
        assert_eq!(r.nr, 1);
        assert_eq!(r.theta_m_deg, 710.0);
        // Without eq. (2) (diff = -3) CNTa would be 11 -> Nr = 2 -> 1070 deg.
    }

    #[test]
    fn equation_3_count_behind_in_first_quadrant() {
        // Shaft at 1085 deg (turn 3, θ1 = 5), count still in the previous
        // turn's fourth quadrant: CNT = 11 instead of 12.
        let r = ro().key_on(6, 5, 5.0).unwrap();
        assert_eq!((r.q1, r.q2), (0, 3));
        assert_eq!(r.equation, QuadrantEquation::Eq3);
        assert_eq!(r.quadrant_diff, -1); // 3 - 0 - 4
        assert_eq!(r.cnt_a, 12);
        assert_eq!(r.nr, 3);
        assert_eq!(r.theta_m_deg, 1085.0);
    }

    #[test]
    fn equations_2_and_3_with_negative_counts() {
        // -370 deg = turn -2, θ1 = 350; ideal CNT = -8 + 3 = -5, count early: -4.
        let r = ro().key_on(-2, -2, 350.0).unwrap();
        assert_eq!((r.q1, r.q2, r.equation), (3, 0, QuadrantEquation::Eq2));
        assert_eq!((r.cnt_a, r.nr, r.theta_m_deg), (-5, -2, -370.0));
        // 5 deg (turn 0), count lagging at -1 (Q2 = 3 by Euclidean mod).
        let r = ro().key_on(-1, 0, 5.0).unwrap();
        assert_eq!((r.q1, r.q2, r.equation), (0, 3, QuadrantEquation::Eq3));
        assert_eq!((r.cnt_a, r.nr, r.theta_m_deg), (0, 0, 5.0));
    }

    #[test]
    fn floor_division_for_negative_angles() {
        // -90 deg: turn -1, θ1 = 270, CNT = -4 + 3 = -1.
        let r = ro().key_on(-1, 0, 270.0).unwrap();
        assert_eq!(r.q2, 3);
        assert_eq!(r.nr, -1, "truncating division would give 0 -> θm = 270");
        assert_eq!(r.theta_m_deg, -90.0);
    }

    #[test]
    fn counter_sum_does_not_wrap() {
        let r = ro().key_on(i16::MAX, i16::MAX, 270.0).unwrap();
        assert_eq!(r.cnt, 65534);
        assert_eq!(r.q2, 2);
        let r = ro().key_on(i16::MIN, i16::MIN, 0.0).unwrap();
        assert_eq!(r.cnt, -65536);
        assert_eq!((r.q2, r.nr), (0, -16384));
        assert_eq!(r.theta_m_deg, -16384.0 * 360.0);
    }

    #[test]
    fn opposite_quadrants_flagged() {
        let r = ro().key_on(0, 2, 0.0).unwrap(); // Q1 = 0, Q2 = 2
        assert_eq!(r.quadrant_diff, 2);
        assert!(r.quadrant_mismatch);
    }

    #[test]
    fn tracking_across_wrap() {
        let r = ro().key_on(2, 1, 359.0).unwrap(); // turn 0, 4th quadrant
        assert_eq!(r.theta_m_deg, 359.0);
        let mut t = ro().tracker(&r);
        assert_eq!(t.update(1.0).unwrap(), 361.0); // +2, not -358
        assert_eq!(t.turns(), 1);
        assert_eq!(t.update(359.0).unwrap(), 359.0); // -2 back
        assert_eq!(t.turns(), 0);
        assert_eq!(t.update(181.0).unwrap(), 181.0); // -178
                                                     // Many small steps down through 0 deg.
        let mut th1 = 10.0;
        t = ro().tracker(&ro().key_on(0, 0, 10.0).unwrap());
        for _ in 0..40 {
            th1 = crate::angle::wrap_360(th1 - 1.0);
            t.update(th1).unwrap();
        }
        assert_eq!(t.theta_m_deg(), -30.0);
        assert!(t.update(360.0).is_err());
    }

    #[test]
    fn wrap_step_of_exactly_180() {
        // A change of exactly -180 deg wraps to +180 ((-180, 180] convention).
        let mut t = ro().tracker(&ro().key_on(0, 0, 10.0).unwrap());
        assert_eq!(t.update(190.0).unwrap(), 190.0); // d = +180 -> +180
        let mut t = ro().tracker(&ro().key_on(0, 2, 190.0).unwrap());
        assert_eq!(t.theta_m_deg(), 190.0);
        assert_eq!(t.update(10.0).unwrap(), 370.0); // d = -180 -> +180
    }

    #[test]
    fn output_and_input_shaft_angles() {
        let ro = Readout::new(ReadoutConfig {
            gear_ratio: 1.0 / 20.0,
            ..Default::default()
        })
        .unwrap();
        let t = ro.tracker(&ro.key_on(20, 20, 0.0).unwrap()); // 10 turns
        let a = t.angles(1.5);
        assert_eq!(a.theta_m_deg, 3600.0);
        assert!((a.theta_o_deg - 180.0).abs() < 1e-12);
        assert!((a.theta_i_deg - 181.5).abs() < 1e-12);
    }

    #[test]
    fn diagnosis() {
        let ro = ro();
        assert!(!ro.theta_abnormal(358.0, Some(2.0))); // 4 deg apart
        assert!(ro.theta_abnormal(357.5, Some(2.5))); // exactly 5 -> abnormal
        assert!(ro.theta_abnormal(100.0, None));
        assert!(!ro.counts_abnormal(5, 4));
        assert!(ro.counts_abnormal(5, 3));
        assert!(ro.counts_abnormal(i16::MIN, i16::MAX));
        assert!(counts_abnormal(-1, 1, 2));
        assert!(ro.key_on(7, 4, 0.0).unwrap().counts_abnormal);
    }

    #[test]
    fn rejects_bad_input() {
        let e = ro().key_on(0, 0, 360.0).unwrap_err();
        assert!(e.to_string().contains("theta1_deg") && e.to_string().contains("[0, 360)"));
        assert!(ro().key_on(0, 0, -0.1).is_err());
        assert!(ro().key_on(0, 0, f64::NAN).is_err());
        assert!(Readout::new(ReadoutConfig {
            diag_threshold_deg: 0.0,
            ..Default::default()
        })
        .is_err());
        assert!(Readout::new(ReadoutConfig {
            count_diff_threshold: 0,
            ..Default::default()
        })
        .is_err());
        assert!(Readout::new(ReadoutConfig {
            gear_ratio: f64::NAN,
            ..Default::default()
        })
        .is_err());
    }
}
