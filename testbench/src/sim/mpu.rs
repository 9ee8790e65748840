//! The MPU 60 of the bench: boot after key-on, register-map polling over the bus, the key-on
//! read-out of FIG. 12-13 ([0108]-[0114], [0137]-[0153]) and the tracking of θm while the key is
//! on ([0115]-[0116]); plus the origin of the true angle (the turn of the counters' first sample).
//!
//! While the key is on and the timeline has no write for the tick, the MPU polls the register
//! map, one address per tick in map order, so the register file's registered read path
//! (`bus_addr` -> `bus_rdata`) is exercised in every waveform and vector file. Its read-out uses
//! the read mux of the same cycle ([`Pmu50::read`]), which is what the polled `bus_rdata` shows
//! one tick later.

use super::front::FrontSample;
use super::rows::{KeyOffRow, KeyOnRow};
use crate::scenario::EnvSpec;
use pmu50_core::register_file::{addr, status, MAP};
use pmu50_core::{Inputs, Outputs, Pmu50};
use pmu50_env::{theta2_deg, wrap_360, AngleTracker, EnvError, MotorProfile, Readout, Sensor1};

/// Everything of the MPU that influences later ticks (for the period repeat test).
#[derive(Clone, Debug, PartialEq)]
pub struct MpuState {
    pub boot_at: Option<u64>,
    pub tracker: Option<AngleTracker>,
    pub turn0: Option<f64>,
    pub prev_sig: bool,
}

/// Ticks of one round of the MPU's polling of the register map (one address a tick).
pub const POLL_CYCLE: u64 = MAP.len() as u64;

#[derive(Clone, Debug)]
pub struct Mpu {
    sensor1: Sensor1,
    readout: Readout,
    boot_ticks: u64,
    theta_t_deg: f64,
    st: MpuState,
    pub keyons: Vec<KeyOnRow>,
    pub keyoffs: Vec<KeyOffRow>,
}

impl Mpu {
    pub fn new(env: &EnvSpec) -> Result<Mpu, EnvError> {
        Ok(Mpu {
            sensor1: Sensor1::new(env.sensor1)?,
            readout: Readout::new(env.readout)?,
            boot_ticks: env.mpu_boot_ticks,
            theta_t_deg: env.theta_t_deg,
            st: MpuState {
                boot_at: None,
                tracker: None,
                turn0: None,
                prev_sig: false,
            },
            keyons: Vec::new(),
            keyoffs: Vec::new(),
        })
    }

    pub fn state(&self) -> &MpuState {
        &self.st
    }

    /// Key edges as the MPU sees them (on `sig`, the synchronised key): boot is scheduled at a
    /// rise; at a fall the MPU loses power and its last tracked θm is recorded.
    pub fn key_edges(&mut self, k: u64, t_ns: u64, out: &Outputs, motor: &MotorProfile) {
        if out.sig && !self.st.prev_sig {
            self.st.boot_at = Some(k + self.boot_ticks);
        }
        if !out.sig && self.st.prev_sig {
            self.st.boot_at = None;
            if let Some(tr) = self.st.tracker.take() {
                let true_deg = motor.angle_at(t_ns) - self.st.turn0.unwrap_or(0.0);
                self.keyoffs.push(KeyOffRow {
                    tick: k,
                    true_deg,
                    theta_m_deg: tr.theta_m_deg(),
                    angles: tr.angles(self.theta_t_deg),
                });
            }
        }
        self.st.prev_sig = out.sig;
    }

    /// Off or waiting for nothing: no boot pending (the bench may fast-forward).
    pub fn idle(&self) -> bool {
        self.st.boot_at.is_none()
    }

    /// Bus polling: while powered, read the next map address. The caller polls only in ticks
    /// the timeline leaves the bus alone (no write, no read of its own).
    /// The round of polls repeats every [`POLL_CYCLE`] ticks.
    pub fn poll_bus(&self, k: u64, out: &Outputs, inputs: &mut Inputs) {
        if out.sig {
            inputs.bus_addr = MAP[(k % MAP.len() as u64) as usize].1;
        }
    }

    /// The read-out at boot, then tracking; returns θ1 (while the first sensor is powered) and
    /// the tracked θm. `theta_deg` is the true angle at the end of this tick.
    pub fn read_and_track(
        &mut self,
        k: u64,
        t_ns: u64,
        core: &Pmu50,
        out: &Outputs,
        theta_deg: f64,
        f: &FrontSample,
    ) -> Result<(Option<f64>, Option<f64>), EnvError> {
        let theta1 = if out.vs1_en {
            Some(self.sensor1.theta1_deg(wrap_360(theta_deg))?)
        } else {
            None
        };
        if let (Some(b), Some(t1)) = (self.st.boot_at, theta1) {
            if k == b {
                let cnt_s = core.read(addr::CNT_S) as i16;
                let cnt_c = core.read(addr::CNT_C) as i16;
                let st = core.read(addr::STATUS);
                let r = self.readout.key_on(cnt_s, cnt_c, t1)?;
                // θ1 is the angle at the end of this tick; compare at that same instant.
                let true_deg = theta_deg - self.st.turn0.unwrap_or(0.0);
                let th2 = theta2_deg(f.vs2_v, f.sin2_v, f.cos2_v);
                let tracker = self.readout.tracker(&r);
                self.keyons.push(KeyOnRow {
                    tick: k,
                    time_ns: t_ns,
                    true_deg,
                    error_deg: r.theta_m_deg - true_deg,
                    diag: st >> status::DIAG & 1 == 1,
                    quadrant_skip: st >> status::QUADRANT_SKIP & 1 == 1,
                    theta_abnormal: self.readout.theta_abnormal(t1, th2),
                    readout: r,
                    angles: tracker.angles(self.theta_t_deg),
                });
                self.st.tracker = Some(tracker);
                self.st.boot_at = None;
            }
        }
        if let (Some(tr), Some(t1)) = (self.st.tracker.as_mut(), theta1) {
            tr.update(t1)?;
        }
        Ok((theta1, self.st.tracker.as_ref().map(|t| t.theta_m_deg())))
    }

    /// The core took its first sample (`first`): the counters' origin is the turn in which that
    /// sample put the shaft, the turn that brings this angle nearest the middle of the sampled
    /// quadrant (at a boundary the chip may see either side, e.g. a settling sine exactly at 0 deg).
    pub fn first_sample(&mut self, after: &Outputs, theta_deg: f64) {
        let q0 = match (after.cs, after.cc) {
            (true, true) => 0.0,
            (true, false) => 1.0,
            (false, false) => 2.0,
            (false, true) => 3.0,
        };
        self.st.turn0 = Some(((theta_deg - (q0 * 90.0 + 45.0)) / 360.0).round() * 360.0);
    }
}
