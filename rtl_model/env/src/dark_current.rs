//! Key-off dark-current accounting.
//!
//! * [0324], [0327]: the width Wt of each intermittent Vs2 output sets the
//!   dark current of the sensor unit 30 and controller 40 while the key is
//!   off; the longer Wt, the larger the dark current.
//! * [0229]-[0231], [0300]-[0302]: with a fixed drive width w = 220 us the
//!   duty ratio is 10 % at the minimum drive interval 2.2 ms and one third of
//!   that at the maximum interval 6.6 ms.
//! * [0190], [0205], [0330]: while the key is off Vm and Vs1 should be off
//!   and Vp stays on; this meter does not assume it, it measures what the
//!   rails actually did, so a rail left on by mistake shows up.
//!
//! The meter accumulates, over ticks with the ignition off only, the on-time
//! of each rail (Vm, Vs1, Vs2, Vp) in integer nanoseconds (so duty ratios are
//! exact rationals), and converts to charge / average current with the
//! configured per-rail load currents plus the regulator 51 quiescent current,
//! which flows during the whole key-off time.
//!
//! The default currents are typical figures of real parts of each kind, with their datasheets
//! listed in docs/power.md (the patent gives none); every one can be overridden in
//! `[env.dark_current]`. The MPU figure could not be confirmed from a datasheet and is marked so;
//! it does not enter a key-off budget, because Vm is off while the key is off ([0191]).

use serde::Deserialize;

/// Per-rail load currents while the rail is on (scenario file).
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct DarkCurrentConfig {
    /// MPU 60 etc. on Vm, mA (default 50: NOT confirmed from a datasheet, docs/power.md; Vm is
    /// off while the key is off, so it does not enter the key-off budget).
    pub i_vm_ma: f64,
    /// First sensor 33 on Vs1, mA (default 6.5: TI TMAG6180-Q1 AMR angle sensor, active-mode
    /// current IACT typ, datasheet SLYS037A section 5.5).
    pub i_vs1_ma: f64,
    /// Second sensor 34 plus comparators 58a/58b on Vs2, mA (default 6.50063: TI TMAG6180-Q1
    /// IACT typ 6.5 mA, SLYS037A 5.5, plus two TI TLV7031 nanopower comparators at 315 nA typ
    /// quiescent current each).
    pub i_vs2_ma: f64,
    /// Counters / logic on the internal supply Vp, uA (default 1.9: always-on low-power CMOS
    /// logic with its clock running, taken as TI MSP430FG461x LPM3 typ at 3 V, 25 degC,
    /// datasheet SLAS508K).
    pub i_vp_ua: f64,
    /// Regulator 51 quiescent current during key-off (4 V mode), uA (default 2.7: TI TPS7B81-Q1
    /// automotive LDO, IQ typ at light load).
    pub i_q_ua: f64,
}

impl Default for DarkCurrentConfig {
    fn default() -> Self {
        Self {
            i_vm_ma: 50.0,
            i_vs1_ma: 6.5,
            i_vs2_ma: 6.5 + 2.0 * 0.000_315,
            i_vp_ua: 1.9,
            i_q_ua: 2.7,
        }
    }
}

impl DarkCurrentConfig {
    /// Every current must be finite and >= 0.
    pub fn validate(&self) -> Result<(), DarkCurrentError> {
        for (field, value) in [
            ("i_vm_ma", self.i_vm_ma),
            ("i_vs1_ma", self.i_vs1_ma),
            ("i_vs2_ma", self.i_vs2_ma),
            ("i_vp_ua", self.i_vp_ua),
            ("i_q_ua", self.i_q_ua),
        ] {
            if !(value.is_finite() && value >= 0.0) {
                return Err(DarkCurrentError::InvalidConfig {
                    field,
                    value,
                    valid: "finite and >= 0",
                });
            }
        }
        Ok(())
    }
}

/// Invalid dark-current configuration.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum DarkCurrentError {
    #[error("dark_current config field `{field}` = {value} is invalid: must be {valid}")]
    InvalidConfig {
        field: &'static str,
        value: f64,
        valid: &'static str,
    },
}

/// Which rails are on during one tick.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct RailStates {
    pub vm: bool,
    pub vs1: bool,
    pub vs2: bool,
    pub vp: bool,
}

/// Summary of the key-off accounting.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DarkCurrentReport {
    /// Total time with the ignition off, ns.
    pub key_off_ns: u64,
    /// Per-rail on-time while the ignition was off, ns.
    pub vm_on_ns: u64,
    pub vs1_on_ns: u64,
    pub vs2_on_ns: u64,
    pub vp_on_ns: u64,
    /// vs2_on_ns / key_off_ns (None when key_off_ns == 0).
    pub vs2_duty: Option<f64>,
    /// Total key-off charge, microcoulombs.
    pub charge_uc: f64,
    /// Average key-off current, microamperes (None when key_off_ns == 0).
    pub avg_current_ua: Option<f64>,
}

impl DarkCurrentReport {
    /// Vs2 duty ratio as an exact fraction (numerator, denominator) in ns.
    pub fn vs2_duty_fraction(&self) -> (u64, u64) {
        (self.vs2_on_ns, self.key_off_ns)
    }
}

/// The meter's accumulated times, ns (the exact integers behind a [`DarkCurrentReport`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct OnTimes {
    pub key_off_ns: u64,
    pub vm_on_ns: u64,
    pub vs1_on_ns: u64,
    pub vs2_on_ns: u64,
    pub vp_on_ns: u64,
}

impl OnTimes {
    /// What was accumulated between `earlier` and `self` (`earlier` taken first).
    pub fn since(&self, earlier: &OnTimes) -> OnTimes {
        OnTimes {
            key_off_ns: self.key_off_ns.saturating_sub(earlier.key_off_ns),
            vm_on_ns: self.vm_on_ns.saturating_sub(earlier.vm_on_ns),
            vs1_on_ns: self.vs1_on_ns.saturating_sub(earlier.vs1_on_ns),
            vs2_on_ns: self.vs2_on_ns.saturating_sub(earlier.vs2_on_ns),
            vp_on_ns: self.vp_on_ns.saturating_sub(earlier.vp_on_ns),
        }
    }
}

/// Accumulates rail on-times while the ignition is off.
#[derive(Debug, Clone, PartialEq)]
pub struct DarkCurrentMeter {
    cfg: DarkCurrentConfig,
    key_off_ns: u64,
    vm_on_ns: u64,
    vs1_on_ns: u64,
    vs2_on_ns: u64,
    vp_on_ns: u64,
}

impl DarkCurrentMeter {
    pub fn new(cfg: DarkCurrentConfig) -> Result<Self, DarkCurrentError> {
        cfg.validate()?;
        Ok(Self {
            cfg,
            key_off_ns: 0,
            vm_on_ns: 0,
            vs1_on_ns: 0,
            vs2_on_ns: 0,
            vp_on_ns: 0,
        })
    }

    pub fn config(&self) -> &DarkCurrentConfig {
        &self.cfg
    }

    /// Accounts one tick of `tick_ns`. Ticks with the ignition on are
    /// ignored. Totals saturate at u64::MAX ns (~584 years).
    pub fn tick(&mut self, ignition_on: bool, rails: RailStates, tick_ns: u64) {
        if ignition_on {
            return;
        }
        let add = |acc: &mut u64, on: bool| {
            if on {
                *acc = acc.saturating_add(tick_ns);
            }
        };
        add(&mut self.key_off_ns, true);
        add(&mut self.vm_on_ns, rails.vm);
        add(&mut self.vs1_on_ns, rails.vs1);
        add(&mut self.vs2_on_ns, rails.vs2);
        add(&mut self.vp_on_ns, rails.vp);
    }

    /// The accumulated times so far.
    pub fn on_times(&self) -> OnTimes {
        OnTimes {
            key_off_ns: self.key_off_ns,
            vm_on_ns: self.vm_on_ns,
            vs1_on_ns: self.vs1_on_ns,
            vs2_on_ns: self.vs2_on_ns,
            vp_on_ns: self.vp_on_ns,
        }
    }

    /// Accounts `n` more repetitions of a stretch that added `delta` (taken with
    /// [`OnTimes::since`]): the same totals as ticking through each repetition, saturating at
    /// u64::MAX ns as [`DarkCurrentMeter::tick`] does (a saturating sum of non-negative terms
    /// is the true sum clamped, whatever the grouping).
    pub fn repeat(&mut self, delta: OnTimes, n: u64) {
        let add = |acc: &mut u64, d: u64| *acc = acc.saturating_add(d.saturating_mul(n));
        add(&mut self.key_off_ns, delta.key_off_ns);
        add(&mut self.vm_on_ns, delta.vm_on_ns);
        add(&mut self.vs1_on_ns, delta.vs1_on_ns);
        add(&mut self.vs2_on_ns, delta.vs2_on_ns);
        add(&mut self.vp_on_ns, delta.vp_on_ns);
    }

    /// Summary so far.
    pub fn report(&self) -> DarkCurrentReport {
        let c = &self.cfg;
        // uA · ns summed, then · 1e-9 s/ns -> uC.
        let ua_ns = c.i_vm_ma * 1e3 * self.vm_on_ns as f64
            + c.i_vs1_ma * 1e3 * self.vs1_on_ns as f64
            + c.i_vs2_ma * 1e3 * self.vs2_on_ns as f64
            + c.i_vp_ua * self.vp_on_ns as f64
            + c.i_q_ua * self.key_off_ns as f64;
        let (vs2_duty, avg_current_ua) = if self.key_off_ns == 0 {
            (None, None)
        } else {
            let t = self.key_off_ns as f64;
            (Some(self.vs2_on_ns as f64 / t), Some(ua_ns / t))
        };
        DarkCurrentReport {
            key_off_ns: self.key_off_ns,
            vm_on_ns: self.vm_on_ns,
            vs1_on_ns: self.vs1_on_ns,
            vs2_on_ns: self.vs2_on_ns,
            vp_on_ns: self.vp_on_ns,
            vs2_duty,
            charge_uc: ua_ns * 1e-9,
            avg_current_ua,
        }
    }

    /// Clears the accumulated times (configuration kept).
    pub fn reset(&mut self) {
        self.key_off_ns = 0;
        self.vm_on_ns = 0;
        self.vs1_on_ns = 0;
        self.vs2_on_ns = 0;
        self.vp_on_ns = 0;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const TICK: u64 = 10_000; // 10 us

    /// Round figures the arithmetic below is written for (not the defaults).
    fn cfg() -> DarkCurrentConfig {
        DarkCurrentConfig {
            i_vm_ma: 50.0,
            i_vs1_ma: 10.0,
            i_vs2_ma: 10.0,
            i_vp_ua: 5.0,
            i_q_ua: 20.0,
        }
    }

    /// Key-off run with Vs2 on for the first `on_ticks` of every
    /// `period_ticks`, Vp always on, Vm/Vs1 off.
    fn run(meter: &mut DarkCurrentMeter, period_ticks: u64, on_ticks: u64, periods: u64) {
        for i in 0..period_ticks * periods {
            let rails = RailStates {
                vs2: i % period_ticks < on_ticks,
                vp: true,
                ..Default::default()
            };
            meter.tick(false, rails, TICK);
        }
    }

    #[test]
    fn duty_10_percent_at_2_2_ms() {
        // [0231]: w = 220 us, interval 2.2 ms -> 10 %.
        let mut m = DarkCurrentMeter::new(cfg()).unwrap();
        run(&mut m, 220, 22, 50);
        let r = m.report();
        assert_eq!(r.key_off_ns, 50 * 2_200_000);
        assert_eq!(r.vs2_on_ns, 50 * 220_000);
        assert_eq!(r.vs2_duty, Some(0.1));
        assert_eq!(r.vm_on_ns, 0);
        assert_eq!(r.vs1_on_ns, 0);
        assert_eq!(r.vp_on_ns, r.key_off_ns);
        // 10 mA · 10 % + 5 uA + 20 uA = 1025 uA.
        assert!((r.avg_current_ua.unwrap() - 1025.0).abs() < 1e-9);
        // Charge = 1025 uA · 110 ms = 112.75 uC.
        assert!((r.charge_uc - 112.75).abs() < 1e-9);
    }

    #[test]
    fn duty_one_third_at_6_6_ms() {
        // [0230]: interval 6.6 ms -> 1/3 of the 2.2 ms duty.
        let mut fast = DarkCurrentMeter::new(cfg()).unwrap();
        run(&mut fast, 220, 22, 30);
        let mut slow = DarkCurrentMeter::new(cfg()).unwrap();
        run(&mut slow, 660, 22, 10);
        let (fn_, fd) = fast.report().vs2_duty_fraction();
        let (sn, sd) = slow.report().vs2_duty_fraction();
        // Exact: slow/fast = 1/3  <=>  3·sn·fd == fn·sd.
        assert_eq!(3 * sn as u128 * fd as u128, fn_ as u128 * sd as u128);
        let d = slow.report().vs2_duty.unwrap();
        assert!((d - 1.0 / 30.0).abs() < 1e-15);
        // Lower duty -> lower dark current ([0303], [0324]).
        assert!(slow.report().avg_current_ua.unwrap() < fast.report().avg_current_ua.unwrap());
    }

    #[test]
    fn key_on_ticks_are_ignored() {
        let mut m = DarkCurrentMeter::new(cfg()).unwrap();
        let all = RailStates {
            vm: true,
            vs1: true,
            vs2: true,
            vp: true,
        };
        m.tick(true, all, TICK);
        assert_eq!(m.report().key_off_ns, 0);
        assert_eq!(m.report().vs2_duty, None);
        assert_eq!(m.report().avg_current_ua, None);
        // A rail wrongly left on during key-off is counted.
        m.tick(false, all, TICK);
        let r = m.report();
        assert_eq!((r.vm_on_ns, r.vs1_on_ns), (TICK, TICK));
        assert!((r.avg_current_ua.unwrap() - (50e3 + 10e3 + 10e3 + 5.0 + 20.0)).abs() < 1e-6);
        m.reset();
        assert_eq!(m.report().vm_on_ns, 0);
    }

    #[test]
    fn repeat_equals_ticking_every_period() {
        // Five periods of 220 ticks with Vs2 on for 22, ticked one by one, against one period
        // ticked and four repeated.
        let mut a = DarkCurrentMeter::new(DarkCurrentConfig::default()).unwrap();
        run(&mut a, 220, 22, 5);
        let mut b = DarkCurrentMeter::new(DarkCurrentConfig::default()).unwrap();
        let before = b.on_times();
        run(&mut b, 220, 22, 1);
        let delta = b.on_times().since(&before);
        assert_eq!(delta.vs2_on_ns, 220_000);
        b.repeat(delta, 4);
        assert_eq!(a.on_times(), b.on_times());
        assert_eq!(a.report(), b.report());
        // Saturation as in `tick`.
        b.repeat(delta, u64::MAX);
        assert_eq!(b.on_times().key_off_ns, u64::MAX);
        assert_eq!(b.on_times().vm_on_ns, 0);
    }

    #[test]
    fn rejects_bad_config() {
        let e = DarkCurrentMeter::new(DarkCurrentConfig {
            i_vs2_ma: -1.0,
            ..Default::default()
        })
        .unwrap_err();
        assert!(e.to_string().contains("i_vs2_ma") && e.to_string().contains(">= 0"));
        assert!(DarkCurrentMeter::new(DarkCurrentConfig {
            i_q_ua: f64::NAN,
            ..Default::default()
        })
        .is_err());
    }

    #[test]
    fn config_deserialize_rejects_unknown_field() {
        use serde::de::value::{Error as DeError, MapDeserializer};
        let ok = DarkCurrentConfig::deserialize(MapDeserializer::<_, DeError>::new(
            vec![("i_vs2_ma", 3.0)].into_iter(),
        ))
        .unwrap();
        assert_eq!(ok.i_vs2_ma, 3.0);
        assert_eq!(ok.i_q_ua, DarkCurrentConfig::default().i_q_ua);
        assert!(
            DarkCurrentConfig::deserialize(MapDeserializer::<_, DeError>::new(
                vec![("i_vs2_a", 3.0)].into_iter(),
            ))
            .is_err()
        );
    }
}
