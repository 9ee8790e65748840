//! Parameter values of the core in ticks: the reset values of the programmable registers of
//! the register file (docs/spec.md, register map) plus two structural parameters (`sync_depth`,
//! `cnt_width`) that the HDL implements as Verilog `parameter`s.

/// The parameter table, declared once: every parameter of the core as (field, type, Verilog
/// parameter name of the twin, default, meaning), the two structural ones first, then the
/// programmable registers with their register file address ([`crate::register_file::addr`]).
/// The order is that of the `// param` lines of a vector file (docs/spec.md 6.2).
///
/// Everything that lists the parameters is generated from it by a macro that receives the table
/// (`param_table!(my_macro)` expands `my_macro! { structural: [...], programmable: [...] }`):
/// [`Params`] and its HDL names here, the register file's parameter registers, their reset,
/// write map and read mux (`register_file.rs`), and the C ABI's conversions (`hdl/ffi`).
#[macro_export]
macro_rules! param_table {
    ($then:ident) => {
        $then! {
            structural: [
                (sync_depth, u8, "SYNC_DEPTH", 2, "Synchronizer depth of `ig` (structural, 1..=4)."),
                (cnt_width, u8, "CNT_W", 16, "Counter width in bits (structural, 2..=16)."),
            ],
            programmable: [
                (adaptive, bool, "ADAPTIVE", true, CTRL, "Adaptive drive interval on (FIG. 17/18) or fixed cycle T = `si_max` (first embodiment); CTRL bit 0."),
                (pw, u16, "PW", 5, PW, "Waiting period Pw [0321], 16 bit."),
                (pi, u16, "PI", 12, PI, "Idle period Pi [0322], 16 bit."),
                (ps, u16, "PS", 5, PS, "Sampling period Ps [0322], 16 bit."),
                (si_max, u16, "SI_MAX", 660, SI_MAX, "Maximum interval x [0216], 16 bit."),
                (si_min, u16, "SI_MIN", 220, SI_MIN, "Minimum interval [0228], 16 bit."),
                (t1, u16, "T1", 220, T1, "Shortening step T1 [0224], 16 bit."),
                (t2, u16, "T2", 110, T2, "Expanding step T2 [0250], 16 bit."),
                (cth, u8, "CTH", 4, CTH, "Count threshold Cth [0250], 8 bit."),
                (smp_on, u16, "SMP_ON", 10, SMP_ON, "On-key sampling period [0349], 16 bit."),
            ]
        }
    };
}

/// A parameter's value type: its width and its conversions to and from a register or a
/// Verilog parameter value.
pub trait ParamValue: Copy {
    /// Bits of the register (1, 8 or 16).
    const BITS: u32;
    /// The value written to the register by a bus write of `d` (its low `BITS` bits).
    fn from_bus(d: u16) -> Self;
    /// As read on the bus.
    fn to_bus(self) -> u16;
    /// As a Verilog parameter value.
    fn to_u64(self) -> u64 {
        u64::from(self.to_bus())
    }
    /// From a Verilog parameter value, `None` when it does not fit in `BITS` bits.
    fn from_u64(v: u64) -> Option<Self> {
        (v >> Self::BITS == 0).then(|| Self::from_bus(v as u16))
    }
}

impl ParamValue for bool {
    const BITS: u32 = 1;
    fn from_bus(d: u16) -> bool {
        d & 1 == 1
    }
    fn to_bus(self) -> u16 {
        u16::from(self)
    }
}

impl ParamValue for u8 {
    const BITS: u32 = 8;
    fn from_bus(d: u16) -> u8 {
        (d & 0xFF) as u8
    }
    fn to_bus(self) -> u16 {
        u16::from(self)
    }
}

impl ParamValue for u16 {
    const BITS: u32 = 16;
    fn from_bus(d: u16) -> u16 {
        d
    }
    fn to_bus(self) -> u16 {
        self
    }
}

macro_rules! params_struct {
    (structural: [$(($sf:ident, $st:ty, $sh:literal, $sd:literal, $sdoc:literal),)*],
     programmable: [$(($f:ident, $t:ty, $h:literal, $d:literal, $a:ident, $doc:literal),)*]) => {
        /// Parameters of the core, all durations in clock ticks: the structural parameters and
        /// the reset values of the programmable registers (the table of [`param_table!`]).
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
        pub struct Params {
            $(#[doc = $sdoc] pub $sf: $st,)*
            $(#[doc = $doc] pub $f: $t,)*
        }

        impl Params {
            /// The patent's defaults at a 10 us clock (see
            /// [`crate::config::CoreConfig::default`]).
            pub const DEFAULT: Params = Params { $($sf: $sd,)* $($f: $d,)* };

            /// The Verilog parameters of the twin with their values, in the order of the
            /// `// param` lines of a vector file (docs/spec.md 6.2).
            pub fn hdl_parameters(&self) -> [(&'static str, u64); PARAM_COUNT] {
                [$(($sh, ParamValue::to_u64(self.$sf)),)* $(($h, ParamValue::to_u64(self.$f)),)*]
            }

            /// Set the parameter whose Verilog name is `name` (`SI_MAX`, as in a `// param`
            /// line of a vector file) to `value`. The set is not validated
            /// ([`Params::validate`]).
            pub fn set_hdl_parameter(&mut self, name: &str, value: u64) -> Result<(), HdlParamError> {
                match name {
                    $($sh => self.$sf = ParamValue::from_u64(value).ok_or(HdlParamError::TooWide { name: $sh, value, bits: <$st as ParamValue>::BITS })?,)*
                    $($h => self.$f = ParamValue::from_u64(value).ok_or(HdlParamError::TooWide { name: $h, value, bits: <$t as ParamValue>::BITS })?,)*
                    _ => return Err(HdlParamError::Unknown { name: name.to_string() }),
                }
                Ok(())
            }
        }

        /// The Verilog parameter names, in table order.
        pub const HDL_NAMES: &[&str] = &[$($sh,)* $($h,)*];

        /// The bits of each parameter's register, in table order (as [`HDL_NAMES`]).
        pub const HDL_BITS: &[u32] = &[
            $(<$st as ParamValue>::BITS,)* $(<$t as ParamValue>::BITS,)*
        ];

        /// Each parameter's default, in table order (as [`HDL_NAMES`]).
        pub const HDL_DEFAULTS: &[u64] = &[$($sd as u64,)* $($d as u64,)*];
    };
}

param_table!(params_struct);

/// Number of parameters (structural and programmable).
pub const PARAM_COUNT: usize = HDL_NAMES.len();

/// What values one parameter may take on its own (docs/spec.md 4).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Rule {
    /// `min..=max`.
    Range { min: u64, max: u64 },
    /// Any value of its register but 0.
    NotZero,
    /// Any value of its register.
    Any,
}

/// The legal values of one parameter on its own.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Legal {
    /// The `[core]` field that sets it, as the errors name it (`x` for `SI_MAX`).
    pub field: &'static str,
    /// Its Verilog parameter name.
    pub hdl: &'static str,
    pub rule: Rule,
}

impl Legal {
    /// The least and the greatest legal value (`Rule::NotZero` and `Rule::Any` up to the
    /// largest value of the register).
    pub fn range(&self) -> (u64, u64) {
        let bits = HDL_NAMES
            .iter()
            .position(|n| *n == self.hdl)
            .map_or(16, |i| HDL_BITS[i]);
        let top = (1u64 << bits) - 1;
        match self.rule {
            Rule::Range { min, max } => (min, max),
            Rule::NotZero => (1, top),
            Rule::Any => (0, top),
        }
    }
}

/// Every parameter's legal values on its own, in the order [`Params::validate`] checks them.
/// The rules between parameters (pw + pi >= 1, min <= x, Wt shorter than the shortest
/// interval) are `validate`'s own.
pub const LEGAL: [Legal; PARAM_COUNT] = [
    legal("sync_depth", "SYNC_DEPTH", Rule::Range { min: 1, max: 4 }),
    legal("cnt_width", "CNT_W", Rule::Range { min: 2, max: 16 }),
    legal("cth", "CTH", Rule::Range { min: 1, max: 255 }),
    legal("ps", "PS", Rule::NotZero),
    legal("x", "SI_MAX", Rule::NotZero),
    legal("min", "SI_MIN", Rule::NotZero),
    legal("t1", "T1", Rule::NotZero),
    legal("t2", "T2", Rule::NotZero),
    legal("smp_on", "SMP_ON", Rule::NotZero),
    legal("adaptive", "ADAPTIVE", Rule::Any),
    legal("pw", "PW", Rule::Any),
    legal("pi", "PI", Rule::Any),
];

const fn legal(field: &'static str, hdl: &'static str, rule: Rule) -> Legal {
    Legal { field, hdl, rule }
}

/// A Verilog parameter that [`Params::set_hdl_parameter`] cannot take.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum HdlParamError {
    #[error("unknown parameter `{name}`; valid are {}", HDL_NAMES.join(", "))]
    Unknown { name: String },
    #[error("parameter {name} = {value} does not fit in its {bits} bits")]
    TooWide {
        name: &'static str,
        value: u64,
        bits: u32,
    },
}

impl Default for Params {
    /// [`Params::DEFAULT`].
    fn default() -> Self {
        Params::DEFAULT
    }
}

#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum ParamError {
    #[error("core.{field} = {value} is out of range; valid is {min}..={max}")]
    OutOfRange {
        field: &'static str,
        value: u64,
        min: u64,
        max: u64,
    },
    #[error("core.{field} must be longer than zero")]
    Zero { field: &'static str },
    #[error("core.min ({min} ticks) is above core.x ({max} ticks); the minimum interval must not exceed the maximum interval x")]
    MinAboveMax { min: u16, max: u16 },
    #[error("pw + pi is 0 ticks: the sample would be taken in the tick Vs2 rises, before the registered activation signal sr is 1, so no key-off sample would ever be taken; pw + pi must be at least 1 tick ([0321] waiting period)")]
    NoSettlingTick,
    #[error("the output window Wt = pw + pi + ps = {wt} ticks is not shorter than the shortest drive interval, {shortest} = {interval} ticks (core.min when adaptive, core.x when adaptive = false; here core.min = {min}, core.x = {max}); Vs2 must switch off between two pulses")]
    WindowTooLong {
        wt: u32,
        min: u16,
        max: u16,
        /// The interval the rule compares with: `core.min`, or `core.x` with the fixed interval.
        shortest: &'static str,
        interval: u16,
    },
}

impl Params {
    /// Output window Wt = Pw + Pi + Ps [0320], in ticks (17 bit: sum of three 16-bit fields).
    pub fn wt(&self) -> u32 {
        u32::from(self.pw) + u32::from(self.pi) + u32::from(self.ps)
    }

    /// The shortest interval the drive interval register can hold in this configuration.
    pub fn shortest_interval(&self) -> u16 {
        if self.adaptive {
            self.si_min
        } else {
            self.si_max
        }
    }

    /// Every rule a legal configuration obeys (docs/spec.md, "Legal parameter values").
    pub fn validate(&self) -> Result<(), ParamError> {
        let range = |field, value: u64, min: u64, max: u64| {
            if value < min || value > max {
                Err(ParamError::OutOfRange {
                    field,
                    value,
                    min,
                    max,
                })
            } else {
                Ok(())
            }
        };
        let values = self.hdl_parameters();
        for l in &LEGAL {
            let value = values.iter().find(|(n, _)| *n == l.hdl).map_or(0, |p| p.1);
            match l.rule {
                Rule::Range { min, max } => range(l.field, value, min, max)?,
                Rule::NotZero if value == 0 => return Err(ParamError::Zero { field: l.field }),
                Rule::NotZero | Rule::Any => {}
            }
        }
        if u32::from(self.pw) + u32::from(self.pi) == 0 {
            return Err(ParamError::NoSettlingTick);
        }
        if self.si_min > self.si_max {
            return Err(ParamError::MinAboveMax {
                min: self.si_min,
                max: self.si_max,
            });
        }
        if self.wt() >= u32::from(self.shortest_interval()) {
            return Err(ParamError::WindowTooLong {
                wt: self.wt(),
                min: self.si_min,
                max: self.si_max,
                shortest: if self.adaptive { "core.min" } else { "core.x" },
                interval: self.shortest_interval(),
            });
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn default_is_legal() {
        assert_eq!(Params::default().validate(), Ok(()));
    }

    #[test]
    fn each_rule_rejects() {
        let d = Params::default();
        let cases: Vec<(Params, &str)> = vec![
            (Params { sync_depth: 0, ..d }, "sync_depth"),
            (Params { sync_depth: 5, ..d }, "sync_depth"),
            (Params { cnt_width: 1, ..d }, "cnt_width"),
            (Params { cnt_width: 17, ..d }, "cnt_width"),
            (Params { cth: 0, ..d }, "cth"),
            (Params { ps: 0, ..d }, "ps"),
            (Params { t1: 0, ..d }, "t1"),
            (Params { t2: 0, ..d }, "t2"),
            (Params { si_min: 0, ..d }, "min"),
            (Params { smp_on: 0, ..d }, "smp_on"),
            (Params { si_min: 700, ..d }, "min"),
            (Params { pi: 300, ..d }, "Wt"),
            (Params { pw: 0, pi: 0, ..d }, "pw + pi"),
        ];
        for (p, word) in cases {
            let e = p.validate().unwrap_err();
            assert!(e.to_string().contains(word), "{word}: {e}");
        }
    }

    #[test]
    fn the_legal_table_names_every_parameter_once_and_holds_the_defaults() {
        let mut names: Vec<&str> = LEGAL.iter().map(|l| l.hdl).collect();
        names.sort_unstable();
        let mut want = HDL_NAMES.to_vec();
        want.sort_unstable();
        assert_eq!(names, want);
        for (k, name) in HDL_NAMES.iter().enumerate() {
            let l = LEGAL.iter().find(|l| l.hdl == *name).unwrap();
            let (min, max) = l.range();
            assert!(min <= HDL_DEFAULTS[k] && HDL_DEFAULTS[k] <= max, "{name}");
            assert!(max < 1 << HDL_BITS[k], "{name}: {max} beyond its register");
        }
    }

    #[test]
    fn a_value_outside_its_legal_range_is_refused_naming_its_field() {
        for l in &LEGAL {
            let (min, max) = l.range();
            let k = HDL_NAMES.iter().position(|n| *n == l.hdl).unwrap();
            let mut outside = vec![];
            if min > 0 {
                outside.push(min - 1);
            }
            if max + 1 < 1 << HDL_BITS[k] {
                outside.push(max + 1);
            }
            for v in outside {
                let mut p = Params::default();
                p.set_hdl_parameter(l.hdl, v).unwrap();
                let e = p.validate().unwrap_err();
                assert!(
                    e.to_string().contains(&format!("core.{} ", l.field)),
                    "{} = {v}: {e}",
                    l.hdl
                );
            }
        }
        // each bound of a range is itself legal
        let p = Params {
            sync_depth: 4,
            cnt_width: 2,
            cth: 255,
            pw: 0,
            ..Params::default()
        };
        assert_eq!(p.validate(), Ok(()));
    }

    #[test]
    fn hdl_parameters_set_back_by_name() {
        let p = Params {
            sync_depth: 3,
            cnt_width: 5,
            adaptive: false,
            pw: 1,
            pi: 2,
            ps: 3,
            si_max: 400,
            si_min: 300,
            t1: 7,
            t2: 8,
            cth: 9,
            smp_on: 11,
        };
        let mut q = Params::default();
        for (name, v) in p.hdl_parameters() {
            q.set_hdl_parameter(name, v).unwrap();
        }
        assert_eq!(q, p);
        assert_eq!(
            p.hdl_parameters().map(|(n, _)| n),
            [
                "SYNC_DEPTH",
                "CNT_W",
                "ADAPTIVE",
                "PW",
                "PI",
                "PS",
                "SI_MAX",
                "SI_MIN",
                "T1",
                "T2",
                "CTH",
                "SMP_ON"
            ]
        );
        let e = q.set_hdl_parameter("SI_MAXX", 1).unwrap_err().to_string();
        assert!(e.contains("`SI_MAXX`") && e.contains("SMP_ON"), "{e}");
        assert_eq!(
            q.set_hdl_parameter("CTH", 256),
            Err(HdlParamError::TooWide {
                name: "CTH",
                value: 256,
                bits: 8
            })
        );
        assert_eq!(
            q.set_hdl_parameter("ADAPTIVE", 2),
            Err(HdlParamError::TooWide {
                name: "ADAPTIVE",
                value: 2,
                bits: 1
            })
        );
        assert_eq!(q, p, "a refused value changes nothing");
    }

    #[test]
    fn window_rule_uses_x_when_not_adaptive() {
        let p = Params {
            adaptive: false,
            si_min: 10,
            pi: 100,
            ..Params::default()
        };
        // Wt = 110 < x = 660: legal even though Wt > min, because min is unused.
        assert_eq!(p.validate(), Ok(()));
        let p = Params {
            si_min: 10,
            pi: 100,
            ..Params::default()
        };
        let e = p.validate().unwrap_err();
        assert!(matches!(
            e,
            ParamError::WindowTooLong {
                shortest: "core.min",
                interval: 10,
                ..
            }
        ));
        // the message names the interval the rule used
        assert!(e.to_string().contains("core.min = 10 ticks"), "{e}");
        let p = Params {
            adaptive: false,
            si_max: 100,
            si_min: 10,
            pi: 100,
            ..Params::default()
        };
        let e = p.validate().unwrap_err();
        assert!(
            e.to_string().contains("interval, core.x = 100 ticks"),
            "{e}"
        );
    }
}
