//! Configuration of the digital core in physical units, and its exact conversion to ticks.
//!
//! Every duration is written with a unit (`"2.2 ms"`, `"220 us"`, `"10us"`, `"500 ns"`, `"1 s"`)
//! and parsed with integer arithmetic into nanoseconds, so `"1.1 ms"` is exactly 1 100 000 ns and
//! never a binary fraction. A duration must be a whole number of clock ticks, else
//! [`ConfigError::NotWholeTicks`] names the field. No floating point is used anywhere here: the
//! digital core never sees a float (DEVELOPERS.md).
//!
//! Defaults are the patent's numbers: T1 = 2.2 ms [0226], T2 = 1.1 ms [0253], x = 6.6 ms [0227],
//! minimum 2.2 ms [0228], Cth = 4 [0253], Wt = 220 us [0229]/[0327] split as
//! Pw + Pi + Ps = 50 + 120 + 50 us ([0320]-[0323]; the split is ours, see docs/spec.md), clock
//! 10 us, on-key sampling period 100 us ([0349]: "shorter than the intermittent output cycle T").

use crate::params::{ParamError, Params};
use std::fmt;

/// A duration in integer nanoseconds.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Default)]
pub struct Dur(pub u64);

impl Dur {
    pub const fn ns(v: u64) -> Dur {
        Dur(v)
    }
    pub const fn us(v: u64) -> Dur {
        Dur(v * 1_000)
    }
    pub const fn ms(v: u64) -> Dur {
        Dur(v * 1_000_000)
    }
    pub const HOUR_NS: u64 = 3_600_000_000_000;
    pub const DAY_NS: u64 = 86_400_000_000_000;

    /// Parse `"<decimal> <unit>"`, unit one of `d` (86 400 s), `h` (3 600 s), `s`, `ms`, `us`
    /// (or `µs`), `ns`; space optional. Hours and days are for parked runs (`"30 d"`, `"12 h"`).
    pub fn parse(text: &str) -> Result<Dur, DurParseError> {
        let t = text.trim();
        let split = t
            .find(|c: char| !(c.is_ascii_digit() || c == '.' || c == '-' || c == '+'))
            .ok_or_else(|| DurParseError::MissingUnit(text.to_string()))?;
        let (num, unit) = t.split_at(split);
        let num = num.trim();
        let unit = unit.trim();
        let scale: u64 = match unit {
            "d" => Dur::DAY_NS,
            "h" => Dur::HOUR_NS,
            "s" => 1_000_000_000,
            "ms" => 1_000_000,
            "us" | "µs" => 1_000,
            "ns" => 1,
            _ => return Err(DurParseError::BadUnit(text.to_string(), unit.to_string())),
        };
        if num.starts_with('-') {
            return Err(DurParseError::Negative(text.to_string()));
        }
        let num = num.strip_prefix('+').unwrap_or(num);
        let (int_part, frac_part) = match num.split_once('.') {
            Some((i, f)) => (i, f),
            None => (num, ""),
        };
        let digits_ok = |s: &str| s.chars().all(|c| c.is_ascii_digit());
        if (int_part.is_empty() && frac_part.is_empty())
            || !digits_ok(int_part)
            || !digits_ok(frac_part)
        {
            return Err(DurParseError::BadNumber(text.to_string()));
        }
        let overflow = || DurParseError::TooLarge(text.to_string());
        let int_val: u64 = if int_part.is_empty() {
            0
        } else {
            int_part.parse().map_err(|_| overflow())?
        };
        let mut total = int_val.checked_mul(scale).ok_or_else(overflow)?;
        // Fractional digits: each digit is worth scale / 10^k ns; it must be whole.
        let mut place = scale;
        for c in frac_part.chars() {
            let d = u64::from(c as u8 - b'0');
            if !place.is_multiple_of(10) {
                if d != 0 {
                    return Err(DurParseError::SubNanosecond(text.to_string()));
                }
                continue;
            }
            place /= 10;
            total = total.checked_add(d * place).ok_or_else(overflow)?;
        }
        Ok(Dur(total))
    }
}

impl fmt::Display for Dur {
    /// Shortest exact form: `2.2 ms`, `220 us`, `10 ns`; whole days and hours as `30 d`, `12 h`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let v = self.0;
        if v > 0 && v.is_multiple_of(Dur::DAY_NS) {
            return write!(f, "{} d", v / Dur::DAY_NS);
        }
        if v > 0 && v.is_multiple_of(Dur::HOUR_NS) {
            return write!(f, "{} h", v / Dur::HOUR_NS);
        }
        let (scale, unit) = if v >= 1_000_000_000 {
            (1_000_000_000, "s")
        } else if v >= 1_000_000 {
            (1_000_000, "ms")
        } else if v >= 1_000 {
            (1_000, "us")
        } else {
            (1, "ns")
        };
        let int = v / scale;
        let frac = v % scale;
        if frac == 0 {
            write!(f, "{int} {unit}")
        } else {
            let width = scale.trailing_zeros() as usize; // scale is 10^k; 2-adic count equals k
            let s = format!("{frac:0width$}");
            write!(f, "{int}.{} {unit}", s.trim_end_matches('0'))
        }
    }
}

#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum DurParseError {
    #[error("duration `{0}` has no unit; write it as e.g. \"2.2 ms\", \"220 us\", \"10 ns\", \"12 h\" (units: s, ms, us, ns, h, d)")]
    MissingUnit(String),
    #[error("duration `{0}` has unknown unit `{1}`; valid units are s, ms, us, ns, and h, d for hours and days")]
    BadUnit(String, String),
    #[error("duration `{0}` is negative; durations are zero or positive")]
    Negative(String),
    #[error("duration `{0}` is not a decimal number followed by a unit")]
    BadNumber(String),
    #[error("duration `{0}` is too large (at most about 584 years)")]
    TooLarge(String),
    #[error("duration `{0}` has a fraction of a nanosecond; the resolution is 1 ns")]
    SubNanosecond(String),
}

/// The configuration of the core in physical units. Field names are the ones used in scenario
/// files (`[core]` table) and in error messages.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct CoreConfig {
    /// Clock period: one call of the top-level step is one rising edge.
    pub clock: Dur,
    /// Depth of the `ig` synchronizer in flip-flops (1..=4) [0213].
    pub sync_depth: u8,
    /// Width of `cnt_s`/`cnt_c` in bits (2..=16), two's complement, wrapping [0096]-[0099].
    pub cnt_width: u8,
    /// Adaptive drive interval (second embodiment, FIG. 17/18). `false` = first embodiment:
    /// fixed cycle T = `x` [0083].
    pub adaptive: bool,
    /// Waiting period Pw [0321].
    pub pw: Dur,
    /// Idle period Pi [0322]-[0323].
    pub pi: Dur,
    /// Sampling period Ps [0322]-[0323].
    pub ps: Dur,
    /// Maximum drive interval x ("first time interval") [0216]; also the fixed cycle T when
    /// `adaptive` is false.
    pub x: Dur,
    /// Minimum drive interval [0228].
    pub min: Dur,
    /// Shortening step T1 [0224].
    pub t1: Dur,
    /// Expanding step T2 [0250].
    pub t2: Dur,
    /// Count threshold Cth [0250].
    pub cth: u32,
    /// Sampling period of the rotation number detection unit while the key is on [0349].
    pub smp_on: Dur,
}

impl Default for CoreConfig {
    fn default() -> Self {
        CoreConfig {
            clock: Dur::us(10),
            sync_depth: 2,
            cnt_width: 16,
            adaptive: true,
            pw: Dur::us(50),
            pi: Dur::us(120),
            ps: Dur::us(50),
            x: Dur::us(6_600),
            min: Dur::us(2_200),
            t1: Dur::us(2_200),
            t2: Dur::us(1_100),
            cth: 4,
            smp_on: Dur::us(100),
        }
    }
}

#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum ConfigError {
    #[error("core.clock must be a positive duration, got {0}")]
    ZeroClock(Dur),
    #[error("core.{field} = {value} is not a whole number of clock ticks (clock = {clock}); use a multiple of {clock}")]
    NotWholeTicks {
        field: &'static str,
        value: Dur,
        clock: Dur,
    },
    #[error("core.{field} = {value} is {ticks} ticks; the register holds at most {max} ticks ({max_dur} at clock {clock})")]
    TooManyTicks {
        field: &'static str,
        value: Dur,
        ticks: u64,
        max: u64,
        max_dur: Dur,
        clock: Dur,
    },
    #[error(transparent)]
    Param(#[from] ParamError),
}

impl ConfigError {
    /// Every configuration field the violated rule involves (names as in `[core]`), so that a
    /// loader can point at the one the user wrote.
    pub fn fields(&self) -> &'static [&'static str] {
        match self {
            ConfigError::ZeroClock(_) => &["clock"],
            ConfigError::NotWholeTicks { field, .. } | ConfigError::TooManyTicks { field, .. } => {
                field_list(field)
            }
            ConfigError::Param(ParamError::OutOfRange { field, .. })
            | ConfigError::Param(ParamError::Zero { field }) => field_list(field),
            ConfigError::Param(ParamError::MinAboveMax { .. }) => &["min", "x"],
            ConfigError::Param(ParamError::WindowTooLong { .. }) => {
                &["pw", "pi", "ps", "min", "x", "adaptive"]
            }
            ConfigError::Param(ParamError::NoSettlingTick) => &["pw", "pi"],
        }
    }
}

/// The `[core]` field names of a scenario file and of `pmu50.Core(**kwargs)`, in the order of
/// docs/spec.md (the fields of [`CoreConfig`]).
pub const FIELDS: [&str; 13] = [
    "clock",
    "sync_depth",
    "cnt_width",
    "adaptive",
    "pw",
    "pi",
    "ps",
    "x",
    "min",
    "t1",
    "t2",
    "cth",
    "smp_on",
];

/// A static one-element list for a field name: the field of [`FIELDS`], else `core`.
fn field_list(field: &str) -> &'static [&'static str] {
    match FIELDS.iter().position(|f| *f == field) {
        Some(i) => &FIELDS[i..=i],
        None => &["core"],
    }
}

impl CoreConfig {
    /// Convert to register values in ticks and check every rule of [`Params::validate`].
    pub fn to_params(&self) -> Result<Params, ConfigError> {
        let clk = self.clock.0;
        if clk == 0 {
            return Err(ConfigError::ZeroClock(self.clock));
        }
        let ticks = |field: &'static str, d: Dur, max: u64| -> Result<u64, ConfigError> {
            if !d.0.is_multiple_of(clk) {
                return Err(ConfigError::NotWholeTicks {
                    field,
                    value: d,
                    clock: self.clock,
                });
            }
            let t = d.0 / clk;
            if t > max {
                return Err(ConfigError::TooManyTicks {
                    field,
                    value: d,
                    ticks: t,
                    max,
                    max_dur: Dur(max.saturating_mul(clk)),
                    clock: self.clock,
                });
            }
            Ok(t)
        };
        let m16 = u64::from(u16::MAX);
        let p = Params {
            sync_depth: self.sync_depth,
            cnt_width: self.cnt_width,
            adaptive: self.adaptive,
            pw: ticks("pw", self.pw, m16)? as u16,
            pi: ticks("pi", self.pi, m16)? as u16,
            ps: ticks("ps", self.ps, m16)? as u16,
            si_max: ticks("x", self.x, m16)? as u16,
            si_min: ticks("min", self.min, m16)? as u16,
            t1: ticks("t1", self.t1, m16)? as u16,
            t2: ticks("t2", self.t2, m16)? as u16,
            cth: u8::try_from(self.cth).map_err(|_| ParamError::OutOfRange {
                field: "cth",
                value: u64::from(self.cth),
                min: 1,
                max: 255,
            })?,
            smp_on: ticks("smp_on", self.smp_on, m16)? as u16,
        };
        p.validate()?;
        Ok(p)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_patent_numbers_exactly() {
        assert_eq!(Dur::parse("2.2 ms"), Ok(Dur(2_200_000)));
        assert_eq!(Dur::parse("1.1ms"), Ok(Dur(1_100_000)));
        assert_eq!(Dur::parse("220 us"), Ok(Dur(220_000)));
        assert_eq!(Dur::parse("220 µs"), Ok(Dur(220_000)));
        assert_eq!(Dur::parse("6.6 ms"), Ok(Dur(6_600_000)));
        assert_eq!(Dur::parse("10 ns"), Ok(Dur(10)));
        assert_eq!(Dur::parse("0.5 s"), Ok(Dur(500_000_000)));
        assert_eq!(Dur::parse(".5 us"), Ok(Dur(500)));
    }

    #[test]
    fn rejects_bad_durations() {
        assert!(matches!(
            Dur::parse("2.2"),
            Err(DurParseError::MissingUnit(_))
        ));
        assert!(matches!(
            Dur::parse("2.2 min"),
            Err(DurParseError::BadUnit(..))
        ));
        assert!(matches!(
            Dur::parse("-1 ms"),
            Err(DurParseError::Negative(_))
        ));
        assert!(matches!(
            Dur::parse("1.5 ns"),
            Err(DurParseError::SubNanosecond(_))
        ));
        assert!(matches!(
            Dur::parse("1.2.3 ms"),
            Err(DurParseError::BadNumber(_))
        ));
        assert!(matches!(
            Dur::parse(" ms"),
            Err(DurParseError::BadNumber(_))
        ));
        assert!(matches!(
            Dur::parse("99999999999999999999 s"),
            Err(DurParseError::TooLarge(_))
        ));
    }

    #[test]
    fn hours_and_days() {
        assert_eq!(Dur::parse("30 d"), Ok(Dur(30 * 86_400 * 1_000_000_000)));
        assert_eq!(Dur::parse("12 h"), Ok(Dur(12 * 3_600 * 1_000_000_000)));
        assert_eq!(Dur::parse("1.5h"), Ok(Dur(5_400 * 1_000_000_000)));
        assert_eq!(Dur::parse("0.25 d"), Ok(Dur(6 * 3_600 * 1_000_000_000)));
        // 1e-11 h = 36 ns exactly; 1e-13 h = 0.36 ns is below the resolution.
        assert_eq!(Dur::parse("0.00000000001 h"), Ok(Dur(36)));
        assert!(matches!(
            Dur::parse("0.0000000000001 h"),
            Err(DurParseError::SubNanosecond(_))
        ));
        assert_eq!(Dur::parse("213503 d"), Ok(Dur(213_503 * Dur::DAY_NS)));
        assert!(matches!(
            Dur::parse("213504 d"),
            Err(DurParseError::TooLarge(_))
        ));
        assert!(matches!(
            Dur::parse("-1 d"),
            Err(DurParseError::Negative(_))
        ));
        assert!(matches!(
            Dur::parse("2 days"),
            Err(DurParseError::BadUnit(..))
        ));
        let e = Dur::parse("2 min").unwrap_err().to_string();
        assert!(e.contains("s, ms, us, ns, and h, d"), "{e}");
        assert_eq!(Dur::parse("30 d").unwrap().to_string(), "30 d");
        assert_eq!(Dur::parse("36 h").unwrap().to_string(), "36 h");
        assert_eq!(Dur::parse("48 h").unwrap().to_string(), "2 d");
        assert_eq!(Dur::parse("5400 s").unwrap().to_string(), "5400 s");
    }

    #[test]
    fn display_round_trips() {
        for s in [
            "2.2 ms",
            "220 us",
            "10 ns",
            "1 s",
            "1.000001 s",
            "6.6 ms",
            "0 ns",
            "30 d",
            "12 h",
            "3601 s",
        ] {
            let d = Dur::parse(s).unwrap();
            assert_eq!(d.to_string(), s);
            assert_eq!(Dur::parse(&d.to_string()), Ok(d));
        }
    }

    #[test]
    fn fields_are_the_config_struct_in_order() {
        // the names of the struct's Debug form: `CoreConfig { clock: Dur(..), sync_depth: 2, ..`
        let debug = format!("{:?}", CoreConfig::default());
        let body = debug
            .strip_prefix("CoreConfig { ")
            .and_then(|b| b.strip_suffix(" }"))
            .unwrap();
        let names: Vec<&str> = body
            .split(", ")
            .filter_map(|part| part.split_once(": ").map(|(n, _)| n))
            .collect();
        assert_eq!(names, FIELDS);
    }

    #[test]
    fn an_error_names_a_field_of_the_table() {
        assert_eq!(field_list("t2"), ["t2"]);
        assert_eq!(field_list("nope"), ["core"]);
        let e = ConfigError::Param(ParamError::Zero { field: "smp_on" });
        assert_eq!(e.fields(), ["smp_on"]);
    }

    #[test]
    fn default_is_the_patent() {
        let p = CoreConfig::default().to_params().unwrap();
        assert_eq!(
            (p.t1, p.t2, p.si_max, p.si_min, p.cth),
            (220, 110, 660, 220, 4)
        );
        assert_eq!(p.pw + p.pi + p.ps, 22, "Wt = 220 us [0229]");
    }

    #[test]
    fn not_whole_ticks_names_the_field() {
        let c = CoreConfig {
            t2: Dur::us(1_105),
            ..CoreConfig::default()
        };
        let e = c.to_params().unwrap_err();
        assert_eq!(
            e,
            ConfigError::NotWholeTicks {
                field: "t2",
                value: Dur::us(1_105),
                clock: Dur::us(10)
            }
        );
        assert!(e.to_string().contains("core.t2"), "{e}");
    }

    #[test]
    fn too_many_ticks_is_an_error() {
        let c = CoreConfig {
            clock: Dur::ns(10),
            ..CoreConfig::default()
        };
        let e = c.to_params().unwrap_err();
        assert!(
            matches!(e, ConfigError::TooManyTicks { field: "x", .. }),
            "{e}"
        );
    }

    #[test]
    fn zero_clock_is_an_error() {
        let c = CoreConfig {
            clock: Dur(0),
            ..CoreConfig::default()
        };
        assert_eq!(c.to_params(), Err(ConfigError::ZeroClock(Dur(0))));
    }
}
