//! Environment models around the power management unit 50 of
//! US 2022/0041215 A1.
//!
//! Everything outside the digital core lives here: the motor rotation shaft 21
//! (angle profile), the second angle sensor 34 and its supply-dependent
//! settling ([0091], [0326]-[0329]), the analog half of comparators 58a/58b
//! ([0086]-[0088], [0128]-[0133], [0350]-[0353]), the first angle sensor 33
//! and the angular position θ1 / θ2 ([0105]-[0107]), the MPU 60 key-on
//! read-out with the quadrant correction of FIG. 12-13 ([0108]-[0119],
//! [0137]-[0153]) and the key-off dark-current accounting
//! ([0226]-[0231], [0300]-[0303], [0324]).
//!
//! These models use `f64` freely; the digital core only ever sees the raw
//! comparator bits, rail enables and the 16-bit counter values.
//!
//! All models are deterministic: no randomness, no hash-map iteration.
//! Constructors validate their configuration and return a typed error
//! instead of panicking.
//!
//! Patent paragraph citations are written `[0084]`; rustdoc would read them
//! as intra-doc links, hence the lint allowance below.

#![allow(rustdoc::broken_intra_doc_links)]

pub mod angle;
pub mod comparator;
pub mod dark_current;
pub mod motor;
pub mod readout;
pub mod sensor1;
pub mod sensor2;

pub use angle::{circular_diff_deg, wrap_180, wrap_360};
pub use comparator::{ComparatorBits, ComparatorConfig, ComparatorError, ComparatorPair};
pub use dark_current::{
    DarkCurrentConfig, DarkCurrentError, DarkCurrentMeter, DarkCurrentReport, OnTimes, RailStates,
};
pub use motor::{MotorConfig, MotorError, MotorProfile, Segment};
pub use readout::{
    AngleTracker, KeyOnReadout, QuadrantEquation, Readout, ReadoutConfig, ReadoutError,
    RotationAngles,
};
pub use sensor1::{theta2_deg, Sensor1, Sensor1Config, Sensor1Error};
pub use sensor2::{Sensor2, Sensor2Config, Sensor2Error};

/// Umbrella error for callers (scenario loader, CLI) that build several
/// environment models and want a single error type.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum EnvError {
    #[error(transparent)]
    Motor(#[from] MotorError),
    #[error(transparent)]
    Sensor2(#[from] Sensor2Error),
    #[error(transparent)]
    Comparator(#[from] ComparatorError),
    #[error(transparent)]
    Sensor1(#[from] Sensor1Error),
    #[error(transparent)]
    Readout(#[from] ReadoutError),
    #[error(transparent)]
    DarkCurrent(#[from] DarkCurrentError),
}
