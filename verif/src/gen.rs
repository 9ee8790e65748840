//! The regression's stimulus generator: one scenario per seed, drawn from the corners of the
//! parameter space as well as its middle, and (with `--directed`) biased towards the coverage
//! bins that earlier seeds have not hit.
//!
//! A seed first draws a set of [`Knobs`] (which corners to visit: a narrow counter, a tight
//! minimum interval, fast rotation, Vs2 faults, key glitches, writes of a given register...),
//! then the scenario from the knobs. Uniform random draws every knob with its base probability;
//! directed draws, for each knob, the base probability or a high one when a bin that knob feeds
//! is still empty ([`Bias::from_missing`]). Both are pure functions of the seed and the bias, so
//! a seed range gives the same scenarios on any number of jobs or machines.
//!
//! The scenario is kept structured ([`Stimulus`]) so that a failing one can be shrunk (fewer
//! events, a shorter run) and written back as TOML.
//!
//! Build modes: with a pool of parameter sets ([`Bias::pooled`], `crate::param_pool`), a seed's
//! reset values, structure and clock are those of a set of the pool ([`ParamSet::pick`]), and a
//! seed whose knobs asked for register values writes what it drew at its first key-on.

use crate::rtl::Fixed;
use pmu50_core::Params;
use pmu50_testbench::random::Rng;
use pmu50_testbench::scenario_text::{EventText, ScenarioText, Segment};

/// The corners a seed may visit. Each is a yes/no decision of the seed.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Knob {
    NarrowCounter,
    Width3To7,
    Width8To15,
    Sync1,
    Sync3,
    Sync4,
    Fixed,
    CthOne,
    CthHigh,
    T1OneStep,
    T1Half,
    T2OneStep,
    T2Half,
    XEqualMin,
    XShort,
    XLong,
    MinTight,
    MinFar,
    PwZero,
    PiZero,
    PsOne,
    SmpOnOne,
    SmpOnShort,
    ClockFast,
    ClockSlow,
    FastMoves,
    Spin,
    LongQuiet,
    Faults,
    Glitches,
    KeyStorm,
    IllegalWrites,
    StatusWrites,
    EarlyWrites,
    ExactStep,
    /// Durations up to the 16-bit top of their registers (reset values and writes).
    LongDurations,
    /// Cth from 64 to 255 (reset value and writes).
    CthTop,
    /// The MPU reads bus addresses outside the register map.
    UnmappedReads,
    /// Port-level stimuli that the bench's MPU and analog front never make: raw bus writes to
    /// read-only and unmapped addresses (some in the tick the key turns on), words with high
    /// bits past a register's width (a CTH write of 0x01xx), and Vs2's power-good leaking high
    /// while the rail is off.
    PortLevel,
}

use Knob::*;

/// Every knob with its base probability in percent (uniform random).
pub const KNOBS: [(Knob, u64); 39] = [
    (NarrowCounter, 8),
    (Width3To7, 10),
    (Width8To15, 10),
    (Sync1, 15),
    (Sync3, 15),
    (Sync4, 15),
    (Fixed, 10),
    (CthOne, 10),
    (CthHigh, 10),
    (T1OneStep, 10),
    (T1Half, 15),
    (T2OneStep, 10),
    (T2Half, 15),
    (XEqualMin, 3),
    (XShort, 15),
    (XLong, 15),
    (MinTight, 5),
    (MinFar, 20),
    (PwZero, 5),
    (PiZero, 5),
    (PsOne, 10),
    (SmpOnOne, 3),
    (SmpOnShort, 20),
    (ClockFast, 3),
    (ClockSlow, 3),
    (FastMoves, 10),
    (Spin, 3),
    (LongQuiet, 3),
    (Faults, 20),
    (Glitches, 5),
    (KeyStorm, 8),
    (IllegalWrites, 20),
    (StatusWrites, 20),
    (EarlyWrites, 5),
    (ExactStep, 5),
    (LongDurations, 8),
    (CthTop, 8),
    (UnmappedReads, 8),
    (PortLevel, 6),
];

/// The knobs drawn from a stream of their own (`seed`, knob): adding one leaves the other
/// knobs, and so the scenarios of the seeds that do not draw it, as they were.
const OWN_STREAM: [Knob; 4] = [LongDurations, CthTop, UnmappedReads, PortLevel];

/// The stream of the corner draws of the [`OWN_STREAM`] knobs.
fn own_stream(seed: u64, what: u64) -> Rng {
    Rng::new(seed ^ 0x434f_524e_4552_5300 ^ what.wrapping_mul(0x9e37_79b9_7f4a_7c15))
}

/// The knob a coverage hint names (rtl_model/coverage/src/model.rs names knobs as the
/// variants of [`Knob`] are spelt).
pub fn knob_named(name: &str) -> Option<Knob> {
    KNOBS
        .iter()
        .map(|&(k, _)| k)
        .find(|k| format!("{k:?}") == name)
}

/// The knobs that make a coverage bin likely, by the bin's full name: the hint declared with
/// the bin in the coverage model (a cross: the knobs of both of its bins and the cross's own);
/// [`Knob::PortLevel`] for a bin only port-level stimuli reach. None for a bin that seeds hit
/// without a knob, that is declared unreachable, or that the model does not have.
pub fn knobs_for(bin: &str) -> Vec<Knob> {
    let Some(b) = pmu50_coverage::layout().bins.iter().find(|b| b.name == bin) else {
        return Vec::new();
    };
    if b.port_only && b.unreachable.is_none() {
        return vec![PortLevel];
    }
    let mut k: Vec<Knob> = b.aim.knobs().iter().filter_map(|n| knob_named(n)).collect();
    k.sort();
    k.dedup();
    k
}

/// The on-key sampling period of the skip-and-clear race (ticks).
const RACE_SMP_ON: u64 = 40;

/// How the knobs of a batch's seeds are drawn.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Bias {
    /// Every knob with its probability in percent.
    pub percent: Vec<(Knob, u64)>,
    /// Directed: the knob sets of the bins still empty (distinct, sorted); seed `s` of the
    /// batch forces set `s mod len` on top of its random draws.
    pub targets: Vec<Vec<Knob>>,
    /// Structural parameters held fixed (`--sync-depth`, `--cnt-width`), for an RTL built for
    /// one configuration.
    pub pins: Pins,
    /// Parameters the RTL under test fixes itself (its top lacks them): every seed keeps them.
    pub fixed: Fixed,
    /// The regression's pool of parameter sets (`--param-sets`): every seed takes its reset
    /// values, structure and clock from one of them ([`ParamSet::pick`]). Empty: each seed
    /// draws its own.
    pub pool: Vec<ParamSet>,
}

/// The Verilog parameters a knob draws (or sets): a knob is not drawn when the RTL under test
/// fixes one of them (docs/hdl-guide.md, "Your RTL").
pub fn knob_params(k: Knob) -> &'static [&'static str] {
    match k {
        NarrowCounter | Width3To7 | Width8To15 => &["CNT_W"],
        Sync1 | Sync3 | Sync4 => &["SYNC_DEPTH"],
        Fixed => &["ADAPTIVE"],
        CthOne | CthHigh => &["CTH"],
        T1OneStep | T1Half => &["T1"],
        T2OneStep | T2Half => &["T2"],
        XEqualMin | XShort | XLong => &["SI_MAX"],
        MinTight | MinFar => &["SI_MIN"],
        PwZero => &["PW"],
        PiZero => &["PI"],
        PsOne => &["PS"],
        SmpOnOne | SmpOnShort | Spin => &["SMP_ON"],
        LongDurations => &[
            "PW", "PI", "PS", "SI_MAX", "SI_MIN", "T1", "T2", "SMP_ON", "ADAPTIVE",
        ],
        CthTop => &["CTH"],
        ExactStep => &["SI_MAX", "T1", "T2"],
        LongQuiet => &["CTH", "T1", "T2"],
        _ => &[],
    }
}

/// The knobs a regression does not draw because the RTL fixes a parameter they need.
pub fn knobs_off(fixed: &Fixed) -> Vec<Knob> {
    KNOBS
        .iter()
        .map(|&(k, _)| k)
        .filter(|&k| knob_params(k).iter().any(|n| fixed.get(n).is_some()))
        .collect()
}

/// Structural parameters a regression holds fixed.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct Pins {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sync_depth: Option<u8>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cnt_width: Option<u8>,
}

/// The length of a long quiet run that does not saturate CNTr at the minimum: at the top of the
/// 16-bit range (`past_16_bits`), or climbing to x in T2 = 1 steps.
fn quiet_ticks(p: &Params, past_16_bits: bool) -> u64 {
    let (x, min) = (u64::from(p.si_max), u64::from(p.si_min));
    if past_16_bits {
        3 * x + (u64::from(p.cth) + 2) * min + u64::from(p.wt())
    } else {
        2 * x + (x.saturating_sub(min) + 2) * x
    }
}

/// What a stimulus that starts from reset needs of the reset values: the long quiet runs and the
/// long durations have the key off from the first tick (no write can set a register before
/// them), and the skip-and-clear race counts its samples from reset. A regression's pool holds a
/// set of each shape any of its seeds could want (`crate::param_pool`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Shape {
    /// CNTr saturated at the minimum interval: Cth = 255, adaptive, x above min.
    QuietSat,
    /// The interval at the top of the 16-bit range: x just below 65535, T1 = 65535, min + T2
    /// past 65535, Cth <= 4, adaptive.
    Quiet16,
    /// The interval climbing to x in T2 = 1 steps past Cth <= 4, after one rotation that takes
    /// it from x to min (adaptive, T1 > x - min), over a span of 300 ticks or more, so that
    /// CNTr passes its 8-bit saturation on the way.
    QuietT2,
    /// Long durations, the window of 40000 ticks or more (min >= 40000).
    LongWindow,
    /// Long durations, x of 40000 or more above a short min.
    LongSpan,
    /// The skip-and-clear race: smp_on = 40 from reset.
    Race,
}

impl Shape {
    pub const ALL: [Shape; 6] = [
        Shape::QuietSat,
        Shape::Quiet16,
        Shape::QuietT2,
        Shape::LongWindow,
        Shape::LongSpan,
        Shape::Race,
    ];

    /// Whether the reset values `p` have this shape.
    pub fn holds(self, p: &Params) -> bool {
        let (x, min) = (u64::from(p.si_max), u64::from(p.si_min));
        match self {
            Shape::QuietSat => p.cth == 255 && p.adaptive && x > min,
            Shape::Quiet16 => {
                p.adaptive
                    && x >= 65_034
                    && p.t1 == u16::MAX
                    && min + u64::from(p.t2) > 65_535
                    && p.cth <= 4
            }
            Shape::QuietT2 => {
                p.adaptive && p.t2 == 1 && p.cth <= 4 && x >= min + 300 && u64::from(p.t1) > x - min
            }
            Shape::LongWindow => min >= 40_000,
            Shape::LongSpan => x >= 40_000 && min < 40_000,
            Shape::Race => u64::from(p.smp_on) == RACE_SMP_ON,
        }
    }
}

/// One parameter set of a regression's pool: the reset values and structure (one build of the
/// RTL) and the clock period of the seeds that draw it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct ParamSet {
    pub params: Params,
    pub clock_us: u64,
}

impl ParamSet {
    /// The indices of the configuration bins (`config.*`) this set hits from reset.
    pub fn config_bins(&self) -> Vec<usize> {
        let cov = pmu50_coverage::Coverage::new(&self.params, self.clock_us * 1000);
        config_indices()
            .iter()
            .copied()
            .filter(|&i| cov.hits()[i] > 0)
            .collect()
    }

    /// The shapes of [`Shape::ALL`] it has.
    pub fn shapes(&self) -> Vec<Shape> {
        Shape::ALL
            .into_iter()
            .filter(|s| s.holds(&self.params))
            .collect()
    }

    /// One line: `SYNC_DEPTH=2 CNT_W=16 ... clock 10 us`.
    pub fn text(&self) -> String {
        let mut t: Vec<String> = self
            .params
            .hdl_parameters()
            .iter()
            .map(|(n, v)| format!("{n}={v}"))
            .collect();
        t.push(format!("clock {} us", self.clock_us));
        t.join(" ")
    }

    /// The set of `pool` a seed draws: one with the shape its stimulus needs from reset (when
    /// one has it), then the one that has most of the configuration bins its knobs asked for;
    /// between sets that tie, one chosen by the seed, so the seeds spread over the pool.
    pub fn pick<'a>(
        pool: &'a [ParamSet],
        seed: u64,
        want: &Params,
        clock_us: u64,
        knobs: &[Knob],
        shape: Option<Shape>,
    ) -> &'a ParamSet {
        let l = pmu50_coverage::layout();
        let wanted = ParamSet {
            params: *want,
            clock_us,
        };
        // the configuration bins the seed's knobs asked for
        let asked: Vec<usize> = wanted
            .config_bins()
            .into_iter()
            .filter(|&i| {
                l.bins[i]
                    .aim
                    .knobs()
                    .iter()
                    .any(|n| knob_named(n).is_some_and(|k| knobs.contains(&k)))
            })
            .collect();
        let score = |s: &ParamSet| -> u64 {
            let bins = s.config_bins();
            let shaped = shape.is_some_and(|h| h.holds(&s.params));
            u64::from(shaped) * 1000 + asked.iter().filter(|i| bins.contains(i)).count() as u64
        };
        let scores: Vec<u64> = pool.iter().map(score).collect();
        let best = scores.iter().copied().max().unwrap_or(0);
        let ties: Vec<&ParamSet> = pool
            .iter()
            .zip(&scores)
            .filter(|(_, &sc)| sc == best)
            .map(|(s, _)| s)
            .collect();
        let mut r = Rng::new(seed ^ 0x504f_4f4c_5345_5400);
        ties[r.range(0, ties.len() as u64 - 1) as usize]
    }
}

/// The indices (in the model's order) of the bins of the configuration points.
pub fn config_indices() -> &'static [usize] {
    static IDX: std::sync::OnceLock<Vec<usize>> = std::sync::OnceLock::new();
    IDX.get_or_init(|| {
        use pmu50_coverage::model::{Sampled, POINTS};
        let l = pmu50_coverage::layout();
        POINTS
            .iter()
            .enumerate()
            .filter(|(_, p)| p.sampled == Sampled::Config)
            .flat_map(|(k, p)| (0..p.bins.len()).map(move |b| l.point_offset[k] + b))
            .collect()
    })
}

impl serde::Serialize for ParamSet {
    /// `{"SYNC_DEPTH": 2, ..., "SMP_ON": 10, "clock_us": 10}`.
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeMap;
        let mut m = s.serialize_map(None)?;
        for (n, v) in self.params.hdl_parameters() {
            m.serialize_entry(n, &v)?;
        }
        m.serialize_entry("clock_us", &self.clock_us)?;
        m.end()
    }
}

impl<'de> serde::Deserialize<'de> for ParamSet {
    /// Every parameter of the table and `clock_us`, a legal set; another field, a missing one or
    /// an illegal set is refused with the reason.
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        use serde::de::Error;
        let m = std::collections::BTreeMap::<String, u64>::deserialize(d)?;
        let mut p = Params::default();
        let mut clock_us = None;
        for (k, v) in &m {
            if k == "clock_us" {
                clock_us = Some(*v);
            } else {
                p.set_hdl_parameter(k, *v)
                    .map_err(|e| D::Error::custom(format!("a parameter set: {e}")))?;
            }
        }
        for n in pmu50_core::params::HDL_NAMES {
            if !m.contains_key(*n) {
                return Err(D::Error::custom(format!("a parameter set lacks `{n}`")));
            }
        }
        let clock_us = clock_us
            .filter(|c| (1..=1_000_000).contains(c))
            .ok_or_else(|| D::Error::custom("a parameter set needs `clock_us` in 1..=1000000"))?;
        p.validate()
            .map_err(|e| D::Error::custom(format!("a parameter set is illegal: {e}")))?;
        Ok(ParamSet {
            params: p,
            clock_us,
        })
    }
}

impl Bias {
    /// Uniform random: every knob at its base probability.
    pub fn uniform() -> Bias {
        Bias {
            percent: KNOBS.to_vec(),
            targets: Vec::new(),
            pins: Pins::default(),
            fixed: Fixed::default(),
            pool: Vec::new(),
        }
    }

    /// Directed, from the coverage so far (hits in the model's order): every bin still empty
    /// that can be hit.
    pub fn directed(hits: &[u64], pins: Pins) -> Bias {
        let l = pmu50_coverage::layout();
        Bias::from_missing(
            l.bins
                .iter()
                .zip(hits)
                .filter(|(b, h)| **h == 0 && b.unreachable.is_none())
                .map(|(b, _)| b.name.as_str()),
        )
        .pinned(pins)
    }

    /// The same bias with these structural parameters held.
    pub fn pinned(self, pins: Pins) -> Bias {
        Bias { pins, ..self }
    }

    /// The same bias drawing every seed's parameters from `pool` (empty: each seed its own).
    pub fn pooled(self, pool: &[ParamSet]) -> Bias {
        Bias {
            pool: pool.to_vec(),
            ..self
        }
    }

    /// The same bias for an RTL that fixes these parameters: the knobs that need one of them
    /// are not drawn, and every seed keeps the values.
    pub fn fixing(self, fixed: &Fixed) -> Bias {
        if fixed.is_empty() {
            return self;
        }
        let off = knobs_off(fixed);
        let percent = self
            .percent
            .into_iter()
            .filter(|(k, _)| !off.contains(k))
            .collect();
        let mut targets: Vec<Vec<Knob>> = self
            .targets
            .into_iter()
            .filter(|t| !t.iter().any(|k| off.contains(k)))
            .collect();
        targets.dedup();
        Bias {
            percent,
            targets,
            pins: self.pins,
            fixed: fixed.clone(),
            pool: self.pool,
        }
    }

    /// Directed: each seed aims at one hole (a set of knobs that makes an empty bin likely).
    pub fn from_missing<'a>(missing: impl IntoIterator<Item = &'a str>) -> Bias {
        let mut sets: Vec<Vec<Knob>> = missing
            .into_iter()
            .map(knobs_for)
            .filter(|k| !k.is_empty())
            .collect();
        sets.sort();
        sets.dedup();
        Bias {
            percent: KNOBS.to_vec(),
            targets: sets,
            pins: Pins::default(),
            fixed: Fixed::default(),
            pool: Vec::new(),
        }
    }

    fn draw(&self, r: &mut Rng, seed: u64) -> Vec<Knob> {
        let mut k: Vec<Knob> = self
            .percent
            .iter()
            .filter(|&&(k, p)| {
                if let Some(i) = OWN_STREAM.iter().position(|&o| o == k) {
                    own_stream(seed, i as u64).percent(p)
                } else {
                    r.percent(p)
                }
            })
            .map(|&(k, _)| k)
            .collect();
        if !self.targets.is_empty() {
            k.extend(
                self.targets[(seed % self.targets.len() as u64) as usize]
                    .iter()
                    .copied(),
            );
            k.sort();
            k.dedup();
        }
        k
    }
}

/// A segment of the motor profile, in ticks and millidegrees.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Motion {
    Hold { ticks: u64 },
    Move { ticks: u64, milli_deg: i64 },
}

impl Motion {
    pub fn ticks(&self) -> u64 {
        match *self {
            Motion::Hold { ticks } | Motion::Move { ticks, .. } => ticks,
        }
    }
}

/// One timeline event.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Action {
    Ig(bool),
    Fault(bool),
    Write {
        reg: &'static str,
        value: u16,
    },
    /// A read of any bus address (the MPU's poll is replaced for the tick).
    Read {
        addr: u8,
    },
    /// A raw bus write: any address, any 16-bit word (port level).
    BusWrite {
        addr: u8,
        data: u16,
    },
    /// Vs2's power-good leaks high while the rail is off (port level).
    PgLeak(bool),
}

/// A generated scenario, structured.
#[derive(Clone, Debug, PartialEq)]
pub struct Stimulus {
    pub seed: u64,
    pub knobs: Vec<Knob>,
    pub params: Params,
    pub clock_us: u64,
    /// Comparator threshold errors, per mille of the amplitude.
    pub vr_err: (i64, i64),
    /// Start angle, tenths of a degree.
    pub start_decideg: u64,
    pub motion: Vec<Motion>,
    pub events: Vec<(u64, Action)>,
    pub ticks: u64,
}

const WRITABLE: [&str; 11] = [
    "CTRL", "PW", "PI", "PS", "SI_MAX", "SI_MIN", "T1", "T2", "CTH", "SMP_ON", "STATUS",
];

/// Draw the parameters from the knobs; always legal.
fn params(r: &mut Rng, k: &[Knob], fixed: &Fixed) -> Params {
    let on = |x: Knob| k.contains(&x);
    // With parameters fixed by the RTL, a draw whose other values do not fit them is drawn
    // again; after 64 draws, the other values come from the defaults.
    let mut tries = 0;
    loop {
        let pw = if on(PwZero) { 0 } else { r.range(1, 8) as u16 };
        let pi = if on(PiZero) && pw > 0 {
            0
        } else {
            r.range(u64::from(pw == 0), 15) as u16
        };
        let ps = if on(PsOne) { 1 } else { r.range(2, 8) as u16 };
        let wt = u64::from(pw) + u64::from(pi) + u64::from(ps);
        let si_min = if on(MinTight) {
            wt + 1
        } else if on(MinFar) {
            r.range(2 * wt + 1, 2 * wt + 400)
        } else {
            r.range(wt + 2, (2 * wt).max(wt + 2))
        };
        let span = if on(XEqualMin) {
            0
        } else if on(XShort) {
            r.range(1, 300u64.saturating_sub(si_min).max(1))
        } else if on(XLong) {
            r.range(701u64.saturating_sub(si_min).max(1), 1200)
        } else {
            r.range(1, 700)
        };
        let si_max = si_min + span;
        let step = |r: &mut Rng, one: bool, half: bool| -> u64 {
            if one {
                r.range(span.max(1), span.max(1) + 50)
            } else if half && span >= 2 {
                r.range(span.div_ceil(2), span - 1).max(1)
            } else {
                r.range(1, (span / 2).saturating_sub(1).max(1))
            }
        };
        let (mut t1, mut t2) = (
            step(r, on(T1OneStep), on(T1Half)),
            step(r, on(T2OneStep), on(T2Half)),
        );
        let mut si_max = si_max;
        if on(ExactStep) && !on(XEqualMin) {
            // the span a whole number of T1 and of T2 steps, so S6 lands exactly on min and S10
            // exactly on x: span = 12 u, T = span / k with k = 1 (one step), 2 (half) or 3, 4
            let u = r.range(1, 60);
            let k = |r: &mut Rng, one: bool, half: bool| {
                if one {
                    1
                } else if half {
                    2
                } else {
                    r.range(3, 4)
                }
            };
            si_max = si_min + 12 * u;
            t1 = 12 * u / k(r, on(T1OneStep), on(T1Half));
            t2 = 12 * u / k(r, on(T2OneStep), on(T2Half));
        }
        let p = Params {
            sync_depth: if on(Sync1) {
                1
            } else if on(Sync4) {
                4
            } else if on(Sync3) {
                3
            } else {
                2
            },
            cnt_width: if on(NarrowCounter) {
                2
            } else if on(Width3To7) {
                r.range(3, 7) as u8
            } else if on(Width8To15) {
                r.range(8, 15) as u8
            } else {
                16
            },
            adaptive: !on(Fixed),
            pw,
            pi,
            ps,
            si_max: si_max.min(u64::from(u16::MAX)) as u16,
            si_min: si_min as u16,
            t1: t1.min(65535) as u16,
            t2: t2.min(65535) as u16,
            cth: if on(CthOne) {
                1
            } else if on(CthHigh) {
                r.range(9, 40) as u8
            } else {
                r.range(2, 8) as u8
            },
            smp_on: if on(SmpOnOne) {
                1
            } else if on(SmpOnShort) {
                r.range(2, 9) as u16
            } else {
                r.range(10, 30) as u16
            },
        };
        let p = fixed.apply(&p);
        if p.validate().is_ok() {
            return p;
        }
        tries += 1;
        if !fixed.is_empty() && tries >= 64 {
            return fixed.apply(&Params::default());
        }
    }
}

impl Stimulus {
    /// The scenario of `seed` under `bias`.
    pub fn generate(seed: u64, bias: &Bias) -> Stimulus {
        let mut r = Rng::new(seed ^ 0x5245_4752_4553_5300);
        let knobs = bias.draw(&mut r, seed);
        let on = |x: Knob| knobs.contains(&x);
        let mut p = params(&mut r, &knobs, &bias.fixed);
        // held structural parameters (they do not take part in legality)
        p.sync_depth = bias.pins.sync_depth.unwrap_or(p.sync_depth);
        p.cnt_width = bias.pins.cnt_width.unwrap_or(p.cnt_width);
        let mut clock_us = if on(ClockFast) {
            5
        } else if on(ClockSlow) {
            20
        } else {
            10
        };
        let mut ticks = r.range(20_000, 60_000);
        // CNTr up to its saturation ([0248]): after a rotation, quiet pulses with the key off,
        // either at the minimum interval with Cth = 255 (S9 holds si), or climbing to x in T2 = 1
        // steps (S10 each pulse past Cth).
        let mut saturate_at_min = on(LongQuiet) && r.percent(50);
        // Or at the top of the 16-bit range (docs/spec.md 2.6): x just below 65535, T1 = 65535
        // so that S6's si - T1 saturates at 0 before its clamp to min, and T2 so large that
        // S10's si + T2 from min passes 65535 before its clamp to x.
        let mut past_16_bits = on(LongQuiet)
            && !saturate_at_min
            && ["SI_MAX", "SI_MIN", "ADAPTIVE"]
                .iter()
                .all(|n| bias.fixed.get(n).is_none())
            && r.percent(70);
        if on(LongQuiet) {
            if saturate_at_min {
                p.cth = 255;
            } else if past_16_bits {
                p.adaptive = true;
                p.si_max = (65_534 - r.range(0, 500)) as u16;
                p.si_min = r.range(20_000, 40_000).max(u64::from(p.wt()) + 1) as u16;
                p.t2 = (65_536 - u64::from(p.si_min) + r.range(0, 1_000)).min(65_535) as u16;
                p.cth = p.cth.min(4);
                ticks = quiet_ticks(&p, true);
            } else {
                p.t2 = 1;
                p.cth = p.cth.min(4);
                ticks = quiet_ticks(&p, false);
            }
            // one rotation takes si from x to min
            p.t1 = if past_16_bits {
                u16::MAX
            } else {
                p.si_max - p.si_min + 1
            };
        }
        // A counter wraps at its width ([0096]-[0099], docs/spec.md 2.5): the key on, sampling
        // every tick (smp_on = 1), the shaft spinning one way at 20 deg a tick.
        if on(Spin) {
            p.smp_on = 1;
            ticks = (1u64 << p.cnt_width) * 9 + 2_000;
        }
        // The corners of the register ranges (docs/spec.md 4: every duration up to 65535 ticks,
        // Cth up to 255), drawn from streams of their own. Long durations: the key off from
        // reset for longer than x, so the timing generator counts past 32768 to x, then the usual
        // timeline with writes over each register's whole legal range.
        let long = on(LongDurations) && !on(Spin) && !on(LongQuiet);
        let mut first_off = 0;
        if long {
            let mut c = own_stream(seed, 16);
            long_durations(&mut c, &mut p);
            let x = u64::from(p.si_max);
            first_off = c.range(x + 100, x + 20_000);
            ticks = first_off + c.range(50_000, 150_000);
        }
        if on(CthTop) && !on(LongQuiet) {
            p.cth = own_stream(seed, 17).range(64, 255) as u8;
        }
        // A seed that races a skip against its W1C (below) wants its on-key period from reset.
        let race_knobs = !on(Spin) && !on(LongQuiet) && !long && on(StatusWrites) && on(FastMoves);
        let mut spin_write = None;
        // What a seed whose knobs asked for register values writes at its first key-on, when
        // its set of the pool has others.
        let mut config_to: Option<Params> = None;
        if !bias.pool.is_empty() {
            let drawn = p;
            // Build modes: the reset values, structure and clock come from the regression's pool,
            // the set nearest to what the knobs drew; the modes that need values from reset
            // follow the set, and a spin writes its sampling period at run time.
            let want = if on(LongQuiet) {
                Some(if saturate_at_min {
                    Shape::QuietSat
                } else if past_16_bits {
                    Shape::Quiet16
                } else {
                    Shape::QuietT2
                })
            } else if long {
                Some(if Shape::LongWindow.holds(&p) {
                    Shape::LongWindow
                } else {
                    Shape::LongSpan
                })
            } else if race_knobs {
                Some(Shape::Race)
            } else {
                None
            };
            let set = ParamSet::pick(&bias.pool, seed, &p, clock_us, &knobs, want);
            p = set.params;
            clock_us = set.clock_us;
            let asks = knobs.iter().any(|&k| {
                knob_params(k)
                    .iter()
                    .any(|n| !matches!(*n, "CNT_W" | "SYNC_DEPTH"))
            });
            let drawn = Params {
                sync_depth: p.sync_depth,
                cnt_width: p.cnt_width,
                ..drawn
            };
            if asks && want.is_none() && drawn != p && drawn.validate().is_ok() {
                config_to = Some(drawn);
            }
            if on(LongQuiet) {
                saturate_at_min = Shape::QuietSat.holds(&p);
                past_16_bits = !saturate_at_min && Shape::Quiet16.holds(&p);
                if !saturate_at_min {
                    ticks = quiet_ticks(&p, past_16_bits);
                }
            }
            if on(Spin) {
                ticks = (1u64 << p.cnt_width) * 9 + 2_000;
                if p.smp_on != 1 {
                    spin_write = Some(u64::from(p.sync_depth) + 1);
                }
            }
            if long {
                let mut c = own_stream(seed, 18);
                let x = u64::from(p.si_max);
                first_off = c.range(x + 100, x + 20_000);
                ticks = first_off + c.range(50_000, 150_000);
            }
        }
        let vr_err = (r.range(0, 200) as i64 - 100, r.range(0, 200) as i64 - 100);
        let mut start_decideg = r.range(0, 3599);
        // A skip and the MPU's W1C of STATUS.quadrant_skip on the same edge (docs/spec.md 2.5:
        // the set wins), then a write of bit 4 alone while the flag is set (no effect) and a
        // W1C of bit 5 while it is set: the key on from reset, on-key samples every
        // RACE_SMP_ON ticks from the edge where sig rises (edge SYNC_DEPTH), the shaft half a
        // turn between the first two of them, from the middle of a quadrant.
        let race = race_knobs
            && if bias.pool.is_empty() {
                bias.fixed.get("SMP_ON").is_none()
            } else {
                Shape::Race.holds(&p)
            }
            && r.percent(50);
        let mut race_events = Vec::new();
        let mut race_end = 0;
        if race {
            const S: u64 = RACE_SMP_ON;
            p.smp_on = S as u16;
            start_decideg = 450 + 900 * (start_decideg % 4);
            let d = u64::from(p.sync_depth);
            // samples at the edges d + n S; an event at tick t is the input of edge t + 1
            for (t, value) in [
                (d + 2 * S - 1, 1 << 5),
                (d + 2 * S + 5, 1 << 4),
                (d + 3 * S + 5, 1 << 5),
            ] {
                let reg = "STATUS";
                race_events.push((t, Action::Write { reg, value }));
            }
            race_end = d + 3 * S + 10;
        }

        // Motor: holds and moves; fast moves skip quadrants.
        let mut motion = Vec::new();
        if on(Spin) {
            let dir = if r.percent(50) { 1 } else { -1 };
            motion.push(Motion::Move {
                ticks,
                milli_deg: dir * 20_000 * ticks as i64,
            });
        } else if on(LongQuiet) {
            // From reset with the key off, samples are taken at the edges wt-1, x+wt-1, 2x+wt-1,
            // ...: the shaft turns a quadrant (mid to mid) between the second and third, so the
            // third detects it (S6 to min, cnt_r := 0) at edge p0; then samples follow every min
            // ticks. With Cth = 255, S9 counts cnt_r to 255 at the 255th quiet sample, and a
            // second quadrant between the 255th and 256th makes the 256th an S5 at min with cnt_r
            // saturated; with T2 = 1 the interval climbs to x after saturation, then turns.
            let dir = if r.percent(50) { 1 } else { -1 };
            let (x, min, wt) = (u64::from(p.si_max), u64::from(p.si_min), u64::from(p.wt()));
            let p0 = 2 * x + wt - 1;
            let second = if saturate_at_min {
                p0 + 255 * min + min / 4
            } else {
                ticks.max(p0 + 2 * x)
            };
            let first_move = (x / 2).max(1);
            let second_move = (min / 2).max(1);
            motion.push(Motion::Hold { ticks: x + wt });
            motion.push(Motion::Move {
                ticks: first_move,
                milli_deg: dir * 90_000,
            });
            motion.push(Motion::Hold {
                ticks: second - (x + wt + first_move),
            });
            motion.push(Motion::Move {
                ticks: second_move,
                milli_deg: dir * 90_000,
            });
            motion.push(Motion::Hold {
                ticks: 2 * min.max(x),
            });
            ticks = motion.iter().map(Motion::ticks).sum();
        } else {
            let mut t = 0;
            if race {
                // still through the first sample, half a turn, still through the second
                let d = u64::from(p.sync_depth);
                let dir = if start_decideg % 1800 < 900 { 1 } else { -1 };
                motion.push(Motion::Hold {
                    ticks: d + RACE_SMP_ON + 2,
                });
                motion.push(Motion::Move {
                    ticks: RACE_SMP_ON / 2,
                    milli_deg: dir * 180_000,
                });
                t = d + RACE_SMP_ON + 2 + RACE_SMP_ON / 2;
                motion.push(Motion::Hold {
                    ticks: race_end - t,
                });
                t = race_end;
            }
            while t < ticks {
                let d = r.range(100, 8_000).min(ticks - t);
                let m = if r.percent(40) {
                    Motion::Hold { ticks: d }
                } else {
                    let fast = on(FastMoves) && r.percent(60) || r.percent(5);
                    let max = if fast { 600 } else { 50 };
                    Motion::Move {
                        ticks: d,
                        milli_deg: (r.range(0, 2000) as i64 - 1000) * max * d as i64 / 1000,
                    }
                };
                motion.push(m);
                t += d;
            }
        }

        // Timeline.
        let mut events = Vec::new();
        let mut ig = if on(Spin) || race {
            true
        } else if on(LongQuiet) || long {
            false
        } else {
            r.percent(50)
        };
        events.push((0, Action::Ig(ig)));
        if let Some(at) = spin_write {
            // the set's sampling period from reset: every tick from the edge after sig rises
            events.push((
                at,
                Action::Write {
                    reg: "SMP_ON",
                    value: 1,
                },
            ));
        }
        if on(Spin) || on(LongQuiet) {
            // nothing else: the key and the parameters hold for the whole run
            // the middle of a quadrant, so that each quarter turn crosses exactly one boundary
            let start_decideg = if on(LongQuiet) {
                450 + 900 * r.range(0, 3)
            } else {
                r.range(0, 3599)
            };
            return Stimulus {
                seed,
                knobs,
                params: p,
                clock_us,
                vr_err: (0, 0),
                start_decideg,
                motion,
                events,
                ticks,
            };
        }
        let gap = if on(KeyStorm) {
            (20, 800)
        } else {
            (50, 15_000)
        };
        let mut at = race_end.max(first_off);
        // The register values in force as the timeline goes (for writes over the legal range).
        let mut cur = p;
        // The values the writes are drawn against: the reset values, or those of the seed's
        // first key-on writes.
        let mut live = p;
        if let Some(to) = config_to.filter(|_| ig) {
            config_to = None;
            let (w, end, after) = config_writes(&p, &to, u64::from(p.sync_depth) + 2);
            events.extend(w);
            (cur, live) = (after, to);
            at = at.max(end);
        }
        if long {
            // the key on after the long key-off stretch, then, once sig is up, a sweep of writes
            // that raises and lowers every bit of every duration register and of Cth
            events.push((at, Action::Ig(true)));
            ig = true;
            at += u64::from(p.sync_depth) + 2;
            for (reg, value) in SWEEP {
                events.push((at, Action::Write { reg, value }));
                written(&mut cur, reg, value);
                at += 1;
            }
        }
        events.extend(race_events);
        let mut port = own_stream(seed, 19);
        let mut fault = false;
        if !race && on(Faults) && r.percent(25) {
            // a dead Vs2 rail from power-on: the first strobes find Sr = 0, so the first sample
            // (the counters' preset, docs/spec.md 2.4-2.5) comes later
            fault = true;
            events.push((0, Action::Fault(true)));
        }
        loop {
            at += r.range(gap.0, gap.1);
            if at >= ticks.saturating_sub(2) {
                break;
            }
            if on(UnmappedReads) && ig && r.percent(25) {
                // the MPU reads addresses outside the register map, one to three ticks in a row
                // (the register file's read mux default; bus_addr bits 7:5 rise and fall)
                for i in 0..r.range(1, 3) {
                    let addr = unmapped_addr(&mut r);
                    events.push((at + i, Action::Read { addr }));
                }
                at += 3;
                continue;
            }
            if on(PortLevel) && port.percent(30) {
                // what only a port-level bench does (own stream: the other draws stay)
                at += port_level(&mut port, at, ticks.saturating_sub(2), &mut ig, &mut events);
                continue;
            }
            let roll = r.range(0, 9);
            if on(Glitches) && r.percent(30) {
                // a pulse of ig shorter than the synchronizer
                let len = r.range(1, 2);
                events.push((at, Action::Ig(!ig)));
                events.push((at + len, Action::Ig(ig)));
                // A low pulse passes the synchronizer: sig falls at edge at + SYNC_DEPTH and
                // rises one edge per tick of the pulse later. With ig back on before that edge,
                // a write there is taken on the key-off edge, and an SI_MAX written there is the
                // x that si starts the key-off period with (docs/spec.md 2.6, si_max_nxt).
                let d = u64::from(p.sync_depth);
                if ig && len < d && r.percent(50) {
                    let value = write_value(&mut r, "SI_MAX", &live, false);
                    events.push((
                        at + d - 1,
                        Action::Write {
                            reg: "SI_MAX",
                            value,
                        },
                    ));
                }
                at += 3;
                continue;
            }
            match roll {
                0..=4 => {
                    ig = !ig;
                    events.push((at, Action::Ig(ig)));
                    if ig && on(EarlyWrites) && r.percent(50) {
                        // a write in the tick the key turns on: sig is still 0 ([0205])
                        let reg = WRITABLE[r.range(0, WRITABLE.len() as u64 - 1) as usize];
                        let value = write_value(&mut r, reg, &live, false);
                        events.push((at, Action::Write { reg, value }));
                    }
                    if let Some(to) = config_to.filter(|_| ig) {
                        config_to = None;
                        let from_at = at + u64::from(p.sync_depth) + 2;
                        let (w, end, after) = config_writes(&cur, &to, from_at);
                        events.extend(w);
                        (cur, live) = (after, to);
                        at = end;
                    }
                }
                5 if on(Faults) || r.percent(30) => {
                    fault = !fault;
                    events.push((at, Action::Fault(fault)));
                }
                _ if ig => {
                    let reg = if on(StatusWrites) && r.percent(40) {
                        "STATUS"
                    } else if on(CthTop) && r.percent(25) {
                        "CTH"
                    } else {
                        WRITABLE[r.range(0, WRITABLE.len() as u64 - 2) as usize]
                    };
                    let wide = (long || on(CthTop) && reg == "CTH") && r.percent(80);
                    let value = match wide.then(|| wide_value(&mut r, reg, &cur, on(IllegalWrites)))
                    {
                        Some(Some(v)) => v,
                        _ => write_value(&mut r, reg, &live, on(IllegalWrites)),
                    };
                    written(&mut cur, reg, value);
                    events.push((at, Action::Write { reg, value }));
                }
                _ => {}
            }
        }
        // One event of a kind per tick: a bus access (a write or a read) shares its tick only
        // with ig.
        let bus = |a: &Action| {
            matches!(
                a,
                Action::Write { .. } | Action::Read { .. } | Action::BusWrite { .. }
            )
        };
        events.sort_by_key(|(t, a)| (*t, bus(a)));
        events.dedup_by(|b, a| {
            a.0 == b.0
                && (std::mem::discriminant(&a.1) == std::mem::discriminant(&b.1)
                    || bus(&a.1) && bus(&b.1))
        });
        Stimulus {
            seed,
            knobs,
            params: p,
            clock_us,
            vr_err,
            start_decideg,
            motion,
            events,
            ticks,
        }
    }

    /// The scenario as TOML (what `pmu50 run` reads).
    pub fn to_toml(&self, name: &str) -> String {
        let knobs: Vec<String> = self.knobs.iter().map(|k| format!("{k:?}")).collect();
        let mut t = ScenarioText::new(
            &format!(
                "pmu50 regress, seed {}: knobs {}",
                self.seed,
                if knobs.is_empty() {
                    "none".into()
                } else {
                    knobs.join(", ")
                }
            ),
            name,
            &format!("regression seed {}", self.seed),
            self.ticks,
            self.clock_us,
        );
        t.core(&self.params);
        t.comparator(self.vr_err.0 as f64 / 1000.0, self.vr_err.1 as f64 / 1000.0);
        let segments: Vec<Segment> = self
            .motion
            .iter()
            .map(|m| match *m {
                Motion::Hold { ticks } => Segment::Hold { ticks },
                Motion::Move { ticks, milli_deg } => Segment::Move {
                    ticks,
                    delta_deg: milli_deg as f64 / 1000.0,
                },
            })
            .collect();
        t.motor(self.start_decideg as f64 / 10.0, &segments);
        for (at, a) in &self.events {
            t.event(
                *at,
                &match a {
                    Action::Ig(v) => EventText::Ig(*v),
                    Action::Fault(v) => EventText::Vs2Fault(*v),
                    Action::Write { reg, value } => EventText::Write {
                        reg: reg.to_string(),
                        value: u64::from(*value),
                    },
                    Action::Read { addr } => EventText::Read {
                        addr: u64::from(*addr),
                    },
                    Action::BusWrite { addr, data } => EventText::BusWrite {
                        addr: u64::from(*addr),
                        data: u64::from(*data),
                    },
                    Action::PgLeak(v) => EventText::Vs2PgLeak(*v),
                },
            );
        }
        t.finish()
    }
}

/// A value to write to `reg`: mostly legal for the parameters drawn, illegal on request. With
/// `illegal`, half the writes aim at a legality rule: past it, or exactly at its bound (min = x
/// and Wt = shortest - 1 are legal; Wt = shortest is not; docs/spec.md 4).
fn write_value(r: &mut Rng, reg: &str, p: &Params, illegal: bool) -> u16 {
    let bad = illegal && r.percent(50);
    // Wt without the written field, and the shortest interval (docs/spec.md 4)
    let shortest = u64::from(p.shortest_interval());
    let wt_without = |f: u16| u64::from(p.wt()) - u64::from(f);
    let v = match reg {
        "CTRL" => r.range(0, 1),
        "STATUS" => {
            [1 << 5, 1 << 9, (1 << 5) | (1 << 9), 0, r.range(0, 0x3FF)][r.range(0, 4) as usize]
        }
        "CTH" if bad => 0,
        "CTH" => r.range(1, 10),
        "SI_MIN" if bad => [
            0,
            u64::from(p.si_max) + 1 + r.range(0, 50),
            u64::from(p.pw) + u64::from(p.pi),
            u64::from(p.si_max),
        ][r.range(0, 3) as usize],
        "SI_MAX" if bad => [
            u64::from(p.si_min).saturating_sub(1 + r.range(0, 20)),
            u64::from(p.si_min),
        ][r.range(0, 1) as usize],
        "SI_MIN" | "SI_MAX" => r.range(
            u64::from(p.si_min).saturating_sub(50),
            u64::from(p.si_max) + 50,
        ),
        // Pw = Pi = 0 leaves no settling tick; a long one makes the window too long
        "PW" if bad && p.pi == 0 => 0,
        "PI" if bad && p.pw == 0 => 0,
        "PW" | "PI" | "PS" if bad && r.percent(50) => {
            // Wt = shortest - 1 (legal) or = shortest (refused), at equality
            let f = match reg {
                "PW" => p.pw,
                "PI" => p.pi,
                _ => p.ps,
            };
            (shortest - 1 + r.range(0, 1)).saturating_sub(wt_without(f))
        }
        "PW" | "PI" if bad => u64::from(p.si_min) + r.range(0, 10),
        "PS" | "T1" | "T2" | "SMP_ON" if bad => 0,
        _ => r.range(0, 320),
    };
    v.min(u64::from(u16::MAX)) as u16
}

/// A, B, A (0xAAAA, 0x5555, 0xAAAA) raise and lower every bit of a 16-bit register; 0xAA, 0x55,
/// 0xAA every bit of Cth.
const SWEEP_A: u16 = 0xAAAA;
const SWEEP_B: u16 = 0x5555;

/// The writes of the long-durations sweep, one a tick, each legal when it comes (docs/spec.md 4)
/// but one: the window made one tick each way (Wt = 2), x and min at the top so that each window
/// field can take A = 43690 (Wt < min = 65535), each field then back to its least; min and x over A and
/// B (min = x = B is legal) and min back to A; T1, T2, smp_on and Cth; and one refused
/// Pw = 65535, whose candidate Wt passes 16 bits.
const SWEEP: [(&str, u16); 36] = [
    ("PW", 1),
    ("PI", 0),
    ("PS", 1),
    ("SI_MAX", 65_535),
    ("SI_MIN", 65_535),
    ("PW", SWEEP_A),
    ("PW", SWEEP_B),
    ("PW", SWEEP_A),
    ("PW", 1),
    ("PI", SWEEP_A),
    ("PI", SWEEP_B),
    ("PI", SWEEP_A),
    ("PI", 0),
    ("PS", SWEEP_A),
    ("PS", SWEEP_B),
    ("PS", SWEEP_A),
    ("PS", 1),
    ("PW", 65_535),
    ("SI_MIN", SWEEP_A),
    ("SI_MIN", SWEEP_B),
    ("SI_MAX", SWEEP_A),
    ("SI_MAX", SWEEP_B),
    ("SI_MAX", SWEEP_A),
    ("SI_MIN", SWEEP_A),
    ("T1", SWEEP_A),
    ("T1", SWEEP_B),
    ("T1", SWEEP_A),
    ("T2", SWEEP_A),
    ("T2", SWEEP_B),
    ("T2", SWEEP_A),
    ("SMP_ON", SWEEP_A),
    ("SMP_ON", SWEEP_B),
    ("SMP_ON", SWEEP_A),
    ("CTH", 0xAA),
    ("CTH", 0x55),
    ("CTH", 0xAA),
];

/// Long durations: the reset values of the duration registers drawn up to their 16-bit top,
/// legal (docs/spec.md 4: every duration up to 65535 ticks, Wt below the shortest interval).
/// Half the seeds take a window of 40000 ticks or more (so that Pw, Pi and Ps can be written
/// past bit 15), the other half a short min under an x of 40000 or more (si, its sums and the
/// timing generator's count cross every bit); T1, T2 and smp_on anywhere in 1..=65535.
fn long_durations(c: &mut Rng, p: &mut Params) {
    if c.percent(50) {
        p.si_min = c.range(40_000, 62_000) as u16;
        p.si_max = c.range(u64::from(p.si_min), 65_535) as u16;
        let third = (u64::from(p.shortest_interval()) - 1) / 3;
        p.pw = c.range(1, third) as u16;
        p.pi = c.range(0, third) as u16;
        p.ps = c.range(1, third) as u16;
    } else {
        let wt = u64::from(p.wt());
        p.si_min = c.range(wt + 1, (wt + 1).max(3_000)) as u16;
        p.si_max = c.range(40_000, 65_535) as u16;
    }
    p.t1 = c.range(1, 65_535) as u16;
    p.t2 = c.range(1, 65_535) as u16;
    if c.percent(50) {
        p.smp_on = c.range(1, 65_535) as u16;
    }
}

/// A value for `reg` over its whole legal range given the registers in force `p` (one of the
/// bounds a time in five), or a window field that takes Wt past 16 bits (refused) for half the
/// illegal ones; `None` for a register without a range (CTRL, STATUS).
fn wide_value(r: &mut Rng, reg: &str, p: &Params, illegal: bool) -> Option<u16> {
    let span = |r: &mut Rng, lo: u64, hi: u64| match r.range(0, 9) {
        _ if hi <= lo => lo,
        0 => lo,
        1 => hi,
        _ => r.range(lo, hi),
    };
    let wt = u64::from(p.wt());
    let shortest = u64::from(p.shortest_interval());
    let v = match reg {
        "PW" | "PI" | "PS" if illegal && r.percent(50) => 65_535 - r.range(0, 3),
        "PW" | "PI" | "PS" => {
            let f = match reg {
                "PW" => p.pw,
                "PI" => p.pi,
                _ => p.ps,
            };
            // Pw + Pi >= 1 and Ps >= 1; Wt < the shortest interval
            let lo = match reg {
                "PW" => u64::from(p.pi == 0),
                "PI" => u64::from(p.pw == 0),
                _ => 1,
            };
            let others = wt - u64::from(f);
            span(r, lo, (shortest - 1).saturating_sub(others))
        }
        "SI_MIN" => span(r, if p.adaptive { wt + 1 } else { 1 }, u64::from(p.si_max)),
        "SI_MAX" => {
            let lo = u64::from(p.si_min);
            span(r, if p.adaptive { lo } else { lo.max(wt + 1) }, 65_535)
        }
        "T1" | "T2" | "SMP_ON" => span(r, 1, 65_535),
        "CTH" => span(r, 1, 255),
        _ => return None,
    };
    Some(v.min(65_535) as u16)
}

/// The registers after a write of `value` to `reg` when the register file takes it (the
/// parameter set stays legal); unchanged when it refuses it. The register file's own write
/// (`register_file::with_write`: the register's width taken from the bus word) and legality check.
fn written(p: &mut Params, reg: &str, value: u16) {
    use pmu50_core::register_file::{reset, with_write, MAP};
    let Some(&(_, a, ..)) = MAP.iter().find(|m| m.0 == reg) else {
        return;
    };
    if let Some(n) = with_write(&reset(p), a, value) {
        let n = n.params(p.sync_depth, p.cnt_width);
        if n.validate().is_ok() {
            *p = n;
        }
    }
}

/// The read-only addresses of the register map (ID, VERSION, CFG, CNT_S, CNT_C, CNT_R, SI).
const READ_ONLY: [u8; 7] = [0x00, 0x01, 0x0C, 0x10, 0x11, 0x12, 0x13];

/// One port-level stimulus from tick `at` (`ig` the key's level, updated): a raw bus write to
/// a read-only or an unmapped address (with the key on, or in the tick it turns on, when sig is
/// still 0), a word with high bits past a register's width (CTH: 0x01xx, low byte 0 half the
/// time, docs/spec.md 2.8; CTRL and STATUS likewise), or a stretch of Vs2's power-good leaking
/// high while the rail is off; every event before tick `end`. Returns the ticks it takes.
fn port_level(
    r: &mut Rng,
    at: u64,
    end: u64,
    ig: &mut bool,
    events: &mut Vec<(u64, Action)>,
) -> u64 {
    if at + 12 >= end {
        return 1;
    }
    match r.range(0, 3) {
        0 => {
            let len = r.range(50, 5_000).min(end - at - 1);
            events.push((at, Action::PgLeak(true)));
            events.push((at + len, Action::PgLeak(false)));
            len + 1
        }
        k => {
            if !*ig || r.percent(25) {
                // in the tick the key turns on, sig still 0: refused, the key is off for the
                // register file ([0205]); the key off long enough first for sig to fall
                let on_at = if *ig {
                    events.push((at, Action::Ig(false)));
                    at + 10
                } else {
                    at
                };
                events.push((on_at, Action::Ig(true)));
                *ig = true;
                let addr = if r.percent(50) {
                    READ_ONLY[r.range(0, READ_ONLY.len() as u64 - 1) as usize]
                } else {
                    unmapped_addr(r)
                };
                let data = r.range(0, 0xFFFF) as u16;
                events.push((on_at, Action::BusWrite { addr, data }));
                return on_at - at + 2;
            }
            let (addr, data) = match k {
                1 if r.percent(50) => (
                    READ_ONLY[r.range(0, READ_ONLY.len() as u64 - 1) as usize],
                    r.range(0, 0xFFFF) as u16,
                ),
                1 => (unmapped_addr(r), r.range(0, 0xFFFF) as u16),
                _ => {
                    let high = (r.range(1, 0xFF) as u16) << 8;
                    match r.range(0, 3) {
                        0 | 1 => (
                            0x0A,
                            high | if r.percent(50) {
                                0
                            } else {
                                r.range(1, 0xFF) as u16
                            },
                        ),
                        2 => (0x02, high | r.range(0, 1) as u16),
                        _ => (0x14, (high & 0xFC00) | r.range(0, 0x3FF) as u16),
                    }
                }
            };
            events.push((at, Action::BusWrite { addr, data }));
            2
        }
    }
}

/// The parameter registers in the order a seed's first key-on writes them.
const CONFIG_REGS: [(&str, &str); 10] = [
    ("CTRL", "ADAPTIVE"),
    ("PW", "PW"),
    ("PI", "PI"),
    ("PS", "PS"),
    ("SI_MAX", "SI_MAX"),
    ("SI_MIN", "SI_MIN"),
    ("T1", "T1"),
    ("T2", "T2"),
    ("CTH", "CTH"),
    ("SMP_ON", "SMP_ON"),
];

/// The writes that take the registers from `from` to `to`, one a tick from tick `at`, each
/// legal when it comes (a write the legality rules would refuse in between waits for the
/// others: docs/spec.md 4); the tick after the last and the registers after them.
fn config_writes(from: &Params, to: &Params, at: u64) -> (Vec<(u64, Action)>, u64, Params) {
    let value = |p: &Params, hdl: &str| {
        p.hdl_parameters()
            .iter()
            .find(|(n, _)| *n == hdl)
            .map_or(0, |(_, v)| *v as u16)
    };
    let (mut cur, mut t, mut out) = (*from, at, Vec::new());
    for _ in 0..CONFIG_REGS.len() {
        let mut moved = false;
        for (reg, hdl) in CONFIG_REGS {
            let v = value(to, hdl);
            if value(&cur, hdl) == v {
                continue;
            }
            let before = cur;
            written(&mut cur, reg, v);
            if cur != before {
                out.push((t, Action::Write { reg, value: v }));
                t += 1;
                moved = true;
            }
        }
        if !moved {
            break;
        }
    }
    (out, t, cur)
}

/// A bus address outside the register map: a hole of the map (below 0x20) half the time, else
/// one of 0x20..=0xFF.
fn unmapped_addr(r: &mut Rng) -> u8 {
    use pmu50_core::register_file::MAP;
    let mapped = |a: u64| MAP.iter().any(|m| u64::from(m.1) == a);
    for _ in 0..16 {
        let a = if r.percent(50) {
            r.range(0, 0x1F)
        } else {
            r.range(0x20, 0xFF)
        };
        if !mapped(a) {
            return a as u8;
        }
    }
    0xFF
}

#[cfg(test)]
mod tests {
    use super::*;
    use pmu50_coverage::model::{Hint, Sampled, POINTS};
    use pmu50_coverage::{layout, Aim, Coverage};

    #[test]
    fn every_knob_a_coverage_hint_names_is_a_knob_of_the_generator() {
        let mut bad = Vec::new();
        for p in POINTS.iter() {
            for b in p.bins {
                if let Hint::Knobs(k) = b.hint {
                    assert!(
                        !k.is_empty(),
                        "{}.{}.{}: an empty knob list",
                        p.group,
                        p.name,
                        b.name
                    );
                    for n in k {
                        if knob_named(n).is_none() {
                            bad.push(format!("{}.{}.{}: {n}", p.group, p.name, b.name));
                        }
                    }
                }
            }
        }
        // the crosses' own knobs, through every cross bin
        for b in &layout().bins {
            for n in b.aim.knobs() {
                if knob_named(n).is_none() {
                    bad.push(format!("{}: {n}", b.name));
                }
            }
        }
        assert!(
            bad.is_empty(),
            "hints name knobs the generator lacks:\n{}",
            bad.join("\n")
        );
        assert_eq!(knob_named("NoSuchKnob"), None);
        assert_eq!(knob_named("LongQuiet"), Some(LongQuiet));
    }

    #[test]
    fn a_directed_seed_aimed_at_a_missing_bin_draws_that_bins_knobs() {
        let l = layout();
        let mut aimed = 0;
        for (i, b) in l.bins.iter().enumerate() {
            let want = knobs_for(&b.name);
            if b.unreachable.is_some() {
                assert!(
                    want.is_empty(),
                    "{}: a bin nothing aims at has knobs",
                    b.name
                );
                continue;
            }
            if b.port_only {
                assert_eq!(want, vec![PortLevel], "{}", b.name);
                continue;
            }
            assert_eq!(
                want.len(),
                b.aim.knobs().len(),
                "{}: a hint's knob is not drawn",
                b.name
            );
            if want.is_empty() {
                assert_eq!(b.aim, Aim::AnySeed, "{}", b.name);
                continue;
            }
            aimed += 1;
            let bias = Bias::from_missing([b.name.as_str()]);
            assert_eq!(bias.targets, vec![want.clone()], "{}", b.name);
            // a configuration bin: the scenario's parameters fall in it (a seed's own random
            // draws may take a knob of the same parameter first, so one of a few seeds)
            let config = POINTS.iter().any(|p| {
                p.sampled == Sampled::Config
                    && b.name.starts_with(&format!("{}.{}.", p.group, p.name))
            });
            let mut in_bin = false;
            for seed in 0..8 {
                let s = Stimulus::generate(seed, &bias);
                for k in &want {
                    assert!(
                        s.knobs.contains(k),
                        "seed {seed} aimed at {} lacks {k:?}",
                        b.name
                    );
                }
                in_bin |= Coverage::new(&s.params, s.clock_us * 1000).hits()[i] > 0;
            }
            assert!(
                !config || in_bin,
                "no seed aimed at {} has its configuration",
                b.name
            );
        }
        assert!(aimed > 200, "only {aimed} bins have knobs");
    }
}
