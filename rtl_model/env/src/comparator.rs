//! Analog side of the first comparator 58a and the second comparator 58b.
//!
//! * [0086]-[0087], [0350], [0353]: the sign signal Cs (Cc) is 1 when sin2
//!   (cos2) is *equal to or greater than* the threshold voltage Vr, else 0.
//! * [0088], [0091], [0193], [0351]-[0352]: Vr follows the supply, nominally
//!   `Vr = Vs2/2` (2.5 V at 5 V, 1.65 V at 3.3 V).
//! * [0128]-[0133] (FIG. 10): the threshold of one comparator may deviate
//!   from its design value, shifting the switching angles and thus the
//!   rise/fall timing of the counts. Each comparator here has its own error,
//!   expressed as a fraction of the signal amplitude `Vs2/2`:
//!   `Vr_s = Vs2/2 + vr_err_s·Vs2/2`, `Vr_c = Vs2/2 + vr_err_c·Vs2/2`
//!   (`vr_err_s = -0.10` lowers the sine threshold by 10 % of the amplitude,
//!   as in FIG. 10A).
//! * [0350], [0353]: the comparators are powered from Vs2; while
//!   `Vs2 == 0` (unpowered) the raw outputs are 0. Holding the last sign
//!   signal while unpowered ([0211]) is the digital core's job, not this one.

use serde::Deserialize;

/// Per-comparator threshold errors (scenario file).
#[derive(Debug, Clone, Copy, PartialEq, Default, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct ComparatorConfig {
    /// Threshold error of comparator 58a (sin2), fraction of `Vs2/2`.
    pub vr_err_s: f64,
    /// Threshold error of comparator 58b (cos2), fraction of `Vs2/2`.
    pub vr_err_c: f64,
}

impl ComparatorConfig {
    /// Checks both fields: finite and strictly inside (-1, 1), so that the
    /// threshold stays strictly between 0 V and Vs2.
    pub fn validate(&self) -> Result<(), ComparatorError> {
        for (field, value) in [("vr_err_s", self.vr_err_s), ("vr_err_c", self.vr_err_c)] {
            if !(value.is_finite() && value > -1.0 && value < 1.0) {
                return Err(ComparatorError::InvalidConfig {
                    field,
                    value,
                    valid:
                        "finite and strictly between -1.0 and 1.0 (fraction of the amplitude Vs2/2)",
                });
            }
        }
        Ok(())
    }
}

/// Invalid comparator configuration.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ComparatorError {
    #[error("comparator config field `{field}` = {value} is invalid: must be {valid}")]
    InvalidConfig {
        field: &'static str,
        value: f64,
        valid: &'static str,
    },
}

/// Raw comparator outputs (sign signals before any latching).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct ComparatorBits {
    /// Sign signal Cs of comparator 58a (sin2 >= Vr_s).
    pub cs: bool,
    /// Sign signal Cc of comparator 58b (cos2 >= Vr_c).
    pub cc: bool,
}

/// The two comparators 58a/58b with their threshold errors.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ComparatorPair {
    cfg: ComparatorConfig,
}

/// One comparator: 1 when `signal_v >= threshold_v` ("equal to or greater",
/// [0086]). NaN input gives 0.
pub fn compare(signal_v: f64, threshold_v: f64) -> bool {
    signal_v >= threshold_v
}

impl ComparatorPair {
    pub fn new(cfg: ComparatorConfig) -> Result<Self, ComparatorError> {
        cfg.validate()?;
        Ok(Self { cfg })
    }

    /// Ideal comparators (both thresholds exactly `Vs2/2`).
    pub fn ideal() -> Self {
        Self {
            cfg: ComparatorConfig::default(),
        }
    }

    pub fn config(&self) -> &ComparatorConfig {
        &self.cfg
    }

    /// Threshold of comparator 58a in volts for supply `vs2_v`.
    pub fn threshold_s_v(&self, vs2_v: f64) -> f64 {
        vs2_v / 2.0 * (1.0 + self.cfg.vr_err_s)
    }

    /// Threshold of comparator 58b in volts for supply `vs2_v`.
    pub fn threshold_c_v(&self, vs2_v: f64) -> f64 {
        vs2_v / 2.0 * (1.0 + self.cfg.vr_err_c)
    }

    /// Raw sign signals for the given supply and sensor outputs.
    /// Unpowered (`vs2_v` not > 0, including NaN) gives both bits 0.
    pub fn compare(&self, vs2_v: f64, sin2_v: f64, cos2_v: f64) -> ComparatorBits {
        if vs2_v.is_nan() || vs2_v <= 0.0 {
            return ComparatorBits::default();
        }
        ComparatorBits {
            cs: compare(sin2_v, self.threshold_s_v(vs2_v)),
            cc: compare(cos2_v, self.threshold_c_v(vs2_v)),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sensor2::{Sensor2, Sensor2Config};

    #[test]
    fn equal_gives_one() {
        let c = ComparatorPair::ideal();
        assert_eq!(c.threshold_s_v(3.3), 1.65);
        let b = c.compare(3.3, 1.65, 1.65);
        assert!(b.cs && b.cc, "sin2 == Vr must give Cs = 1 ([0086])");
        let b = c.compare(3.3, 1.65 - 1e-12, 1.65 - 1e-12);
        assert!(!b.cs && !b.cc);
        assert!(compare(2.5, 2.5));
        assert!(!compare(f64::NAN, 2.5));
    }

    #[test]
    fn thresholds_follow_supply() {
        let c = ComparatorPair::ideal();
        assert_eq!(c.threshold_s_v(5.0), 2.5);
        assert_eq!(c.threshold_c_v(3.3), 1.65);
        let c = ComparatorPair::new(ComparatorConfig {
            vr_err_s: -0.10,
            vr_err_c: 0.2,
        })
        .unwrap();
        assert!((c.threshold_s_v(5.0) - 2.25).abs() < 1e-12);
        assert!((c.threshold_c_v(5.0) - 3.0).abs() < 1e-12);
    }

    #[test]
    fn unpowered_outputs_zero() {
        let c = ComparatorPair::new(ComparatorConfig {
            vr_err_s: -0.5,
            vr_err_c: -0.5,
        })
        .unwrap();
        // Even a signal above the (zero) threshold gives 0 when Vs2 == 0.
        assert_eq!(c.compare(0.0, 1.0, 1.0), ComparatorBits::default());
        assert_eq!(c.compare(f64::NAN, 1.0, 1.0), ComparatorBits::default());
    }

    /// Switching angles of Cs/Cc over one increasing turn, steady state.
    /// (angle, new level) of each switching of Cs and of Cc.
    type Edges = Vec<(f64, bool)>;

    fn edges(c: &ComparatorPair) -> (Edges, Edges) {
        let s = Sensor2::new(Sensor2Config::default()).unwrap();
        let vs2 = 3.3;
        let (mut es, mut ec) = (Vec::new(), Vec::new());
        let mut prev: Option<ComparatorBits> = None;
        for i in 0..=400_000 {
            let th = -10.0 + i as f64 * 0.001; // -10 .. 390 deg
            let (a, b) = s.target(vs2, th);
            let bits = c.compare(vs2, a, b);
            if let Some(p) = prev {
                if p.cs != bits.cs {
                    es.push((th, bits.cs));
                }
                if p.cc != bits.cc {
                    ec.push((th, bits.cc));
                }
            }
            prev = Some(bits);
        }
        (es, ec)
    }

    #[test]
    fn ideal_switching_angles() {
        let (es, ec) = edges(&ComparatorPair::ideal());
        // Cs: 1 on [0,180), 0 on [180,360) ([0092]); Cc: 1 on [0,90)∪[270,360) ([0093]).
        assert_eq!(es.len(), 3);
        assert!((es[0].0 - 0.0).abs() < 0.002 && es[0].1);
        assert!((es[1].0 - 180.0).abs() < 0.002 && !es[1].1);
        assert!((es[2].0 - 360.0).abs() < 0.002 && es[2].1);
        assert_eq!(ec.len(), 2);
        assert!((ec[0].0 - 90.0).abs() < 0.002 && !ec[0].1);
        assert!((ec[1].0 - 270.0).abs() < 0.002 && ec[1].1);
    }

    #[test]
    fn fig10_lower_sine_threshold_switches_early() {
        // FIG. 10A: threshold of comparator 58a lower than design.
        let c = ComparatorPair::new(ComparatorConfig {
            vr_err_s: -0.10,
            vr_err_c: 0.0,
        })
        .unwrap();
        let (es, ec) = edges(&c);
        let shift = 0.1f64.asin().to_degrees(); // 5.739 deg
        assert_eq!(es.len(), 3);
        // Rising edge (0 -> 1) comes *early*: before 0 / 360 deg.
        assert!(
            es[0].1 && (es[0].0 - (0.0 - shift)).abs() < 0.002,
            "{:?}",
            es
        );
        assert!(
            es[2].1 && (es[2].0 - (360.0 - shift)).abs() < 0.002,
            "{:?}",
            es
        );
        // Falling edge (1 -> 0) comes late: after 180 deg.
        assert!(
            !es[1].1 && (es[1].0 - (180.0 + shift)).abs() < 0.002,
            "{:?}",
            es
        );
        // The cosine comparator is unaffected.
        assert!((ec[0].0 - 90.0).abs() < 0.002 && (ec[1].0 - 270.0).abs() < 0.002);
    }

    #[test]
    fn rejects_bad_config() {
        for bad in [-1.0, 1.0, f64::NAN, 2.0] {
            let e = ComparatorPair::new(ComparatorConfig {
                vr_err_s: 0.0,
                vr_err_c: bad,
            })
            .unwrap_err();
            assert!(e.to_string().contains("vr_err_c"));
        }
    }
}
