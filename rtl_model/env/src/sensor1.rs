//! First angle sensor 33 and the angular positions θ1 / θ2 computed by the
//! angular position calculation unit 61 of the MPU 60.
//!
//! * [0105]-[0106]: θ1 is the angular position of the motor rotation shaft 21
//!   within one rotation (0 to 360 deg), computed from sin1/cos1 after error
//!   compensation. This model skips the analog sin1/cos1 and produces θ1
//!   directly: `θ1 = (true angle + error_deg) mod 360`, quantised to
//!   `resolution_deg`. `error_deg` is the residual error left after the
//!   compensation of [0105] (default 0).
//! * Quantisation rule (deterministic): round to the nearest multiple of the
//!   resolution, ties to even code, and the top code wraps to 0, so θ1 is
//!   always in `[0, 360)`. Code `k` maps to `k·360/n` with `n = 360/resolution`
//!   codes per turn, so multiples of 90 deg are represented exactly.
//!   `resolution_deg` must divide 360 into an integer number (>= 4) of codes;
//!   `resolution_deg = 0` disables quantisation.
//! * [0107]: θ2 is computed in the same way from the second sensor signals:
//!   `θ2 = atan2(sin2 - Vs2/2, cos2 - Vs2/2)` mapped to `[0, 360)`. No error
//!   compensation is applied here, so second-sensor errors show up in θ2 and
//!   can be caught by the θ1/θ2 diagnosis of [0118].

use serde::Deserialize;

use crate::angle::wrap_360;

/// First-sensor parameters (scenario file).
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Sensor1Config {
    /// θ1 resolution in degrees (default 0.1). Must divide 360 into an
    /// integer number >= 4 of codes; 0 = no quantisation.
    pub resolution_deg: f64,
    /// Residual angle error of θ1 after compensation, degrees (default 0).
    pub error_deg: f64,
}

impl Default for Sensor1Config {
    fn default() -> Self {
        Self {
            resolution_deg: 0.1,
            error_deg: 0.0,
        }
    }
}

/// Invalid first-sensor configuration or input.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum Sensor1Error {
    #[error("sensor1 config field `{field}` = {value} is invalid: must be {valid}")]
    InvalidConfig {
        field: &'static str,
        value: f64,
        valid: &'static str,
    },
    #[error("sensor1 input `{field}` = {value} is invalid: must be {valid}")]
    InvalidInput {
        field: &'static str,
        value: f64,
        valid: &'static str,
    },
}

/// First sensor 33 + θ1 computation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sensor1 {
    cfg: Sensor1Config,
    /// Codes per turn; None = no quantisation.
    codes: Option<u32>,
}

/// Largest supported number of θ1 codes per turn.
pub const MAX_CODES_PER_TURN: u32 = 1 << 24;

impl Default for Sensor1 {
    /// 0.1 deg resolution, no error.
    fn default() -> Self {
        Self {
            cfg: Sensor1Config::default(),
            codes: Some(3600),
        }
    }
}

impl Sensor1 {
    pub fn new(cfg: Sensor1Config) -> Result<Self, Sensor1Error> {
        if !(cfg.error_deg.is_finite() && cfg.error_deg.abs() < 360.0) {
            return Err(Sensor1Error::InvalidConfig {
                field: "error_deg",
                value: cfg.error_deg,
                valid: "finite and strictly between -360 and 360",
            });
        }
        let r = cfg.resolution_deg;
        let bad_res = || Sensor1Error::InvalidConfig {
            field: "resolution_deg",
            value: r,
            valid: "0 (no quantisation) or a value in [360/16777216, 90] that divides 360 \
                    into an integer number of codes (e.g. 0.1, 0.5, 1.0)",
        };
        let codes = if r == 0.0 {
            None
        } else {
            if !(r.is_finite() && r > 0.0 && r <= 90.0) {
                return Err(bad_res());
            }
            let n = (360.0 / r).round();
            if n < 4.0 || n > MAX_CODES_PER_TURN as f64 || ((n * r - 360.0).abs() > 1e-9 * 360.0) {
                return Err(bad_res());
            }
            Some(n as u32)
        };
        Ok(Self { cfg, codes })
    }

    /// Ideal sensor: no error, no quantisation.
    pub fn ideal() -> Self {
        Self {
            cfg: Sensor1Config {
                resolution_deg: 0.0,
                error_deg: 0.0,
            },
            codes: None,
        }
    }

    pub fn config(&self) -> &Sensor1Config {
        &self.cfg
    }

    /// Codes per turn (None = not quantised).
    pub fn codes_per_turn(&self) -> Option<u32> {
        self.codes
    }

    /// θ1 in `[0, 360)` for the true multi-turn shaft angle.
    pub fn theta1_deg(&self, true_angle_deg: f64) -> Result<f64, Sensor1Error> {
        if !true_angle_deg.is_finite() {
            return Err(Sensor1Error::InvalidInput {
                field: "true_angle_deg",
                value: true_angle_deg,
                valid: "finite",
            });
        }
        let a = wrap_360(true_angle_deg + self.cfg.error_deg);
        Ok(match self.codes {
            None => a,
            Some(n) => {
                let n_f = n as f64;
                // a in [0,360) => a*n/360 in [0, n]; code n wraps to 0.
                let code = (a * n_f / 360.0).round_ties_even() as u64 % n as u64;
                code as f64 * 360.0 / n_f
            }
        })
    }
}

/// θ2 in `[0, 360)` from the second sensor signals ([0107]):
/// `atan2(sin2 - Vs2/2, cos2 - Vs2/2)`.
///
/// None when it cannot be computed: `vs2_v` not > 0 (unpowered), any input
/// non-finite, or both centred signals exactly 0 (no angle information).
pub fn theta2_deg(vs2_v: f64, sin2_v: f64, cos2_v: f64) -> Option<f64> {
    if !(vs2_v.is_finite() && vs2_v > 0.0 && sin2_v.is_finite() && cos2_v.is_finite()) {
        return None;
    }
    let y = sin2_v - vs2_v / 2.0;
    let x = cos2_v - vs2_v / 2.0;
    if x == 0.0 && y == 0.0 {
        return None;
    }
    Some(wrap_360(y.atan2(x).to_degrees()))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sensor2::{Sensor2, Sensor2Config};

    #[test]
    fn default_resolution_quantises_to_nearest_tenth() {
        let s = Sensor1::new(Sensor1Config::default()).unwrap();
        assert_eq!(s, Sensor1::default());
        assert_eq!(s.codes_per_turn(), Some(3600));
        assert_eq!(s.theta1_deg(12.34).unwrap(), 123.0 * 360.0 / 3600.0);
        assert_eq!(s.theta1_deg(12.36).unwrap(), 124.0 * 360.0 / 3600.0);
        // Multi-turn and negative angles fold into [0, 360).
        assert_eq!(s.theta1_deg(720.0 + 90.0).unwrap(), 90.0);
        assert_eq!(s.theta1_deg(-90.0).unwrap(), 270.0);
        // Top code wraps to 0.
        assert_eq!(s.theta1_deg(359.97).unwrap(), 0.0);
        assert_eq!(s.theta1_deg(-0.01).unwrap(), 0.0);
        assert_eq!(s.theta1_deg(-1e-20).unwrap(), 0.0);
        // Quadrant boundaries are exact.
        assert_eq!(s.theta1_deg(179.96).unwrap(), 180.0);
        assert_eq!(s.theta1_deg(269.99).unwrap(), 270.0);
    }

    #[test]
    fn ties_to_even_code() {
        let s = Sensor1::new(Sensor1Config {
            resolution_deg: 1.0,
            error_deg: 0.0,
        })
        .unwrap();
        assert_eq!(s.theta1_deg(2.5).unwrap(), 2.0);
        assert_eq!(s.theta1_deg(3.5).unwrap(), 4.0);
        assert_eq!(s.theta1_deg(359.5).unwrap(), 0.0); // code 360 -> 0
    }

    #[test]
    fn error_and_no_quantisation() {
        let s = Sensor1::new(Sensor1Config {
            resolution_deg: 0.0,
            error_deg: 2.0,
        })
        .unwrap();
        assert!((s.theta1_deg(359.0).unwrap() - 1.0).abs() < 1e-12);
        assert!((Sensor1::ideal().theta1_deg(-370.25).unwrap() - 349.75).abs() < 1e-12);
    }

    #[test]
    fn rejects_bad_config() {
        for r in [-0.1, 0.7, 100.0, f64::NAN, 1e-9] {
            let e = Sensor1::new(Sensor1Config {
                resolution_deg: r,
                error_deg: 0.0,
            })
            .unwrap_err();
            assert!(e.to_string().contains("resolution_deg"), "{r}");
        }
        assert!(Sensor1::new(Sensor1Config {
            resolution_deg: 0.1,
            error_deg: 400.0
        })
        .is_err());
        assert!(Sensor1::ideal().theta1_deg(f64::NAN).is_err());
    }

    #[test]
    fn theta2_from_second_sensor() {
        let s2 = Sensor2::new(Sensor2Config::default()).unwrap();
        for th in [0.0, 10.0, 89.0, 135.0, 181.0, 300.0, 359.9, 725.0, -45.0] {
            let (a, b) = s2.target(3.3, th);
            let t2 = theta2_deg(3.3, a, b).unwrap();
            assert!(
                crate::angle::circular_diff_deg(t2, th) < 1e-9,
                "{th} -> {t2}"
            );
            assert!((0.0..360.0).contains(&t2));
        }
        assert_eq!(theta2_deg(0.0, 0.0, 0.0), None);
        assert_eq!(theta2_deg(5.0, 2.5, 2.5), None);
        assert_eq!(theta2_deg(5.0, f64::NAN, 2.5), None);
    }
}
