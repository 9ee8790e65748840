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

use super::rtl::Fixed;
use crate::random::Rng;
use pmu50_core::Params;
use std::fmt::Write;

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
}

use Knob::*;

/// Every knob with its base probability in percent (uniform random).
pub const KNOBS: [(Knob, u64); 35] = [
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
];

/// The knob a coverage hint names (rtl_model/coverage/src/model.rs names knobs as the
/// variants of [`Knob`] are spelt).
pub fn knob_named(name: &str) -> Option<Knob> {
    KNOBS
        .iter()
        .map(|&(k, _)| k)
        .find(|k| format!("{k:?}") == name)
}

/// The knobs that make a coverage bin likely, by the bin's full name: the hint declared with
/// the bin in the coverage model (a cross: the knobs of both of its bins and the cross's own).
/// None for a bin that seeds hit without a knob, that only port-level stimuli reach, that is
/// declared unreachable, or that the model does not have.
pub fn knobs_for(bin: &str) -> Vec<Knob> {
    let Some(b) = pmu50_coverage::layout().bins.iter().find(|b| b.name == bin) else {
        return Vec::new();
    };
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

impl Bias {
    /// Uniform random: every knob at its base probability.
    pub fn uniform() -> Bias {
        Bias {
            percent: KNOBS.to_vec(),
            targets: Vec::new(),
            pins: Pins::default(),
            fixed: Fixed::default(),
        }
    }

    /// Directed, from the coverage so far (hits in the model's order): every bin still empty
    /// that can be hit and that scenario stimuli reach.
    pub fn directed(hits: &[u64], pins: Pins) -> Bias {
        let l = pmu50_coverage::layout();
        Bias::from_missing(
            l.bins
                .iter()
                .zip(hits)
                .filter(|(b, h)| **h == 0 && b.unreachable.is_none() && !b.port_only)
                .map(|(b, _)| b.name.as_str()),
        )
        .pinned(pins)
    }

    /// The same bias with these structural parameters held.
    pub fn pinned(self, pins: Pins) -> Bias {
        Bias { pins, ..self }
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
        }
    }

    fn draw(&self, r: &mut Rng, seed: u64) -> Vec<Knob> {
        let mut k: Vec<Knob> = self
            .percent
            .iter()
            .filter(|&&(_, p)| r.percent(p))
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
    Write { reg: &'static str, value: u16 },
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
        let clock_us = if on(ClockFast) {
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
        let saturate_at_min = on(LongQuiet) && r.percent(50);
        // Or at the top of the 16-bit range (docs/spec.md 2.6): x just below 65535, T1 = 65535
        // so that S6's si - T1 saturates at 0 before its clamp to min, and T2 so large that
        // S10's si + T2 from min passes 65535 before its clamp to x.
        let past_16_bits = on(LongQuiet)
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
                let (x, min) = (u64::from(p.si_max), u64::from(p.si_min));
                ticks = 3 * x + (u64::from(p.cth) + 2) * min + u64::from(p.wt());
            } else {
                p.t2 = 1;
                p.cth = p.cth.min(4);
                let span = u64::from(p.si_max - p.si_min);
                ticks = 2 * u64::from(p.si_max) + (span + 2) * u64::from(p.si_max);
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
        let vr_err = (r.range(0, 200) as i64 - 100, r.range(0, 200) as i64 - 100);
        let mut start_decideg = r.range(0, 3599);
        // A skip and the MPU's W1C of STATUS.quadrant_skip on the same edge (docs/spec.md 2.5:
        // the set wins), then a write of bit 4 alone while the flag is set (no effect) and a
        // W1C of bit 5 while it is set: the key on from reset, on-key samples every
        // RACE_SMP_ON ticks from the edge where sig rises (edge SYNC_DEPTH), the shaft half a
        // turn between the first two of them, from the middle of a quadrant.
        let race = !on(Spin)
            && !on(LongQuiet)
            && on(StatusWrites)
            && on(FastMoves)
            && bias.fixed.get("SMP_ON").is_none()
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
        } else if on(LongQuiet) {
            false
        } else {
            r.percent(50)
        };
        events.push((0, Action::Ig(ig)));
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
        let mut at = race_end;
        events.extend(race_events);
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
                    let value = write_value(&mut r, "SI_MAX", &p, false);
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
                        let value = write_value(&mut r, reg, &p, false);
                        events.push((at, Action::Write { reg, value }));
                    }
                }
                5 if on(Faults) || r.percent(30) => {
                    fault = !fault;
                    events.push((at, Action::Fault(fault)));
                }
                _ if ig => {
                    let reg = if on(StatusWrites) && r.percent(40) {
                        "STATUS"
                    } else {
                        WRITABLE[r.range(0, WRITABLE.len() as u64 - 2) as usize]
                    };
                    let value = write_value(&mut r, reg, &p, on(IllegalWrites));
                    events.push((at, Action::Write { reg, value }));
                }
                _ => {}
            }
        }
        // One event of a kind per tick: a write shares its tick only with ig.
        events.sort_by_key(|(t, a)| (*t, matches!(a, Action::Write { .. })));
        events.dedup_by(|b, a| {
            a.0 == b.0 && std::mem::discriminant(&a.1) == std::mem::discriminant(&b.1)
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
        let p = &self.params;
        let us = |t: u64| format!("\"{} us\"", t * self.clock_us);
        let mut s = String::new();
        let knobs: Vec<String> = self.knobs.iter().map(|k| format!("{k:?}")).collect();
        let _ = writeln!(
            s,
            "# pmu50 regress, seed {}: knobs {}",
            self.seed,
            if knobs.is_empty() {
                "none".into()
            } else {
                knobs.join(", ")
            }
        );
        let _ = writeln!(s, "name = \"{name}\"");
        let _ = writeln!(s, "description = \"regression seed {}\"", self.seed);
        let _ = writeln!(s, "duration = {}\n", us(self.ticks));
        let _ = writeln!(s, "[core]\nclock = \"{} us\"", self.clock_us);
        let _ = writeln!(
            s,
            "sync_depth = {}\ncnt_width = {}\nadaptive = {}",
            p.sync_depth, p.cnt_width, p.adaptive
        );
        for (n, v) in [
            ("pw", p.pw),
            ("pi", p.pi),
            ("ps", p.ps),
            ("x", p.si_max),
            ("min", p.si_min),
            ("t1", p.t1),
            ("t2", p.t2),
            ("smp_on", p.smp_on),
        ] {
            let _ = writeln!(s, "{n} = {}", us(u64::from(v)));
        }
        let _ = writeln!(s, "cth = {}\n", p.cth);
        let _ = writeln!(
            s,
            "[env.comparator]\nvr_err_s = {:.3}\nvr_err_c = {:.3}\n",
            self.vr_err.0 as f64 / 1000.0,
            self.vr_err.1 as f64 / 1000.0
        );
        let _ = writeln!(
            s,
            "[motor]\nstart_deg = {:.1}\nsegments = [",
            self.start_decideg as f64 / 10.0
        );
        for m in &self.motion {
            match *m {
                Motion::Hold { ticks } => {
                    let _ = writeln!(s, "  {{ kind = \"hold\", duration = {} }},", us(ticks));
                }
                Motion::Move { ticks, milli_deg } => {
                    let _ = writeln!(
                        s,
                        "  {{ kind = \"move\", duration = {}, delta_deg = {:.3} }},",
                        us(ticks),
                        milli_deg as f64 / 1000.0
                    );
                }
            }
        }
        let _ = writeln!(s, "]");
        for (t, a) in &self.events {
            let _ = write!(s, "\n[[events]]\nat = {}\n", us(*t));
            let _ = match a {
                Action::Ig(v) => writeln!(s, "ig = {v}"),
                Action::Fault(v) => writeln!(s, "vs2_fault = {v}"),
                Action::Write { reg, value } => {
                    writeln!(s, "write = {{ reg = \"{reg}\", value = {value} }}")
                }
            };
        }
        s
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
            if b.unreachable.is_some() || b.port_only {
                assert!(
                    want.is_empty(),
                    "{}: a bin nothing aims at has knobs",
                    b.name
                );
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
