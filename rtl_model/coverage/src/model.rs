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
}

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
}

macro_rules! bins {
    ($($name:literal : $meaning:literal),* $(,)?) => { &[$(Bin { name: $name, meaning: $meaning }),*] };
}

// Point indices (the order of POINTS).
pub const FIG17: usize = 0;
pub const FIG18: usize = 1;
pub const RULE: usize = 2;
pub const SAMPLE_MODE: usize = 3;
pub const WRAP: usize = 4;
pub const PRESET: usize = 5;
pub const SKIP: usize = 6;
pub const SHORTEN_TO: usize = 7;
pub const EXPAND_TO: usize = 8;
pub const SI_AT_EDGE: usize = 9;
pub const CLAMP: usize = 10;
pub const CNT_R: usize = 11;
pub const CNT_R_BEFORE: usize = 12;
pub const HIST: usize = 13;
pub const KEY_EDGE: usize = 14;
pub const KEY_PHASE: usize = 15;
pub const VS2: usize = 16;
pub const SYNC_GLITCH: usize = 17;
pub const DIAG: usize = 18;
pub const SKIP_CLEAR: usize = 19;
pub const READ: usize = 20;
pub const WRITE_REG: usize = 21;
pub const WRITE_OUTCOME: usize = 22;
pub const ILLEGAL: usize = 23;
pub const W1C: usize = 24;
pub const CFG_CTH: usize = 25;
pub const CFG_T1: usize = 26;
pub const CFG_T2: usize = 27;
pub const CFG_X: usize = 28;
pub const CFG_MIN: usize = 29;
pub const CFG_WINDOW: usize = 30;
pub const CFG_SMP_ON: usize = 31;
pub const CFG_CNT_W: usize = 32;
pub const CFG_SYNC: usize = 33;
pub const CFG_ADAPTIVE: usize = 34;
pub const CFG_CLOCK: usize = 35;

/// The readable register addresses, in the order of the `bus.read` bins (the last bin is
/// every other address).
pub const READ_ADDRS: [u8; 18] = [
    0x00, 0x01, 0x02, 0x03, 0x04, 0x05, 0x06, 0x07, 0x08, 0x09, 0x0A, 0x0B, 0x0C, 0x10, 0x11, 0x12,
    0x13, 0x14,
];

/// Every coverpoint.
pub static POINTS: [Point; 36] = [
    Point {
        group: "fig17",
        name: "path",
        cite: "FIG. 17, [0216]-[0262]; docs/spec.md 2.6",
        meaning: "the branch the drive interval changing unit took at a key-off sampling strobe",
        sampled: Sampled::Edge,
        bins: bins!(
            "s1_no_rise": "S1: N, the activation signal Sr did not rise (Vs2 rail dead): nothing changes",
            "s5_at_min": "S3: Y, S4, S5: Y: rotation at the minimum interval, cnt_r := 0, si held",
            "s6_shorten": "S3: Y, S4, S5: N, S6: rotation, si shortened by T1",
            "s7_at_max": "S3: N, S7: Y: quiet at the maximum interval x, nothing changes",
            "s9_count": "S3: N, S7: N, S8: N, S9: quiet, cnt_r += 1",
            "s10_expand": "S8: Y, S10, S11, S9: quiet for Cth pulses, si expanded by T2, history cleared",
            "fixed": "adaptive = 0 (first embodiment): si := x",
        ),
        unreachable: &[],
    },
    Point {
        group: "fig18",
        name: "path",
        cite: "FIG. 18, [0263]-[0291]; docs/spec.md 2.6",
        meaning: "the branch of the rotation detection at a key-off sampling strobe",
        sampled: Sampled::Edge,
        bins: bins!(
            "s23_detected_cs": "S20: Y, S21: N, S22, S23: rotation detected through Cs",
            "s21_cs_repeat": "S20: Y, S21: Y, S24: Cs changed again before Cc ([0232]-[0236])",
            "s28_detected_cc": "S20: N, S25: Y, S26: N, S27, S28: rotation detected through Cc",
            "s26_cc_repeat": "S25: Y, S26: Y, S24: Cc changed again before Cs",
            "s25_no_change": "S20: N, S25: N, S24: no sign changed",
        ),
        unreachable: &[],
    },
    Point {
        group: "counter",
        name: "rule",
        cite: "[0096]-[0099]; docs/spec.md 2.5",
        meaning: "the counting rule applied at a sample where exactly one sign changed",
        sampled: Sampled::Edge,
        bins: bins!(
            "s_0096_up": "[0096] Cs 0->1 while Cc = 1: cnt_s + 1",
            "s_0096_down": "[0096] Cs 1->0 while Cc = 1: cnt_s - 1",
            "s_0097_up": "[0097] Cs 1->0 while Cc = 0: cnt_s + 1",
            "s_0097_down": "[0097] Cs 0->1 while Cc = 0: cnt_s - 1",
            "c_0098_up": "[0098] Cc 0->1 while Cs = 0: cnt_c + 1",
            "c_0098_down": "[0098] Cc 1->0 while Cs = 0: cnt_c - 1",
            "c_0099_up": "[0099] Cc 1->0 while Cs = 1: cnt_c + 1",
            "c_0099_down": "[0099] Cc 0->1 while Cs = 1: cnt_c - 1",
        ),
        unreachable: &[],
    },
    Point {
        group: "counter",
        name: "sample_mode",
        cite: "[0331]-[0349]; docs/spec.md 2.2",
        meaning: "whether a sample that moved the latches was taken with the key off (intermittent Vs2) or on (on-key sampling)",
        sampled: Sampled::Edge,
        bins: bins!("key_off": "sample of a key-off output pulse", "key_on": "on-key sample, every smp_on ticks"),
        unreachable: &[],
    },
    Point {
        group: "counter",
        name: "wrap",
        cite: "docs/spec.md 2.5 (cnt_width bits, two's complement, wrapping like hardware)",
        meaning: "a counter stepping past its extreme value at the configured width",
        sampled: Sampled::Edge,
        bins: bins!(
            "cnt_s_up": "cnt_s + 1 from the largest value 2^(W-1)-1 to -2^(W-1)",
            "cnt_s_down": "cnt_s - 1 from -2^(W-1) to 2^(W-1)-1",
            "cnt_c_up": "cnt_c + 1 from the largest value to the smallest",
            "cnt_c_down": "cnt_c - 1 from the smallest value to the largest",
        ),
        unreachable: &[],
    },
    Point {
        group: "counter",
        name: "preset",
        cite: "[0092]-[0093]; docs/spec.md 2.5 (first sample after reset)",
        meaning: "the quadrant of the first sample, which presets the counters",
        sampled: Sampled::Edge,
        bins: bins!(
            "q0": "Cs = 1, Cc = 1: (0, 0)",
            "q1": "Cs = 1, Cc = 0: (0, 1)",
            "q2": "Cs = 0, Cc = 0: (1, 1)",
            "q3": "Cs = 0, Cc = 1: (1, 2)",
        ),
        unreachable: &[],
    },
    Point {
        group: "counter",
        name: "quadrant_skip",
        cite: "docs/spec.md 2.5 (both signs change in one sample)",
        meaning: "a sample where both signs changed: the counters hold and quadrant_skip is set",
        sampled: Sampled::Edge,
        bins: bins!("key_off": "at a key-off sample", "key_on": "at an on-key sample"),
        unreachable: &[],
    },
    Point {
        group: "interval",
        name: "shorten_to",
        cite: "[0224]-[0228], [0260]-[0262]; docs/spec.md 2.6",
        meaning: "where S6 put the drive interval in [min, x] (thirds of the span)",
        sampled: Sampled::Edge,
        bins: bins!(
            "min_clamped": "si - T1 < min: clamped to min ([0260]-[0262])",
            "min_exact": "si - T1 = min",
            "low": "min < si' <= min + span/3",
            "mid": "min + span/3 < si' <= min + 2 span/3",
            "high": "si' > min + 2 span/3 (si' < x)",
        ),
        unreachable: &[],
    },
    Point {
        group: "interval",
        name: "expand_to",
        cite: "[0250]-[0258], [0260]; docs/spec.md 2.6",
        meaning: "where S10 put the drive interval in [min, x] (thirds of the span)",
        sampled: Sampled::Edge,
        bins: bins!(
            "low": "si' <= min + span/3 (si' > min)",
            "mid": "min + span/3 < si' <= min + 2 span/3",
            "high": "min + 2 span/3 < si' < x",
            "x_exact": "si + T2 = x",
            "x_clamped": "si + T2 > x: clamped to x ([0260])",
        ),
        unreachable: &[],
    },
    Point {
        group: "interval",
        name: "at_edge",
        cite: "[0216]-[0228]; docs/spec.md 2.6",
        meaning: "the drive interval in force at a key-off sample (thirds of [min, x])",
        sampled: Sampled::Edge,
        bins: bins!(
            "min": "si = min",
            "low": "min < si <= min + span/3",
            "mid": "min + span/3 < si <= min + 2 span/3",
            "high": "min + 2 span/3 < si < x",
            "x": "si = x",
        ),
        unreachable: &[],
    },
    Point {
        group: "interval",
        name: "clamp",
        cite: "[0260]-[0262]",
        meaning: "a step of the drive interval cut short by a limit",
        sampled: Sampled::Edge,
        bins: bins!("min": "S6: si - T1 below min, clamped to min", "x": "S10: si + T2 above x, clamped to x"),
        unreachable: &[],
    },
    Point {
        group: "cnt_r",
        name: "value",
        cite: "[0248]-[0250]; docs/spec.md 2.6",
        meaning: "the power supply count after a quiet key-off pulse (S9), by class up to its 8-bit saturation",
        sampled: Sampled::Edge,
        bins: bins!(
            "one": "cnt_r becomes 1",
            "below_cth": "1 < cnt_r' < Cth",
            "at_cth": "cnt_r' = Cth",
            "above_cth": "Cth < cnt_r' < 255 (the interval could not expand further)",
            "saturated": "cnt_r was 255 and stays 255 (8-bit saturation)",
        ),
        unreachable: &[],
    },
    Point {
        group: "cnt_r",
        name: "before",
        cite: "[0248], S4 of FIG. 17",
        meaning: "the power supply count at a key-off sample where the sensor answered",
        sampled: Sampled::Edge,
        bins: bins!(
            "zero": "cnt_r = 0",
            "below_cth": "0 < cnt_r < Cth",
            "at_or_above_cth": "Cth <= cnt_r < 255",
            "saturated": "cnt_r = 255",
        ),
        unreachable: &[],
    },
    Point {
        group: "fig18",
        name: "history",
        cite: "[0237]-[0241]; docs/spec.md 2.6",
        meaning: "the change history flip-flops before a FIG. 18 evaluation",
        sampled: Sampled::Edge,
        bins: bins!("none": "hist_s = 0, hist_c = 0", "s": "hist_s = 1", "c": "hist_c = 1", "both": "hist_s = 1 and hist_c = 1"),
        unreachable: &[("both", "S23 sets hist_s and clears hist_c, S28 the reverse, S11 and key-off clear both: no path sets both (docs/spec.md 2.6)")],
    },
    Point {
        group: "key",
        name: "edge",
        cite: "[0196]-[0198], [0213]; docs/spec.md 2.1",
        meaning: "an edge of the synchronised key sig",
        sampled: Sampled::Edge,
        bins: bins!("on": "sig rises (kon)", "off": "sig falls (koff): si reloads to x"),
        unreachable: &[],
    },
    Point {
        group: "key",
        name: "phase",
        cite: "[0319]-[0323], [0349]; docs/spec.md 2.2",
        meaning: "where in the timing generator's cycle a key edge fell",
        sampled: Sampled::Edge,
        bins: bins!(
            "off_pw": "key off, inside the waiting period Pw of an output pulse",
            "off_pi": "key off, inside the idle period Pi",
            "off_ps": "key off, inside the sampling period Ps before its last tick",
            "off_smp": "key off, the sampling tick (last tick of Ps)",
            "off_gap": "key off, between two output pulses (Vs2 off)",
            "on_smp": "key on, the on-key sampling tick",
            "on_between": "key on, between on-key samples",
        ),
        unreachable: &[],
    },
    Point {
        group: "faults",
        name: "vs2",
        cite: "[0209], [0347]; docs/spec.md 2.3",
        meaning: "a sampling strobe with Vs2 enabled but its power-good low, so Sr is 0 and no sample is taken",
        sampled: Sampled::Edge,
        bins: bins!("key_off": "a key-off strobe on a dead rail (FIG. 17 S1: N)", "key_on": "an on-key strobe on a dead rail"),
        unreachable: &[],
    },
    Point {
        group: "faults",
        name: "sync_glitch",
        cite: "[0213]; docs/spec.md 2.1",
        meaning: "ig toggles again while its previous edge is still inside the synchronizer",
        sampled: Sampled::Edge,
        bins: bins!("short_high": "a high pulse of ig shorter than the synchronizer", "short_low": "a low pulse of ig shorter than the synchronizer"),
        unreachable: &[],
    },
    Point {
        group: "faults",
        name: "diag",
        cite: "[0119]; docs/spec.md 2.7",
        meaning: "the count diagnosis flag rising, by cause",
        sampled: Sampled::Edge,
        bins: bins!("skip": "a quadrant was skipped (counts equal but half a turn off)", "difference": "|cnt_s - cnt_c| >= 2 without a skip"),
        unreachable: &[("difference", "cnt_s - cnt_c is 0 in quadrants 0 and 2 and -1 in 1 and 3 after every preset, counting rule and skip (each rule of [0096]-[0099] moves the counter that keeps it so, and a skip keeps the quadrant's parity): the difference guards against a corrupted counter, which no input can cause")],
    },
    Point {
        group: "faults",
        name: "skip_clear",
        cite: "docs/spec.md 2.8 (STATUS.quadrant_skip is W1C)",
        meaning: "a write of 1 to STATUS.quadrant_skip while it is set",
        sampled: Sampled::Edge,
        bins: bins!("cleared": "the sticky skip flag cleared by the MPU"),
        unreachable: &[],
    },
    Point {
        group: "bus",
        name: "read",
        cite: "[0108], [0163]; docs/spec.md 2.8",
        meaning: "the address read by the MPU in a key-on cycle without a write",
        sampled: Sampled::Edge,
        bins: bins!(
            "id": "0x00 ID", "version": "0x01 VERSION", "ctrl": "0x02 CTRL", "pw": "0x03 PW", "pi": "0x04 PI", "ps": "0x05 PS",
            "si_max": "0x06 SI_MAX", "si_min": "0x07 SI_MIN", "t1": "0x08 T1", "t2": "0x09 T2", "cth": "0x0A CTH", "smp_on": "0x0B SMP_ON",
            "cfg": "0x0C CFG", "cnt_s": "0x10 CNT_S", "cnt_c": "0x11 CNT_C", "cnt_r": "0x12 CNT_R", "si": "0x13 SI", "status": "0x14 STATUS",
            "unmapped": "any other address (reads 0)",
        ),
        unreachable: &[],
    },
    Point {
        group: "bus",
        name: "write_reg",
        cite: "docs/spec.md 2.8 (register map)",
        meaning: "the register a bus write addressed",
        sampled: Sampled::Edge,
        bins: bins!(
            "ctrl": "CTRL", "pw": "PW", "pi": "PI", "ps": "PS", "si_max": "SI_MAX", "si_min": "SI_MIN", "t1": "T1", "t2": "T2",
            "cth": "CTH", "smp_on": "SMP_ON", "status": "STATUS (W1C)", "read_only": "ID, VERSION, CFG, CNT_*, SI", "unmapped": "an address outside the map",
        ),
        unreachable: &[],
    },
    Point {
        group: "bus",
        name: "write_outcome",
        cite: "[0205], [0259]; docs/spec.md 2.8 and 4",
        meaning: "what the register file did with a bus write",
        sampled: Sampled::Edge,
        bins: bins!(
            "taken": "written (a parameter register, or a STATUS W1C)",
            "refused_key_off": "refused: sig = 0, the MPU is not powered ([0205])",
            "refused_not_writable": "refused: read-only or unmapped address",
            "refused_illegal": "refused: the parameter set would become illegal (docs/spec.md 4)",
        ),
        unreachable: &[],
    },
    Point {
        group: "bus",
        name: "illegal_rule",
        cite: "docs/spec.md 4 (legality of the parameter set), [0319]",
        meaning: "the legality rule that refused a parameter write",
        sampled: Sampled::Edge,
        bins: bins!(
            "zero_period": "a period of zero (Ps, x, min, T1, T2, smp_on)",
            "min_above_max": "min above x",
            "no_settling_tick": "pw + pi = 0",
            "window_too_long": "Wt = pw + pi + ps not shorter than the shortest interval",
            "cth_zero": "Cth = 0 (valid is 1..255; the other ranges are structural and not on the bus)",
        ),
        unreachable: &[],
    },
    Point {
        group: "bus",
        name: "w1c",
        cite: "docs/spec.md 2.8 (STATUS bits 5 and 9 are write-1-to-clear)",
        meaning: "which sticky STATUS bits a STATUS write cleared (set or not)",
        sampled: Sampled::Edge,
        bins: bins!("none": "no W1C bit written", "quadrant_skip": "bit 5 only", "bus_err": "bit 9 only", "both": "bits 5 and 9"),
        unreachable: &[],
    },
    Point {
        group: "config",
        name: "cth",
        cite: "[0250], [0259]",
        meaning: "the count threshold Cth in force",
        sampled: Sampled::Config,
        bins: bins!("one": "Cth = 1", "2_4": "2..4 (the patent's 4)", "5_8": "5..8", "9_up": "9..255"),
        unreachable: &[],
    },
    Point {
        group: "config",
        name: "t1",
        cite: "[0224], [0259]",
        meaning: "the shortening step T1 against the span x - min",
        sampled: Sampled::Config,
        bins: bins!("one_step": "T1 >= x - min: one rotation takes si to min", "half_or_more": "(x - min)/2 <= T1 < x - min", "small": "T1 < (x - min)/2"),
        unreachable: &[],
    },
    Point {
        group: "config",
        name: "t2",
        cite: "[0250], [0259]",
        meaning: "the expanding step T2 against the span x - min",
        sampled: Sampled::Config,
        bins: bins!("one_step": "T2 >= x - min", "half_or_more": "(x - min)/2 <= T2 < x - min", "small": "T2 < (x - min)/2"),
        unreachable: &[],
    },
    Point {
        group: "config",
        name: "x",
        cite: "[0216], [0259]",
        meaning: "the maximum interval x, in ticks",
        sampled: Sampled::Config,
        bins: bins!("equal_min": "x = min: the interval cannot move", "le_300": "x <= 300 ticks", "301_700": "301..700 (the patent's 660)", "above_700": "above 700"),
        unreachable: &[],
    },
    Point {
        group: "config",
        name: "min",
        cite: "[0228], [0319]",
        meaning: "the minimum interval against the output window Wt",
        sampled: Sampled::Config,
        bins: bins!("wt_plus_1": "min = Wt + 1, the tightest legal", "le_2wt": "Wt + 1 < min <= 2 Wt", "above_2wt": "min > 2 Wt"),
        unreachable: &[],
    },
    Point {
        group: "config",
        name: "window",
        cite: "[0319]-[0323]",
        meaning: "the shape of the output window Pw, Pi, Ps",
        sampled: Sampled::Config,
        bins: bins!("pw_zero": "Pw = 0", "pi_zero": "Pi = 0", "ps_one": "Ps = 1 tick", "all_nonzero": "Pw, Pi > 0 and Ps > 1"),
        unreachable: &[],
    },
    Point {
        group: "config",
        name: "smp_on",
        cite: "[0349]",
        meaning: "the on-key sampling period",
        sampled: Sampled::Config,
        bins: bins!("one": "smp_on = 1: every tick", "2_9": "2..9", "10_up": "10 and more (the default 10)"),
        unreachable: &[],
    },
    Point {
        group: "config",
        name: "cnt_w",
        cite: "docs/spec.md 2.5 (CNT_W)",
        meaning: "the counter width CNT_W",
        sampled: Sampled::Config,
        bins: bins!("2": "2 bits, the narrowest", "3_7": "3..7", "8_15": "8..15", "16": "16, the default"),
        unreachable: &[],
    },
    Point {
        group: "config",
        name: "sync_depth",
        cite: "[0213]; docs/spec.md 2.1 (SYNC_DEPTH)",
        meaning: "the synchronizer depth SYNC_DEPTH",
        sampled: Sampled::Config,
        bins: bins!("1": "1 flop", "2": "2 flops, the default", "3": "3 flops", "4": "4 flops"),
        unreachable: &[],
    },
    Point {
        group: "config",
        name: "adaptive",
        cite: "[0214], [0413]-[0414]",
        meaning: "the drive interval mode",
        sampled: Sampled::Config,
        bins: bins!("fixed": "first embodiment: fixed cycle T = x", "adaptive": "second embodiment: FIG. 17/18"),
        unreachable: &[],
    },
    Point {
        group: "config",
        name: "clock",
        cite: "docs/spec.md 6.1 (clock period)",
        meaning: "the clock period of the run",
        sampled: Sampled::Config,
        bins: bins!("below_10us": "faster than 10 us", "10us": "10 us, the default", "above_10us": "slower than 10 us"),
        unreachable: &[],
    },
];

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
    (a == "key_on").then_some("interval.at_edge is sampled at key-off samples only")
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
pub static CROSSES: [Cross; 13] = [
    Cross {
        name: "fig17_x_fig18",
        cite: "FIG. 17 x FIG. 18",
        meaning: "each FIG. 17 path with each FIG. 18 path that leads to it",
        rows: FIG17,
        columns: FIG18,
        unreachable: fig17_x_fig18,
    },
    Cross {
        name: "rule_x_interval",
        cite: "[0096]-[0099] x [0216]-[0228]",
        meaning: "each counting rule at each interval class of the key-off sample that applied it",
        rows: RULE,
        columns: SI_AT_EDGE,
        unreachable: rule_x_interval,
    },
    Cross {
        name: "rule_x_mode",
        cite: "[0096]-[0099] x [0349]",
        meaning: "each counting rule with the key off and on",
        rows: RULE,
        columns: SAMPLE_MODE,
        unreachable: none,
    },
    Cross {
        name: "key_edge_x_phase",
        cite: "[0213] x [0319]-[0323], [0349]",
        meaning: "key edges in each phase of the output pulse window and of the on-key cycle",
        rows: KEY_EDGE,
        columns: KEY_PHASE,
        unreachable: key_edge_x_phase,
    },
    Cross {
        name: "wrap_x_cnt_w",
        cite: "docs/spec.md 2.5",
        meaning: "counter wraps at each class of CNT_W",
        rows: WRAP,
        columns: CFG_CNT_W,
        unreachable: none,
    },
    Cross {
        name: "rule_x_cnt_w",
        cite: "[0096]-[0099] x CNT_W",
        meaning: "each counting rule at each class of CNT_W",
        rows: RULE,
        columns: CFG_CNT_W,
        unreachable: rule_x_cnt_w,
    },
    Cross {
        name: "fig18_x_history",
        cite: "[0237]-[0241] x FIG. 18",
        meaning: "each FIG. 18 path from each state of the change history",
        rows: HIST,
        columns: FIG18,
        unreachable: hist_x_fig18,
    },
    Cross {
        name: "fig17_x_cnt_r",
        cite: "FIG. 17 x [0248]",
        meaning: "each FIG. 17 path from each class of CNTr",
        rows: FIG17,
        columns: CNT_R_BEFORE,
        unreachable: fig17_x_cnt_r,
    },
    Cross {
        name: "preset_x_mode",
        cite: "[0092]-[0093] x [0349]",
        meaning: "the first-sample preset of each quadrant, key off and key on",
        rows: PRESET,
        columns: SAMPLE_MODE,
        unreachable: preset_x_mode,
    },
    Cross {
        name: "skip_x_interval",
        cite: "docs/spec.md 2.5 x [0216]-[0228]",
        meaning: "quadrant skips at each interval class (too fast for the interval in force)",
        rows: SKIP,
        columns: SI_AT_EDGE,
        unreachable: skip_x_interval,
    },
    Cross {
        name: "shorten_x_t1",
        cite: "[0224] x [0260]-[0262]",
        meaning: "where S6 lands for each class of T1",
        rows: SHORTEN_TO,
        columns: CFG_T1,
        unreachable: shorten_x_t1,
    },
    Cross {
        name: "expand_x_t2",
        cite: "[0250] x [0260]",
        meaning: "where S10 lands for each class of T2",
        rows: EXPAND_TO,
        columns: CFG_T2,
        unreachable: expand_x_t2,
    },
    Cross {
        name: "write_reg_x_outcome",
        cite: "docs/spec.md 2.8 and 4",
        meaning: "each register with each outcome of a write",
        rows: WRITE_REG,
        columns: WRITE_OUTCOME,
        unreachable: write_reg_x_outcome,
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
}];

/// Bins only port-level stimuli reach (cocotb, a DPI bench, the stress vectors): a scenario's
/// MPU reads the register map's addresses only, and `pmu50 check` refuses a scenario that writes
/// a read-only or unmapped address. They count in the coverage; `pmu50 regress` reports its
/// closure over the other bins too, and closes these when port-level coverage is merged in.
pub const PORT_ONLY: [&str; 4] = [
    "bus.read.unmapped",
    "bus.write_reg.read_only",
    "bus.write_reg.unmapped",
    "bus.write_outcome.refused_not_writable",
];

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
    /// Only port-level stimuli reach it ([`PORT_ONLY`]).
    pub port_only: bool,
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
                let port_only = PORT_ONLY.contains(&name.as_str());
                bins.push(BinInfo {
                    name,
                    kind: Kind::Point,
                    group: p.group,
                    cite: p.cite,
                    meaning: b.meaning.to_string(),
                    unreachable,
                    port_only,
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
                    let port_only = [(pa, ba), (pb, bb)].iter().any(|(p, b)| {
                        PORT_ONLY.contains(&format!("{}.{}.{}", p.group, p.name, b.name).as_str())
                    });
                    bins.push(BinInfo {
                        port_only,
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
