//! Sampling the coverage model from the core's state at each clock edge.
//!
//! [`Coverage::sample`] takes one edge: the registers before and after it, the ports during the
//! cycle before it (the Moore outputs the environment saw), the inputs applied at it and the
//! core's combinational internals. It costs a table lookup on an ordinary edge (a key-on cycle
//! counts the MPU's read) and decodes the rest only on the rare edges that can hit a bin: a bus
//! write, a key edge, a sampling strobe, a diag rise, a W1C strobe, an ig edge inside the
//! synchronizer, the first edge out of reset, or Vs2's power-good disagreeing with its enable.

use crate::bin;
use crate::model::*;
use pmu50_core::drive_interval_changing_56b::{Fig17, Fig18};
use pmu50_core::pmu50::Structural;
use pmu50_core::register_file::{self as rf, WriteRefusal};
use pmu50_core::{Inputs, Internals, Outputs, ParamError, Params, Regs};
use std::sync::OnceLock;

/// The flattened model, built once.
pub fn layout() -> &'static Layout {
    static L: OnceLock<Layout> = OnceLock::new();
    L.get_or_init(Layout::new)
}

/// One clock edge, as the coverage model samples it.
#[derive(Clone, Copy, Debug)]
pub struct Edge<'a> {
    /// Registers before the edge.
    pub before: &'a Regs,
    /// Registers after the edge.
    pub after: &'a Regs,
    /// Ports during the cycle before the edge (decoded from `before`).
    pub out: &'a Outputs,
    /// Inputs applied at the edge.
    pub inputs: &'a Inputs,
    /// Combinational internals of the cycle.
    pub internals: &'a Internals,
}

const NONE: u8 = u8::MAX;
const N_POINTS: usize = POINTS.len();

/// `bus.read` bin of every address.
/// Bins of `bus.read`: one a readable address, and one for the others.
const N_READ_BINS: usize = READ_ADDRS.len() + 1;

static READ_BIN: [u8; 256] = {
    let mut t = [READ_ADDRS.len() as u8; 256];
    let mut i = 0;
    while i < READ_ADDRS.len() {
        t[READ_ADDRS[i] as usize] = i as u8;
        i += 1;
    }
    t
};

/// The hit counters of one coverage run (or of many, merged).
#[derive(Clone, Debug)]
pub struct Coverage {
    hits: Vec<u64>,
    /// The bin of each configuration point for the parameters in force (NONE for edge points).
    config: [u8; N_POINTS],
    clock_ns: u64,
    structural: Structural,
    read_offset: usize,
    /// Bins counted since the last [`Coverage::mark`] (a repeated period, key off or key on, for
    /// replaying skipped copies of it), and the journal of the period before.
    journal: Vec<u32>,
    last_period: Vec<u32>,
    /// The journal outgrew [`JOURNAL_MAX`]: that period cannot be replayed.
    journal_full: bool,
    last_full: bool,
    /// The MPU's reads (key on, one a tick) are counted straight into `hits`, outside the
    /// journal: their counts at the last mark, and the reads of the period before it.
    reads_at_mark: [u64; N_READ_BINS],
    last_reads: [u64; N_READ_BINS],
    /// The synchronizer with every stage set (a key held on).
    sync_full: u8,
    /// The ticks of the last two period boundaries.
    mark_at: Option<u64>,
    prev_at: Option<u64>,
    /// The first edge out of reset was sampled (`key.start`).
    started: bool,
}

/// Entries a period's journal keeps; a repeated period hits a few dozen bins.
const JOURNAL_MAX: usize = 4096;

impl Coverage {
    /// Empty counters for a core of these parameters, at this clock period; samples the
    /// configuration once.
    pub fn new(p: &Params, clock_ns: u64) -> Coverage {
        let l = layout();
        let mut c = Coverage {
            hits: vec![0; l.bins.len()],
            config: [NONE; N_POINTS],
            clock_ns,
            structural: Structural {
                sync_depth: p.sync_depth,
                cnt_width: p.cnt_width,
            },
            read_offset: l.point_offset[READ],
            journal: Vec::new(),
            last_period: Vec::new(),
            journal_full: false,
            last_full: true,
            reads_at_mark: [0; N_READ_BINS],
            last_reads: [0; N_READ_BINS],
            sync_full: ((1u16 << p.sync_depth) - 1) as u8,
            mark_at: None,
            prev_at: None,
            started: false,
        };
        c.sample_config(p);
        c
    }

    /// Step `core` one edge on `i` (the non-skipping step) and sample that edge: a vector file
    /// or a witness replayed edge by edge.
    pub fn step(&mut self, core: &mut pmu50_core::Pmu50, i: &Inputs) {
        let before = *core.regs();
        let out = core.peek();
        let pmu50_core::TracedStep { internals, .. } = core.step_traced(i);
        let after = *core.regs();
        self.sample(&Edge {
            before: &before,
            after: &after,
            out: &out,
            inputs: i,
            internals: &internals,
        });
    }

    /// Hit counts in the model's storage order ([`Layout::bins`]).
    pub fn hits(&self) -> &[u64] {
        &self.hits
    }

    /// Add another run's counts (the same model: always, it is one type).
    pub fn add(&mut self, other: &[u64]) {
        for (a, b) in self.hits.iter_mut().zip(other) {
            *a = a.saturating_add(*b);
        }
    }

    /// A period starts at tick `k` (docs/spec.md 5.1, the bench's `period_boundary`): what was
    /// counted since the previous boundary is the last period, which [`Coverage::replay`] can
    /// add again (the MPU's reads with the key on included).
    pub fn period_boundary(&mut self, k: u64) {
        self.prev_at = self.mark_at;
        self.mark_at = Some(k);
        self.mark();
    }

    /// Whether the period `[k - len, k)` is the last one counted whole, so that the bench may
    /// skip copies of it ([`Coverage::replay`]).
    pub fn can_replay(&self, k: u64, len: u64) -> bool {
        self.mark_at == Some(k) && self.prev_at == k.checked_sub(len) && self.can_repeat()
    }

    /// The bench skipped `periods` copies of the last period: count them; the next boundary
    /// starts afresh.
    pub fn replay(&mut self, periods: u64) {
        self.repeat_last_period(periods);
        self.mark_at = None;
        self.prev_at = None;
    }

    fn mark(&mut self) {
        std::mem::swap(&mut self.journal, &mut self.last_period);
        self.journal.clear();
        self.last_full = self.journal_full;
        self.journal_full = false;
        let reads = &self.hits[self.read_offset..self.read_offset + N_READ_BINS];
        for ((last, at_mark), &now) in self
            .last_reads
            .iter_mut()
            .zip(self.reads_at_mark.iter_mut())
            .zip(reads)
        {
            *last = now.saturating_sub(*at_mark);
            *at_mark = now;
        }
    }

    /// Whether the last period can be replayed (its journal is complete).
    fn can_repeat(&self) -> bool {
        !self.last_full
    }

    /// Add `times` copies of the counts of the last period (a repeated period that the bench
    /// skipped); the next period starts empty.
    fn repeat_last_period(&mut self, times: u64) {
        for &k in &self.last_period {
            let h = &mut self.hits[k as usize];
            *h = h.saturating_add(times);
        }
        let reads = &mut self.hits[self.read_offset..self.read_offset + N_READ_BINS];
        for ((h, &n), at_mark) in reads
            .iter_mut()
            .zip(&self.last_reads)
            .zip(self.reads_at_mark.iter_mut())
        {
            *h = h.saturating_add(n.saturating_mul(times));
            *at_mark = *h;
        }
        self.journal.clear();
        self.journal_full = false;
        self.last_full = true;
    }

    fn count(&mut self, k: usize) {
        self.hits[k] += 1;
        if self.journal.len() < JOURNAL_MAX {
            self.journal.push(k as u32);
        } else {
            self.journal_full = true;
        }
    }

    /// Sample the configuration in force (at the start of a run and after a parameter write).
    pub fn sample_config(&mut self, p: &Params) {
        let span = p.si_max - p.si_min;
        // T1 and T2 have the same bins.
        let step = |t: u16| {
            if t >= span {
                bin!(CFG_T1, "one_step")
            } else if u32::from(t) * 2 >= u32::from(span) {
                bin!(CFG_T1, "half_or_more")
            } else {
                bin!(CFG_T1, "small")
            }
        };
        let wt = p.wt();
        let bins: [(usize, u8); 11] = [
            (
                CFG_CTH,
                match p.cth {
                    0 | 1 => bin!(CFG_CTH, "one"),
                    2..=4 => bin!(CFG_CTH, "2_4"),
                    5..=8 => bin!(CFG_CTH, "5_8"),
                    _ => bin!(CFG_CTH, "9_up"),
                },
            ),
            (CFG_T1, step(p.t1)),
            (CFG_T2, step(p.t2)),
            (
                CFG_X,
                if span == 0 {
                    bin!(CFG_X, "equal_min")
                } else if p.si_max <= 300 {
                    bin!(CFG_X, "le_300")
                } else if p.si_max <= 700 {
                    bin!(CFG_X, "301_700")
                } else {
                    bin!(CFG_X, "above_700")
                },
            ),
            (
                CFG_MIN,
                if u32::from(p.si_min) == wt + 1 {
                    bin!(CFG_MIN, "wt_plus_1")
                } else if u32::from(p.si_min) <= 2 * wt {
                    bin!(CFG_MIN, "le_2wt")
                } else {
                    bin!(CFG_MIN, "above_2wt")
                },
            ),
            (
                CFG_WINDOW,
                if p.pw == 0 {
                    bin!(CFG_WINDOW, "pw_zero")
                } else if p.pi == 0 {
                    bin!(CFG_WINDOW, "pi_zero")
                } else if p.ps == 1 {
                    bin!(CFG_WINDOW, "ps_one")
                } else {
                    bin!(CFG_WINDOW, "all_nonzero")
                },
            ),
            (
                CFG_SMP_ON,
                match p.smp_on {
                    0 | 1 => bin!(CFG_SMP_ON, "one"),
                    2..=9 => bin!(CFG_SMP_ON, "2_9"),
                    _ => bin!(CFG_SMP_ON, "10_up"),
                },
            ),
            (
                CFG_CNT_W,
                match p.cnt_width {
                    0..=2 => bin!(CFG_CNT_W, "2"),
                    3..=7 => bin!(CFG_CNT_W, "3_7"),
                    8..=15 => bin!(CFG_CNT_W, "8_15"),
                    _ => bin!(CFG_CNT_W, "16"),
                },
            ),
            (CFG_SYNC, p.sync_depth.clamp(1, 4) - 1),
            (
                CFG_ADAPTIVE,
                if p.adaptive {
                    bin!(CFG_ADAPTIVE, "adaptive")
                } else {
                    bin!(CFG_ADAPTIVE, "fixed")
                },
            ),
            (
                CFG_CLOCK,
                match self.clock_ns {
                    0..=9_999 => bin!(CFG_CLOCK, "below_10us"),
                    10_000 => bin!(CFG_CLOCK, "10us"),
                    _ => bin!(CFG_CLOCK, "above_10us"),
                },
            ),
        ];
        let off = &layout().point_offset;
        for (point, bin) in bins {
            self.config[point] = bin;
            self.count(off[point] + usize::from(bin));
        }
    }

    /// Sample one clock edge.
    #[inline]
    pub fn sample(&mut self, e: &Edge<'_>) {
        let (i, n) = (e.inputs, e.internals);
        if e.out.sig && !i.bus_we {
            self.hits[self.read_offset + usize::from(READ_BIN[usize::from(i.bus_addr)])] += 1;
        }
        let sync = e.before.action_switching.sync;
        let in_flight = sync != 0 && sync != self.sync_full;
        let diag_rise = e.after.count_diagnosis.diag && !e.before.count_diagnosis.diag;
        // A sample that moves nothing (most on-key strobes) hits no bin: only a first sample, a
        // sign change, or a strobe on a dead rail does.
        let moved = n.upd && (n.first || n.chg_s || n.chg_c);
        let dead = e.out.smp && !e.out.sr;
        // Vs2's power-good against its enable and Sr
        let pg = (e.out.sr && e.out.vs2_en && !i.vs2_ok) || (i.vs2_ok && !e.out.vs2_en);
        if i.bus_we
            || !self.started
            || pg
            || n.kon
            || n.koff
            || moved
            || n.fig17 != Fig17::Idle
            || n.skip_clr
            || dead
            || diag_rise
            || in_flight
        {
            self.sample_rare(e, in_flight, diag_rise);
        }
    }

    #[cold]
    #[inline(never)]
    fn sample_rare(&mut self, e: &Edge<'_>, in_flight: bool, diag_rise: bool) {
        let (b, a, out, i, n) = (e.before, e.after, e.out, e.inputs, e.internals);
        let p = b
            .register_file
            .params(self.structural.sync_depth, self.structural.cnt_width);
        let mut sel = self.config;
        let mode = u8::from(out.sig);
        if !self.started {
            self.started = true;
            sel[KEY_START] = if i.ig {
                bin!(KEY_START, "on")
            } else {
                bin!(KEY_START, "off")
            };
        }

        // FIG. 17 / FIG. 18 at a key-off sampling strobe.
        if n.fig17 != Fig17::Idle {
            sel[FIG17] = n.fig17 as u8 - 1;
            sel[SI_AT_EDGE] = thirds(b.drive_interval.si, p.si_min, p.si_max, true);
            let di = (&b.drive_interval, &a.drive_interval);
            match n.fig17 {
                Fig17::S5AtMin
                | Fig17::S6Shorten
                | Fig17::S7AtMax
                | Fig17::S9Count
                | Fig17::S10Expand => {
                    let r = di.0.cnt_r;
                    sel[CNT_R_BEFORE] = if r == 255 {
                        bin!(CNT_R_BEFORE, "saturated")
                    } else if r == 0 {
                        bin!(CNT_R_BEFORE, "zero")
                    } else if r < p.cth {
                        bin!(CNT_R_BEFORE, "below_cth")
                    } else {
                        bin!(CNT_R_BEFORE, "at_or_above_cth")
                    };
                }
                _ => {}
            }
            match n.fig17 {
                Fig17::S6Shorten => {
                    let raw = i32::from(di.0.si) - i32::from(p.t1);
                    let min = i32::from(p.si_min);
                    sel[SHORTEN_TO] = if raw < min {
                        bin!(SHORTEN_TO, "min_clamped")
                    } else if raw == min {
                        bin!(SHORTEN_TO, "min_exact")
                    } else {
                        // low, mid, high follow min_exact
                        bin!(SHORTEN_TO, "min_exact") + thirds(di.1.si, p.si_min, p.si_max, false)
                    };
                    if raw < 0 {
                        sel[CLAMP] = bin!(CLAMP, "min_below_zero");
                    } else if raw < min {
                        sel[CLAMP] = bin!(CLAMP, "min");
                    }
                }
                Fig17::S10Expand => {
                    let raw = u32::from(di.0.si) + u32::from(p.t2);
                    let x = u32::from(p.si_max);
                    sel[EXPAND_TO] = if raw > x {
                        bin!(EXPAND_TO, "x_clamped")
                    } else if raw == x {
                        bin!(EXPAND_TO, "x_exact")
                    } else {
                        // low, mid, high are the first three
                        bin!(EXPAND_TO, "low") + thirds(di.1.si, p.si_min, p.si_max, false) - 1
                    };
                    if raw > u32::from(u16::MAX) {
                        sel[CLAMP] = bin!(CLAMP, "x_past_16_bits");
                    } else if raw > x {
                        sel[CLAMP] = bin!(CLAMP, "x");
                    }
                }
                _ => {}
            }
            if matches!(n.fig17, Fig17::S9Count | Fig17::S10Expand) {
                let (r0, r1) = (di.0.cnt_r, di.1.cnt_r);
                sel[CNT_R] = if r0 == 255 {
                    bin!(CNT_R, "saturated")
                } else if r1 == 1 {
                    bin!(CNT_R, "one")
                } else if r1 < p.cth {
                    bin!(CNT_R, "below_cth")
                } else if r1 == p.cth {
                    bin!(CNT_R, "at_cth")
                } else {
                    bin!(CNT_R, "above_cth")
                };
            }
        }
        if n.fig18 != Fig18::Idle {
            sel[FIG18] = n.fig18 as u8 - 1;
            let d = &b.drive_interval;
            sel[HIST] = u8::from(d.hist_s) | u8::from(d.hist_c) << 1;
        }

        // Samples of the comparator latches: presets, counting rules, skips, wraps.
        if n.upd {
            let (cs, cc) = (b.comparator_latch.cs, b.comparator_latch.cc);
            if n.first {
                sel[SAMPLE_MODE] = mode;
                let l = &a.comparator_latch;
                sel[PRESET] = match (l.cs, l.cc) {
                    (true, true) => bin!(PRESET, "q0"),
                    (true, false) => bin!(PRESET, "q1"),
                    (false, false) => bin!(PRESET, "q2"),
                    (false, true) => bin!(PRESET, "q3"),
                };
            } else if n.chg_s && n.chg_c {
                sel[SAMPLE_MODE] = mode;
                sel[SKIP] = if !out.sig {
                    bin!(SKIP, "key_off")
                } else if n.skip_clr {
                    bin!(SKIP, "key_on_w1c")
                } else {
                    bin!(SKIP, "key_on")
                };
            } else if n.chg_s || n.chg_c {
                sel[SAMPLE_MODE] = mode;
                // (rule bin, counts up?)
                let (rule, up) = if n.chg_s {
                    match (cs, cc) {
                        (false, true) => (bin!(RULE, "s_0096_up"), true),
                        (true, true) => (bin!(RULE, "s_0096_down"), false),
                        (true, false) => (bin!(RULE, "s_0097_up"), true),
                        (false, false) => (bin!(RULE, "s_0097_down"), false),
                    }
                } else {
                    match (cc, cs) {
                        (false, false) => (bin!(RULE, "c_0098_up"), true),
                        (true, false) => (bin!(RULE, "c_0098_down"), false),
                        (true, true) => (bin!(RULE, "c_0099_up"), true),
                        (false, true) => (bin!(RULE, "c_0099_down"), false),
                    }
                };
                sel[RULE] = rule;
                let w = self.structural.cnt_width.clamp(2, 16);
                let top = (1u16 << (w - 1)) - 1;
                let v = if n.chg_s {
                    b.updown_counter.cnt_s
                } else {
                    b.updown_counter.cnt_c
                };
                if up && v == top {
                    sel[WRAP] = if n.chg_s {
                        bin!(WRAP, "cnt_s_up")
                    } else {
                        bin!(WRAP, "cnt_c_up")
                    };
                } else if !up && v == top + 1 {
                    sel[WRAP] = if n.chg_s {
                        bin!(WRAP, "cnt_s_down")
                    } else {
                        bin!(WRAP, "cnt_c_down")
                    };
                }
            }
        }

        // The counters' difference after a sample that moved the latches, modulo 2^CNT_W.
        if n.upd && (n.first || n.chg_s || n.chg_c) {
            let w = self.structural.cnt_width.clamp(2, 16);
            let mask = ((1u32 << w) - 1) as u16;
            let (s, c) = (a.updown_counter.cnt_s & mask, a.updown_counter.cnt_c & mask);
            sel[DIFFERENCE] = if s == mask && c == 0 {
                bin!(DIFFERENCE, "minus_one_wrap")
            } else if s.wrapping_add(1) & mask == c {
                bin!(DIFFERENCE, "minus_one")
            } else {
                bin!(DIFFERENCE, "zero")
            };
        }

        // Key edges and where in the timer's cycle they fell.
        if n.kon || n.koff {
            sel[KEY_EDGE] = if n.koff {
                bin!(KEY_EDGE, "off")
            } else {
                bin!(KEY_EDGE, "on")
            };
            let t = u32::from(b.timing_generator.tmr);
            let (pw, pi, wt) = (u32::from(p.pw), u32::from(p.pw) + u32::from(p.pi), p.wt());
            sel[KEY_PHASE] = if out.sig {
                if t + 1 == u32::from(p.smp_on) {
                    bin!(KEY_PHASE, "on_smp")
                } else {
                    bin!(KEY_PHASE, "on_between")
                }
            } else if t < pw {
                bin!(KEY_PHASE, "off_pw")
            } else if t < pi {
                bin!(KEY_PHASE, "off_pi")
            } else if t + 1 < wt {
                bin!(KEY_PHASE, "off_ps")
            } else if t + 1 == wt {
                bin!(KEY_PHASE, "off_smp")
            } else {
                bin!(KEY_PHASE, "off_gap")
            };
        }

        // Faults.
        if out.smp && !out.sr {
            sel[VS2] = mode;
            sel[DEAD_STROBE] = if b.comparator_latch.vld {
                bin!(DEAD_STROBE, "after_first")
            } else {
                bin!(DEAD_STROBE, "before_first")
            };
        }
        if out.sr && out.vs2_en && !i.vs2_ok {
            sel[PG_DROP] = bin!(PG_DROP, "sr_falls");
        }
        if i.vs2_ok && !out.vs2_en {
            sel[PG_UNPOWERED] = bin!(PG_UNPOWERED, "high");
        }
        if in_flight && i.ig != (b.action_switching.sync & 1 == 1) {
            sel[SYNC_GLITCH] = if i.ig {
                bin!(SYNC_GLITCH, "short_high")
            } else {
                bin!(SYNC_GLITCH, "short_low")
            };
        }
        if diag_rise {
            sel[DIAG] = if a.updown_counter.quadrant_skip {
                bin!(DIAG, "skip")
            } else {
                bin!(DIAG, "difference")
            };
        }
        let status_write = i.bus_we && out.sig && i.bus_addr == rf::addr::STATUS;
        let skip_set = b.updown_counter.quadrant_skip;
        if status_write && ((i.bus_wdata >> rf::status::QUADRANT_SKIP) & 1 == 1 || skip_set) {
            sel[SKIP_CLEAR] = if n.skip_clr && n.upd && !n.first && n.chg_s && n.chg_c {
                bin!(SKIP_CLEAR, "set_wins")
            } else if n.skip_clr && skip_set {
                bin!(SKIP_CLEAR, "cleared")
            } else if n.skip_clr {
                bin!(SKIP_CLEAR, "while_clear")
            } else {
                bin!(SKIP_CLEAR, "other_bit_while_set")
            };
        }

        // Bus writes.
        let mut params_changed = false;
        if i.bus_we {
            let a8 = i.bus_addr;
            sel[WRITE_REG] = match a8 {
                // the parameter registers in address order, CTRL first
                rf::addr::CTRL..=rf::addr::SMP_ON => {
                    bin!(WRITE_REG, "ctrl") + (a8 - rf::addr::CTRL)
                }
                rf::addr::STATUS => bin!(WRITE_REG, "status"),
                _ if READ_BIN[usize::from(a8)] < READ_ADDRS.len() as u8 => {
                    bin!(WRITE_REG, "read_only")
                }
                _ => bin!(WRITE_REG, "unmapped"),
            };
            let rfi = rf::Inputs {
                bus_we: true,
                bus_addr: a8,
                bus_wdata: i.bus_wdata,
                sig: out.sig,
                ..Default::default()
            };
            let (sd, cw) = (self.structural.sync_depth, self.structural.cnt_width);
            let block = rf::RegisterFile::new(sd, cw);
            let result = block.bus_write(&b.register_file, &rfi);
            if let Ok(Some(cand)) = &result {
                // a taken parameter write
                let np = cand.params(sd, cw);
                sel[LEGAL_AT_BOUND] = if np.si_min == np.si_max {
                    bin!(LEGAL_AT_BOUND, "min_eq_max")
                } else if np.wt() + 1 == u32::from(np.shortest_interval()) {
                    bin!(LEGAL_AT_BOUND, "wt_shortest_minus_one")
                } else if u32::from(np.pw) + u32::from(np.pi) == 1 {
                    bin!(LEGAL_AT_BOUND, "settle_one")
                } else {
                    NONE
                };
                if np != p {
                    sel[WRITE_CHANGES] = bin!(WRITE_CHANGES, "ctrl") + (a8 - rf::addr::CTRL);
                }
                if n.koff && a8 == rf::addr::SI_MAX {
                    sel[OFF_EDGE_WRITE] = bin!(OFF_EDGE_WRITE, "si_max");
                }
                if a8 == rf::addr::SMP_ON {
                    let t = u32::from(b.timing_generator.tmr);
                    sel[PERIOD_WRITE] = if u32::from(np.smp_on) <= t && t + 1 < u32::from(p.smp_on)
                    {
                        bin!(PERIOD_WRITE, "behind_timer")
                    } else {
                        bin!(PERIOD_WRITE, "ahead")
                    };
                }
            }
            sel[WRITE_OUTCOME] = match result {
                Ok(_) => bin!(WRITE_OUTCOME, "taken"),
                Err(WriteRefusal::KeyOff) => bin!(WRITE_OUTCOME, "refused_key_off"),
                Err(WriteRefusal::NotWritable) => bin!(WRITE_OUTCOME, "refused_not_writable"),
                Err(WriteRefusal::Illegal(err)) => {
                    sel[ILLEGAL] = match err {
                        ParamError::Zero { .. } => bin!(ILLEGAL, "zero_period"),
                        ParamError::MinAboveMax { min, max }
                            if u32::from(min) == u32::from(max) + 1 =>
                        {
                            bin!(ILLEGAL, "min_above_max_by_one")
                        }
                        ParamError::MinAboveMax { .. } => bin!(ILLEGAL, "min_above_max"),
                        ParamError::NoSettlingTick => bin!(ILLEGAL, "no_settling_tick"),
                        // the refusal names the interval it compared Wt with
                        ParamError::WindowTooLong { wt, interval, .. } => {
                            if u32::from(interval) == wt {
                                bin!(ILLEGAL, "window_at_shortest")
                            } else {
                                bin!(ILLEGAL, "window_too_long")
                            }
                        }
                        ParamError::OutOfRange { .. } if i.bus_wdata >> 8 != 0 => {
                            bin!(ILLEGAL, "cth_zero_high_bits")
                        }
                        ParamError::OutOfRange { .. } => bin!(ILLEGAL, "cth_zero"),
                    };
                    bin!(WRITE_OUTCOME, "refused_illegal")
                }
            };
            if a8 == rf::addr::STATUS && out.sig {
                let bit = |k: usize| (i.bus_wdata >> k) & 1 == 1;
                sel[W1C] = match (bit(rf::status::QUADRANT_SKIP), bit(rf::status::BUS_ERR)) {
                    (false, false) => bin!(W1C, "none"),
                    (true, false) if out.quadrant_skip => bin!(W1C, "quadrant_skip_set"),
                    (true, false) => bin!(W1C, "quadrant_skip_clear"),
                    (false, true) if out.bus_err => bin!(W1C, "bus_err_set"),
                    (false, true) => bin!(W1C, "bus_err_clear"),
                    (true, true) => bin!(W1C, "both"),
                };
            }
            params_changed = sel[WRITE_OUTCOME] == bin!(WRITE_OUTCOME, "taken")
                && a.register_file
                    .params(self.structural.sync_depth, self.structural.cnt_width)
                    != p;
        }

        let l = layout();
        for (point, &bin) in sel.iter().enumerate() {
            if bin != NONE && POINTS[point].sampled == Sampled::Edge {
                self.count(l.point_offset[point] + usize::from(bin));
            }
        }
        for (c, &off) in crosses().zip(&l.cross_offset) {
            let (x, y) = (sel[c.rows], sel[c.columns]);
            if x != NONE
                && y != NONE
                && (POINTS[c.rows].sampled == Sampled::Edge
                    || POINTS[c.columns].sampled == Sampled::Edge)
            {
                self.count(off + usize::from(x) * POINTS[c.columns].bins.len() + usize::from(y));
            }
        }
        if params_changed {
            let np = a
                .register_file
                .params(self.structural.sync_depth, self.structural.cnt_width);
            self.sample_config(&np);
        }
    }
}

/// The class of `si` in [min, x]: with `ends`, 0 = min, 1-3 = thirds, 4 = x; without, the
/// thirds as 1-3 (the caller has handled the ends).
fn thirds(si: u16, min: u16, max: u16, ends: bool) -> u8 {
    if ends && si <= min {
        return 0;
    }
    if ends && si >= max {
        return 4;
    }
    let span = u32::from(max.saturating_sub(min)).max(1);
    let pos = u32::from(si.saturating_sub(min)) * 3;
    if pos <= span {
        1
    } else if pos <= 2 * span {
        2
    } else {
        3
    }
}
