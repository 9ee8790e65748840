//! The rows of a run's tables: the per-pulse event table, the key-on read-outs and the key-off
//! angles ([`super::RunResult`]).

use pmu50_core::drive_interval_changing_56b::{Fig17, Fig18};
use pmu50_env::{KeyOnReadout, RotationAngles};

/// One row of the per-pulse event table: the state after a key-off sampling edge.
#[derive(Clone, Debug, PartialEq)]
pub struct PulseRow {
    /// Edge number (the sample was taken at the end of tick `tick - 1`).
    pub tick: u64,
    pub time_ns: u64,
    pub cs: bool,
    pub cc: bool,
    pub hist_s: bool,
    pub hist_c: bool,
    pub cnt_r: u8,
    pub si: u16,
    pub cnt_s: i32,
    pub cnt_c: i32,
    pub fig17: Fig17,
    pub fig18: Fig18,
}

/// One key-on read-out by the MPU.
#[derive(Clone, Debug, PartialEq)]
pub struct KeyOnRow {
    pub tick: u64,
    pub time_ns: u64,
    /// True multi-turn angle relative to the turn the counters started in.
    pub true_deg: f64,
    pub readout: KeyOnReadout,
    /// θm, θo = θm·Rg, θi = θo + θt at the read-out ([0116]).
    pub angles: RotationAngles,
    pub error_deg: f64,
    /// STATUS.diag and STATUS.quadrant_skip as read by the MPU.
    pub diag: bool,
    pub quadrant_skip: bool,
    /// θ1 against θ2 diagnosis ([0118]).
    pub theta_abnormal: bool,
}

/// θm at the moment the key goes off (end of tracking), against the true angle.
#[derive(Clone, Debug, PartialEq)]
pub struct KeyOffRow {
    pub tick: u64,
    pub true_deg: f64,
    pub theta_m_deg: f64,
    /// θm, θo, θi as tracked up to key-off ([0115]-[0116]).
    pub angles: RotationAngles,
}
