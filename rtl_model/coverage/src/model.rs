//! The coverage model, declared once: every coverpoint with its bins, every cross, each citing
//! the patent paragraph or the docs/spec.md section it measures, and the bins that can never be
//! hit, each with its reason.
//!
//! A bin's full name is `group.point.bin` (crosses: `cross.<name>.<bin a>*<bin b>`); the list of
//! names and their order is the model's identity ([`model_id`]), which every coverage file
//! carries, so two files merge only if they were sampled with the same model.

/// One bin of a coverpoint.
#[derive(Clone, Copy, Debug)]
pub struct Bin {
    pub name: &'static str,
    pub meaning: &'static str,
    /// How the bin is classified, as a Verilog expression over the coverage monitor's signals
    /// (hdl/formal/pmu50_cov.sv, [`crate::monitor`]): the first bin of its point, in
    /// declaration order, whose expression holds at a sampled edge is the one hit.
    pub sv: &'static str,
    /// How the directed generator aims at the bin (verif/src/gen.rs).
    pub hint: Hint,
}

/// How the regression's directed generator (verif/src/gen.rs) aims at a bin that is still
/// empty. Every bin declares one; a test fails when a reachable bin has none, or when a knob
/// named here is not one of the generator's.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Hint {
    /// The generator's knobs (`Knob` of verif/src/gen.rs, by name) that make the bin likely:
    /// a directed seed aimed at the bin forces them all.
    Knobs(&'static [&'static str]),
    /// Seeds hit it without any knob: a default class of the configuration, or a path that
    /// every run with motion and the key on and off takes.
    AnySeed,
    /// Only port-level stimuli reach it (cocotb, a DPI bench, the formal witness replayed): no
    /// scenario can, so the generator does not aim at it.
    PortLevel,
    /// Declared unreachable (the point's `unreachable` list): nothing to aim at.
    Never,
}

/// `knobs!(FastMoves, StatusWrites)`: the knobs of a [`Hint`], named as the generator's `Knob`s.
macro_rules! knobs {
    ($($k:ident),+ $(,)?) => {
        Hint::Knobs(&[$(stringify!($k)),+])
    };
}

const ANY: Hint = Hint::AnySeed;
const PORT: Hint = Hint::PortLevel;
const NEVER: Hint = Hint::Never;

/// When a coverpoint is sampled.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Sampled {
    /// At the clock edges where its condition holds.
    Edge,
    /// Once per run and at every change of the parameter registers (a taken write): the
    /// configuration in force. Its bin also stays selected for the crosses of later edges.
    Config,
}

/// A coverpoint.
#[derive(Clone, Copy, Debug)]
pub struct Point {
    pub group: &'static str,
    pub name: &'static str,
    pub cite: &'static str,
    pub meaning: &'static str,
    pub sampled: Sampled,
    /// When the point is sampled, as a Verilog expression over the monitor's signals (empty for
    /// a [`Sampled::Config`] point: at the start of a run and at a write that changes the
    /// parameters, with its bins' expressions over the parameter registers).
    pub when: &'static str,
    pub bins: &'static [Bin],
    /// Bins that can never be hit: (bin name, reason).
    pub unreachable: &'static [(&'static str, &'static str)],
}

/// A cross of two coverpoints: hit at an edge where both are selected.
#[derive(Clone, Copy, Debug)]
pub struct Cross {
    pub name: &'static str,
    pub cite: &'static str,
    pub meaning: &'static str,
    /// The crossed points (indices in [`POINTS`]): a cross bin is (bin of `rows`, bin of `columns`),
    /// shown as a matrix in the report.
    pub rows: usize,
    pub columns: usize,
    /// Why the pair (bin of `rows`, bin of `columns`) can never be hit, if it cannot.
    pub unreachable: fn(&str, &str) -> Option<&'static str>,
    /// Knobs a pair needs besides those of its two bins' hints (by name, as [`Hint::Knobs`]).
    pub hint: fn(&str, &str) -> &'static [&'static str],
}

macro_rules! bins {
    ($($name:literal : $meaning:literal => $sv:literal ; $hint:expr),* $(,)?) => {
        &[$(Bin { name: $name, meaning: $meaning, sv: $sv, hint: $hint }),*]
    };
}

// Point indices, looked up in POINTS by name at compile time (a name that is not declared
// does not compile).
pub const FIG17: usize = point_index("fig17", "path");
pub const FIG18: usize = point_index("fig18", "path");
pub const RULE: usize = point_index("counter", "rule");
pub const SAMPLE_MODE: usize = point_index("counter", "sample_mode");
pub const WRAP: usize = point_index("counter", "wrap");
pub const PRESET: usize = point_index("counter", "preset");
pub const SKIP: usize = point_index("counter", "quadrant_skip");
pub const SHORTEN_TO: usize = point_index("interval", "shorten_to");
pub const EXPAND_TO: usize = point_index("interval", "expand_to");
pub const SI_AT_EDGE: usize = point_index("interval", "at_edge");
pub const CLAMP: usize = point_index("interval", "clamp");
pub const CNT_R: usize = point_index("cnt_r", "value");
pub const CNT_R_BEFORE: usize = point_index("cnt_r", "before");
pub const HIST: usize = point_index("fig18", "history");
pub const KEY_EDGE: usize = point_index("key", "edge");
pub const KEY_PHASE: usize = point_index("key", "phase");
pub const VS2: usize = point_index("faults", "vs2");
pub const SYNC_GLITCH: usize = point_index("faults", "sync_glitch");
pub const DIAG: usize = point_index("faults", "diag");
pub const SKIP_CLEAR: usize = point_index("faults", "skip_clear");
pub const READ: usize = point_index("bus", "read");
pub const WRITE_REG: usize = point_index("bus", "write_reg");
pub const WRITE_OUTCOME: usize = point_index("bus", "write_outcome");
pub const ILLEGAL: usize = point_index("bus", "illegal_rule");
pub const W1C: usize = point_index("bus", "w1c");
pub const LEGAL_AT_BOUND: usize = point_index("bus", "legal_at_bound");
pub const WRITE_CHANGES: usize = point_index("bus", "write_changes");
pub const DEAD_STROBE: usize = point_index("faults", "dead_strobe");
pub const PG_DROP: usize = point_index("faults", "pg_drop");
pub const PG_UNPOWERED: usize = point_index("faults", "pg_unpowered");
pub const OFF_EDGE_WRITE: usize = point_index("key", "off_edge_write");
pub const KEY_START: usize = point_index("key", "start");
pub const PERIOD_WRITE: usize = point_index("timer", "period_write");
pub const DIFFERENCE: usize = point_index("counter", "difference");
pub const CFG_CTH: usize = point_index("config", "cth");
pub const CFG_T1: usize = point_index("config", "t1");
pub const CFG_T2: usize = point_index("config", "t2");
pub const CFG_X: usize = point_index("config", "x");
pub const CFG_MIN: usize = point_index("config", "min");
pub const CFG_WINDOW: usize = point_index("config", "window");
pub const CFG_SMP_ON: usize = point_index("config", "smp_on");
pub const CFG_CNT_W: usize = point_index("config", "cnt_w");
pub const CFG_SYNC: usize = point_index("config", "sync_depth");
pub const CFG_ADAPTIVE: usize = point_index("config", "adaptive");
pub const CFG_CLOCK: usize = point_index("config", "clock");

/// The readable register addresses, in the order of the `bus.read` bins (the last bin is
/// every other address).
pub const READ_ADDRS: [u8; 18] = [
    0x00, 0x01, 0x02, 0x03, 0x04, 0x05, 0x06, 0x07, 0x08, 0x09, 0x0A, 0x0B, 0x0C, 0x10, 0x11, 0x12,
    0x13, 0x14,
];

/// Every coverpoint.
pub static POINTS: [Point; 45] = POINT_TABLE;

const POINT_TABLE: [Point; 45] = [
    Point {
        group: "fig17",
        name: "path",
        cite: "FIG. 17, [0216]-[0262]; docs/spec.md 2.6",
        meaning: "the branch the drive interval changing unit took at a key-off sampling strobe",
        sampled: Sampled::Edge,
        when: "fig17 != 3'd0",
        bins: bins!(
            "s1_no_rise": "S1: N, the activation signal Sr did not rise (Vs2 rail dead): nothing changes" => "fig17 == 3'd1"; knobs!(Faults),
            "s5_at_min": "S3: Y, S4, S5: Y: rotation at the minimum interval, cnt_r := 0, si held" => "fig17 == 3'd2"; ANY,
            "s6_shorten": "S3: Y, S4, S5: N, S6: rotation, si shortened by T1" => "fig17 == 3'd3"; ANY,
            "s7_at_max": "S3: N, S7: Y: quiet at the maximum interval x, nothing changes" => "fig17 == 3'd4"; ANY,
            "s9_count": "S3: N, S7: N, S8: N, S9: quiet, cnt_r += 1" => "fig17 == 3'd5"; ANY,
            "s10_expand": "S8: Y, S10, S11, S9: quiet for Cth pulses, si expanded by T2, history cleared" => "fig17 == 3'd6"; ANY,
            "fixed": "adaptive = 0 (first embodiment): si := x" => "fig17 == 3'd7"; knobs!(Fixed),
        ),
        unreachable: &[],
    },
    Point {
        group: "fig18",
        name: "path",
        cite: "FIG. 18, [0263]-[0291]; docs/spec.md 2.6",
        meaning: "the branch of the rotation detection at a key-off sampling strobe",
        sampled: Sampled::Edge,
        when: "fig18 != 3'd0",
        bins: bins!(
            "s23_detected_cs": "S20: Y, S21: N, S22, S23: rotation detected through Cs" => "fig18 == 3'd1"; knobs!(FastMoves),
            "s21_cs_repeat": "S20: Y, S21: Y, S24: Cs changed again before Cc ([0232]-[0236])" => "fig18 == 3'd2"; knobs!(FastMoves),
            "s28_detected_cc": "S20: N, S25: Y, S26: N, S27, S28: rotation detected through Cc" => "fig18 == 3'd3"; knobs!(FastMoves),
            "s26_cc_repeat": "S25: Y, S26: Y, S24: Cc changed again before Cs" => "fig18 == 3'd4"; knobs!(FastMoves),
            "s25_no_change": "S20: N, S25: N, S24: no sign changed" => "fig18 == 3'd5"; knobs!(FastMoves),
        ),
        unreachable: &[],
    },
    Point {
        group: "counter",
        name: "rule",
        cite: "[0096]-[0099]; docs/spec.md 2.5",
        meaning: "the counting rule applied at a sample where exactly one sign changed",
        sampled: Sampled::Edge,
        when: "upd && !first && (chg_s != chg_c)",
        bins: bins!(
            "s_0096_up": "[0096] Cs 0->1 while Cc = 1: cnt_s + 1" => "chg_s && !cs && cc"; ANY,
            "s_0096_down": "[0096] Cs 1->0 while Cc = 1: cnt_s - 1" => "chg_s && cs && cc"; ANY,
            "s_0097_up": "[0097] Cs 1->0 while Cc = 0: cnt_s + 1" => "chg_s && cs && !cc"; ANY,
            "s_0097_down": "[0097] Cs 0->1 while Cc = 0: cnt_s - 1" => "chg_s && !cs && !cc"; ANY,
            "c_0098_up": "[0098] Cc 0->1 while Cs = 0: cnt_c + 1" => "chg_c && !cc && !cs"; ANY,
            "c_0098_down": "[0098] Cc 1->0 while Cs = 0: cnt_c - 1" => "chg_c && cc && !cs"; ANY,
            "c_0099_up": "[0099] Cc 1->0 while Cs = 1: cnt_c + 1" => "chg_c && cc && cs"; ANY,
            "c_0099_down": "[0099] Cc 0->1 while Cs = 1: cnt_c - 1" => "chg_c && !cc && cs"; ANY,
        ),
        unreachable: &[],
    },
    Point {
        group: "counter",
        name: "sample_mode",
        cite: "[0331]-[0349]; docs/spec.md 2.2",
        meaning: "whether a sample that moved the latches was taken with the key off (intermittent Vs2) or on (on-key sampling)",
        sampled: Sampled::Edge,
        when: "upd && (first || chg_s || chg_c)",
        bins: bins!("key_off": "sample of a key-off output pulse" => "!sig"; ANY, "key_on": "on-key sample, every smp_on ticks" => "sig"; ANY),
        unreachable: &[],
    },
    Point {
        group: "counter",
        name: "wrap",
        cite: "docs/spec.md 2.5 (cnt_width bits, two's complement, wrapping like hardware)",
        meaning: "a counter stepping past its extreme value at the configured width",
        sampled: Sampled::Edge,
        when: "upd && !first && (chg_s != chg_c)",
        bins: bins!(
            "cnt_s_up": "cnt_s + 1 from the largest value 2^(W-1)-1 to -2^(W-1)" => "chg_s && (cs != cc) && cnt_s == CNT_TOP"; knobs!(Spin),
            "cnt_s_down": "cnt_s - 1 from -2^(W-1) to 2^(W-1)-1" => "chg_s && (cs == cc) && cnt_s == CNT_MIN"; knobs!(Spin),
            "cnt_c_up": "cnt_c + 1 from the largest value to the smallest" => "chg_c && (cc == cs) && cnt_c == CNT_TOP"; knobs!(Spin),
            "cnt_c_down": "cnt_c - 1 from the smallest value to the largest" => "chg_c && (cc != cs) && cnt_c == CNT_MIN"; knobs!(Spin),
        ),
        unreachable: &[],
    },
    Point {
        group: "counter",
        name: "preset",
        cite: "[0092]-[0093]; docs/spec.md 2.5 (first sample after reset)",
        meaning: "the quadrant of the first sample, which presets the counters",
        sampled: Sampled::Edge,
        when: "first",
        bins: bins!(
            "q0": "Cs = 1, Cc = 1: (0, 0)" => "cmp_s && cmp_c"; ANY,
            "q1": "Cs = 1, Cc = 0: (0, 1)" => "cmp_s && !cmp_c"; ANY,
            "q2": "Cs = 0, Cc = 0: (1, 1)" => "!cmp_s && !cmp_c"; ANY,
            "q3": "Cs = 0, Cc = 1: (1, 2)" => "!cmp_s && cmp_c"; ANY,
        ),
        unreachable: &[],
    },
    Point {
        group: "counter",
        name: "quadrant_skip",
        cite: "docs/spec.md 2.5 (both signs change in one sample)",
        meaning: "a sample where both signs changed: the counters hold and quadrant_skip is set",
        sampled: Sampled::Edge,
        when: "upd && !first && chg_s && chg_c",
        bins: bins!(
            "key_off": "at a key-off sample" => "!sig"; knobs!(FastMoves),
            "key_on_w1c": "at an on-key sample on the edge of the MPU's W1C of STATUS.quadrant_skip: the set wins" => "skip_clr"; knobs!(StatusWrites, FastMoves),
            "key_on": "at an on-key sample" => "1'b1"; knobs!(FastMoves),
        ),
        unreachable: &[],
    },
    Point {
        group: "interval",
        name: "shorten_to",
        cite: "[0224]-[0228], [0260]-[0262]; docs/spec.md 2.6",
        meaning: "where S6 put the drive interval in [min, x] (thirds of the span)",
        sampled: Sampled::Edge,
        when: "fig17 == 3'd3",
        bins: bins!(
            "min_clamped": "si - T1 < min: clamped to min ([0260]-[0262])" => "{1'b0, si} < {1'b0, t1} + {1'b0, si_min}"; knobs!(FastMoves),
            "min_exact": "si - T1 = min" => "{1'b0, si} == {1'b0, t1} + {1'b0, si_min}"; knobs!(ExactStep, FastMoves),
            "low": "min < si' <= min + span/3" => "th_si_n == 3'd1"; knobs!(FastMoves),
            "mid": "min + span/3 < si' <= min + 2 span/3" => "th_si_n == 3'd2"; knobs!(FastMoves),
            "high": "si' > min + 2 span/3 (si' < x)" => "th_si_n == 3'd3"; knobs!(FastMoves),
        ),
        unreachable: &[],
    },
    Point {
        group: "interval",
        name: "expand_to",
        cite: "[0250]-[0258], [0260]; docs/spec.md 2.6",
        meaning: "where S10 put the drive interval in [min, x] (thirds of the span)",
        sampled: Sampled::Edge,
        when: "fig17 == 3'd6",
        bins: bins!(
            "low": "si' <= min + span/3 (si' > min)" => "{1'b0, si} + {1'b0, t2} < {1'b0, si_max} && th_si_n == 3'd1"; knobs!(FastMoves),
            "mid": "min + span/3 < si' <= min + 2 span/3" => "{1'b0, si} + {1'b0, t2} < {1'b0, si_max} && th_si_n == 3'd2"; knobs!(FastMoves),
            "high": "min + 2 span/3 < si' < x" => "{1'b0, si} + {1'b0, t2} < {1'b0, si_max} && th_si_n == 3'd3"; knobs!(FastMoves),
            "x_exact": "si + T2 = x" => "{1'b0, si} + {1'b0, t2} == {1'b0, si_max}"; knobs!(ExactStep, FastMoves),
            "x_clamped": "si + T2 > x: clamped to x ([0260])" => "{1'b0, si} + {1'b0, t2} > {1'b0, si_max}"; knobs!(FastMoves),
        ),
        unreachable: &[],
    },
    Point {
        group: "interval",
        name: "at_edge",
        cite: "[0216]-[0228]; docs/spec.md 2.6",
        meaning: "the drive interval in force at a key-off sample (thirds of [min, x])",
        sampled: Sampled::Edge,
        when: "fig17 != 3'd0",
        bins: bins!(
            "min": "si = min" => "th_si == 3'd0"; knobs!(FastMoves),
            "low": "min < si <= min + span/3" => "th_si == 3'd1"; knobs!(FastMoves),
            "mid": "min + span/3 < si <= min + 2 span/3" => "th_si == 3'd2"; knobs!(FastMoves),
            "high": "min + 2 span/3 < si < x" => "th_si == 3'd3"; knobs!(FastMoves),
            "x": "si = x" => "th_si == 3'd4"; knobs!(FastMoves),
        ),
        unreachable: &[],
    },
    Point {
        group: "interval",
        name: "clamp",
        cite: "[0260]-[0262]",
        meaning: "a step of the drive interval cut short by a limit",
        sampled: Sampled::Edge,
        when: "fig17 == 3'd3 || fig17 == 3'd6",
        bins: bins!(
            "min_below_zero": "S6: si - T1 below 0, saturated at 0 before the clamp to min (16-bit arithmetic)" => "fig17 == 3'd3 && si < t1"; knobs!(LongQuiet),
            "min": "S6: si - T1 in [0, min), clamped to min" => "fig17 == 3'd3 && {1'b0, si} < {1'b0, t1} + {1'b0, si_min}"; knobs!(FastMoves),
            "x_past_16_bits": "S10: si + T2 past 65535 (the 17th bit) before the clamp to x" => "fig17 == 3'd6 && {1'b0, si} + {1'b0, t2} > 17'h0FFFF"; knobs!(LongQuiet),
            "x": "S10: si + T2 in (x, 65535], clamped to x" => "fig17 == 3'd6 && {1'b0, si} + {1'b0, t2} > {1'b0, si_max}"; knobs!(FastMoves),
        ),
        unreachable: &[],
    },
    Point {
        group: "cnt_r",
        name: "value",
        cite: "[0248]-[0250]; docs/spec.md 2.6",
        meaning: "the power supply count after a quiet key-off pulse (S9), by class up to its 8-bit saturation",
        sampled: Sampled::Edge,
        when: "fig17 == 3'd5 || fig17 == 3'd6",
        bins: bins!(
            "one": "cnt_r becomes 1" => "cnt_r != 8'hFF && cnt_r_n == 8'd1"; ANY,
            "below_cth": "1 < cnt_r' < Cth" => "cnt_r != 8'hFF && cnt_r_n < cth"; ANY,
            "at_cth": "cnt_r' = Cth" => "cnt_r != 8'hFF && cnt_r_n == cth"; ANY,
            "above_cth": "Cth < cnt_r' < 255 (the interval could not expand further)" => "cnt_r != 8'hFF"; knobs!(LongQuiet),
            "saturated": "cnt_r was 255 and stays 255 (8-bit saturation)" => "1'b1"; knobs!(LongQuiet),
        ),
        unreachable: &[],
    },
    Point {
        group: "cnt_r",
        name: "before",
        cite: "[0248], S4 of FIG. 17",
        meaning: "the power supply count at a key-off sample where the sensor answered",
        sampled: Sampled::Edge,
        when: "fig17 >= 3'd2 && fig17 <= 3'd6",
        bins: bins!(
            "zero": "cnt_r = 0" => "cnt_r == 8'd0"; ANY,
            "below_cth": "0 < cnt_r < Cth" => "cnt_r < cth"; ANY,
            "at_or_above_cth": "Cth <= cnt_r < 255" => "cnt_r != 8'hFF"; ANY,
            "saturated": "cnt_r = 255" => "1'b1"; knobs!(LongQuiet),
        ),
        unreachable: &[],
    },
    Point {
        group: "fig18",
        name: "history",
        cite: "[0237]-[0241]; docs/spec.md 2.6",
        meaning: "the change history flip-flops before a FIG. 18 evaluation",
        sampled: Sampled::Edge,
        when: "fig18 != 3'd0",
        bins: bins!("none": "hist_s = 0, hist_c = 0" => "!hist_s && !hist_c"; knobs!(FastMoves), "s": "hist_s = 1" => "hist_s && !hist_c"; knobs!(FastMoves), "c": "hist_c = 1" => "!hist_s && hist_c"; knobs!(FastMoves), "both": "hist_s = 1 and hist_c = 1" => "hist_s && hist_c"; NEVER),
        unreachable: &[("both", "S23 sets hist_s and clears hist_c, S28 the reverse, S11 and key-off clear both: no path sets both (docs/spec.md 2.6)")],
    },
    Point {
        group: "key",
        name: "edge",
        cite: "[0196]-[0198], [0213]; docs/spec.md 2.1",
        meaning: "an edge of the synchronised key sig",
        sampled: Sampled::Edge,
        when: "kon || koff",
        bins: bins!("on": "sig rises (kon)" => "!koff"; knobs!(KeyStorm), "off": "sig falls (koff): si reloads to x" => "koff"; knobs!(KeyStorm)),
        unreachable: &[],
    },
    Point {
        group: "key",
        name: "phase",
        cite: "[0319]-[0323], [0349]; docs/spec.md 2.2",
        meaning: "where in the timing generator's cycle a key edge fell",
        sampled: Sampled::Edge,
        when: "kon || koff",
        bins: bins!(
            "off_pw": "key off, inside the waiting period Pw of an output pulse" => "!sig && t18 < pw18"; knobs!(KeyStorm),
            "off_pi": "key off, inside the idle period Pi" => "!sig && t18 < pw18 + pi18"; knobs!(KeyStorm),
            "off_ps": "key off, inside the sampling period Ps before its last tick" => "!sig && t18 + 18'd1 < wt18"; knobs!(KeyStorm),
            "off_smp": "key off, the sampling tick (last tick of Ps)" => "!sig && t18 + 18'd1 == wt18"; knobs!(KeyStorm),
            "off_gap": "key off, between two output pulses (Vs2 off)" => "!sig"; knobs!(KeyStorm),
            "on_smp": "key on, the on-key sampling tick" => "t18 + 18'd1 == {2'b00, smp_on}"; knobs!(KeyStorm),
            "on_between": "key on, between on-key samples" => "1'b1"; knobs!(KeyStorm),
        ),
        unreachable: &[],
    },
    Point {
        group: "faults",
        name: "vs2",
        cite: "[0209], [0347]; docs/spec.md 2.3",
        meaning: "a sampling strobe with Vs2 enabled but its power-good low, so Sr is 0 and no sample is taken",
        sampled: Sampled::Edge,
        when: "smp && !sr",
        bins: bins!("key_off": "a key-off strobe on a dead rail (FIG. 17 S1: N)" => "!sig"; knobs!(Faults), "key_on": "an on-key strobe on a dead rail" => "sig"; knobs!(Faults)),
        unreachable: &[],
    },
    Point {
        group: "faults",
        name: "sync_glitch",
        cite: "[0213]; docs/spec.md 2.1",
        meaning: "ig toggles again while its previous edge is still inside the synchronizer",
        sampled: Sampled::Edge,
        when: "in_flight && (ig != sync[0])",
        bins: bins!("short_high": "a high pulse of ig shorter than the synchronizer" => "ig"; knobs!(Glitches), "short_low": "a low pulse of ig shorter than the synchronizer" => "!ig"; knobs!(Glitches)),
        unreachable: &[],
    },
    Point {
        group: "faults",
        name: "diag",
        cite: "[0119]; docs/spec.md 2.7",
        meaning: "the count diagnosis flag rising, by cause",
        sampled: Sampled::Edge,
        when: "diag_n && !diag",
        bins: bins!("skip": "a quadrant was skipped (counts equal but half a turn off)" => "skip_n"; knobs!(FastMoves), "difference": "|cnt_s - cnt_c| >= 2 without a skip" => "!skip_n"; NEVER),
        unreachable: &[("difference", "cnt_s - cnt_c is 0 in quadrants 0 and 2 and -1 in 1 and 3 after every preset, counting rule and skip (each rule of [0096]-[0099] moves the counter that keeps it so, and a skip keeps the quadrant's parity): the difference guards against a corrupted counter, which no input can cause")],
    },
    Point {
        group: "faults",
        name: "skip_clear",
        cite: "docs/spec.md 2.8 (STATUS.quadrant_skip is W1C)",
        meaning: "a STATUS write that writes bit 5 (W1C of quadrant_skip) or finds the flag set, by the flag's state",
        sampled: Sampled::Edge,
        when: "sig && bus_we && bus_addr == 8'h14 && (bus_wdata[5] || quadrant_skip)",
        bins: bins!(
            "set_wins": "W1C of bit 5 on the edge a skip sets the flag: the set wins (docs/spec.md 2.5)" => "skip_clr && upd && !first && chg_s && chg_c"; knobs!(StatusWrites, FastMoves),
            "cleared": "W1C of bit 5 while the flag is set: the sticky skip flag cleared by the MPU" => "skip_clr && quadrant_skip"; knobs!(StatusWrites, FastMoves),
            "while_clear": "W1C of bit 5 while the flag is clear: nothing changes" => "skip_clr"; knobs!(StatusWrites),
            "other_bit_while_set": "a STATUS write without bit 5 (bit 4, say) while the flag is set: it stays set" => "1'b1"; knobs!(StatusWrites, FastMoves),
        ),
        unreachable: &[],
    },
    Point {
        group: "bus",
        name: "read",
        cite: "[0108], [0163]; docs/spec.md 2.8",
        meaning: "the address read by the MPU in a key-on cycle without a write",
        sampled: Sampled::Edge,
        when: "sig && !bus_we",
        bins: bins!(
            "id": "0x00 ID" => "bus_addr == 8'h00"; ANY, "version": "0x01 VERSION" => "bus_addr == 8'h01"; ANY, "ctrl": "0x02 CTRL" => "bus_addr == 8'h02"; ANY, "pw": "0x03 PW" => "bus_addr == 8'h03"; ANY, "pi": "0x04 PI" => "bus_addr == 8'h04"; ANY, "ps": "0x05 PS" => "bus_addr == 8'h05"; ANY,
            "si_max": "0x06 SI_MAX" => "bus_addr == 8'h06"; ANY, "si_min": "0x07 SI_MIN" => "bus_addr == 8'h07"; ANY, "t1": "0x08 T1" => "bus_addr == 8'h08"; ANY, "t2": "0x09 T2" => "bus_addr == 8'h09"; ANY, "cth": "0x0A CTH" => "bus_addr == 8'h0A"; ANY, "smp_on": "0x0B SMP_ON" => "bus_addr == 8'h0B"; ANY,
            "cfg": "0x0C CFG" => "bus_addr == 8'h0C"; ANY, "cnt_s": "0x10 CNT_S" => "bus_addr == 8'h10"; ANY, "cnt_c": "0x11 CNT_C" => "bus_addr == 8'h11"; ANY, "cnt_r": "0x12 CNT_R" => "bus_addr == 8'h12"; ANY, "si": "0x13 SI" => "bus_addr == 8'h13"; ANY, "status": "0x14 STATUS" => "bus_addr == 8'h14"; ANY,
            "unmapped": "any other address (reads 0)" => "1'b1"; PORT,
        ),
        unreachable: &[],
    },
    Point {
        group: "bus",
        name: "write_reg",
        cite: "docs/spec.md 2.8 (register map)",
        meaning: "the register a bus write addressed",
        sampled: Sampled::Edge,
        when: "bus_we",
        bins: bins!(
            "ctrl": "CTRL" => "bus_addr == 8'h02"; ANY, "pw": "PW" => "bus_addr == 8'h03"; ANY, "pi": "PI" => "bus_addr == 8'h04"; ANY, "ps": "PS" => "bus_addr == 8'h05"; ANY, "si_max": "SI_MAX" => "bus_addr == 8'h06"; ANY, "si_min": "SI_MIN" => "bus_addr == 8'h07"; ANY, "t1": "T1" => "bus_addr == 8'h08"; ANY, "t2": "T2" => "bus_addr == 8'h09"; ANY,
            "cth": "CTH" => "bus_addr == 8'h0A"; ANY, "smp_on": "SMP_ON" => "bus_addr == 8'h0B"; ANY, "status": "STATUS (W1C)" => "bus_addr == 8'h14"; knobs!(StatusWrites), "read_only": "ID, VERSION, CFG, CNT_*, SI" => "readable"; PORT, "unmapped": "an address outside the map" => "1'b1"; PORT,
        ),
        unreachable: &[],
    },
    Point {
        group: "bus",
        name: "write_outcome",
        cite: "[0205], [0259]; docs/spec.md 2.8 and 4",
        meaning: "what the register file did with a bus write",
        sampled: Sampled::Edge,
        when: "bus_we",
        bins: bins!(
            "taken": "written (a parameter register, or a STATUS W1C)" => "sig && (bus_addr == 8'h14 || (is_param && c_legal))"; ANY,
            "refused_key_off": "refused: sig = 0, the MPU is not powered ([0205])" => "!sig"; knobs!(EarlyWrites),
            "refused_not_writable": "refused: read-only or unmapped address" => "!is_param"; PORT,
            "refused_illegal": "refused: the parameter set would become illegal (docs/spec.md 4)" => "1'b1"; knobs!(IllegalWrites),
        ),
        unreachable: &[],
    },
    Point {
        group: "bus",
        name: "illegal_rule",
        cite: "docs/spec.md 4 (legality of the parameter set), [0319]",
        meaning: "the legality rule that refused a parameter write",
        sampled: Sampled::Edge,
        when: "bus_we && sig && is_param && !c_legal",
        bins: bins!(
            "zero_period": "a period of zero (Ps, x, min, T1, T2, smp_on)" => "c_cth != 8'd0 && c_zero"; knobs!(IllegalWrites),
            "min_above_max_by_one": "min = x + 1: the rule at its bound (min = x is legal)" => "c_cth != 8'd0 && !c_no_settle && {1'b0, c_si_min} == {1'b0, c_si_max} + 17'd1"; knobs!(IllegalWrites, KeyStorm),
            "min_above_max": "min above x + 1" => "c_cth != 8'd0 && !c_no_settle && c_si_min > c_si_max"; knobs!(IllegalWrites),
            "no_settling_tick": "pw + pi = 0" => "c_cth != 8'd0 && c_no_settle"; knobs!(PiZero, IllegalWrites, KeyStorm),
            "window_at_shortest": "Wt = pw + pi + ps equal to the shortest interval: the rule at its bound (Wt = shortest - 1 is legal)" => "c_cth != 8'd0 && c_wt18 == c_short"; knobs!(IllegalWrites, KeyStorm),
            "window_too_long": "Wt = pw + pi + ps longer than the shortest interval" => "c_cth != 8'd0"; knobs!(IllegalWrites),
            "cth_zero_high_bits": "Cth = 0 in the register's 8 bits with high bits set in the written word (the register's width is taken before the check, spec 2.8); port-level only: a scenario's write must fit the register" => "bus_wdata[15:8] != 8'd0"; PORT,
            "cth_zero": "Cth = 0 (valid is 1..255; the other ranges are structural and not on the bus)" => "1'b1"; knobs!(IllegalWrites),
        ),
        unreachable: &[],
    },
    Point {
        group: "bus",
        name: "w1c",
        cite: "docs/spec.md 2.8 (STATUS bits 5 and 9 are write-1-to-clear)",
        meaning: "which sticky STATUS bits a STATUS write cleared, and whether the bit was set",
        sampled: Sampled::Edge,
        when: "bus_we && sig && bus_addr == 8'h14",
        bins: bins!(
            "none": "no W1C bit written" => "!bus_wdata[5] && !bus_wdata[9]"; knobs!(StatusWrites),
            "quadrant_skip_set": "bit 5 only, while quadrant_skip is set: cleared" => "bus_wdata[5] && !bus_wdata[9] && quadrant_skip"; knobs!(StatusWrites, FastMoves),
            "quadrant_skip_clear": "bit 5 only, while quadrant_skip is clear" => "bus_wdata[5] && !bus_wdata[9]"; knobs!(StatusWrites),
            "bus_err_set": "bit 9 only, while bus_err is set: cleared" => "!bus_wdata[5] && bus_wdata[9] && bus_err"; knobs!(StatusWrites, IllegalWrites),
            "bus_err_clear": "bit 9 only, while bus_err is clear" => "!bus_wdata[5] && bus_wdata[9]"; knobs!(StatusWrites),
            "both": "bits 5 and 9" => "1'b1"; knobs!(StatusWrites),
        ),
        unreachable: &[],
    },
    Point {
        group: "bus",
        name: "legal_at_bound",
        cite: "docs/spec.md 4 (legality of the parameter set), [0319]",
        meaning: "a taken parameter write whose set sits at a legality rule's bound (the first that holds)",
        sampled: Sampled::Edge,
        when: "param_wr && (c_si_min == c_si_max || c_wt18 + 18'd1 == c_short || {1'b0, c_pw} + {1'b0, c_pi} == 17'd1)",
        bins: bins!(
            "min_eq_max": "min = x: legal (min > x is refused)" => "c_si_min == c_si_max"; knobs!(XEqualMin),
            "wt_shortest_minus_one": "Wt = the shortest interval - 1: legal (Wt = shortest is refused)" => "c_wt18 + 18'd1 == c_short"; knobs!(MinTight),
            "settle_one": "pw + pi = 1: legal (pw + pi = 0 is refused)" => "1'b1"; knobs!(PiZero, KeyStorm),
        ),
        unreachable: &[],
    },
    Point {
        group: "bus",
        name: "write_changes",
        cite: "docs/spec.md 2.8 (register map; the read mux sees the registers before the edge)",
        meaning: "a taken write that changes its register: the MPU's bus cycle reads the address written, and must see the value before the edge",
        sampled: Sampled::Edge,
        when: "cfg_change",
        bins: bins!(
            "ctrl": "CTRL" => "bus_addr == 8'h02"; knobs!(KeyStorm), "pw": "PW" => "bus_addr == 8'h03"; knobs!(KeyStorm), "pi": "PI" => "bus_addr == 8'h04"; knobs!(KeyStorm), "ps": "PS" => "bus_addr == 8'h05"; knobs!(KeyStorm), "si_max": "SI_MAX" => "bus_addr == 8'h06"; knobs!(KeyStorm),
            "si_min": "SI_MIN" => "bus_addr == 8'h07"; knobs!(KeyStorm), "t1": "T1" => "bus_addr == 8'h08"; knobs!(KeyStorm), "t2": "T2" => "bus_addr == 8'h09"; knobs!(KeyStorm), "cth": "CTH" => "bus_addr == 8'h0A"; knobs!(KeyStorm), "smp_on": "SMP_ON" => "1'b1"; knobs!(KeyStorm),
        ),
        unreachable: &[],
    },
    Point {
        group: "faults",
        name: "dead_strobe",
        cite: "[0209], [0347]; docs/spec.md 2.3-2.4 (vld marks the first sample)",
        meaning: "a sampling strobe on a dead rail (Sr = 0), by whether a first sample was taken before it",
        sampled: Sampled::Edge,
        when: "smp && !sr",
        bins: bins!(
            "before_first": "no sample since reset (vld = 0): the strobe must leave vld at 0" => "!vld"; knobs!(Faults),
            "after_first": "after the first sample" => "1'b1"; knobs!(Faults),
        ),
        unreachable: &[],
    },
    Point {
        group: "faults",
        name: "pg_drop",
        cite: "[0209]; docs/spec.md 2.3 (Sr = vs2_en && vs2_ok, registered)",
        meaning: "Vs2's power-good dropping while Sr = 1 and Vs2 is enabled: Sr must fall at this edge",
        sampled: Sampled::Edge,
        when: "sr && vs2_en && !vs2_ok",
        bins: bins!("sr_falls": "Sr falls on the power-good, not on the enable" => "1'b1"; knobs!(Faults)),
        unreachable: &[],
    },
    Point {
        group: "faults",
        name: "pg_unpowered",
        cite: "[0209]; docs/spec.md 2.3",
        meaning: "Vs2's power-good high while Vs2 is off: Sr must stay 0 (port-level only: the bench's power-good follows the enable)",
        sampled: Sampled::Edge,
        when: "vs2_ok && !vs2_en",
        bins: bins!("high": "power-good high with Vs2 off" => "1'b1"; PORT),
        unreachable: &[],
    },
    Point {
        group: "key",
        name: "off_edge_write",
        cite: "[0213]; docs/spec.md 2.6 (the key-off reload takes si_max_nxt)",
        meaning: "an SI_MAX write taken on the edge sig falls (ig back on after a low pulse the synchronizer passes)",
        sampled: Sampled::Edge,
        when: "koff && param_wr && bus_addr == 8'h06",
        bins: bins!("si_max": "si reloads to the x written on this edge" => "1'b1"; knobs!(Glitches)),
        unreachable: &[],
    },
    Point {
        group: "key",
        name: "start",
        cite: "[0213]; docs/spec.md 2.1 (the synchronizer resets to 0)",
        meaning: "the key at the first edge out of reset",
        sampled: Sampled::Edge,
        when: "cfg_start",
        bins: bins!(
            "on": "ig = 1 from reset: sig rises SYNC_DEPTH edges later" => "ig"; ANY,
            "off": "ig = 0 from reset" => "1'b1"; ANY,
        ),
        unreachable: &[],
    },
    Point {
        group: "timer",
        name: "period_write",
        cite: "[0349]; docs/spec.md 2.2 (the cycle ends when the timer reaches its period)",
        meaning: "a taken SMP_ON write with the key on, against the running timer",
        sampled: Sampled::Edge,
        when: "param_wr && sig && bus_addr == 8'h0B",
        bins: bins!(
            "behind_timer": "SMP_ON written at or below the timer, which runs on past it: the cycle must still end" => "{2'b00, c_smp_on} <= t18 && t18 + 18'd1 < {2'b00, smp_on}"; knobs!(KeyStorm),
            "ahead": "any other SMP_ON write" => "1'b1"; knobs!(KeyStorm),
        ),
        unreachable: &[],
    },
    Point {
        group: "counter",
        name: "difference",
        cite: "[0119]; docs/spec.md 2.7 (cnt_s - cnt_c modulo 2^CNT_W)",
        meaning: "cnt_s - cnt_c after a sample that moved the latches, as the count diagnosis compares it",
        sampled: Sampled::Edge,
        when: "upd && (first || chg_s || chg_c)",
        bins: bins!(
            "minus_one_wrap": "cnt_s = -1, cnt_c = 0: -1 across the counters' wrap" => "cnt_s_n == {CNT_W{1'b1}} && cnt_c_n == {CNT_W{1'b0}}"; ANY,
            "minus_one": "cnt_s = cnt_c - 1 (quadrants 1 and 3), cnt_s below cnt_c as unsigned numbers" => "cnt_s_n + {{(CNT_W-1){1'b0}}, 1'b1} == cnt_c_n"; ANY,
            "zero": "cnt_s = cnt_c (quadrants 0 and 2)" => "1'b1"; ANY,
        ),
        unreachable: &[],
    },
    Point {
        group: "config",
        name: "cth",
        cite: "[0250], [0259]",
        meaning: "the count threshold Cth in force",
        sampled: Sampled::Config,
        when: "",
        bins: bins!("one": "Cth = 1" => "cth <= 8'd1"; knobs!(CthOne), "2_4": "2..4 (the patent's 4)" => "cth <= 8'd4"; ANY, "5_8": "5..8" => "cth <= 8'd8"; ANY, "9_up": "9..255" => "1'b1"; knobs!(CthHigh)),
        unreachable: &[],
    },
    Point {
        group: "config",
        name: "t1",
        cite: "[0224], [0259]",
        meaning: "the shortening step T1 against the span x - min",
        sampled: Sampled::Config,
        when: "",
        bins: bins!("one_step": "T1 >= x - min: one rotation takes si to min" => "t1 >= si_max - si_min"; knobs!(T1OneStep), "half_or_more": "(x - min)/2 <= T1 < x - min" => "17'd2 * t1 >= si_max - si_min"; knobs!(T1Half), "small": "T1 < (x - min)/2" => "1'b1"; ANY),
        unreachable: &[],
    },
    Point {
        group: "config",
        name: "t2",
        cite: "[0250], [0259]",
        meaning: "the expanding step T2 against the span x - min",
        sampled: Sampled::Config,
        when: "",
        bins: bins!("one_step": "T2 >= x - min" => "t2 >= si_max - si_min"; knobs!(T2OneStep), "half_or_more": "(x - min)/2 <= T2 < x - min" => "17'd2 * t2 >= si_max - si_min"; knobs!(T2Half), "small": "T2 < (x - min)/2" => "1'b1"; ANY),
        unreachable: &[],
    },
    Point {
        group: "config",
        name: "x",
        cite: "[0216], [0259]",
        meaning: "the maximum interval x, in ticks",
        sampled: Sampled::Config,
        when: "",
        bins: bins!("equal_min": "x = min: the interval cannot move" => "si_max == si_min"; knobs!(XEqualMin), "le_300": "x <= 300 ticks" => "si_max <= 16'd300"; knobs!(XShort), "301_700": "301..700 (the patent's 660)" => "si_max <= 16'd700"; ANY, "above_700": "above 700" => "1'b1"; knobs!(XLong)),
        unreachable: &[],
    },
    Point {
        group: "config",
        name: "min",
        cite: "[0228], [0319]",
        meaning: "the minimum interval against the output window Wt",
        sampled: Sampled::Config,
        when: "",
        bins: bins!("wt_plus_1": "min = Wt + 1, the tightest legal" => "{2'b00, si_min} == 18'd1 + pw + pi + ps"; knobs!(MinTight), "le_2wt": "Wt + 1 < min <= 2 Wt" => "{3'b000, si_min} <= 19'd2 * (pw + pi + ps)"; ANY, "above_2wt": "min > 2 Wt" => "1'b1"; knobs!(MinFar)),
        unreachable: &[],
    },
    Point {
        group: "config",
        name: "window",
        cite: "[0319]-[0323]",
        meaning: "the shape of the output window Pw, Pi, Ps",
        sampled: Sampled::Config,
        when: "",
        bins: bins!("pw_zero": "Pw = 0" => "pw == 16'd0"; knobs!(PwZero), "pi_zero": "Pi = 0" => "pi == 16'd0"; knobs!(PiZero), "ps_one": "Ps = 1 tick" => "ps == 16'd1"; knobs!(PsOne), "all_nonzero": "Pw, Pi > 0 and Ps > 1" => "1'b1"; ANY),
        unreachable: &[],
    },
    Point {
        group: "config",
        name: "smp_on",
        cite: "[0349]",
        meaning: "the on-key sampling period",
        sampled: Sampled::Config,
        when: "",
        bins: bins!("one": "smp_on = 1: every tick" => "smp_on <= 16'd1"; knobs!(SmpOnOne), "2_9": "2..9" => "smp_on <= 16'd9"; knobs!(SmpOnShort), "10_up": "10 and more (the default 10)" => "1'b1"; ANY),
        unreachable: &[],
    },
    Point {
        group: "config",
        name: "cnt_w",
        cite: "docs/spec.md 2.5 (CNT_W)",
        meaning: "the counter width CNT_W",
        sampled: Sampled::Config,
        when: "",
        bins: bins!("2": "2 bits, the narrowest" => "CNT_W <= 2"; knobs!(NarrowCounter), "3_7": "3..7" => "CNT_W <= 7"; knobs!(Width3To7), "8_15": "8..15" => "CNT_W <= 15"; knobs!(Width8To15), "16": "16, the default" => "1'b1"; ANY),
        unreachable: &[],
    },
    Point {
        group: "config",
        name: "sync_depth",
        cite: "[0213]; docs/spec.md 2.1 (SYNC_DEPTH)",
        meaning: "the synchronizer depth SYNC_DEPTH",
        sampled: Sampled::Config,
        when: "",
        bins: bins!("1": "1 flop" => "SYNC_DEPTH <= 1"; knobs!(Sync1), "2": "2 flops, the default" => "SYNC_DEPTH == 2"; ANY, "3": "3 flops" => "SYNC_DEPTH == 3"; knobs!(Sync3), "4": "4 flops" => "1'b1"; knobs!(Sync4)),
        unreachable: &[],
    },
    Point {
        group: "config",
        name: "adaptive",
        cite: "[0214], [0413]-[0414]",
        meaning: "the drive interval mode",
        sampled: Sampled::Config,
        when: "",
        bins: bins!("fixed": "first embodiment: fixed cycle T = x" => "!adaptive"; knobs!(Fixed), "adaptive": "second embodiment: FIG. 17/18" => "1'b1"; ANY),
        unreachable: &[],
    },
    Point {
        group: "config",
        name: "clock",
        cite: "docs/spec.md 6.1 (clock period)",
        meaning: "the clock period of the run",
        sampled: Sampled::Config,
        when: "",
        bins: bins!("below_10us": "faster than 10 us" => "CLOCK_NS < 10000"; knobs!(ClockFast), "10us": "10 us, the default" => "CLOCK_NS == 10000"; ANY, "above_10us": "slower than 10 us" => "1'b1"; knobs!(ClockSlow)),
        unreachable: &[],
    },
];

const fn str_eq(a: &str, b: &str) -> bool {
    let (a, b) = (a.as_bytes(), b.as_bytes());
    if a.len() != b.len() {
        return false;
    }
    let mut i = 0;
    while i < a.len() {
        if a[i] != b[i] {
            return false;
        }
        i += 1;
    }
    true
}

/// The index in [`POINTS`] of the point `group.name` (compile-time; panics if undeclared).
pub const fn point_index(group: &str, name: &str) -> usize {
    let mut i = 0;
    while i < POINT_TABLE.len() {
        if str_eq(POINT_TABLE[i].group, group) && str_eq(POINT_TABLE[i].name, name) {
            return i;
        }
        i += 1;
    }
    panic!("no such coverpoint")
}

/// The index of bin `name` in point `point` (compile-time; panics if undeclared).
pub const fn bin_index(point: usize, name: &str) -> u8 {
    let bins = POINT_TABLE[point].bins;
    let mut i = 0;
    while i < bins.len() {
        if str_eq(bins[i].name, name) {
            return i as u8;
        }
        i += 1;
    }
    panic!("no such bin")
}

/// The bin `name` of point `point` as a constant: `bin!(FIG17, "s6_shorten")`; a name that is not
/// declared does not compile.
#[macro_export]
macro_rules! bin {
    ($point:expr, $name:literal) => {
        const { $crate::model::bin_index($point, $name) }
    };
}

const DETECTED: [&str; 2] = ["s23_detected_cs", "s28_detected_cc"];

fn fig17_x_fig18(a: &str, b: &str) -> Option<&'static str> {
    match a {
        "s1_no_rise" | "fixed" => {
            Some("FIG. 18 is evaluated only after S1: Y with the adaptive interval")
        }
        "s5_at_min" | "s6_shorten" if !DETECTED.contains(&b) => {
            Some("S3: Y (S5/S6) follows only a detected rotation (S23 or S28)")
        }
        "s7_at_max" | "s9_count" | "s10_expand" if DETECTED.contains(&b) => {
            Some("S3: N (S7-S10) follows only when no rotation was detected")
        }
        _ => None,
    }
}

fn none(_: &str, _: &str) -> Option<&'static str> {
    None
}

fn no_extra(_: &str, _: &str) -> &'static [&'static str] {
    &[]
}

fn fig17_x_fig18_hint(a: &str, b: &str) -> &'static [&'static str] {
    // FIG. 18 runs at x only when x = min (a detection at x shortens the interval)
    if a == "s7_at_max" && b != "s25_no_change" {
        &["XEqualMin"]
    } else {
        &[]
    }
}

fn key_edge_x_phase_hint(_: &str, b: &str) -> &'static [&'static str] {
    // the sampling tick is one tick of Ps: Ps = 1 makes it the whole sampling period
    if b == "off_smp" {
        &["PsOne"]
    } else {
        &[]
    }
}

fn key_edge_x_phase(a: &str, b: &str) -> Option<&'static str> {
    match (a, b.starts_with("on_")) {
        ("on", true) => Some("before sig rises the key is off: the timer runs the key-off cycle"),
        ("off", false) => Some("before sig falls the key is on: the timer runs the on-key cycle"),
        _ => None,
    }
}

fn rule_x_interval(_: &str, _: &str) -> Option<&'static str> {
    None
}

fn write_reg_x_outcome(a: &str, b: &str) -> Option<&'static str> {
    let rw = !matches!(a, "status" | "read_only" | "unmapped");
    match b {
        "refused_not_writable" if rw || a == "status" => Some("the register is writable"),
        "taken" | "refused_illegal" if !rw && a != "status" => {
            Some("a read-only or unmapped address is never written")
        }
        "refused_illegal" if a == "status" => {
            Some("a STATUS write clears flags and changes no parameter")
        }
        _ => None,
    }
}

fn hist_x_fig18(a: &str, b: &str) -> Option<&'static str> {
    if a == "both" {
        return Some("hist_s and hist_c are never both set");
    }
    match (a, b) {
        ("s", "s23_detected_cs") => Some("S21: Y whenever hist_s is set and Cs changes"),
        ("c", "s28_detected_cc") => Some("S26: Y whenever hist_c is set and Cc changes"),
        ("none" | "c", "s21_cs_repeat") => Some("S21: Y needs hist_s = 1"),
        ("none" | "s", "s26_cc_repeat") => Some("S26: Y needs hist_c = 1"),
        _ => None,
    }
}

fn fig17_x_cnt_r(a: &str, b: &str) -> Option<&'static str> {
    match (a, b) {
        ("s10_expand", "zero" | "below_cth") => Some("S8: Y needs cnt_r >= Cth"),
        ("s9_count", "at_or_above_cth" | "saturated") => Some("S8: N needs cnt_r < Cth; S9 with cnt_r >= Cth is S10's path"),
        ("s7_at_max", "below_cth") => Some("si reaches x only by the key-off reload, which clears cnt_r, or by an S10, which leaves cnt_r above Cth; Cth changes only while the key is on, and the next key-off clears cnt_r"),
        ("s1_no_rise" | "fixed", _) => Some("cnt_r.before is sampled only when the sensor answered with the adaptive interval"),
        _ => None,
    }
}

fn preset_x_mode(_: &str, _: &str) -> Option<&'static str> {
    None
}

fn skip_x_interval(a: &str, _: &str) -> Option<&'static str> {
    a.starts_with("key_on")
        .then_some("interval.at_edge is sampled at key-off samples only")
}

fn vs2_x_interval(a: &str, _: &str) -> Option<&'static str> {
    (a == "key_on").then_some("interval.at_edge is sampled at key-off samples only")
}

fn rule_x_cnt_w(_: &str, _: &str) -> Option<&'static str> {
    None
}

fn shorten_x_t1(a: &str, b: &str) -> Option<&'static str> {
    match (a, b) {
        ("low" | "mid" | "high", "one_step") => {
            Some("T1 >= x - min takes any si <= x to min or below")
        }
        ("high", "half_or_more") => {
            Some("T1 >= (x - min)/2 takes any si <= x to min + span/2 or below")
        }
        _ => None,
    }
}

fn expand_x_t2(a: &str, b: &str) -> Option<&'static str> {
    match (a, b) {
        ("low" | "mid" | "high", "one_step") => {
            Some("T2 >= x - min takes any si >= min to x or above")
        }
        ("low", "half_or_more") => {
            Some("T2 >= (x - min)/2 takes any si >= min to min + span/2 or above")
        }
        _ => None,
    }
}

/// Every cross.
pub static CROSSES: [Cross; 15] = [
    Cross {
        name: "fig17_x_fig18",
        cite: "FIG. 17 x FIG. 18",
        meaning: "each FIG. 17 path with each FIG. 18 path that leads to it",
        rows: FIG17,
        columns: FIG18,
        unreachable: fig17_x_fig18,
        hint: fig17_x_fig18_hint,
    },
    Cross {
        name: "rule_x_interval",
        cite: "[0096]-[0099] x [0216]-[0228]",
        meaning: "each counting rule at each interval class of the key-off sample that applied it",
        rows: RULE,
        columns: SI_AT_EDGE,
        unreachable: rule_x_interval,
        hint: no_extra,
    },
    Cross {
        name: "rule_x_mode",
        cite: "[0096]-[0099] x [0349]",
        meaning: "each counting rule with the key off and on",
        rows: RULE,
        columns: SAMPLE_MODE,
        unreachable: none,
        hint: no_extra,
    },
    Cross {
        name: "key_edge_x_phase",
        cite: "[0213] x [0319]-[0323], [0349]",
        meaning: "key edges in each phase of the output pulse window and of the on-key cycle",
        rows: KEY_EDGE,
        columns: KEY_PHASE,
        unreachable: key_edge_x_phase,
        hint: key_edge_x_phase_hint,
    },
    Cross {
        name: "wrap_x_cnt_w",
        cite: "docs/spec.md 2.5",
        meaning: "counter wraps at each class of CNT_W",
        rows: WRAP,
        columns: CFG_CNT_W,
        unreachable: none,
        hint: no_extra,
    },
    Cross {
        name: "rule_x_cnt_w",
        cite: "[0096]-[0099] x CNT_W",
        meaning: "each counting rule at each class of CNT_W",
        rows: RULE,
        columns: CFG_CNT_W,
        unreachable: rule_x_cnt_w,
        hint: no_extra,
    },
    Cross {
        name: "fig18_x_history",
        cite: "[0237]-[0241] x FIG. 18",
        meaning: "each FIG. 18 path from each state of the change history",
        rows: HIST,
        columns: FIG18,
        unreachable: hist_x_fig18,
        hint: no_extra,
    },
    Cross {
        name: "fig17_x_cnt_r",
        cite: "FIG. 17 x [0248]",
        meaning: "each FIG. 17 path from each class of CNTr",
        rows: FIG17,
        columns: CNT_R_BEFORE,
        unreachable: fig17_x_cnt_r,
        hint: no_extra,
    },
    Cross {
        name: "preset_x_mode",
        cite: "[0092]-[0093] x [0349]",
        meaning: "the first-sample preset of each quadrant, key off and key on",
        rows: PRESET,
        columns: SAMPLE_MODE,
        unreachable: preset_x_mode,
        hint: no_extra,
    },
    Cross {
        name: "skip_x_interval",
        cite: "docs/spec.md 2.5 x [0216]-[0228]",
        meaning: "quadrant skips at each interval class (too fast for the interval in force)",
        rows: SKIP,
        columns: SI_AT_EDGE,
        unreachable: skip_x_interval,
        hint: no_extra,
    },
    Cross {
        name: "shorten_x_t1",
        cite: "[0224] x [0260]-[0262]",
        meaning: "where S6 lands for each class of T1",
        rows: SHORTEN_TO,
        columns: CFG_T1,
        unreachable: shorten_x_t1,
        hint: no_extra,
    },
    Cross {
        name: "expand_x_t2",
        cite: "[0250] x [0260]",
        meaning: "where S10 lands for each class of T2",
        rows: EXPAND_TO,
        columns: CFG_T2,
        unreachable: expand_x_t2,
        hint: no_extra,
    },
    Cross {
        name: "write_reg_x_outcome",
        cite: "docs/spec.md 2.8 and 4",
        meaning: "each register with each outcome of a write",
        rows: WRITE_REG,
        columns: WRITE_OUTCOME,
        unreachable: write_reg_x_outcome,
        hint: no_extra,
    },
    Cross {
        name: "difference_x_cnt_w",
        cite: "[0119] x docs/spec.md 2.5 (CNT_W)",
        meaning: "the counters' difference, as the diagnosis compares it modulo 2^CNT_W, at each class of CNT_W",
        rows: DIFFERENCE,
        columns: CFG_CNT_W,
        unreachable: none,
        hint: no_extra,
    },
    Cross {
        name: "start_x_sync_depth",
        cite: "[0213] x SYNC_DEPTH",
        meaning: "the key from reset through each depth of the synchronizer",
        rows: KEY_START,
        columns: CFG_SYNC,
        unreachable: none,
        hint: no_extra,
    },
];

/// Fold the vs2 cross in as an extra declared cross of the fault group (kept separate from the
/// table above so the table reads as the plan).
pub static FAULT_CROSSES: [Cross; 1] = [Cross {
    name: "vs2_x_interval",
    cite: "[0209] x [0216]-[0228]",
    meaning: "a dead Vs2 rail at a key-off sample of each interval class",
    rows: VS2,
    columns: SI_AT_EDGE,
    unreachable: vs2_x_interval,
    hint: no_extra,
}];

/// One bin of the flattened model.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct BinInfo {
    /// `group.point.bin`, or `cross.<name>.<a>*<b>`.
    pub name: String,
    pub kind: Kind,
    pub group: &'static str,
    pub cite: &'static str,
    pub meaning: String,
    /// Why the bin can never be hit, if it cannot.
    pub unreachable: Option<&'static str>,
    /// Only port-level stimuli reach it ([`Hint::PortLevel`]): a scenario's MPU reads the
    /// register map's addresses only, and `pmu50 check` refuses a scenario that writes a
    /// read-only or unmapped address. They count in the coverage; `pmu50 regress` reports its
    /// closure over the other bins too, and closes these when port-level coverage is merged in.
    pub port_only: bool,
    /// How the directed generator aims at it: a point bin's [`Hint`], a cross bin's from both
    /// of its bins' and the cross's own.
    pub aim: Aim,
}

/// A bin's [`Hint`], resolved for the flattened model (a cross bin: the union of its two bins'
/// knobs and the cross's own).
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Aim {
    /// Force these knobs (by name, sorted, distinct).
    Knobs(Vec<&'static str>),
    /// Seeds hit it without a knob.
    AnySeed,
    /// Port-level stimuli only.
    PortLevel,
    /// Declared unreachable.
    Never,
}

impl Aim {
    fn of(h: Hint) -> Aim {
        match h {
            Hint::Knobs(k) => {
                let mut k = k.to_vec();
                k.sort_unstable();
                k.dedup();
                Aim::Knobs(k)
            }
            Hint::AnySeed => Aim::AnySeed,
            Hint::PortLevel => Aim::PortLevel,
            Hint::Never => Aim::Never,
        }
    }

    /// The aim of a cross bin from those of its two bins and the cross's extra knobs.
    fn cross(a: &Aim, b: &Aim, extra: &[&'static str], unreachable: bool) -> Aim {
        use Aim::*;
        if unreachable || *a == Never || *b == Never {
            return Never;
        }
        if *a == PortLevel || *b == PortLevel {
            return PortLevel;
        }
        let mut k: Vec<&'static str> = extra.to_vec();
        for x in [a, b] {
            if let Knobs(v) = x {
                k.extend(v.iter().copied());
            }
        }
        if k.is_empty() {
            return AnySeed;
        }
        k.sort_unstable();
        k.dedup();
        Knobs(k)
    }

    /// The knobs to force (none for the other aims).
    pub fn knobs(&self) -> &[&'static str] {
        match self {
            Aim::Knobs(k) => k,
            _ => &[],
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Kind {
    Point,
    Cross,
}

/// Every cross of the model, in order.
pub fn crosses() -> impl Iterator<Item = &'static Cross> {
    CROSSES.iter().chain(FAULT_CROSSES.iter())
}

/// The flattened model: every bin in storage order (points in [`POINTS`] order, then crosses,
/// each cross row-major over its points' bins), with the offset of each point and cross.
#[derive(Clone, Debug)]
pub struct Layout {
    pub bins: Vec<BinInfo>,
    pub point_offset: Vec<usize>,
    pub cross_offset: Vec<usize>,
}

impl Layout {
    pub fn new() -> Layout {
        let mut bins = Vec::new();
        let mut point_offset = Vec::new();
        for p in POINTS.iter() {
            point_offset.push(bins.len());
            for b in p.bins {
                let unreachable = p
                    .unreachable
                    .iter()
                    .find(|(n, _)| *n == b.name)
                    .map(|(_, r)| *r);
                let name = format!("{}.{}.{}", p.group, p.name, b.name);
                bins.push(BinInfo {
                    port_only: b.hint == Hint::PortLevel,
                    aim: Aim::of(b.hint),
                    name,
                    kind: Kind::Point,
                    group: p.group,
                    cite: p.cite,
                    meaning: b.meaning.to_string(),
                    unreachable,
                });
            }
        }
        let mut cross_offset = Vec::new();
        for c in crosses() {
            cross_offset.push(bins.len());
            let (pa, pb) = (&POINTS[c.rows], &POINTS[c.columns]);
            for ba in pa.bins {
                for bb in pb.bins {
                    let own = |p: &Point, b: &str| {
                        p.unreachable.iter().find(|(n, _)| *n == b).map(|(_, r)| *r)
                    };
                    let unreachable = (c.unreachable)(ba.name, bb.name)
                        .or(own(pa, ba.name))
                        .or(own(pb, bb.name));
                    let port_only = ba.hint == Hint::PortLevel || bb.hint == Hint::PortLevel;
                    let aim = Aim::cross(
                        &Aim::of(ba.hint),
                        &Aim::of(bb.hint),
                        (c.hint)(ba.name, bb.name),
                        unreachable.is_some(),
                    );
                    bins.push(BinInfo {
                        port_only,
                        aim,
                        name: format!("cross.{}.{}*{}", c.name, ba.name, bb.name),
                        kind: Kind::Cross,
                        group: "cross",
                        cite: c.cite,
                        meaning: format!("{}: {} / {}", c.meaning, ba.meaning, bb.meaning),
                        unreachable,
                    });
                }
            }
        }
        Layout {
            bins,
            point_offset,
            cross_offset,
        }
    }
}

impl Default for Layout {
    fn default() -> Self {
        Layout::new()
    }
}

/// The model's identity: a name, the number of bins and an FNV-1a hash of their names in order.
pub fn model_id(layout: &Layout) -> String {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for b in &layout.bins {
        for byte in b.name.bytes().chain(std::iter::once(b'\n')) {
            h ^= u64::from(byte);
            h = h.wrapping_mul(0x0000_0100_0000_01b3);
        }
    }
    format!("pmu50-coverage/{}/{:016x}", layout.bins.len(), h)
}
