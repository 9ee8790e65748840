//! The signal table: every top-level port, register and internal signal of the core, declared
//! once (name, width or width parameter, direction, display radix, signedness, reset value, VCD
//! scope, meaning, patent paragraphs), with an accessor that reads its value from
//! [`Inputs`], [`Outputs`], [`Regs`] or [`Internals`].
//!
//! Everything that lists signals is generated from these four lists: the `values()` lists of
//! [`crate::pmu50`], the VCD declarations and GTKWave display formats (`testbench/src/observers/waveform.rs`), the
//! change log's signedness (`testbench/src/observers/changelog.rs`), the vector file's `columns` header
//! (`testbench/src/observers/vectors.rs`), the C ABI mirror and its widths (`hdl/ffi`, whose header
//! `hdl/ffi/include/pmu50.h` is checked against this table by a test) and the tables of
//! `docs/signals.md` (checked by `rtl_model/core/tests/signal_table.rs`; regenerate both with
//! `PMU50_REGENERATE=1 cargo test -p pmu50-core --test signal_table` and
//! `PMU50_REGENERATE=1 cargo test -p pmu50-ffi --test header`).
//!
//! The order of each list is the VCD declaration order, the vector file's column order and the
//! C ABI's index order; it must not change without a reason (golden files depend on it).

use crate::pmu50::{Inputs, Internals, Outputs, Regs, Structural};

/// Bit width of a signal: fixed, or one of the structural parameters (Verilog `parameter`s).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Width {
    Bits(u8),
    /// `CNT_W` = `cnt_width`, 2..=16.
    CntWidth,
    /// `SYNC_DEPTH` = `sync_depth`, 1..=4.
    SyncDepth,
}

impl Width {
    /// The width in bits in a core with these structural parameters.
    pub const fn bits(self, s: &Structural) -> u8 {
        match self {
            Width::Bits(b) => b,
            Width::CntWidth => s.cnt_width,
            Width::SyncDepth => s.sync_depth,
        }
    }

    /// The largest width over every legal structural configuration (storage size in the C ABI).
    pub const fn max_bits(self) -> u8 {
        match self {
            Width::Bits(b) => b,
            Width::CntWidth => 16,
            Width::SyncDepth => 4,
        }
    }

    /// As written in the docs: `16`, `CNT_W`, `SYNC_DEPTH`.
    pub fn doc(self) -> String {
        match self {
            Width::Bits(b) => b.to_string(),
            Width::CntWidth => "CNT_W".to_string(),
            Width::SyncDepth => "SYNC_DEPTH".to_string(),
        }
    }
}

/// Kind of signal: a port of the top level, a register (flip-flop) of a block, or an internal
/// combinational signal of the cycle.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Dir {
    In,
    Out,
    Reg,
    Internal,
}

impl Dir {
    pub const fn doc(self) -> &'static str {
        match self {
            Dir::In => "in",
            Dir::Out => "out",
            Dir::Reg => "reg",
            Dir::Internal => "internal",
        }
    }
}

/// Display radix of a multi-bit value (GTKWave trace format, change log); a 1-bit signal is
/// always shown as a bit.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Radix {
    Binary,
    Hex,
    Decimal,
}

/// Reset value of a register.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Reset {
    /// A constant.
    Value(u64),
    /// The value of this Verilog parameter of the twin (a configured reset value).
    Param(&'static str),
    /// Not a flip-flop: a port or internal signal, decoded from registers and inputs.
    None,
}

impl Reset {
    pub fn doc(self) -> String {
        match self {
            Reset::Value(v) => v.to_string(),
            Reset::Param(p) => format!("`{p}`"),
            Reset::None => "-".to_string(),
        }
    }
}

/// One signal of the core. `T` is the struct it is read from ([`Inputs`], [`Outputs`],
/// [`Regs`] or [`Internals`]).
#[derive(Clone, Copy, Debug)]
pub struct Signal<T> {
    pub name: &'static str,
    /// VCD scope below `pmu50`: `""` for the ports (top scope), the block instance for a
    /// register (the field of [`Regs`], e.g. `updown_counter`), `internals` for internals.
    pub scope: &'static str,
    pub dir: Dir,
    pub width: Width,
    pub radix: Radix,
    /// Two's complement (shown as a signed decimal).
    pub signed: bool,
    pub reset: Reset,
    /// Changes at every tick (the free-running timer): left out of the change log.
    pub free_running: bool,
    /// One of the contract signals with the HDL team (docs/signals.md, first table).
    pub contract: bool,
    pub meaning: &'static str,
    /// Patent paragraphs, e.g. `[0096]-[0097]`.
    pub patent: &'static str,
    /// Read the value (zero-extended to 64 bits).
    pub get: fn(&T) -> u64,
}

impl<T> Signal<T> {
    /// Width in bits in a core with these structural parameters.
    pub const fn bits(&self, s: &Structural) -> u8 {
        self.width.bits(s)
    }

    /// Dotted path below `pmu50`: `si`, `drive_interval.si`, `internals.fig17`.
    pub fn path(&self) -> String {
        if self.scope.is_empty() {
            self.name.to_string()
        } else {
            format!("{}.{}", self.scope, self.name)
        }
    }

    /// The value as shown to a person: signed decimal for signed signals (in the signal's width),
    /// unsigned decimal otherwise.
    pub fn show(&self, value: u64, s: &Structural) -> String {
        if self.signed {
            sext64(value, self.bits(s)).to_string()
        } else {
            value.to_string()
        }
    }
}

/// Two's-complement value of the low `width` bits of `v`.
pub fn sext64(v: u64, width: u8) -> i64 {
    let w = u32::from(width.clamp(1, 64));
    if w == 64 {
        return v as i64;
    }
    let v = v & ((1u64 << w) - 1);
    if (v >> (w - 1)) & 1 == 1 {
        v as i64 - (1i64 << w)
    } else {
        v as i64
    }
}

#[allow(clippy::too_many_arguments)]
const fn port<T>(
    name: &'static str,
    dir: Dir,
    width: Width,
    radix: Radix,
    signed: bool,
    contract: bool,
    meaning: &'static str,
    patent: &'static str,
    get: fn(&T) -> u64,
) -> Signal<T> {
    Signal {
        name,
        scope: "",
        dir,
        width,
        radix,
        signed,
        reset: Reset::None,
        free_running: false,
        contract,
        meaning,
        patent,
        get,
    }
}

#[allow(clippy::too_many_arguments)]
const fn reg(
    scope: &'static str,
    name: &'static str,
    width: Width,
    radix: Radix,
    signed: bool,
    reset: Reset,
    meaning: &'static str,
    patent: &'static str,
    get: fn(&Regs) -> u64,
) -> Signal<Regs> {
    Signal {
        name,
        scope,
        dir: Dir::Reg,
        width,
        radix,
        signed,
        reset,
        free_running: false,
        contract: false,
        meaning,
        patent,
        get,
    }
}

const fn internal(
    name: &'static str,
    width: Width,
    radix: Radix,
    meaning: &'static str,
    patent: &'static str,
    get: fn(&Internals) -> u64,
) -> Signal<Internals> {
    Signal {
        name,
        scope: "internals",
        dir: Dir::Internal,
        width,
        radix,
        signed: false,
        reset: Reset::None,
        free_running: false,
        contract: false,
        meaning,
        patent,
        get,
    }
}

use Radix::{Binary as B, Decimal as D, Hex as H};
use Width::{Bits, CntWidth, SyncDepth};

const fn b(v: bool) -> u64 {
    v as u64
}

/// Top-level inputs, in vector-file column order.
pub const INPUTS: &[Signal<Inputs>] = &[
    port(
        "ig",
        Dir::In,
        Bits(1),
        B,
        false,
        true,
        "ignition key signal IG",
        "[0080]",
        |i| b(i.ig),
    ),
    port(
        "vs2_ok",
        Dir::In,
        Bits(1),
        B,
        false,
        false,
        "Vs2 power-good from the analog rail monitor",
        "[0209]",
        |i| b(i.vs2_ok),
    ),
    port(
        "cmp_s",
        Dir::In,
        Bits(1),
        B,
        false,
        false,
        "raw decision of comparator 58a (sin2 >= Vr)",
        "[0086]",
        |i| b(i.cmp_s),
    ),
    port(
        "cmp_c",
        Dir::In,
        Bits(1),
        B,
        false,
        false,
        "raw decision of comparator 58b (cos2 >= Vr)",
        "[0087]",
        |i| b(i.cmp_c),
    ),
    port(
        "bus_we",
        Dir::In,
        Bits(1),
        B,
        false,
        false,
        "register write strobe",
        "[0259]",
        |i| b(i.bus_we),
    ),
    port(
        "bus_addr",
        Dir::In,
        Bits(8),
        B,
        false,
        false,
        "register address",
        "[0259]",
        |i| i.bus_addr as u64,
    ),
    port(
        "bus_wdata",
        Dir::In,
        Bits(16),
        B,
        false,
        false,
        "register write data",
        "[0259]",
        |i| i.bus_wdata as u64,
    ),
];

/// Writes an input from a 64-bit value (low bits; a 1-bit input is true when non-zero), in the
/// order of [`INPUTS`].
pub const INPUT_SETTERS: [fn(&mut Inputs, u64); 7] = [
    |i, v| i.ig = v != 0,
    |i, v| i.vs2_ok = v != 0,
    |i, v| i.cmp_s = v != 0,
    |i, v| i.cmp_c = v != 0,
    |i, v| i.bus_we = v != 0,
    |i, v| i.bus_addr = v as u8,
    |i, v| i.bus_wdata = v as u16,
];

/// Top-level outputs (all Moore), in vector-file column order.
pub const OUTPUTS: &[Signal<Outputs>] = &[
    port(
        "sig",
        Dir::Out,
        Bits(1),
        B,
        false,
        true,
        "operation switching signal Sig",
        "[0196]-[0198]",
        |o| b(o.sig),
    ),
    port(
        "vr_hi",
        Dir::Out,
        Bits(1),
        B,
        false,
        false,
        "regulator 51: 6 V (1) / 4 V (0)",
        "[0340]",
        |o| b(o.vr_hi),
    ),
    port(
        "vm_en",
        Dir::Out,
        Bits(1),
        B,
        false,
        true,
        "power source Vm on (unit 52)",
        "[0202]",
        |o| b(o.vm_en),
    ),
    port(
        "vs1_en",
        Dir::Out,
        Bits(1),
        B,
        false,
        true,
        "first sensor power Vs1 on (unit 53)",
        "[0203]",
        |o| b(o.vs1_en),
    ),
    port(
        "vs2_en",
        Dir::Out,
        Bits(1),
        B,
        false,
        true,
        "second sensor power Vs2 on (unit 54)",
        "[0206], [0347]",
        |o| b(o.vs2_en),
    ),
    port(
        "vp_en",
        Dir::Out,
        Bits(1),
        B,
        false,
        true,
        "internal power Vp on (always 1)",
        "[0330]",
        |o| b(o.vp_en),
    ),
    port(
        "rail_hi",
        Dir::Out,
        Bits(1),
        B,
        false,
        false,
        "Vs2 and Vp at Vcc1 (1) / Vcc2 (0)",
        "[0343], [0345], [0348]",
        |o| b(o.rail_hi),
    ),
    port(
        "st",
        Dir::Out,
        Bits(1),
        B,
        false,
        true,
        "timing signal St",
        "[0336]",
        |o| b(o.st),
    ),
    port(
        "sr",
        Dir::Out,
        Bits(1),
        B,
        false,
        true,
        "activation signal Sr",
        "[0209]",
        |o| b(o.sr),
    ),
    port(
        "ps_win",
        Dir::Out,
        Bits(1),
        B,
        false,
        false,
        "inside the sampling period Ps",
        "[0322]-[0323]",
        |o| b(o.ps_win),
    ),
    port(
        "smp",
        Dir::Out,
        Bits(1),
        B,
        false,
        false,
        "sampling strobe",
        "[0354]",
        |o| b(o.smp),
    ),
    port(
        "cs",
        Dir::Out,
        Bits(1),
        B,
        false,
        true,
        "sign signal Cs (latched)",
        "[0086]",
        |o| b(o.cs),
    ),
    port(
        "cc",
        Dir::Out,
        Bits(1),
        B,
        false,
        true,
        "sign signal Cc (latched)",
        "[0087]",
        |o| b(o.cc),
    ),
    port(
        "cnt_s",
        Dir::Out,
        CntWidth,
        D,
        true,
        true,
        "sine count value CNTs",
        "[0096]-[0097]",
        |o| o.cnt_s as u64,
    ),
    port(
        "cnt_c",
        Dir::Out,
        CntWidth,
        D,
        true,
        true,
        "cosine count value CNTc",
        "[0098]-[0099]",
        |o| o.cnt_c as u64,
    ),
    port(
        "cnt_r",
        Dir::Out,
        Bits(8),
        D,
        false,
        true,
        "power supply count CNTr",
        "[0248]",
        |o| o.cnt_r as u64,
    ),
    port(
        "si",
        Dir::Out,
        Bits(16),
        D,
        false,
        true,
        "drive interval instruction Si, in ticks",
        "[0199]",
        |o| o.si as u64,
    ),
    port(
        "hist_s",
        Dir::Out,
        Bits(1),
        B,
        false,
        true,
        "change history of Cs",
        "[0237]",
        |o| b(o.hist_s),
    ),
    port(
        "hist_c",
        Dir::Out,
        Bits(1),
        B,
        false,
        true,
        "change history of Cc",
        "[0240]",
        |o| b(o.hist_c),
    ),
    port(
        "diag",
        Dir::Out,
        Bits(1),
        B,
        false,
        true,
        "count diagnosis",
        "[0119]",
        |o| b(o.diag),
    ),
    port(
        "quadrant_skip",
        Dir::Out,
        Bits(1),
        B,
        false,
        false,
        "sticky: both signs changed in one sample",
        "[0119]",
        |o| b(o.quadrant_skip),
    ),
    port(
        "bus_rdata",
        Dir::Out,
        Bits(16),
        H,
        false,
        false,
        "registered read data",
        "[0108]",
        |o| o.bus_rdata as u64,
    ),
    port(
        "bus_err",
        Dir::Out,
        Bits(1),
        B,
        false,
        false,
        "sticky: a write was refused",
        "[0259]",
        |o| b(o.bus_err),
    ),
];

/// Every register, grouped by block in evaluation order (the VCD sub-scopes `pmu50.<block>`).
pub const REGISTERS: &[Signal<Regs>] = &[
    reg(
        "action_switching",
        "sync",
        SyncDepth,
        H,
        false,
        Reset::Value(0),
        "synchronizer stages of `ig`, bit 0 first; the last stage is `sig`",
        "[0213]",
        |r| r.action_switching.sync as u64,
    ),
    reg(
        "register_file",
        "adaptive",
        Bits(1),
        B,
        false,
        Reset::Param("ADAPTIVE"),
        "CTRL bit 0: adaptive drive interval",
        "[0214]",
        |r| b(r.register_file.adaptive),
    ),
    reg(
        "register_file",
        "pw",
        Bits(16),
        D,
        false,
        Reset::Param("PW"),
        "waiting period Pw, ticks",
        "[0321]",
        |r| r.register_file.pw as u64,
    ),
    reg(
        "register_file",
        "pi",
        Bits(16),
        D,
        false,
        Reset::Param("PI"),
        "idle period Pi, ticks",
        "[0322]",
        |r| r.register_file.pi as u64,
    ),
    reg(
        "register_file",
        "ps",
        Bits(16),
        D,
        false,
        Reset::Param("PS"),
        "sampling period Ps, ticks",
        "[0322]",
        |r| r.register_file.ps as u64,
    ),
    reg(
        "register_file",
        "si_max",
        Bits(16),
        D,
        false,
        Reset::Param("SI_MAX"),
        "maximum interval x, ticks",
        "[0216]",
        |r| r.register_file.si_max as u64,
    ),
    reg(
        "register_file",
        "si_min",
        Bits(16),
        D,
        false,
        Reset::Param("SI_MIN"),
        "minimum interval, ticks",
        "[0228]",
        |r| r.register_file.si_min as u64,
    ),
    reg(
        "register_file",
        "t1",
        Bits(16),
        D,
        false,
        Reset::Param("T1"),
        "shortening step T1, ticks",
        "[0224]",
        |r| r.register_file.t1 as u64,
    ),
    reg(
        "register_file",
        "t2",
        Bits(16),
        D,
        false,
        Reset::Param("T2"),
        "expanding step T2, ticks",
        "[0250]",
        |r| r.register_file.t2 as u64,
    ),
    reg(
        "register_file",
        "cth",
        Bits(8),
        D,
        false,
        Reset::Param("CTH"),
        "count threshold Cth",
        "[0250]",
        |r| r.register_file.cth as u64,
    ),
    reg(
        "register_file",
        "smp_on",
        Bits(16),
        D,
        false,
        Reset::Param("SMP_ON"),
        "on-key sampling period, ticks",
        "[0349]",
        |r| r.register_file.smp_on as u64,
    ),
    reg(
        "register_file",
        "bus_err",
        Bits(1),
        B,
        false,
        Reset::Value(0),
        "sticky: a write was refused",
        "[0259]",
        |r| b(r.register_file.bus_err),
    ),
    reg(
        "register_file",
        "rdata",
        Bits(16),
        H,
        false,
        Reset::Value(0),
        "registered read data",
        "[0108]",
        |r| r.register_file.rdata as u64,
    ),
    Signal {
        free_running: true,
        ..reg(
            "timing_generator",
            "tmr",
            Bits(16),
            D,
            false,
            Reset::Value(0),
            "ticks since the start of the current cycle (free-running timer)",
            "[0336]",
            |r| r.timing_generator.tmr as u64,
        )
    },
    reg(
        "sensor_power_determination",
        "sr",
        Bits(1),
        B,
        false,
        Reset::Value(0),
        "activation signal Sr",
        "[0209]",
        |r| b(r.sensor_power_determination.sr),
    ),
    reg(
        "comparator_latch",
        "cs",
        Bits(1),
        B,
        false,
        Reset::Value(0),
        "sign signal Cs",
        "[0086]",
        |r| b(r.comparator_latch.cs),
    ),
    reg(
        "comparator_latch",
        "cc",
        Bits(1),
        B,
        false,
        Reset::Value(0),
        "sign signal Cc",
        "[0087]",
        |r| b(r.comparator_latch.cc),
    ),
    reg(
        "comparator_latch",
        "vld",
        Bits(1),
        B,
        false,
        Reset::Value(0),
        "a sample has been taken since reset",
        "[0092]",
        |r| b(r.comparator_latch.vld),
    ),
    reg(
        "updown_counter",
        "cnt_s",
        CntWidth,
        D,
        true,
        Reset::Value(0),
        "sine count value CNTs",
        "[0096]-[0097]",
        |r| r.updown_counter.cnt_s as u64,
    ),
    reg(
        "updown_counter",
        "cnt_c",
        CntWidth,
        D,
        true,
        Reset::Value(0),
        "cosine count value CNTc",
        "[0098]-[0099]",
        |r| r.updown_counter.cnt_c as u64,
    ),
    reg(
        "updown_counter",
        "quadrant_skip",
        Bits(1),
        B,
        false,
        Reset::Value(0),
        "sticky: both signs changed in one sample",
        "[0119]",
        |r| b(r.updown_counter.quadrant_skip),
    ),
    reg(
        "drive_interval",
        "si",
        Bits(16),
        D,
        false,
        Reset::Param("SI_MAX"),
        "drive interval Si, ticks",
        "[0199], [0226]",
        |r| r.drive_interval.si as u64,
    ),
    reg(
        "drive_interval",
        "hist_s",
        Bits(1),
        B,
        false,
        Reset::Value(0),
        "change history of Cs",
        "[0237]",
        |r| b(r.drive_interval.hist_s),
    ),
    reg(
        "drive_interval",
        "hist_c",
        Bits(1),
        B,
        false,
        Reset::Value(0),
        "change history of Cc",
        "[0240]",
        |r| b(r.drive_interval.hist_c),
    ),
    reg(
        "drive_interval",
        "cnt_r",
        Bits(8),
        D,
        false,
        Reset::Value(0),
        "power supply count CNTr, saturating at 255",
        "[0248]",
        |r| r.drive_interval.cnt_r as u64,
    ),
    reg(
        "count_diagnosis",
        "diag",
        Bits(1),
        B,
        false,
        Reset::Value(0),
        "count diagnosis flag",
        "[0119]",
        |r| b(r.count_diagnosis.diag),
    ),
];

/// Combinational signals of the cycle (they depend on this cycle's inputs).
pub const INTERNALS: &[Signal<Internals>] = &[
    internal(
        "kon",
        Bits(1),
        B,
        "`sig` rises at this edge (key on)",
        "[0213]",
        |x| b(x.kon),
    ),
    internal(
        "koff",
        Bits(1),
        B,
        "`sig` falls at this edge (key off)",
        "[0213]",
        |x| b(x.koff),
    ),
    internal(
        "upd",
        Bits(1),
        B,
        "a sample is taken at this edge (`smp` & `sr`)",
        "[0265]",
        |x| b(x.upd),
    ),
    internal(
        "first",
        Bits(1),
        B,
        "this sample is the first since reset",
        "[0092]",
        |x| b(x.first),
    ),
    internal(
        "chg_s",
        Bits(1),
        B,
        "`cs` changes at this edge",
        "[0268]",
        |x| b(x.chg_s),
    ),
    internal(
        "chg_c",
        Bits(1),
        B,
        "`cc` changes at this edge",
        "[0268]",
        |x| b(x.chg_c),
    ),
    internal(
        "skip_clr",
        Bits(1),
        B,
        "write-1-to-clear strobe of STATUS.quadrant_skip",
        "[0119]",
        |x| b(x.skip_clr),
    ),
    internal(
        "fig17",
        Bits(3),
        D,
        "FIG. 17 path taken at this edge (spec 2.6)",
        "[0263]-[0291]",
        |x| x.fig17 as u64,
    ),
    internal(
        "fig18",
        Bits(3),
        D,
        "FIG. 18 path taken at this edge (spec 2.6)",
        "[0268]-[0279]",
        |x| x.fig18 as u64,
    ),
];

pub const N_INPUTS: usize = INPUTS.len();
pub const N_OUTPUTS: usize = OUTPUTS.len();
pub const N_REGISTERS: usize = REGISTERS.len();
pub const N_INTERNALS: usize = INTERNALS.len();

/// Ports of the Verilog twin that the model does not have (its step is one rising edge, its
/// construction is the reset): (name, width, direction, meaning).
pub const HDL_ONLY_PORTS: &[(&str, u8, &str, &str)] = &[
    (
        "clk",
        1,
        "in",
        "clock (HDL only; the model's step is one rising edge)",
    ),
    ("rst_n", 1, "in", "power-on reset, active low (HDL only)"),
];

/// Values of `list` read from `v`, in table order.
pub fn values<T, const N: usize>(list: &[Signal<T>], v: &T) -> [u64; N] {
    std::array::from_fn(|k| (list[k].get)(v))
}

/// Index of a register by `name`, `block.name` or `pmu50.block.name` (a bare name must be
/// unique among the registers).
pub fn find_register(q: &str) -> Result<usize, FindError> {
    let q = q.strip_prefix("pmu50.").unwrap_or(q);
    let hits: Vec<usize> = REGISTERS
        .iter()
        .enumerate()
        .filter(|(_, r)| match q.split_once('.') {
            Some((blk, n)) => r.scope == blk && r.name == n,
            None => r.name == q,
        })
        .map(|(k, _)| k)
        .collect();
    match hits.as_slice() {
        [k] => Ok(*k),
        [] => Err(FindError::Unknown(q.to_string())),
        many => Err(FindError::Ambiguous(
            q.to_string(),
            many.iter()
                .map(|&k| REGISTERS[k].path())
                .collect::<Vec<_>>()
                .join(", "),
        )),
    }
}

#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum FindError {
    #[error(
        "no register `{0}`; names are `name`, `block.name` or `pmu50.block.name` (docs/signals.md)"
    )]
    Unknown(String),
    #[error("register name `{0}` is ambiguous ({1}); use `block.name`")]
    Ambiguous(String, String),
}

// ------------------------------------------------------------------------------------------
// docs/signals.md

fn port_row<T>(s: &Signal<T>, with_patent: bool) -> String {
    let w = match s.width {
        Width::CntWidth => "16 (CNT_W)".to_string(),
        w => w.doc(),
    };
    if with_patent {
        format!(
            "| `{}` | {} | {} | {} | {} |\n",
            s.name,
            w,
            s.dir.doc(),
            s.meaning,
            s.patent
        )
    } else {
        format!(
            "| `{}` | {} | {} | {} |\n",
            s.name,
            w,
            s.dir.doc(),
            s.meaning
        )
    }
}

/// The generated tables of docs/signals.md (between the `<!-- signal table -->` markers).
pub fn markdown_tables() -> String {
    let mut m = String::new();
    m += "## Contract signals\n\n| name | width | direction | meaning | patent |\n|---|---|---|---|---|\n";
    for s in INPUTS.iter().filter(|s| s.contract) {
        m += &port_row(s, true);
    }
    for s in OUTPUTS.iter().filter(|s| s.contract) {
        m += &port_row(s, true);
    }
    m += "\n## Other ports\n\n| name | width | direction | meaning |\n|---|---|---|---|\n";
    for (n, w, d, meaning) in HDL_ONLY_PORTS {
        m += &format!("| `{n}` | {w} | {d} | {meaning} |\n");
    }
    for s in INPUTS.iter().filter(|s| !s.contract) {
        m += &port_row(s, false);
    }
    for s in OUTPUTS.iter().filter(|s| !s.contract) {
        m += &port_row(s, false);
    }
    m += "\n## Registers (scope `pmu50.<block>`)\n\n";
    m += "The VCD scopes, the Verilog instance names of the twin and the Rust fields of `pmu50::Regs` are\n";
    m += "the same. Widths in bits; `CNT_W` (2..16, default 16) and `SYNC_DEPTH` (1..4, default 2) are\n";
    m += "the structural parameters. A reset value in backquotes is the Verilog parameter of that name\n";
    m += "(the configured value).\n\n";
    m += "| scope | register | width | reset | meaning | patent |\n|---|---|---|---|---|---|\n";
    for r in REGISTERS {
        m += &format!(
            "| `pmu50.{}` | `{}` | {} | {} | {} | {} |\n",
            r.scope,
            r.name,
            r.width.doc(),
            r.reset.doc(),
            r.meaning,
            r.patent
        );
    }
    m += "\n## Internal signals (scope `pmu50.internals`)\n\n";
    m += "Combinational values of the cycle that ends at the edge.\n\n";
    m += "| name | width | meaning | patent |\n|---|---|---|---|\n";
    for x in INTERNALS {
        m += &format!(
            "| `{}` | {} | {} | {} |\n",
            x.name,
            x.width.doc(),
            x.meaning,
            x.patent
        );
    }
    m
}

/// Replace the text between the lines `begin` and `end` of `doc` with `body`; `None` when a
/// marker is missing.
pub fn splice(doc: &str, begin: &str, end: &str, body: &str) -> Option<String> {
    let a = doc.find(begin)? + begin.len();
    let a = a + doc[a..].find('\n')? + 1;
    let z = a + doc[a..].find(end)?;
    let z = doc[..z].rfind('\n').map_or(z, |p| p + 1);
    Some(format!("{}{}{}", &doc[..a], body, &doc[z..]))
}

/// For the tests that keep a file in step with the code (docs/signals.md, the C header, a stored
/// stimulus): with `PMU50_REGENERATE` set, writes `want` to `path` (a temporary file beside it,
/// then a rename) and returns true, the check then being done; otherwise returns false and
/// leaves the comparison to the caller.
pub fn regenerate(path: &std::path::Path, want: &str) -> bool {
    if std::env::var_os("PMU50_REGENERATE").is_none() {
        return false;
    }
    let mut tmp = path.as_os_str().to_owned();
    tmp.push(".tmp");
    std::fs::write(&tmp, want)
        .unwrap_or_else(|e| panic!("{}: {e}", std::path::Path::new(&tmp).display()));
    std::fs::rename(&tmp, path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    true
}

/// The check of a file of the workspace whose part between the lines `begin` and `end` is
/// generated from the signal table (`body`): with `PMU50_REGENERATE` set the part is rewritten
/// ([`regenerate`]); otherwise the file must hold it already. `file` is the file's path from the
/// workspace root `root` (the test passes its checkout's; the message names `file`), `command`
/// the command that regenerates it.
pub fn check_generated(
    root: &std::path::Path,
    file: &str,
    (begin, end): (&str, &str),
    body: &str,
    command: &str,
) -> Result<(), String> {
    let path = root.join(file);
    let text = std::fs::read_to_string(&path).map_err(|e| format!("{file}: {e}"))?;
    let want = splice(&text, begin, end, body)
        .ok_or_else(|| format!("{file} lost its BEGIN/END GENERATED markers"))?;
    if regenerate(&path, &want) || text == want {
        return Ok(());
    }
    Err(format!("{file} differs from the signal table (rtl_model/core/src/signals.rs); regenerate with PMU50_REGENERATE=1 {command} and review the diff"))
}

// The values of the core's ports, registers and internals in the order of the tables above.

/// One register of the core, for waveforms, change logs and lockstep read-back.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RegValue {
    /// Block instance name (the field of [`Regs`]).
    pub block: &'static str,
    pub name: &'static str,
    pub width: u8,
    pub value: u64,
}

impl Regs {
    /// Every register with its width and value, in a fixed order (block order of [`eval`]):
    /// [`REGISTERS`].
    pub fn values(&self, s: &Structural) -> Vec<RegValue> {
        REGISTERS
            .iter()
            .map(|r| RegValue {
                block: r.scope,
                name: r.name,
                width: r.bits(s),
                value: (r.get)(self),
            })
            .collect()
    }
}

impl Outputs {
    /// Every output port as (name, width, value), in the order of [`OUTPUTS`].
    pub fn values(&self, s: &Structural) -> [(&'static str, u8, u64); N_OUTPUTS] {
        std::array::from_fn(|k| {
            let o = &OUTPUTS[k];
            (o.name, o.bits(s), (o.get)(self))
        })
    }
}

impl Inputs {
    /// Every input port as (name, width, value), in the order of [`INPUTS`].
    pub fn values(&self) -> [(&'static str, u8, u64); N_INPUTS] {
        // Inputs have no structural width.
        let s = Structural {
            sync_depth: 1,
            cnt_width: 16,
        };
        std::array::from_fn(|k| {
            let i = &INPUTS[k];
            (i.name, i.bits(&s), (i.get)(self))
        })
    }
}

impl Internals {
    /// Every internal signal as (name, width, value), in the order of [`INTERNALS`].
    pub fn values(&self) -> [(&'static str, u8, u64); N_INTERNALS] {
        let s = Structural {
            sync_depth: 1,
            cnt_width: 16,
        };
        std::array::from_fn(|k| {
            let x = &INTERNALS[k];
            (x.name, x.bits(&s), (x.get)(self))
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_are_unique_per_scope_and_widths_fit_the_storage() {
        let mut seen = std::collections::HashSet::new();
        let paths = INPUTS
            .iter()
            .map(|s| (s.path(), s.width))
            .chain(OUTPUTS.iter().map(|s| (s.path(), s.width)))
            .chain(REGISTERS.iter().map(|s| (s.path(), s.width)))
            .chain(INTERNALS.iter().map(|s| (s.path(), s.width)));
        for (p, w) in paths {
            assert!(seen.insert(p.clone()), "{p} declared twice");
            assert!((1..=16).contains(&w.max_bits()), "{p}");
        }
    }

    #[test]
    fn ports_without_a_structural_width_are_fixed() {
        for w in INPUTS
            .iter()
            .map(|s| s.width)
            .chain(INTERNALS.iter().map(|s| s.width))
        {
            assert!(
                matches!(w, Width::Bits(_)),
                "inputs and internals have fixed widths"
            );
        }
    }

    #[test]
    fn each_input_setter_writes_its_own_input() {
        for (k, set) in INPUT_SETTERS.iter().enumerate() {
            let mut i = Inputs::default();
            set(&mut i, 1);
            for (j, s) in INPUTS.iter().enumerate() {
                assert_eq!(
                    (s.get)(&i),
                    u64::from(j == k),
                    "setter {k} vs input {}",
                    s.name
                );
            }
        }
        assert_eq!(INPUT_SETTERS.len(), N_INPUTS);
    }

    #[test]
    fn find_register_resolves_every_form() {
        let k = find_register("updown_counter.cnt_s").unwrap();
        assert_eq!(REGISTERS[k].name, "cnt_s");
        assert_eq!(find_register("cnt_s"), Ok(k));
        assert_eq!(find_register("pmu50.updown_counter.cnt_s"), Ok(k));
        assert!(matches!(find_register("nope"), Err(FindError::Unknown(_))));
        assert_eq!(
            REGISTERS[find_register("bus_err").unwrap()].scope,
            "register_file"
        );
    }

    #[test]
    fn sext64_is_two_complement() {
        assert_eq!(sext64(0xFFFF, 16), -1);
        assert_eq!(sext64(0x7, 3), -1);
        assert_eq!(sext64(0x3, 3), 3);
        assert_eq!(sext64(0x8000, 16), -32768);
    }

    #[test]
    fn splice_replaces_between_markers() {
        let d = "a\n<!-- b -->\nold\nold\n<!-- e -->\nz\n";
        assert_eq!(
            splice(d, "<!-- b -->", "<!-- e -->", "new\n").unwrap(),
            "a\n<!-- b -->\nnew\n<!-- e -->\nz\n"
        );
        assert_eq!(splice(d, "<!-- x -->", "<!-- e -->", ""), None);
    }
}
