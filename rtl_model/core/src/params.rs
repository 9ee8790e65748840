//! Parameter values of the core in ticks: the reset values of the programmable registers of
//! the register file (docs/spec.md, register map) plus two structural parameters (`sync_depth`,
//! `cnt_width`) that the HDL implements as Verilog `parameter`s.

/// Programmable parameters, all durations in clock ticks.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Params {
    /// Synchronizer depth of `ig` (structural, 1..=4).
    pub sync_depth: u8,
    /// Counter width in bits (structural, 2..=16).
    pub cnt_width: u8,
    /// Adaptive drive interval on (FIG. 17/18) or fixed cycle T = `si_max` (first embodiment).
    pub adaptive: bool,
    /// Waiting period Pw [0321], 16 bit.
    pub pw: u16,
    /// Idle period Pi [0322], 16 bit.
    pub pi: u16,
    /// Sampling period Ps [0322], 16 bit.
    pub ps: u16,
    /// Maximum interval x [0216], 16 bit.
    pub si_max: u16,
    /// Minimum interval [0228], 16 bit.
    pub si_min: u16,
    /// Shortening step T1 [0224], 16 bit.
    pub t1: u16,
    /// Expanding step T2 [0250], 16 bit.
    pub t2: u16,
    /// Count threshold Cth [0250], 8 bit.
    pub cth: u8,
    /// On-key sampling period [0349], 16 bit.
    pub smp_on: u16,
}

impl Default for Params {
    /// The patent's defaults at a 10 us clock (see [`crate::config::CoreConfig::default`]).
    fn default() -> Self {
        Params {
            sync_depth: 2,
            cnt_width: 16,
            adaptive: true,
            pw: 5,
            pi: 12,
            ps: 5,
            si_max: 660,
            si_min: 220,
            t1: 220,
            t2: 110,
            cth: 4,
            smp_on: 10,
        }
    }
}

#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum ParamError {
    #[error("core.{field} = {value} is out of range; valid is {min}..={max}")]
    OutOfRange { field: &'static str, value: u64, min: u64, max: u64 },
    #[error("core.{field} must be longer than zero")]
    Zero { field: &'static str },
    #[error("core.min ({min} ticks) is above core.x ({max} ticks); the minimum interval must not exceed the maximum interval x")]
    MinAboveMax { min: u16, max: u16 },
    #[error("pw + pi is 0 ticks: the sample would be taken in the tick Vs2 rises, before the registered activation signal sr is 1, so no key-off sample would ever be taken; pw + pi must be at least 1 tick ([0321] waiting period)")]
    NoSettlingTick,
    #[error("the output window Wt = pw + pi + ps = {wt} ticks is not shorter than the shortest drive interval core.min = {min} ticks (core.x = {max} ticks when adaptive = false); Vs2 must switch off between two pulses")]
    WindowTooLong { wt: u32, min: u16, max: u16 },
}

impl Params {
    /// Output window Wt = Pw + Pi + Ps [0320], in ticks (17 bit: sum of three 16-bit fields).
    pub fn wt(&self) -> u32 {
        u32::from(self.pw) + u32::from(self.pi) + u32::from(self.ps)
    }

    /// The shortest interval the drive interval register can hold in this configuration.
    pub fn shortest_interval(&self) -> u16 {
        if self.adaptive { self.si_min } else { self.si_max }
    }

    /// The Verilog parameters of the twin with their values, in the order of the `// param`
    /// lines of a vector file (docs/spec.md 6.2).
    pub fn hdl_parameters(&self) -> [(&'static str, u64); 12] {
        [
            ("SYNC_DEPTH", u64::from(self.sync_depth)),
            ("CNT_W", u64::from(self.cnt_width)),
            ("ADAPTIVE", u64::from(self.adaptive)),
            ("PW", u64::from(self.pw)),
            ("PI", u64::from(self.pi)),
            ("PS", u64::from(self.ps)),
            ("SI_MAX", u64::from(self.si_max)),
            ("SI_MIN", u64::from(self.si_min)),
            ("T1", u64::from(self.t1)),
            ("T2", u64::from(self.t2)),
            ("CTH", u64::from(self.cth)),
            ("SMP_ON", u64::from(self.smp_on)),
        ]
    }

    /// Every rule a legal configuration obeys (docs/spec.md, "Legal parameter values").
    pub fn validate(&self) -> Result<(), ParamError> {
        let range = |field, value: u64, min: u64, max: u64| {
            if value < min || value > max {
                Err(ParamError::OutOfRange { field, value, min, max })
            } else {
                Ok(())
            }
        };
        range("sync_depth", self.sync_depth.into(), 1, 4)?;
        range("cnt_width", self.cnt_width.into(), 2, 16)?;
        range("cth", self.cth.into(), 1, 255)?;
        for (field, v) in [
            ("ps", self.ps),
            ("x", self.si_max),
            ("min", self.si_min),
            ("t1", self.t1),
            ("t2", self.t2),
            ("smp_on", self.smp_on),
        ] {
            if v == 0 {
                return Err(ParamError::Zero { field });
            }
        }
        if u32::from(self.pw) + u32::from(self.pi) == 0 {
            return Err(ParamError::NoSettlingTick);
        }
        if self.si_min > self.si_max {
            return Err(ParamError::MinAboveMax { min: self.si_min, max: self.si_max });
        }
        if self.wt() >= u32::from(self.shortest_interval()) {
            return Err(ParamError::WindowTooLong { wt: self.wt(), min: self.si_min, max: self.si_max });
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
    fn window_rule_uses_x_when_not_adaptive() {
        let p = Params { adaptive: false, si_min: 10, pi: 100, ..Params::default() };
        // Wt = 110 < x = 660: legal even though Wt > min, because min is unused.
        assert_eq!(p.validate(), Ok(()));
        let p = Params { si_min: 10, pi: 100, ..Params::default() };
        assert!(matches!(p.validate(), Err(ParamError::WindowTooLong { .. })));
    }
}
