//! Time units and timescales shared by the writer, reader and diff.

use std::fmt;

/// A VCD time unit (IEEE 1364 §18.2.3.5 allows exactly these six).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum TimeUnit {
    /// seconds
    S,
    /// milliseconds
    Ms,
    /// microseconds
    Us,
    /// nanoseconds
    Ns,
    /// picoseconds
    Ps,
    /// femtoseconds
    Fs,
}

impl TimeUnit {
    /// Power of ten of one unit in seconds (`Us` → -6).
    pub fn exponent(self) -> i32 {
        match self {
            TimeUnit::S => 0,
            TimeUnit::Ms => -3,
            TimeUnit::Us => -6,
            TimeUnit::Ns => -9,
            TimeUnit::Ps => -12,
            TimeUnit::Fs => -15,
        }
    }

    /// The unit whose exponent is `exp`, if it is one of the six VCD units.
    pub fn from_exponent(exp: i32) -> Option<TimeUnit> {
        Some(match exp {
            0 => TimeUnit::S,
            -3 => TimeUnit::Ms,
            -6 => TimeUnit::Us,
            -9 => TimeUnit::Ns,
            -12 => TimeUnit::Ps,
            -15 => TimeUnit::Fs,
            _ => return None,
        })
    }

    /// The VCD spelling (`"us"`).
    pub fn as_str(self) -> &'static str {
        match self {
            TimeUnit::S => "s",
            TimeUnit::Ms => "ms",
            TimeUnit::Us => "us",
            TimeUnit::Ns => "ns",
            TimeUnit::Ps => "ps",
            TimeUnit::Fs => "fs",
        }
    }

    pub(crate) fn to_vcd(self) -> vcd::TimescaleUnit {
        match self {
            TimeUnit::S => vcd::TimescaleUnit::S,
            TimeUnit::Ms => vcd::TimescaleUnit::MS,
            TimeUnit::Us => vcd::TimescaleUnit::US,
            TimeUnit::Ns => vcd::TimescaleUnit::NS,
            TimeUnit::Ps => vcd::TimescaleUnit::PS,
            TimeUnit::Fs => vcd::TimescaleUnit::FS,
        }
    }
}

impl fmt::Display for TimeUnit {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

/// A timescale: one tick of the file is `factor` × `unit` (`$timescale 10 us $end`).
///
/// The VCD writer only accepts the IEEE factors 1, 10 and 100; the reader and
/// the diff accept whatever factor a file declares.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Timescale {
    /// Multiplier of the unit (1, 10 or 100 in IEEE VCD).
    pub factor: u32,
    /// The unit.
    pub unit: TimeUnit,
}

impl Timescale {
    /// `Timescale::new(1, TimeUnit::Us)` is `1 us`.
    pub const fn new(factor: u32, unit: TimeUnit) -> Self {
        Timescale { factor, unit }
    }

    /// True for the factors IEEE 1364 allows in `$timescale` (1, 10, 100).
    pub fn is_ieee(&self) -> bool {
        matches!(self.factor, 1 | 10 | 100)
    }
}

impl fmt::Display for Timescale {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} {}", self.factor, self.unit)
    }
}
