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
}

use Knob::*;

/// Every knob with its base probability in percent (uniform random).
pub const KNOBS: [(Knob, u64); 34] = [
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
];

/// The knobs that make a coverage bin likely, by the bin's name.
pub fn knobs_for(bin: &str) -> Vec<Knob> {
    let has = |p: &str| bin.contains(p);
    let mut k = Vec::new();
    let rules: &[(&str, &[Knob])] = &[
        ("config.cnt_w.2", &[NarrowCounter]),
        ("config.cnt_w.3_7", &[Width3To7]),
        ("config.cnt_w.8_15", &[Width8To15]),
        ("config.sync_depth.1", &[Sync1]),
        ("config.sync_depth.3", &[Sync3]),
        ("config.sync_depth.4", &[Sync4]),
        ("config.adaptive.fixed", &[Fixed]),
        ("fig17.path.fixed", &[Fixed]),
        ("config.cth.one", &[CthOne]),
        ("config.cth.9_up", &[CthHigh]),
        ("t1.one_step", &[T1OneStep]),
        ("t1.half_or_more", &[T1Half]),
        ("t2.one_step", &[T2OneStep]),
        ("t2.half_or_more", &[T2Half]),
        ("config.x.equal_min", &[XEqualMin]),
        ("config.x.le_300", &[XShort]),
        ("config.x.above_700", &[XLong]),
        ("config.min.wt_plus_1", &[MinTight]),
        ("config.min.above_2wt", &[MinFar]),
        ("config.window.pw_zero", &[PwZero]),
        ("config.window.pi_zero", &[PiZero]),
        ("config.window.ps_one", &[PsOne]),
        ("config.smp_on.one", &[SmpOnOne]),
        ("config.smp_on.2_9", &[SmpOnShort]),
        ("config.clock.below_10us", &[ClockFast]),
        ("config.clock.above_10us", &[ClockSlow]),
        ("wrap", &[Spin, NarrowCounter]),
        ("quadrant_skip", &[FastMoves]),
        ("faults.diag", &[FastMoves, NarrowCounter]),
        ("skip_x_interval", &[FastMoves]),
        ("cnt_r.value.saturated", &[LongQuiet]),
        ("cnt_r.before.saturated", &[LongQuiet]),
        ("above_cth", &[LongQuiet, XEqualMin]),
        ("faults.vs2", &[Faults]),
        ("s1_no_rise", &[Faults]),
        ("sync_glitch", &[Glitches]),
        ("key.", &[KeyStorm]),
        ("key_edge_x_phase", &[KeyStorm]),
        ("illegal", &[IllegalWrites]),
        ("bus.w1c", &[StatusWrites]),
        ("skip_clear", &[StatusWrites, FastMoves]),
        ("refused_key_off", &[EarlyWrites]),
        ("bus.write_reg", &[IllegalWrites, StatusWrites]),
        ("interval.", &[FastMoves, T1Half, T2Half]),
        ("counter.rule", &[Spin]),
        ("counter.preset", &[KeyStorm]),
    ];
    for (p, ks) in rules {
        if has(p) {
            k.extend_from_slice(ks);
        }
    }
    k.sort();
    k.dedup();
    k
}

/// The probability of each knob for the seeds of one batch.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Bias {
    pub percent: Vec<(Knob, u64)>,
}

impl Bias {
    /// Uniform random: every knob at its base probability.
    pub fn uniform() -> Bias {
        Bias { percent: KNOBS.to_vec() }
    }

    /// Directed: a knob that feeds a bin still empty is drawn with probability 60 %.
    pub fn from_missing<'a>(missing: impl IntoIterator<Item = &'a str>) -> Bias {
        let mut want = std::collections::BTreeSet::new();
        for b in missing {
            want.extend(knobs_for(b));
        }
        Bias { percent: KNOBS.iter().map(|&(k, p)| (k, if want.contains(&k) { p.max(60) } else { p })).collect() }
    }

    fn draw(&self, r: &mut Rng) -> Vec<Knob> {
        self.percent.iter().filter(|&&(_, p)| r.chance(p)).map(|&(k, _)| k).collect()
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

const WRITABLE: [&str; 11] = ["CTRL", "PW", "PI", "PS", "SI_MAX", "SI_MIN", "T1", "T2", "CTH", "SMP_ON", "STATUS"];

/// Draw the parameters from the knobs; always legal.
fn params(r: &mut Rng, k: &[Knob]) -> Params {
    let on = |x: Knob| k.contains(&x);
    loop {
        let pw = if on(PwZero) { 0 } else { r.range(1, 8) as u16 };
        let pi = if on(PiZero) && pw > 0 { 0 } else { r.range(u64::from(pw == 0), 15) as u16 };
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
        let (t1, t2) = (step(r, on(T1OneStep), on(T1Half)), step(r, on(T2OneStep), on(T2Half)));
        let p = Params {
            sync_depth: if on(Sync1) { 1 } else if on(Sync4) { 4 } else if on(Sync3) { 3 } else { 2 },
            cnt_width: if on(NarrowCounter) { 2 } else if on(Width3To7) { r.range(3, 7) as u8 } else if on(Width8To15) { r.range(8, 15) as u8 } else { 16 },
            adaptive: !on(Fixed),
            pw,
            pi,
            ps,
            si_max: si_max.min(u64::from(u16::MAX)) as u16,
            si_min: si_min as u16,
            t1: t1.min(65535) as u16,
            t2: t2.min(65535) as u16,
            cth: if on(CthOne) { 1 } else if on(CthHigh) { r.range(9, 40) as u8 } else { r.range(2, 8) as u8 },
            smp_on: if on(SmpOnOne) { 1 } else if on(SmpOnShort) { r.range(2, 9) as u16 } else { r.range(10, 30) as u16 },
        };
        if p.validate().is_ok() {
            return p;
        }
    }
}

impl Stimulus {
    /// The scenario of `seed` under `bias`.
    pub fn generate(seed: u64, bias: &Bias) -> Stimulus {
        let mut r = Rng::new(seed ^ 0x5245_4752_4553_5300);
        let knobs = bias.draw(&mut r);
        let on = |x: Knob| knobs.contains(&x);
        let mut p = params(&mut r, &knobs);
        let clock_us = if on(ClockFast) { 5 } else if on(ClockSlow) { 20 } else { 10 };
        let mut ticks = r.range(20_000, 60_000);
        if on(LongQuiet) {
            // Enough quiet pulses at a small T2 for CNTr to count past 255 ([0248]).
            p.t2 = 1;
            p.cth = p.cth.min(4);
            ticks = ticks.max(300 * u64::from(p.si_max) + 10_000);
        }
        let vr_err = (r.range(0, 200) as i64 - 100, r.range(0, 200) as i64 - 100);
        let start_decideg = r.range(0, 3599);

        // Motor: holds and moves; fast moves skip quadrants, a spin turns one way for long.
        let mut motion = Vec::new();
        let mut t = 0;
        while t < ticks {
            let d = if on(LongQuiet) && t > 5_000 { ticks - t } else { r.range(100, 8_000).min(ticks - t) };
            let m = if on(LongQuiet) && t > 5_000 {
                Motion::Hold { ticks: d }
            } else if on(Spin) && r.chance(70) {
                // steady rotation below the tracking bound 90 deg per x ticks (docs/analysis.md)
                let per_tick = 90_000 / i64::from(p.si_max.max(p.smp_on)) * 6 / 10;
                Motion::Move { ticks: d, milli_deg: per_tick * d as i64 }
            } else if r.chance(40) {
                Motion::Hold { ticks: d }
            } else {
                let fast = on(FastMoves) && r.chance(60) || r.chance(5);
                let max = if fast { 600 } else { 50 };
                Motion::Move { ticks: d, milli_deg: (r.range(0, 2000) as i64 - 1000) * max * d as i64 / 1000 }
            };
            motion.push(m);
            t += d;
        }

        // Timeline.
        let mut events = Vec::new();
        let mut ig = r.chance(50);
        events.push((0, Action::Ig(ig)));
        let gap = if on(KeyStorm) { (20, 800) } else { (50, 15_000) };
        let mut at = 0u64;
        let mut fault = false;
        loop {
            at += r.range(gap.0, gap.1);
            if at >= ticks.saturating_sub(2) {
                break;
            }
            let roll = r.range(0, 9);
            if on(Glitches) && r.chance(30) {
                // a pulse of ig shorter than the synchronizer
                events.push((at, Action::Ig(!ig)));
                events.push((at + r.range(1, 2), Action::Ig(ig)));
                at += 3;
                continue;
            }
            match roll {
                0..=4 => {
                    ig = !ig;
                    events.push((at, Action::Ig(ig)));
                    if ig && on(EarlyWrites) && r.chance(50) {
                        // a write in the tick the key turns on: sig is still 0 ([0205])
                        events.push((at, Action::Write { reg: "T2", value: p.t2 }));
                    }
                }
                5 if on(Faults) || r.chance(30) => {
                    fault = !fault;
                    events.push((at, Action::Fault(fault)));
                }
                _ if ig => {
                    let reg = if on(StatusWrites) && r.chance(40) { "STATUS" } else { WRITABLE[r.range(0, WRITABLE.len() as u64 - 2) as usize] };
                    let value = write_value(&mut r, reg, &p, on(IllegalWrites));
                    events.push((at, Action::Write { reg, value }));
                }
                _ => {}
            }
        }
        // One event of a kind per tick: a write shares its tick only with ig.
        events.sort_by_key(|(t, a)| (*t, matches!(a, Action::Write { .. })));
        events.dedup_by(|b, a| a.0 == b.0 && std::mem::discriminant(&a.1) == std::mem::discriminant(&b.1));
        Stimulus { seed, knobs, params: p, clock_us, vr_err, start_decideg, motion, events, ticks }
    }

    /// The scenario as TOML (what `pmu50 run` reads).
    pub fn to_toml(&self, name: &str) -> String {
        let p = &self.params;
        let us = |t: u64| format!("\"{} us\"", t * self.clock_us);
        let mut s = String::new();
        let knobs: Vec<String> = self.knobs.iter().map(|k| format!("{k:?}")).collect();
        let _ = writeln!(s, "# pmu50 regress, seed {}: knobs {}", self.seed, if knobs.is_empty() { "none".into() } else { knobs.join(", ") });
        let _ = writeln!(s, "name = \"{name}\"");
        let _ = writeln!(s, "description = \"regression seed {}\"", self.seed);
        let _ = writeln!(s, "duration = {}\n", us(self.ticks));
        let _ = writeln!(s, "[core]\nclock = \"{} us\"", self.clock_us);
        let _ = writeln!(s, "sync_depth = {}\ncnt_width = {}\nadaptive = {}", p.sync_depth, p.cnt_width, p.adaptive);
        for (n, v) in [("pw", p.pw), ("pi", p.pi), ("ps", p.ps), ("x", p.si_max), ("min", p.si_min), ("t1", p.t1), ("t2", p.t2), ("smp_on", p.smp_on)] {
            let _ = writeln!(s, "{n} = {}", us(u64::from(v)));
        }
        let _ = writeln!(s, "cth = {}\n", p.cth);
        let _ = writeln!(s, "[env.comparator]\nvr_err_s = {:.3}\nvr_err_c = {:.3}\n", self.vr_err.0 as f64 / 1000.0, self.vr_err.1 as f64 / 1000.0);
        let _ = writeln!(s, "[motor]\nstart_deg = {:.1}\nsegments = [", self.start_decideg as f64 / 10.0);
        for m in &self.motion {
            match *m {
                Motion::Hold { ticks } => {
                    let _ = writeln!(s, "  {{ kind = \"hold\", duration = {} }},", us(ticks));
                }
                Motion::Move { ticks, milli_deg } => {
                    let _ = writeln!(s, "  {{ kind = \"move\", duration = {}, delta_deg = {:.3} }},", us(ticks), milli_deg as f64 / 1000.0);
                }
            }
        }
        let _ = writeln!(s, "]");
        for (t, a) in &self.events {
            let _ = write!(s, "\n[[events]]\nat = {}\n", us(*t));
            let _ = match a {
                Action::Ig(v) => writeln!(s, "ig = {v}"),
                Action::Fault(v) => writeln!(s, "vs2_fault = {v}"),
                Action::Write { reg, value } => writeln!(s, "write = {{ reg = \"{reg}\", value = {value} }}"),
            };
        }
        s
    }
}

/// A value to write to `reg`: mostly legal for the parameters drawn, illegal on request.
fn write_value(r: &mut Rng, reg: &str, p: &Params, illegal: bool) -> u16 {
    let bad = illegal && r.chance(50);
    let v = match reg {
        "CTRL" => r.range(0, 1),
        "STATUS" => [1 << 5, 1 << 9, (1 << 5) | (1 << 9), 0, r.range(0, 0x3FF)][r.range(0, 4) as usize],
        "CTH" if bad => 0,
        "CTH" => r.range(1, 10),
        "SI_MIN" if bad => [0, u64::from(p.si_max) + 1 + r.range(0, 50), u64::from(p.pw) + u64::from(p.pi)][r.range(0, 2) as usize],
        "SI_MAX" if bad => u64::from(p.si_min).saturating_sub(1 + r.range(0, 20)),
        "SI_MIN" | "SI_MAX" => r.range(u64::from(p.si_min).saturating_sub(50), u64::from(p.si_max) + 50),
        "PW" | "PI" if bad => u64::from(p.si_min) + r.range(0, 10),
        "PS" | "T1" | "T2" | "SMP_ON" if bad => 0,
        _ => r.range(0, 320),
    };
    v.min(u64::from(u16::MAX)) as u16
}
