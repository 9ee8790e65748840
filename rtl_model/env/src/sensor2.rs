//! Second angle sensor 34: second sine-wave signal sin2 and second
//! cosine-wave signal cos2, including supply-dependent settling.
//!
//! * Signal shape, [0091]: amplitude `Vs2/2`, DC offset `Vs2/2`, so the
//!   signals swing between 0 V and `Vs2`. With the optional error terms of
//!   [0109] (offset, amplitude and phase errors of the second sensor signals)
//!   the steady-state targets are
//!   `sin2 = Vs2/2 + (Vs2/2)·gain_s·sin(θ + phase_s) + offset_s`,
//!   `cos2 = Vs2/2 + (Vs2/2)·gain_c·cos(θ + phase_c) + offset_c`.
//! * Supply: `Vs2` is `Vcc1` (e.g. 5 V) while the key is on and `Vcc2`
//!   (e.g. 3.3 V) intermittently while the key is off ([0189], [0192],
//!   [0206], [0319], [0345]).
//! * Settling, [0326]: when the supply starts, the signal "changes with a
//!   certain time constant from 0" to its steady value. [0329]: it is
//!   realistic to reach about 99 % after 100 us, hence the default
//!   `tau = 100 us / ln(100) ≈ 21.715 us` (`1 - exp(-100/tau) = 0.99`).
//!
//! Model (first-order low-pass of the steady-state target, exact per tick):
//! `v += (target - v)·(1 - exp(-dt/tau))`, evaluated with the target at the
//! end of the tick. While `Vs2 == 0` both outputs are 0 V (the sensor is
//! unpowered), so every rise of `Vs2` settles from 0 V. A level change while
//! powered (e.g. 5 V -> 3.3 V at key-off) settles from the previous output
//! towards the new target with the same tau. Outputs are not clamped to the
//! rails (gains > 1 or offsets can push them outside `[0, Vs2]`).

use serde::Deserialize;

/// `100 / ln(100)` microseconds: 99 % settled after 100 us ([0329]).
pub const DEFAULT_TAU_US: f64 = 21.714_724_095_162_59;

/// Second-sensor error and settling parameters (scenario file).
/// The time since the last rise of Vs2 is counted up to this (10 ms, some 460 time constants
/// of the default settling: the outputs have reached their float fixed point long before).
pub const ON_NS_MAX: u64 = 10_000_000;

#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Sensor2Config {
    /// Amplitude factor of sin2 (1.0 = ideal amplitude `Vs2/2`).
    pub gain_s: f64,
    /// Amplitude factor of cos2 (1.0 = ideal).
    pub gain_c: f64,
    /// Additive offset error of sin2, volts (0 = ideal).
    pub offset_s_v: f64,
    /// Additive offset error of cos2, volts (0 = ideal).
    pub offset_c_v: f64,
    /// Phase error of sin2, degrees (0 = ideal).
    pub phase_s_deg: f64,
    /// Phase error of cos2, degrees (0 = ideal).
    pub phase_c_deg: f64,
    /// Settling time constant, microseconds (0 = settles within one step).
    pub tau_us: f64,
}

impl Default for Sensor2Config {
    fn default() -> Self {
        Self {
            gain_s: 1.0,
            gain_c: 1.0,
            offset_s_v: 0.0,
            offset_c_v: 0.0,
            phase_s_deg: 0.0,
            phase_c_deg: 0.0,
            tau_us: DEFAULT_TAU_US,
        }
    }
}

impl Sensor2Config {
    /// Checks every field; the error names the field and the valid range.
    pub fn validate(&self) -> Result<(), Sensor2Error> {
        let pos = |field: &'static str, value: f64| {
            if value.is_finite() && value > 0.0 {
                Ok(())
            } else {
                Err(Sensor2Error::InvalidConfig {
                    field,
                    value,
                    valid: "finite and > 0",
                })
            }
        };
        let fin = |field: &'static str, value: f64| {
            if value.is_finite() {
                Ok(())
            } else {
                Err(Sensor2Error::InvalidConfig {
                    field,
                    value,
                    valid: "finite",
                })
            }
        };
        pos("gain_s", self.gain_s)?;
        pos("gain_c", self.gain_c)?;
        fin("offset_s_v", self.offset_s_v)?;
        fin("offset_c_v", self.offset_c_v)?;
        fin("phase_s_deg", self.phase_s_deg)?;
        fin("phase_c_deg", self.phase_c_deg)?;
        if !(self.tau_us.is_finite() && self.tau_us >= 0.0) {
            return Err(Sensor2Error::InvalidConfig {
                field: "tau_us",
                value: self.tau_us,
                valid: "finite and >= 0",
            });
        }
        Ok(())
    }
}

/// Invalid second-sensor configuration or input.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum Sensor2Error {
    #[error("sensor2 config field `{field}` = {value} is invalid: must be {valid}")]
    InvalidConfig {
        field: &'static str,
        value: f64,
        valid: &'static str,
    },
    #[error("sensor2 input `{field}` = {value} is invalid: must be {valid}")]
    InvalidInput {
        field: &'static str,
        value: f64,
        valid: &'static str,
    },
}

/// Stateful second sensor 34 (outputs sin2, cos2 in volts).
#[derive(Debug, Clone, PartialEq)]
pub struct Sensor2 {
    cfg: Sensor2Config,
    sin2_v: f64,
    cos2_v: f64,
    /// Vs2 level during the previous step (0 = unpowered).
    last_vs2_v: f64,
    /// Time powered since the last 0 -> on rise, ns (None while unpowered).
    on_ns: Option<u64>,
    /// Cache of `1 - exp(-dt/tau)` for the last dt.
    alpha_dt_ns: u64,
    alpha: f64,
}

impl Sensor2 {
    /// New, unpowered sensor (outputs 0 V).
    pub fn new(cfg: Sensor2Config) -> Result<Self, Sensor2Error> {
        cfg.validate()?;
        let mut s = Self {
            cfg,
            sin2_v: 0.0,
            cos2_v: 0.0,
            last_vs2_v: 0.0,
            on_ns: None,
            alpha_dt_ns: 0,
            alpha: 0.0,
        };
        s.alpha = s.compute_alpha(0);
        Ok(s)
    }

    /// The configuration in use.
    pub fn config(&self) -> &Sensor2Config {
        &self.cfg
    }

    fn compute_alpha(&self, dt_ns: u64) -> f64 {
        if self.cfg.tau_us == 0.0 {
            return if dt_ns == 0 { 0.0 } else { 1.0 };
        }
        let x = dt_ns as f64 / (self.cfg.tau_us * 1e3);
        -(-x).exp_m1()
    }

    /// Steady-state (fully settled) outputs `(sin2, cos2)` in volts for
    /// supply `vs2_v` and shaft angle `theta_deg`; `(0, 0)` when `vs2_v == 0`.
    pub fn target(&self, vs2_v: f64, theta_deg: f64) -> (f64, f64) {
        if vs2_v == 0.0 {
            return (0.0, 0.0);
        }
        let half = vs2_v / 2.0;
        let s = (theta_deg + self.cfg.phase_s_deg).to_radians().sin();
        let c = (theta_deg + self.cfg.phase_c_deg).to_radians().cos();
        (
            half + half * self.cfg.gain_s * s + self.cfg.offset_s_v,
            half + half * self.cfg.gain_c * c + self.cfg.offset_c_v,
        )
    }

    /// Advances the sensor by `dt_ns`, with `Vs2 = vs2_volts` during the interval
    /// and the shaft at `theta_deg` at its end; returns `(sin2, cos2)` volts
    /// at the end of the interval.
    ///
    /// `vs2_volts == 0` forces both outputs to 0 V immediately (unpowered).
    pub fn step(
        &mut self,
        vs2_volts: f64,
        theta_deg: f64,
        dt_ns: u64,
    ) -> Result<(f64, f64), Sensor2Error> {
        if !(vs2_volts.is_finite() && vs2_volts >= 0.0) {
            return Err(Sensor2Error::InvalidInput {
                field: "vs2_volts",
                value: vs2_volts,
                valid: "finite and >= 0",
            });
        }
        if !theta_deg.is_finite() {
            return Err(Sensor2Error::InvalidInput {
                field: "theta_deg",
                value: theta_deg,
                valid: "finite",
            });
        }
        if vs2_volts == 0.0 {
            self.sin2_v = 0.0;
            self.cos2_v = 0.0;
            self.last_vs2_v = 0.0;
            self.on_ns = None;
            return Ok((0.0, 0.0));
        }
        if self.last_vs2_v == 0.0 {
            // Rise of Vs2: the outputs are already 0 V (forced while
            // unpowered), so they settle from 0 V ([0326]).
            self.on_ns = Some(0);
        }
        self.last_vs2_v = vs2_volts;
        // Counted up to ON_NS_MAX only: past it the outputs have long settled, and a powered
        // sensor on a still shaft is then in the same state from tick to tick, which lets the
        // bench skip repeated key-on periods (docs/spec.md 5.1).
        self.on_ns = self.on_ns.map(|t| t.saturating_add(dt_ns).min(ON_NS_MAX));
        if dt_ns != self.alpha_dt_ns {
            self.alpha_dt_ns = dt_ns;
            self.alpha = self.compute_alpha(dt_ns);
        }
        let (ts, tc) = self.target(vs2_volts, theta_deg);
        self.sin2_v += (ts - self.sin2_v) * self.alpha;
        self.cos2_v += (tc - self.cos2_v) * self.alpha;
        Ok((self.sin2_v, self.cos2_v))
    }

    /// Current outputs `(sin2, cos2)` in volts.
    pub fn outputs(&self) -> (f64, f64) {
        (self.sin2_v, self.cos2_v)
    }

    /// Time since the last rise of Vs2, up to [`ON_NS_MAX`] (None while unpowered).
    pub fn time_since_rise_ns(&self) -> Option<u64> {
        self.on_ns
    }

    /// "No change before the next rise of Vs2": while unpowered the outputs are forced to 0 V
    /// whatever the angle, and every step with `vs2_volts = 0` leaves the state as it is. (While
    /// powered the state changes every step: the time since the rise grows.)
    pub fn is_unpowered(&self) -> bool {
        self.last_vs2_v == 0.0 && self.on_ns.is_none() && self.sin2_v == 0.0 && self.cos2_v == 0.0
    }

    /// Back to the unpowered state.
    pub fn reset(&mut self) {
        self.sin2_v = 0.0;
        self.cos2_v = 0.0;
        self.last_vs2_v = 0.0;
        self.on_ns = None;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const TICK: u64 = 10_000; // 10 us

    #[test]
    fn default_tau_is_100us_over_ln100() {
        assert!((DEFAULT_TAU_US - 100.0 / 100f64.ln()).abs() < 1e-12);
        assert_eq!(Sensor2Config::default().tau_us, DEFAULT_TAU_US);
    }

    #[test]
    fn reaches_99_percent_after_100us() {
        let mut s = Sensor2::new(Sensor2Config::default()).unwrap();
        // θ = 90°: sin2 target = Vs2, cos2 target = Vs2/2.
        let vs2 = 3.3;
        let mut out = (0.0, 0.0);
        for i in 1..=10 {
            out = s.step(vs2, 90.0, TICK).unwrap();
            if i == 9 {
                // Not yet 99 % at 90 us.
                assert!(out.0 / vs2 < 0.985, "{}", out.0 / vs2);
            }
        }
        assert_eq!(s.time_since_rise_ns(), Some(100_000));
        assert!((out.0 / vs2 - 0.99).abs() < 1e-12, "{}", out.0 / vs2);
        assert!((out.1 / (vs2 / 2.0) - 0.99).abs() < 1e-12);
        // One big step of 100 us gives the same.
        let mut s2 = Sensor2::new(Sensor2Config::default()).unwrap();
        let o2 = s2.step(vs2, 90.0, 100_000).unwrap();
        assert!((o2.0 / vs2 - 0.99).abs() < 1e-12);
    }

    #[test]
    fn unpowered_is_zero_and_next_rise_restarts_from_zero() {
        let mut s = Sensor2::new(Sensor2Config::default()).unwrap();
        for _ in 0..100 {
            s.step(3.3, 30.0, TICK).unwrap();
        }
        let settled = s.outputs();
        let tgt = s.target(3.3, 30.0);
        assert!((settled.0 - tgt.0).abs() < 1e-9);
        assert_eq!(s.step(0.0, 30.0, TICK).unwrap(), (0.0, 0.0));
        assert_eq!(s.time_since_rise_ns(), None);
        let first = s.step(3.3, 30.0, TICK).unwrap();
        let alpha = 1.0 - (-10.0 / DEFAULT_TAU_US).exp();
        assert!((first.0 - tgt.0 * alpha).abs() < 1e-12);
        assert!((first.1 - tgt.1 * alpha).abs() < 1e-12);
    }

    #[test]
    fn unpowered_steps_change_nothing() {
        let mut s = Sensor2::new(Sensor2Config::default()).unwrap();
        assert!(s.is_unpowered());
        s.step(3.3, 30.0, TICK).unwrap();
        assert!(!s.is_unpowered());
        s.step(0.0, 30.0, TICK).unwrap();
        assert!(s.is_unpowered());
        let before = s.clone();
        for th in [0.0, 90.0, 271.5] {
            assert_eq!(s.step(0.0, th, 123_456).unwrap(), (0.0, 0.0));
        }
        assert_eq!(s, before, "unpowered steps leave the whole state as it was");
    }

    #[test]
    fn level_change_settles_from_previous_value() {
        let mut s = Sensor2::new(Sensor2Config::default()).unwrap();
        for _ in 0..200 {
            s.step(5.0, 90.0, TICK).unwrap();
        }
        let prev = s.outputs().0;
        assert!((prev - 5.0).abs() < 1e-9);
        let v = s.step(3.3, 90.0, TICK).unwrap().0;
        let alpha = 1.0 - (-10.0 / DEFAULT_TAU_US).exp();
        assert!((v - (prev + (3.3 - prev) * alpha)).abs() < 1e-9);
        assert!(v > 3.3, "must not restart from 0 V on a level change");
    }

    #[test]
    fn error_terms_in_target() {
        let cfg = Sensor2Config {
            gain_s: 0.9,
            gain_c: 1.1,
            offset_s_v: 0.05,
            offset_c_v: -0.02,
            phase_s_deg: 2.0,
            phase_c_deg: -3.0,
            tau_us: 0.0,
        };
        let mut s = Sensor2::new(cfg).unwrap();
        let (a, b) = s.step(5.0, 40.0, TICK).unwrap();
        assert!((a - (2.5 + 2.5 * 0.9 * 42f64.to_radians().sin() + 0.05)).abs() < 1e-12);
        assert!((b - (2.5 + 2.5 * 1.1 * 37f64.to_radians().cos() - 0.02)).abs() < 1e-12);
    }

    #[test]
    fn rejects_bad_config_and_input() {
        let bad = Sensor2Config {
            tau_us: -1.0,
            ..Default::default()
        };
        assert!(matches!(
            Sensor2::new(bad),
            Err(Sensor2Error::InvalidConfig {
                field: "tau_us",
                ..
            })
        ));
        let bad = Sensor2Config {
            gain_c: 0.0,
            ..Default::default()
        };
        let e = Sensor2::new(bad).unwrap_err();
        assert!(e.to_string().contains("gain_c") && e.to_string().contains("> 0"));
        let mut s = Sensor2::new(Sensor2Config::default()).unwrap();
        assert!(s.step(-1.0, 0.0, TICK).is_err());
        assert!(s.step(f64::NAN, 0.0, TICK).is_err());
        assert!(s.step(3.3, f64::INFINITY, TICK).is_err());
    }

    #[test]
    fn config_deserialize_defaults_and_unknown_fields() {
        use serde::de::value::{Error as DeError, MapDeserializer};
        let cfg = Sensor2Config::deserialize(MapDeserializer::<_, DeError>::new(
            vec![("tau_us", 10.0), ("offset_s_v", 0.1)].into_iter(),
        ))
        .unwrap();
        assert_eq!(cfg.tau_us, 10.0);
        assert_eq!(cfg.offset_s_v, 0.1);
        assert_eq!(cfg.gain_s, 1.0);
        let err = Sensor2Config::deserialize(MapDeserializer::<_, DeError>::new(
            vec![("tau_ms", 10.0)].into_iter(),
        ));
        assert!(err.is_err());
    }
}
