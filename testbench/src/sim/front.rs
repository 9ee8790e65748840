//! Analog front of the bench: the Vs2 rail (unit 54 output, with an injectable fault), the second
//! angle sensor 34 with its supply-dependent settling ([0091], [0326]-[0329]) and the analog half
//! of comparators 58a/58b against Vr = Vs2/2 ([0086]-[0088], [0350]-[0353]).
//!
//! One call of [`AnalogFront::sample`] is one tick: the rail level this tick follows the core's
//! Moore outputs `vs2_en`/`rail_hi`, the sensor settles towards the shaft angle at the end of the
//! tick, and the comparators give the raw sign bits the core latches at the next edge.
//!
//! Quiet time ("no change before t", for the period skip-ahead of docs/spec.md 5.1): the comparator pair is stateless, its bits change
//! only when its inputs do; the sensor is a first-order lag whose whole state is compared by
//! value ([`FrontState`]) at key-off period boundaries, where it is unpowered (Vs2 off since the
//! end of the previous window), so a period that starts in the same state with the same held
//! angle repeats exactly.

use crate::scenario::EnvSpec;
use pmu50_core::Outputs;
use pmu50_env::{ComparatorBits, ComparatorPair, EnvError, Sensor2};

/// The analog values of one tick.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrontSample {
    /// Vs2 rail voltage during the tick (0 when off or faulted).
    pub vs2_v: f64,
    /// Vp rail voltage (Vcc1 or Vcc2 by `rail_hi`).
    pub vp_v: f64,
    pub sin2_v: f64,
    pub cos2_v: f64,
    /// Raw comparator decisions (inputs `cmp_s`, `cmp_c` of the core).
    pub bits: ComparatorBits,
}

/// Everything of the front that influences later ticks (for the period repeat test).
#[derive(Clone, Debug, PartialEq)]
pub struct FrontState {
    pub sensor2: Sensor2,
    pub fault: bool,
    pub pg_leak: bool,
}

/// Rail, second sensor and comparators.
#[derive(Clone, Debug)]
pub struct AnalogFront {
    sensor2: Sensor2,
    cmp: ComparatorPair,
    vcc1_v: f64,
    vcc2_v: f64,
    /// Injected Vs2 fault: the rail does not come up while true (scenario `vs2_fault`).
    fault: bool,
    /// Injected power-good leak: power-good reads high while the rail is off (scenario
    /// `vs2_pg_leak`).
    pg_leak: bool,
}

impl AnalogFront {
    pub fn new(env: &EnvSpec) -> Result<AnalogFront, EnvError> {
        Ok(AnalogFront {
            sensor2: Sensor2::new(env.sensor2)?,
            cmp: ComparatorPair::new(env.comparator)?,
            vcc1_v: env.vcc1_v,
            vcc2_v: env.vcc2_v,
            fault: false,
            pg_leak: false,
        })
    }

    pub fn set_fault(&mut self, on: bool) {
        self.fault = on;
    }

    pub fn set_pg_leak(&mut self, on: bool) {
        self.pg_leak = on;
    }

    /// Vs2's power-good this tick (input `vs2_ok`): the rail is up, or it is off (not enabled)
    /// while the power-good leaks.
    pub fn power_good(&self, f: &FrontSample, out: &Outputs) -> bool {
        f.vs2_v > 0.0 || (self.pg_leak && !out.vs2_en)
    }

    /// Whether the power-good leaks now (the bench then steps every tick: an idle key-off
    /// stretch has `vs2_ok` low).
    pub fn pg_leak(&self) -> bool {
        self.pg_leak
    }

    /// One tick: rail from the core's outputs, sensor settling towards `theta_deg` over
    /// `clock_ns`, comparator bits.
    pub fn sample(
        &mut self,
        out: &Outputs,
        theta_deg: f64,
        clock_ns: u64,
    ) -> Result<FrontSample, EnvError> {
        let level = if out.rail_hi {
            self.vcc1_v
        } else {
            self.vcc2_v
        };
        let vs2_v = if out.vs2_en && !self.fault {
            level
        } else {
            0.0
        };
        let (sin2_v, cos2_v) = self.sensor2.step(vs2_v, theta_deg, clock_ns)?;
        Ok(FrontSample {
            vs2_v,
            vp_v: level,
            sin2_v,
            cos2_v,
            bits: self.cmp.compare(vs2_v, sin2_v, cos2_v),
        })
    }

    /// A fast-forwarded stretch with Vs2 off: the sensor is unpowered (its outputs are forced to
    /// 0 V whatever the angle), the comparators give 0.
    pub fn unpowered(&mut self, clock_ns: u64) -> Result<(), EnvError> {
        self.sensor2.step(0.0, 0.0, clock_ns)?;
        Ok(())
    }

    /// Quiet until Vs2 next rises: the sensor is unpowered, the comparators (stateless) give 0.
    pub fn quiet_while_off(&self) -> bool {
        self.sensor2.is_unpowered()
    }

    pub fn state(&self) -> FrontState {
        FrontState {
            sensor2: self.sensor2.clone(),
            fault: self.fault,
            pg_leak: self.pg_leak,
        }
    }
}
