//! Checked, deterministic VCD writer.
//!
//! Two phases, two types:
//!
//! 1. [`VcdBuilder`] declares `module` scopes and variables (single-bit `wire`/`reg`,
//!    `[msb:lsb]` vectors, `real`), each with an initial value, and returns a
//!    [`SigId`] handle per variable.
//! 2. [`VcdBuilder::start`] writes the header (`$version`, `$timescale`, scopes,
//!    `$enddefinitions`; never `$date`, so equal inputs give byte-identical files)
//!    and returns a [`VcdWriter`] that dumps value changes.
//!
//! The writer checks what the `vcd` crate leaves to the caller: time never goes
//! backwards, a variable is assigned at most once per time step, values fit
//! their declared width, reals are finite, handles belong to this writer.
//! Only real value *changes* are written; assigning the current value again is
//! silently skipped.
//!
//! Time steps are buffered: everything assigned between two [`VcdWriter::set_time`]
//! calls is written when time advances (or at [`VcdWriter::finish`]). The first
//! written step is a full `$dumpvars` section with every variable's value, so
//! assignments made at time 0 become the initial values of the `#0 $dumpvars`
//! section rather than a second value at time 0.
//!
//! For values dumped every step, a [`Frame`] ([`Writer::frame`]) is declared once and checked
//! then (bit or vector variables of at most 64 bits, each once): [`Writer::dump_frame`] takes
//! all its values and compares them with the last ones; [`Writer::frame_step`] takes only the
//! values the caller says may have changed ([`FrameStep::set`]), the others keeping theirs. Both
//! keep every check below and write what the single changes would. [`Writer::frame_run`] lends
//! the writer to one frame for a run of such steps ([`FrameRun`]): nothing else can write while
//! it lives, so a step inside the window skips the writer's per-variable bookkeeping and its
//! changes are written straight from the frame's copy (the fast path of a tracer).
//!
//! A *direct* step of a frame run is one inside the window, after the first dump, later than
//! the writer's current time, with the frame in declaration order and no `x`/`z` values; other
//! steps are [`FrameStep`]s. The writer's own per-variable values are brought up to date when
//! the run ends, and its last step becomes the writer's pending step, so a single change at
//! that time afterwards is merged or refused as after a frame step.
//!
//! For a VCD, [`VcdWriter::text_run`] goes further ([`TextRun`]): each step ([`TextStep`],
//! from [`TextRun::step`]) writes its text at once into the writer's buffer: the time stamp
//! ahead (taken back when nothing changed), then each changed value's line
//! ([`TextStep::line`], with the position, order and width checks of a direct step), with room
//! for the whole step reserved when it begins. A step that cannot be written at once
//! (`TextRun::step` gives `Ok(None)`) goes through [`TextRun::frame_run`]. When the run ends its
//! last step is taken back out of the buffer and becomes the writer's pending step; its changed
//! positions are read back from its text. Inside a run:
//! - the frame's positions are *slots* (`TextSlot`): each position's value and change line side
//!   by side, the frame's values while text steps last, given back when they end;
//! - a text step holds the end of the text it writes, so a caller that keeps the step in a local
//!   keeps it in a register; each line also stores it in the writer (never loading it back), so
//!   a step leaked with `mem::forget` loses nothing (`a_leaked_text_step_keeps_its_lines`);
//! - [`TextStep::change`] is a line for a value its caller guarantees changed, fits its variable
//!   and comes in increasing positions: those three checks of `line` are asserted in debug
//!   builds (where the tests run) and not made in release builds. [`TextStep::change_w`] is the
//!   same for a variable the caller knows to be exactly `N` bits wide, written by
//!   [`crate::vcd_text::ChangeLine::write_w`] with the width's tests resolved at compile time.
//!
//! Every run writes the file [`Writer::dump_frame`] would write from every value
//! (`frame_runs_equal_dump_frame`, `text_runs_equal_dump_frame` in `waves/tests/writer.rs`).
//!
//! With a time window `[start, end)` ([`VcdBuilder::window`]) nothing before
//! `start` or at/after `end` is written; the file begins with `#start $dumpvars`
//! holding the values current at `start`, and time stamps stay absolute.
//!
//! ```
//! use pmu50_waves::writer::{BitType, Logic, VcdBuilder};
//! use pmu50_waves::{Timescale, TimeUnit};
//!
//! let mut b = VcdBuilder::new(Timescale::new(1, TimeUnit::Us), "pmu50 model").unwrap();
//! b.push_scope("pmu50").unwrap();
//! let clk = b.add_bit(BitType::Wire, "clk", Logic::Zero).unwrap();
//! let cnt = b.add_vector(BitType::Reg, "cnt_s", 15, 0, 0).unwrap();
//! b.pop_scope().unwrap();
//! let mut w = b.start(Vec::new()).unwrap();
//! w.set_time(1).unwrap();
//! w.change_bool(clk, true).unwrap();
//! w.change_vector(cnt, 3).unwrap();
//! let vcd = String::from_utf8(w.finish().unwrap()).unwrap();
//! assert!(vcd.contains("$var reg 16 \" cnt_s [15:0] $end"));
//! ```

use std::collections::HashSet;
use std::io::Write;
use std::sync::atomic::{AtomicU32, Ordering};

use thiserror::Error;
use vcd::{IdCode, ReferenceIndex, VarType};

use crate::time::Timescale;
use crate::vcd_text::{ChangeLine, Stamps, SLACK};

static NEXT_BUILDER_ID: AtomicU32 = AtomicU32::new(1);

/// Widest vector the writer accepts, in bits.
pub const MAX_WIDTH: u32 = 1 << 16;

/// Handle of one declared variable, returned by the `add_*` methods.
///
/// A handle is only valid for the builder/writer that issued it; using it with
/// another writer is reported as [`WriteError::UnknownId`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct SigId {
    owner: u32,
    index: u32,
}

/// One four-state logic value.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Logic {
    /// logic 0
    Zero,
    /// logic 1
    One,
    /// unknown
    X,
    /// high impedance
    Z,
}

impl Logic {
    fn as_byte(self) -> u8 {
        match self {
            Logic::Zero => b'0',
            Logic::One => b'1',
            Logic::X => b'x',
            Logic::Z => b'z',
        }
    }
}

impl From<bool> for Logic {
    fn from(b: bool) -> Self {
        if b {
            Logic::One
        } else {
            Logic::Zero
        }
    }
}

/// IEEE VCD net/variable type of a bit or vector variable.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum BitType {
    /// `$var wire ...`
    Wire,
    /// `$var reg ...`
    Reg,
}

/// Everything that can go wrong while declaring or writing a VCD.
#[derive(Debug, Error)]
pub enum WriteError {
    /// Timescale factor not allowed by IEEE 1364.
    #[error("invalid timescale factor {factor}: VCD allows only 1, 10 or 100 (e.g. `1 us`, `10 us`, `100 ns`)")]
    InvalidTimescale {
        /// the rejected factor
        factor: u32,
    },
    /// `$version` text that would break the header.
    #[error("invalid $version text {text:?}: it must be non-empty, must not contain `$end` and must not contain control characters other than newline")]
    InvalidVersion {
        /// the rejected text
        text: String,
    },
    /// Time window with `start >= end`.
    #[error("invalid time window [{start}, {end}): start must be smaller than end (the window is start-inclusive, end-exclusive, in timescale units)")]
    InvalidWindow {
        /// window start
        start: u64,
        /// window end
        end: u64,
    },
    /// A scope or variable name that is not a plain identifier.
    #[error("invalid {what} name {name:?} in scope `{scope}`: names must start with an ASCII letter or `_` and contain only ASCII letters, digits, `_` or `$`")]
    InvalidName {
        /// "scope" or "variable"
        what: &'static str,
        /// the rejected name
        name: String,
        /// dotted path of the enclosing scope (empty at top level)
        scope: String,
    },
    /// Two declarations with the same full path.
    #[error("duplicate declaration `{path}`: every scope and variable must have a unique hierarchical name")]
    Duplicate {
        /// the full dotted path
        path: String,
    },
    /// Variable declared before any `push_scope`.
    #[error("variable `{name}` declared outside any module scope: call push_scope first (VCD variables must live in a $scope)")]
    NoScope {
        /// the variable name
        name: String,
    },
    /// `pop_scope` without a matching `push_scope`.
    #[error("pop_scope called with no open scope")]
    NoOpenScope,
    /// `start` called while scopes are still open.
    #[error("{open} scope(s) still open at start (innermost `{innermost}`): call pop_scope for each push_scope before start")]
    UnclosedScopes {
        /// number of open scopes
        open: usize,
        /// dotted path of the innermost open scope
        innermost: String,
    },
    /// `start` called with nothing declared.
    #[error("no variables declared: a VCD needs at least one $var (GTKWave refuses files without symbols)")]
    NoVariables,
    /// Vector range wider than the writer supports.
    #[error("vector `{name}` [{msb}:{lsb}] is out of range: msb and lsb must be at most {max_index} and the width |msb - lsb| + 1 at most {MAX_WIDTH} bits", max_index = i32::MAX)]
    RangeTooLarge {
        /// variable name
        name: String,
        /// declared msb
        msb: u32,
        /// declared lsb
        lsb: u32,
    },
    /// Time went backwards.
    #[error("set_time({requested}) goes backwards: current time is {current}; time must be non-decreasing")]
    TimeBackwards {
        /// the requested time
        requested: u64,
        /// the current time
        current: u64,
    },
    /// A variable assigned twice in one time step.
    #[error("`{name}` changed twice at time {time}: each variable may change at most once per time step")]
    DoubleChange {
        /// full path of the variable
        name: String,
        /// the time step
        time: u64,
    },
    /// Integer value does not fit the declared width.
    #[error("value {value} (0x{value:x}) does not fit `{name}`, which is {width} bit(s) wide: valid values are 0..={max}")]
    ValueTooWide {
        /// full path of the variable
        name: String,
        /// the rejected value
        value: u64,
        /// declared width
        width: u32,
        /// largest valid value
        max: u64,
    },
    /// Bit string or single bit with the wrong number of bits.
    #[error("`{name}` is {expected} bit(s) wide but the value has {got} bit(s)")]
    WrongWidth {
        /// full path of the variable
        name: String,
        /// declared width
        expected: u32,
        /// width of the passed value
        got: usize,
    },
    /// Bit string with a character other than 0/1/x/z.
    #[error("invalid bit {ch:?} at position {pos} (msb first) of the value for `{name}`: valid bits are 0, 1, x, z (X and Z are accepted too)")]
    InvalidBit {
        /// full path of the variable
        name: String,
        /// the offending character
        ch: char,
        /// index in the string, 0 = msb
        pos: usize,
    },
    /// Real change on a bit variable or bit change on a real variable.
    #[error("`{name}` is a {declared} variable and cannot take a {given} value")]
    TypeMismatch {
        /// full path of the variable
        name: String,
        /// declared kind ("real", "1-bit", "16-bit vector")
        declared: String,
        /// kind of the passed value
        given: &'static str,
    },
    /// NaN or infinite real.
    #[error("real value {value} for `{name}` is not finite: only finite values can be dumped (NaN and infinities are rejected)")]
    NotFinite {
        /// full path of the variable
        name: String,
        /// the rejected value
        value: f64,
    },
    /// Handle not issued by this writer.
    #[error("unknown signal handle {id:?}: it was not returned by this writer's builder")]
    UnknownId {
        /// the rejected handle
        id: SigId,
    },
    /// More than [`MAX_FRAMES`] frames declared on one writer.
    #[error("too many frames: one writer serves at most {MAX_FRAMES}; put more variables into one frame instead")]
    TooManyFrames,
    /// A frame declared without variables.
    #[error("a frame needs at least one variable (Writer::frame got an empty list)")]
    EmptyFrame,
    /// A frame used with a writer that did not declare it.
    #[error("unknown frame: it was not declared by this writer (Writer::frame)")]
    UnknownFrame,
    /// `dump_frame` with a value list of the wrong length.
    #[error("dump_frame got {got} values for a frame of {expected} variables: pass exactly one value per variable, in the frame's order")]
    FrameLength {
        /// variables in the frame
        expected: usize,
        /// values passed
        got: usize,
    },
    /// [`RunStep::set`] with a position not after the last one given in the step.
    #[error("frame position {position} given after position {previous} in one step of a frame run: give a step's positions in increasing order, each at most once (a position given twice is a double assignment)")]
    FrameOrder {
        /// the rejected position
        position: usize,
        /// the position given before it
        previous: usize,
    },
    /// [`FrameStep::set`] with a position outside the frame.
    #[error("frame position {position} does not exist: the frame has {len} variables (positions 0..{len}, in the order given to Writer::frame)")]
    FramePosition {
        /// the rejected position
        position: usize,
        /// variables in the frame
        len: usize,
    },
    /// FST output failure (from the `fst-writer` crate).
    #[error("FST output: {0}")]
    Fst(String),
    /// Underlying I/O failure.
    #[error("I/O error while writing the waveform: {0}")]
    Io(#[from] std::io::Error),
}

pub(crate) type Result<T> = std::result::Result<T, WriteError>;

/// Stored value of a variable, canonical so that `==` means "same value".
#[derive(Debug, Clone, PartialEq)]
enum Stored {
    /// two-state value of a variable at most 64 bits wide
    Int(u64),
    /// msb-first ASCII bits (`0 1 x z`), used when x/z present or width > 64
    Bits(Box<[u8]>),
    /// real value, never NaN, never -0.0
    Real(f64),
}

#[derive(Debug, Clone)]
enum Kind {
    Bits {
        ty: BitType,
        width: u32,
        range: Option<(u32, u32)>,
    },
    Real,
}

#[derive(Debug, Clone)]
struct VarDecl {
    name: String,
    path: String,
    kind: Kind,
}

impl VarDecl {
    fn width(&self) -> u32 {
        match self.kind {
            Kind::Bits { width, .. } => width,
            Kind::Real => 64,
        }
    }

    fn describe(&self) -> String {
        match self.kind {
            Kind::Bits {
                width: 1,
                range: None,
                ..
            } => "1-bit".to_string(),
            Kind::Bits { width, .. } => format!("{width}-bit vector"),
            Kind::Real => "real".to_string(),
        }
    }

    fn gtkwave_name(&self) -> String {
        match self.kind {
            Kind::Bits {
                range: Some((msb, lsb)),
                ..
            } if msb == lsb => {
                format!("{}[{}]", self.path, msb)
            }
            Kind::Bits {
                range: Some((msb, lsb)),
                ..
            } => format!("{}[{}:{}]", self.path, msb, lsb),
            _ => self.path.clone(),
        }
    }
}

#[derive(Debug, Clone)]
enum Item {
    Scope(String),
    Upscope,
    Var(usize),
}

fn valid_identifier(name: &str) -> bool {
    let mut chars = name.chars();
    match chars.next() {
        Some(c) if c.is_ascii_alphabetic() || c == '_' => {}
        _ => return false,
    }
    chars.all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '$')
}

fn canon_bits(bytes: Vec<u8>) -> Stored {
    if bytes.len() <= 64 && bytes.iter().all(|b| *b == b'0' || *b == b'1') {
        let mut v = 0u64;
        for b in &bytes {
            v = (v << 1) | u64::from(*b == b'1');
        }
        Stored::Int(v)
    } else {
        Stored::Bits(bytes.into_boxed_slice())
    }
}

fn max_for_width(width: u32) -> u64 {
    if width >= 64 {
        u64::MAX
    } else {
        (1u64 << width) - 1
    }
}

/// Deterministic text for a finite real: shortest round-trip digits, plain
/// notation for moderate magnitudes, exponent notation otherwise; `-0` is `0`.
#[cfg(test)]
pub(crate) fn format_real(v: f64) -> String {
    let mut b = RealBuf::new();
    String::from_utf8_lossy(&real_text(v, &mut b)).into_owned()
}

/// Room for the text of a real ([`real_text`]): the digits of a value on the grid of 1e-6,
/// `zmij`'s buffer (plain notation) or `ryu`'s (exponent notation).
pub(crate) struct RealBuf {
    grid: [u8; 24],
    zmij: zmij::Buffer,
    ryu: ryu::Buffer,
}

impl RealBuf {
    #[inline]
    pub(crate) fn new() -> RealBuf {
        RealBuf {
            grid: [0; 24],
            zmij: zmij::Buffer::new(),
            ryu: ryu::Buffer::new(),
        }
    }
}

/// [`format_real`] without allocating: the text in `b`, or a static `0`. The text is `ryu`'s
/// (shortest round-trip digits, the same as `std::fmt`'s but where a double lies halfway between
/// two 17-digit texts, a tie the two break differently). `ryu` writes plain notation for
/// 1e-5 <= |v| < 1e16 with a `.0` after an integer, and exponent notation (`1e30`, `1.5e-7`)
/// otherwise, as Rust's `{:e}`; the `.0` is dropped, and the rare 1e-5 <= |v| < 1e-4 (plain in
/// `ryu`, exponent here) takes Rust's `{:e}` (tests/writer.rs compares with `format!` on random
/// values).
///
/// In plain notation (1e-4 <= |v| < 1e16) the text is `zmij`'s, which writes the same text as
/// `ryu` there, ties between two 17-digit texts included, about a third faster
/// (`real_text_tests::zmij_as_ryu_in_plain_notation`).
///
/// A value of 1e-4 <= |v| < 1e9 that is the double nearest to a decimal `n`·1e-6 (the rounded
/// analog values of a waveform mostly are) is written from `n` without either, the same text:
/// that decimal has at most 15 significant digits and lies within the double's rounding
/// interval, narrower than 2^-52·|v|; two decimals of at most 15 significant digits differ by
/// more than that, so it is the only one of its length or shorter there, the shortest
/// round-trip text, which `ryu` writes in plain notation in this range
/// (`real_text_tests::grid_values_as_ryu` compares the two).
#[inline]
pub(crate) fn real_text(v: f64, b: &mut RealBuf) -> std::borrow::Cow<'_, [u8]> {
    if v == 0.0 {
        return b"0"[..].into();
    }
    let a = v.abs();
    if (1e-4..1e9).contains(&a) {
        let x = v * 1e6;
        // the integer nearest to x (|x| < 1e15, exact in an f64; a double nearest to n·1e-6
        // is within 0.2 of n·1e6 here), and the correctly rounded division: equality means `v`
        // is the double nearest to n·1e-6
        let n = (x + 0.5f64.copysign(x)) as i64;
        if n as f64 / 1e6 == v {
            return grid_text(n, &mut b.grid).into();
        }
    }
    if (1e-4..1e16).contains(&a) {
        let s = b.zmij.format_finite(v);
        s.strip_suffix(".0").unwrap_or(s).as_bytes().into()
    } else if (1e-5..1e-4).contains(&a) {
        format!("{v:e}").into_bytes().into()
    } else {
        b.ryu.format_finite(v).as_bytes().into()
    }
}

/// Two decimal digits of each number below 100.
const DIGIT_PAIRS: &[u8; 200] = b"00010203040506070809101112131415161718192021222324252627282930313233343536373839404142434445464748495051525354555657585960616263646566676869707172737475767778798081828384858687888990919293949596979899";

/// The decimal `n`·1e-6 (`n` not zero, |n| < 1e15) in plain notation, without trailing zeros
/// after the point nor a point after an integer: its integer part ends at byte 17 of `out`, the
/// point, then six places, of which the trailing zeros are cut.
#[inline]
fn grid_text(n: i64, out: &mut [u8; 24]) -> &[u8] {
    let u = n.unsigned_abs();
    let (mut int, frac) = (u / 1_000_000, (u % 1_000_000) as usize);
    let pair = |k: usize| [DIGIT_PAIRS[2 * k], DIGIT_PAIRS[2 * k + 1]];
    let end = if frac == 0 {
        17
    } else {
        out[17] = b'.';
        out[18..20].copy_from_slice(&pair(frac / 10_000));
        out[20..22].copy_from_slice(&pair(frac / 100 % 100));
        out[22..24].copy_from_slice(&pair(frac % 100));
        let mut end = 24;
        while out[end - 1] == b'0' {
            end -= 1;
        }
        end
    };
    let mut i = 17;
    while int >= 100 {
        i -= 2;
        out[i..i + 2].copy_from_slice(&pair((int % 100) as usize));
        int /= 100;
    }
    if int >= 10 {
        i -= 2;
        out[i..i + 2].copy_from_slice(&pair(int as usize));
    } else {
        i -= 1;
        out[i] = b'0' + int as u8;
    }
    if n < 0 {
        i -= 1;
        out[i] = b'-';
    }
    &out[i..end]
}

/// A real's change line `r<text> <code>\n` into `out`, exactly as long.
#[inline]
fn real_line(out: &mut [u8], text: &[u8], code: &[u8]) {
    let n = text.len();
    out[0] = b'r';
    out[1..=n].copy_from_slice(text);
    out[n + 1] = b' ';
    out[n + 2..n + 2 + code.len()].copy_from_slice(code);
    out[n + 2 + code.len()] = b'\n';
}

/// FST's encoding of a real value: the IEEE 754 bits, little endian.
pub(crate) fn format_real_bits(v: f64) -> [u8; 8] {
    v.to_le_bytes()
}

/// Declares the VCD header: timescale, version, optional window, scopes and variables.
#[derive(Debug)]
pub struct VcdBuilder {
    owner: u32,
    timescale: Timescale,
    version: String,
    window: (u64, u64),
    items: Vec<Item>,
    vars: Vec<VarDecl>,
    init: Vec<Stored>,
    stack: Vec<String>,
    names: HashSet<String>,
}

impl VcdBuilder {
    /// New header with the given `$timescale` (factor 1, 10 or 100) and fixed
    /// `$version` text. No `$date` is ever written.
    pub fn new(timescale: Timescale, version: &str) -> Result<Self> {
        if !timescale.is_ieee() {
            return Err(WriteError::InvalidTimescale {
                factor: timescale.factor,
            });
        }
        if version.trim().is_empty()
            || version.contains("$end")
            || version.chars().any(|c| c.is_control() && c != '\n')
        {
            return Err(WriteError::InvalidVersion {
                text: version.to_string(),
            });
        }
        Ok(VcdBuilder {
            owner: NEXT_BUILDER_ID.fetch_add(1, Ordering::Relaxed),
            timescale,
            version: version.to_string(),
            window: (0, u64::MAX),
            items: Vec::new(),
            vars: Vec::new(),
            init: Vec::new(),
            stack: Vec::new(),
            names: HashSet::new(),
        })
    }

    /// Only dump the time window `[start, end)` (timescale units; use
    /// `u64::MAX` for "until the end"). The file starts with `#start $dumpvars`.
    pub fn window(&mut self, start: u64, end: u64) -> Result<()> {
        if start >= end {
            return Err(WriteError::InvalidWindow { start, end });
        }
        self.window = (start, end);
        Ok(())
    }

    fn scope_path(&self) -> String {
        self.stack.join(".")
    }

    fn child_path(&self, name: &str) -> String {
        if self.stack.is_empty() {
            name.to_string()
        } else {
            format!("{}.{}", self.scope_path(), name)
        }
    }

    fn claim(&mut self, what: &'static str, name: &str) -> Result<String> {
        if !valid_identifier(name) {
            return Err(WriteError::InvalidName {
                what,
                name: name.to_string(),
                scope: self.scope_path(),
            });
        }
        let path = self.child_path(name);
        if !self.names.insert(path.clone()) {
            return Err(WriteError::Duplicate { path });
        }
        Ok(path)
    }

    /// Open a `module` scope inside the current one.
    pub fn push_scope(&mut self, name: &str) -> Result<()> {
        self.claim("scope", name)?;
        self.stack.push(name.to_string());
        self.items.push(Item::Scope(name.to_string()));
        Ok(())
    }

    /// Close the innermost open scope.
    pub fn pop_scope(&mut self) -> Result<()> {
        if self.stack.pop().is_none() {
            return Err(WriteError::NoOpenScope);
        }
        self.items.push(Item::Upscope);
        Ok(())
    }

    fn add(&mut self, name: &str, kind: Kind, init: Stored) -> Result<SigId> {
        if self.stack.is_empty() {
            return Err(WriteError::NoScope {
                name: name.to_string(),
            });
        }
        let path = self.claim("variable", name)?;
        let index = self.vars.len();
        self.vars.push(VarDecl {
            name: name.to_string(),
            path,
            kind,
        });
        self.init.push(init);
        self.items.push(Item::Var(index));
        Ok(SigId {
            owner: self.owner,
            index: index as u32,
        })
    }

    /// Declare a single-bit `wire` or `reg` (no range suffix) with its initial value.
    pub fn add_bit(&mut self, ty: BitType, name: &str, init: Logic) -> Result<SigId> {
        let kind = Kind::Bits {
            ty,
            width: 1,
            range: None,
        };
        self.add(name, kind, canon_bits(vec![init.as_byte()]))
    }

    /// Declare a vector `name [msb:lsb]` of width `|msb - lsb| + 1` with an
    /// initial value (`msb == lsb` gives a one-bit select `name [msb]`).
    pub fn add_vector(
        &mut self,
        ty: BitType,
        name: &str,
        msb: u32,
        lsb: u32,
        init: u64,
    ) -> Result<SigId> {
        if msb > i32::MAX as u32 || lsb > i32::MAX as u32 || msb.abs_diff(lsb) >= MAX_WIDTH {
            return Err(WriteError::RangeTooLarge {
                name: name.to_string(),
                msb,
                lsb,
            });
        }
        let width = msb.abs_diff(lsb) + 1;
        if init > max_for_width(width) {
            return Err(WriteError::ValueTooWide {
                name: self.child_path(name),
                value: init,
                width,
                max: max_for_width(width),
            });
        }
        let kind = Kind::Bits {
            ty,
            width,
            range: Some((msb, lsb)),
        };
        let init = if width <= 64 {
            Stored::Int(init)
        } else {
            canon_bits(int_to_bits(init, width))
        };
        self.add(name, kind, init)
    }

    /// Declare a `real` variable with its (finite) initial value.
    pub fn add_real(&mut self, name: &str, init: f64) -> Result<SigId> {
        if !init.is_finite() {
            return Err(WriteError::NotFinite {
                name: self.child_path(name),
                value: init,
            });
        }
        self.add(name, Kind::Real, Stored::Real(init + 0.0))
    }

    /// GTKWave's name for a declared variable: full dotted path plus
    /// `[msb:lsb]` for vectors (`pmu50.drive_interval.si[15:0]`).
    pub fn gtkwave_name(&self, id: SigId) -> Result<String> {
        if id.owner != self.owner || id.index as usize >= self.vars.len() {
            return Err(WriteError::UnknownId { id });
        }
        Ok(self.vars[id.index as usize].gtkwave_name())
    }

    /// Check the declarations before the value-change phase (every scope closed, at least one
    /// variable).
    fn check_complete(&self) -> Result<()> {
        if !self.stack.is_empty() {
            return Err(WriteError::UnclosedScopes {
                open: self.stack.len(),
                innermost: self.scope_path(),
            });
        }
        if self.vars.is_empty() {
            return Err(WriteError::NoVariables);
        }
        Ok(())
    }

    /// Write the VCD header to `out` and switch to the value-change phase.
    pub fn start<W: Write>(self, mut out: W) -> Result<VcdWriter<W>> {
        self.check_complete()?;
        let mut w = vcd::Writer::new(Slot(Some(Vec::with_capacity(4096))));
        w.version(&self.version)?;
        w.timescale(self.timescale.factor, self.timescale.unit.to_vcd())?;
        let mut codes = vec![Box::<[u8]>::default(); self.vars.len()];
        let mut next = IdCode::FIRST;
        for item in &self.items {
            match item {
                Item::Scope(name) => w.add_module(name)?,
                Item::Upscope => w.upscope()?,
                Item::Var(i) => {
                    let v = &self.vars[*i];
                    let (ty, index) = match v.kind {
                        Kind::Bits { ty, range, .. } => {
                            let ty = match ty {
                                BitType::Wire => VarType::Wire,
                                BitType::Reg => VarType::Reg,
                            };
                            let index = range.map(|(msb, lsb)| {
                                if msb == lsb {
                                    ReferenceIndex::BitSelect(msb as i32)
                                } else {
                                    ReferenceIndex::Range(msb as i32, lsb as i32)
                                }
                            });
                            (ty, index)
                        }
                        Kind::Real => (VarType::Real, None),
                    };
                    w.var_def(ty, v.width(), next, &v.name, index)?;
                    codes[*i] = next.to_string().into_bytes().into_boxed_slice();
                    next = next.next();
                }
            }
        }
        w.enddefinitions()?;
        let header = w.writer().0.take().unwrap_or_default();
        out.write_all(&header)?;
        let widths: Vec<u32> = self.vars.iter().map(|v| v.width()).collect();
        let emitter = VcdOut::new(out, codes, widths);
        Ok(self.into_writer(emitter))
    }

    /// The checked writer over an emitter (VCD here, FST in [`crate::fst`]).
    pub(crate) fn into_writer<E: Emitter>(self, e: E) -> Writer<E> {
        let n = self.vars.len();
        Writer {
            emitter: e,
            owner: self.owner,
            vars: self.vars,
            cur: self.init,
            assigned: vec![0; n],
            single_step: 0,
            var_frames: vec![0; n],
            pending: vec![0; n].into_boxed_slice(),
            npending: 0,
            pending_sorted: true,
            time: 0,
            step: 1,
            window: self.window,
            dumped: false,
            last_written: None,
            generation: 0,
            frame_steps: Vec::new(),
            frame_overlap: Vec::new(),
        }
    }

    /// Variables in declaration order, for other emitters: (scope path, name, width, is real).
    pub(crate) fn declarations(&self) -> Vec<Declaration> {
        let mut out = Vec::new();
        let mut stack: Vec<String> = Vec::new();
        for item in &self.items {
            match item {
                Item::Scope(name) => {
                    out.push(Declaration::Scope(name.clone()));
                    stack.push(name.clone());
                }
                Item::Upscope => {
                    out.push(Declaration::Upscope);
                    stack.pop();
                }
                Item::Var(i) => {
                    let v = &self.vars[*i];
                    let (wire, range) = match v.kind {
                        Kind::Bits { ty, range, .. } => (ty == BitType::Wire, range),
                        Kind::Real => (false, None),
                    };
                    out.push(Declaration::Var {
                        index: *i,
                        name: v.name.clone(),
                        width: v.width(),
                        real: matches!(v.kind, Kind::Real),
                        wire,
                        range,
                    });
                }
            }
        }
        out
    }

    pub(crate) fn timescale(&self) -> Timescale {
        self.timescale
    }

    pub(crate) fn window_start(&self) -> u64 {
        self.window.0
    }

    pub(crate) fn window_end(&self) -> u64 {
        self.window.1
    }

    pub(crate) fn version(&self) -> &str {
        &self.version
    }

    pub(crate) fn complete(&self) -> Result<()> {
        self.check_complete()
    }
}

/// One item of the declared hierarchy, for emitters other than VCD.
#[derive(Debug, Clone)]
pub(crate) enum Declaration {
    Scope(String),
    Upscope,
    Var {
        index: usize,
        name: String,
        width: u32,
        real: bool,
        wire: bool,
        range: Option<(u32, u32)>,
    },
}

fn int_to_bits(v: u64, width: u32) -> Vec<u8> {
    (0..width)
        .rev()
        .map(|i| {
            if i < 64 && (v >> i) & 1 == 1 {
                b'1'
            } else {
                b'0'
            }
        })
        .collect()
}

/// One variable's current value, as handed to an [`Emitter`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ValueRef<'a> {
    /// two-state value of a bit or vector variable at most 64 bits wide
    Int(u64),
    /// msb-first ASCII bits (`0 1 x z`), exactly the declared width
    Bits(&'a [u8]),
    /// finite real, never -0.0
    Real(f64),
}

impl Stored {
    fn as_ref(&self) -> ValueRef<'_> {
        match self {
            Stored::Int(v) => ValueRef::Int(*v),
            Stored::Bits(b) => ValueRef::Bits(b),
            Stored::Real(v) => ValueRef::Real(*v),
        }
    }
}

/// Output format of a checked [`Writer`]: the writer does every check and keeps the values; the
/// emitter only formats what the writer hands it. [`VcdOut`] writes VCD text,
/// [`crate::fst::FstOut`] writes FST.
pub trait Emitter {
    /// What [`Writer::finish`] returns.
    type Output;
    /// Start of the first written step, at time `t`: every variable's value follows.
    fn dump_begin(&mut self, t: u64) -> Result<()>;
    /// End of the first written step.
    fn dump_end(&mut self) -> Result<()>;
    /// Start of a later step with at least one change, at time `t`.
    fn timestamp(&mut self, t: u64) -> Result<()>;
    /// The value of variable `index` (declaration order) in the current step.
    fn value(&mut self, index: usize, v: ValueRef<'_>) -> Result<()>;
    /// Close the output; `closing` is a final time stamp to write when the run ends after the
    /// last written change.
    fn finish(self, closing: Option<u64>) -> Result<Self::Output>;
}

/// Bytes of VCD text collected before one write to the output. 1 MiB rather than 128 KiB: with
/// the tracer writing a new file, the page cache's share of a traced tick fell by a third (the
/// Rust tracer into a file +3-5 % on both stimuli of `make bench`; 64 KiB and 256 KiB measured
/// slower), for 1 MiB of memory per open VCD.
const VCD_BUFFER: usize = 1 << 20;

/// VCD text emitter: identifier codes and the text after every change's value precomputed at
/// declaration; a change is its value's characters and one fixed-size copy of that text, into
/// one buffer that goes to the output in large writes.
pub struct VcdOut<W: Write> {
    out: W,
    /// `VCD_BUFFER + SLACK` bytes; `buf[..pos]` is the text not yet written to `out`
    buf: Box<[u8]>,
    pos: usize,
    codes: Vec<Box<[u8]>>,
    widths: Vec<u32>,
    /// Per variable, the fixed part of its two-state change line ([`ChangeLine::GENERAL`]: the
    /// general path).
    lines: Vec<ChangeLine>,
    /// the time stamps, each from the last one when the clock's step repeats
    stamps: Stamps,
}

impl<W: Write> VcdOut<W> {
    fn new(out: W, codes: Vec<Box<[u8]>>, widths: Vec<u32>) -> VcdOut<W> {
        let lines = codes
            .iter()
            .zip(&widths)
            .map(|(code, &w)| ChangeLine::new(code, w).unwrap_or(ChangeLine::GENERAL))
            .collect();
        VcdOut {
            out,
            buf: vec![0; VCD_BUFFER + SLACK].into_boxed_slice(),
            pos: 0,
            codes,
            widths,
            lines,
            stamps: Stamps::new(),
        }
    }

    /// Write the buffer out once it holds [`VCD_BUFFER`] bytes; afterwards at least [`SLACK`]
    /// bytes are free.
    #[inline(always)]
    fn room(&mut self) -> Result<()> {
        if self.pos >= VCD_BUFFER {
            self.out.write_all(&self.buf[..self.pos])?;
            self.pos = 0;
        }
        Ok(())
    }

    /// `#t\n` at `buf[pos]` ([`Stamps::write`]; the buffer has [`SLACK`] bytes free).
    #[inline(always)]
    fn stamp(&mut self, t: u64) {
        let p = self.pos;
        let out: &mut [u8; SLACK] = (&mut self.buf[p..p + SLACK])
            .try_into()
            .expect("SLACK bytes free after room()");
        self.pos = p + self.stamps.write(out, t);
    }

    /// A change without a [`ChangeLine`]: four-state bits, reals, vectors wider than 64 bits, variables
    /// whose identifier code is longer than [`crate::vcd_text::CODE`].
    #[cold]
    #[inline(never)]
    fn value_general(&mut self, i: usize, v: ValueRef<'_>) -> Result<()> {
        let width = self.widths[i];
        let mut line = Vec::with_capacity(width as usize + 16);
        match v {
            ValueRef::Int(v) if width == 1 => line.push(b'0' + (v & 1) as u8),
            ValueRef::Int(v) => {
                line.push(b'b');
                line.extend_from_slice(&int_to_bits(v, width));
                line.push(b' ');
            }
            ValueRef::Bits(bits) if width == 1 => line.extend_from_slice(bits),
            ValueRef::Bits(bits) => {
                line.push(b'b');
                line.extend_from_slice(bits);
                line.push(b' ');
            }
            ValueRef::Real(r) => {
                line.push(b'r');
                line.extend_from_slice(&real_text(r, &mut RealBuf::new()));
                line.push(b' ');
            }
        }
        line.extend_from_slice(&self.codes[i]);
        line.push(b'\n');
        self.put(&line)
    }

    /// A real's change line, `r<text> <code>`, straight into the buffer ([`real_text`]).
    #[inline]
    fn value_real(&mut self, i: usize, r: f64) -> Result<()> {
        let mut b = RealBuf::new();
        let text = real_text(r, &mut b);
        let n = text.len() + self.codes[i].len() + 3;
        if n > SLACK {
            return self.value_general(i, ValueRef::Real(r));
        }
        self.room()?;
        real_line(&mut self.buf[self.pos..self.pos + n], &text, &self.codes[i]);
        self.pos += n;
        Ok(())
    }

    /// Append text of any length (the general path).
    fn put(&mut self, text: &[u8]) -> Result<()> {
        self.room()?;
        if self.pos + text.len() <= self.buf.len() {
            self.buf[self.pos..self.pos + text.len()].copy_from_slice(text);
            self.pos += text.len();
        } else {
            self.out.write_all(&self.buf[..self.pos])?;
            self.pos = 0;
            self.out.write_all(text)?;
        }
        Ok(())
    }
}

impl<W: Write> Emitter for VcdOut<W> {
    type Output = W;

    fn dump_begin(&mut self, t: u64) -> Result<()> {
        self.timestamp(t)?;
        self.put(b"$dumpvars\n")
    }

    fn dump_end(&mut self) -> Result<()> {
        self.put(b"$end\n")
    }

    /// `#t`: `VcdOut::stamp` after making room.
    #[inline(always)]
    fn timestamp(&mut self, t: u64) -> Result<()> {
        self.room()?;
        self.stamp(t);
        Ok(())
    }

    /// A two-state value from its [`ChangeLine`], anything else by the general path.
    #[inline(always)]
    fn value(&mut self, i: usize, v: ValueRef<'_>) -> Result<()> {
        match v {
            ValueRef::Int(v) if self.lines[i].is_line() => {
                self.room()?;
                let p = self.pos;
                let out: &mut [u8; SLACK] = (&mut self.buf[p..p + SLACK])
                    .try_into()
                    .expect("SLACK bytes free after room()");
                self.pos = p + self.lines[i].write(out, v);
                Ok(())
            }
            ValueRef::Real(r) => self.value_real(i, r),
            v => self.value_general(i, v),
        }
    }

    fn finish(mut self, closing: Option<u64>) -> Result<W> {
        if let Some(t) = closing {
            self.timestamp(t)?;
        }
        self.out.write_all(&self.buf[..self.pos])?;
        self.out.flush()?;
        Ok(self.out)
    }
}

/// The checked VCD writer (see the module documentation).
pub type VcdWriter<W> = Writer<VcdOut<W>>;

/// Most frames one writer serves (each frame owns one bit of a per-variable mask).
pub const MAX_FRAMES: usize = 32;

/// A fixed list of variables that are dumped together, every step: declared once with
/// [`Writer::frame`] (which checks that each is a bit or vector variable of at most 64 bits, so
/// [`Writer::dump_frame`] only has to check the values that changed against their width).
/// The frame keeps the values it last dumped, so a step compares plain integers.
#[derive(Debug, Clone)]
pub struct Frame {
    owner: u32,
    id: u32,
    idx: Vec<u32>,
    max: Vec<u64>,
    prev: Vec<u64>,
    /// writer generation after this frame's last dump (`u64::MAX`: never dumped)
    generation: u64,
    /// positions set in the current [`FrameStep`], one bit each
    seen: Vec<u64>,
    /// the variables are in declaration order (`idx` increasing): a [`FrameRun`] may write
    /// its steps directly
    sorted: bool,
    /// `open[..nopen]`: the positions changed in a [`FrameRun`]'s open direct step, increasing
    open: Box<[u32]>,
    nopen: usize,
}

impl Frame {
    /// Number of variables in the frame.
    pub fn len(&self) -> usize {
        self.idx.len()
    }

    /// True for a frame without variables.
    pub fn is_empty(&self) -> bool {
        self.idx.is_empty()
    }

    /// The largest value position `k` can take (`2^width - 1` of its variable); `None` past
    /// the end. A caller of [`TextStep::change`] checks its values against these once.
    pub fn max(&self, k: usize) -> Option<u64> {
        self.max.get(k).copied()
    }
}

/// One step of a [`Frame`] whose values are given one by one ([`Writer::frame_step`]).
struct FrameStep<'a, E: Emitter> {
    writer: &'a mut Writer<E>,
    frame: &'a mut Frame,
    /// A variable of the frame holds a four-state value (a single change), which the frame's
    /// integer copy cannot hold: compare with the writer's values in this step.
    slow: bool,
    current: bool,
}

impl<E: Emitter> FrameStep<'_, E> {
    /// True when no variable of the writer changed since this frame's last step (by a single
    /// change or another frame): the frame's variables hold exactly the values of that step, so
    /// a caller that kept them may leave out every value that is still the same. False at the
    /// frame's first step.
    #[inline]
    pub fn is_current(&self) -> bool {
        self.current
    }

    /// Give the value of the frame's variable at position `k` (the order of
    /// [`Writer::frame`]'s list) in this step. Only a value that differs from the variable's
    /// current one is compared with its width and written. Errors: a position outside the frame
    /// ([`WriteError::FramePosition`]), a position given twice in the step
    /// ([`WriteError::DoubleChange`]), a changed value wider than the variable
    /// ([`WriteError::ValueTooWide`]: nothing assigned, and the position may still be given a
    /// value in this step).
    #[inline(always)]
    pub fn set(&mut self, k: usize, v: u64) -> Result<()> {
        let f = &mut *self.frame;
        let (Some(&prev), Some(seen)) = (f.prev.get(k), f.seen.get_mut(k / 64)) else {
            return Err(position_error(f, k));
        };
        let bit = 1u64 << (k % 64);
        if *seen & bit != 0 {
            return Err(self.writer.double_change(f.idx[k] as usize));
        }
        let same = if self.slow {
            self.writer.cur[f.idx[k] as usize] == Stored::Int(v)
        } else {
            v == prev
        };
        if !same && !self.changed(k, v) {
            return Err(too_wide(self.writer, self.frame, k, v));
        }
        self.frame.seen[k / 64] |= bit;
        Ok(())
    }

    /// The rarer half of [`FrameStep::set`]: a value that changed. False (nothing assigned)
    /// when it is wider than its variable.
    #[inline(always)]
    fn changed(&mut self, k: usize, v: u64) -> bool {
        let (f, w) = (&mut *self.frame, &mut *self.writer);
        let i = f.idx[k] as usize;
        if v > f.max[k] {
            return false;
        }
        f.prev[k] = v;
        match &mut w.cur[i] {
            Stored::Int(c) => *c = v,
            c => *c = Stored::Int(v),
        }
        w.push_pending(i);
        w.generation += 1;
        if !self.slow {
            f.generation = w.generation;
        }
        true
    }
}

/// A [`Writer`] lent to one [`Frame`] for a run of steps ([`Writer::frame_run`]), the way a
/// simulator's tracer owns its waveform: while the run lives nothing else can write, so a step
/// inside the window is *direct*. Its changed values go to the frame's copy and a list of
/// positions, and that list is written out (time stamp and change lines) when the next step
/// begins; the writer's own values and pending changes are brought up to date only when the
/// run ends (the last step then becomes the writer's pending step, so a later single change at
/// its time is merged or refused exactly as after [`Writer::frame_step`]) or when a step cannot
/// be direct. A step is a [`FrameStep`] (every bookkeeping of the writer, per change) when it
/// is at the writer's current time, before the first dump, outside the window, when a variable
/// of the frame holds `x`/`z`, or when the frame is not in declaration order.
///
/// Every check of [`Writer::frame_step`] stays (time order, double assignment, positions,
/// the width of every changed value); in addition a step's positions come in increasing order
/// ([`WriteError::FrameOrder`]), which is what lets a direct step write its changes in
/// declaration order without sorting and without a per-position mark. The file is byte for
/// byte the one `dump_frame` writes (tests/writer.rs compares them on random runs).
///
/// A direct step's changes are written one step late (at the next [`FrameRun::step`] or when
/// the run is dropped), and until the run is dropped the writer's own values are stale: the run
/// must be dropped, not leaked (`std::mem::forget` loses its last step). Ending a run in which
/// no value changed costs nothing; otherwise it copies the frame's values into the writer once.
pub struct FrameRun<'a, E: Emitter> {
    writer: &'a mut Writer<E>,
    /// the frame; its `open[..nopen]` are the positions changed in the open direct step
    frame: &'a mut Frame,
    /// the open step (at the writer's time) is direct
    direct: bool,
    /// a direct step of this run changed a value (the writer's values are stale)
    dirty: bool,
    /// the `real` variables given in the open direct step ([`FrameRun::real`]), in increasing
    /// declaration order: index, value, changed (the writer holds their values already)
    reals: Vec<(u32, f64, bool)>,
}

impl<E: Emitter> Writer<E> {
    /// Lend the writer to `frame` for a run of steps ([`FrameRun::step`]); the writer is
    /// brought up to date when the run is dropped. Error: a frame of another writer.
    pub fn frame_run<'a>(&'a mut self, frame: &'a mut Frame) -> Result<FrameRun<'a, E>> {
        if frame.owner != self.owner || frame.id as usize >= self.frame_steps.len() {
            return Err(WriteError::UnknownFrame);
        }
        frame.nopen = 0;
        Ok(FrameRun {
            writer: self,
            frame,
            direct: false,
            dirty: false,
            reals: Vec::new(),
        })
    }
}

impl<'a, E: Emitter> FrameRun<'a, E> {
    /// Start the frame's step at time `t`: as [`Writer::frame_step`], with the positions of the
    /// step given in increasing order ([`RunStep::set`]). When the previous step was direct its
    /// changes are written now.
    #[inline]
    pub fn step(&mut self, t: u64) -> Result<RunStep<'_, E>> {
        if self.direct {
            let w = &mut *self.writer;
            if t < w.time {
                return Err(WriteError::TimeBackwards {
                    requested: t,
                    current: w.time,
                });
            }
            if t == w.time {
                // the open step assigned every variable of the frame at `t`
                return Err(w.double_change(self.frame.idx[0] as usize));
            }
            if w.in_window(t) {
                let f = &mut *self.frame;
                let reals = self.reals.iter().any(|r| r.2);
                if f.nopen > 0 || reals {
                    self.dirty |= f.nopen > 0;
                    w.emitter.timestamp(w.time)?;
                    for &k in &f.open[..f.nopen] {
                        w.emitter.value(
                            f.idx[k as usize] as usize,
                            ValueRef::Int(f.prev[k as usize]),
                        )?;
                    }
                    for &(i, v, _) in self.reals.iter().filter(|r| r.2) {
                        w.emitter.value(i as usize, ValueRef::Real(v))?;
                    }
                    w.last_written = Some(w.time);
                    f.nopen = 0;
                }
                self.reals.clear();
                w.time = t;
                w.step += 1;
                w.frame_steps[self.frame.id as usize] = w.step;
                return Ok(RunStep {
                    inner: Inner::Direct {
                        writer: &*self.writer,
                        frame: &mut *self.frame,
                    },
                    next: 0,
                    current: true,
                });
            }
            self.close();
        }
        let (w, f) = (&mut *self.writer, &mut *self.frame);
        if t > w.time && f.sorted {
            w.frame_prologue(f, t)?;
            if w.dumped && w.in_window(t) {
                let current = f.generation == w.generation;
                let all_int = current
                    || f.idx
                        .iter()
                        .all(|&i| matches!(w.cur[i as usize], Stored::Int(_)));
                if all_int {
                    if !current {
                        for (k, &i) in f.idx.iter().enumerate() {
                            if let Stored::Int(c) = w.cur[i as usize] {
                                f.prev[k] = c;
                            }
                        }
                    }
                    w.frame_steps[f.id as usize] = w.step;
                    self.direct = true;
                    f.nopen = 0;
                    return Ok(RunStep {
                        inner: Inner::Direct {
                            writer: &*self.writer,
                            frame: &mut *self.frame,
                        },
                        next: 0,
                        current,
                    });
                }
            }
        }
        let s = self.writer.frame_step(self.frame, t)?;
        let current = s.is_current();
        Ok(RunStep {
            inner: Inner::Checked(s),
            next: 0,
            current,
        })
    }

    /// The `real` variable `id` (declared after every variable of the frame) at the time of
    /// the open step: in a direct step it is written after the frame's changes of that step,
    /// otherwise (no step yet, or a step that was not direct) through
    /// [`Writer::change_real`]. The same checks as `change_real` (a `real` variable, finite,
    /// given once per step); in a direct step the reals come in increasing declaration order
    /// ([`WriteError::FrameOrder`]). The file is the one of `dump_frame` and `change_real` at
    /// each step (tests/writer.rs).
    pub fn real(&mut self, id: SigId, v: f64) -> Result<()> {
        if !self.direct {
            let current = self.frame.generation == self.writer.generation;
            self.writer.change_real(id, v)?;
            if current {
                self.frame.generation = self.writer.generation;
            }
            return Ok(());
        }
        let w = &mut *self.writer;
        let i = w.index(id)?;
        let Stored::Real(old) = w.cur[i] else {
            return Err(w.type_mismatch(i, "real"));
        };
        if let Some(&last) = self.frame.idx.last().filter(|&&last| i as u32 <= last) {
            return Err(order_error(i, last as usize + 1));
        }
        if let Some(&(last, ..)) = self.reals.last().filter(|r| i as u32 <= r.0) {
            return Err(if last == i as u32 {
                w.double_change(i)
            } else {
                order_error(i, last as usize + 1)
            });
        }
        if !v.is_finite() {
            return Err(WriteError::NotFinite {
                name: w.vars[i].path.clone(),
                value: v,
            });
        }
        let v = v + 0.0;
        let changed = old != v;
        if changed {
            w.cur[i] = Stored::Real(v);
        }
        self.reals.push((i as u32, v, changed));
        Ok(())
    }

    /// The writer takes over the frame's values after direct steps: every variable of the frame
    /// its value, and the open step's changes as its pending step.
    fn close(&mut self) {
        if !std::mem::replace(&mut self.direct, false) {
            return;
        }
        let (w, f) = (&mut *self.writer, &mut *self.frame);
        if std::mem::replace(&mut self.dirty, false) || f.nopen > 0 {
            for (k, &i) in f.idx.iter().enumerate() {
                w.cur[i as usize] = Stored::Int(f.prev[k]);
            }
            for &k in &f.open[..f.nopen] {
                w.push_pending(f.idx[k as usize] as usize);
            }
            f.nopen = 0;
            w.generation += 1;
        }
        // (when nothing changed, the writer's values are the frame's copy, refreshed when the
        // first direct step began)
        f.generation = w.generation;
        // the reals of the open step: assigned in it, the changed ones pending
        for &(i, _, changed) in &self.reals {
            w.assigned[i as usize] = w.step;
            w.single_step = w.step;
            if changed {
                w.push_pending(i as usize);
            }
        }
        self.reals.clear();
    }
}

impl<E: Emitter> Drop for FrameRun<'_, E> {
    fn drop(&mut self) {
        self.close();
    }
}

/// One step of a [`FrameRun`]: [`RunStep::set`] takes the step's positions in increasing order.
pub struct RunStep<'r, E: Emitter> {
    inner: Inner<'r, E>,
    /// the lowest position still allowed in this step
    next: usize,
    current: bool,
}

enum Inner<'r, E: Emitter> {
    Direct {
        writer: &'r Writer<E>,
        frame: &'r mut Frame,
    },
    Checked(FrameStep<'r, E>),
}

impl<E: Emitter> RunStep<'_, E> {
    /// As [`FrameStep::is_current`]: the frame's variables hold exactly the values of its last
    /// step (true in every direct step after the first; a checked step is current as
    /// [`FrameStep::is_current`] says, so not while a frame variable holds `x`/`z`).
    #[inline]
    pub fn is_current(&self) -> bool {
        self.current
    }

    /// As [`FrameStep::set`], with positions in increasing order within the step
    /// ([`WriteError::FrameOrder`]); a value too wide for its variable assigns nothing, and
    /// the position may be given again.
    #[inline(always)]
    pub fn set(&mut self, k: usize, v: u64) -> Result<()> {
        if k < self.next {
            return Err(order_error(k, self.next));
        }
        match &mut self.inner {
            Inner::Direct {
                writer: w,
                frame: f,
            } => {
                let Some(prev) = f.prev.get_mut(k) else {
                    return Err(position_error(f, k));
                };
                if v != *prev {
                    if v > f.max[k] {
                        return Err(too_wide(w, f, k, v));
                    }
                    *prev = v;
                    f.open[f.nopen] = k as u32;
                    f.nopen += 1;
                }
            }
            Inner::Checked(s) => s.set(k, v)?,
        }
        self.next = k + 1;
        Ok(())
    }
}

/// The error of position `k` given after `next - 1`.
#[cold]
#[inline(never)]
fn order_error(k: usize, next: usize) -> WriteError {
    WriteError::FrameOrder {
        position: k,
        previous: next - 1,
    }
}

/// The error of a position outside the frame.
#[cold]
#[inline(never)]
fn position_error(f: &Frame, k: usize) -> WriteError {
    WriteError::FramePosition {
        position: k,
        len: f.idx.len(),
    }
}

/// The error of a frame value `v` at position `k` wider than its variable.
#[cold]
#[inline(never)]
fn too_wide<E: Emitter>(w: &Writer<E>, f: &Frame, k: usize, v: u64) -> WriteError {
    WriteError::ValueTooWide {
        name: w.vars[f.idx[k] as usize].path.clone(),
        value: v,
        width: 64 - f.max[k].leading_zeros(),
        max: f.max[k],
    }
}

/// A [`FrameRun`] for VCD whose direct steps write their text at once ([`VcdWriter::text_run`]):
/// the writer's text buffer is lent to one frame for a run of steps, the way Verilator's tracer
/// owns its file.
///
/// [`TextRun::step`] starts a step at a later time and writes its time stamp ahead; each
/// [`TextStep::line`] writes one changed value's line straight into the buffer, in increasing
/// positions; a step in which nothing changed takes its stamp back. The checks of a direct
/// [`RunStep::set`] stay, per line: position in the frame and increasing within the step, the
/// value's width; per step: time order. The rest moves to the start of a step: the frame is
/// this writer's, in declaration order, of two-state variables each with a change line
/// ([`crate::vcd_text::ChangeLine`]), the step is inside the window, the writer has dumped
/// (its own step at its time, if any, is written first, as [`Writer::set_time`] does) and the
/// frame holds the writer's values. When any of these does not hold, [`TextRun::step`]
/// returns `None` and the caller takes that step through [`TextRun::frame_run`] (which ends the
/// text steps first).
///
/// The last step stays open until the next step or the end of the run; when the run ends (it
/// is dropped, or [`TextRun::frame_run`] is called) its text is taken back out of the buffer
/// and its changes become the writer's pending step, exactly as a [`FrameRun`]'s last step does,
/// so a single change at that time afterwards is merged or refused as after
/// [`Writer::frame_step`]. The file is byte for byte the one `dump_frame` writes with every
/// value (tests/writer.rs). As with a [`FrameRun`], the run must be dropped, not leaked
/// (`std::mem::forget` loses its last step and leaves the writer's and the frame's values stale);
/// a [`TextStep`] may be leaked: its lines are the writer's as soon as they are written.
pub struct TextRun<'a, W: Write> {
    writer: &'a mut VcdWriter<W>,
    frame: &'a mut Frame,
    /// the frame's variables all have change lines and are in declaration order
    eligible: bool,
    /// per position of the frame: its value and its change line (one bounds check and one
    /// base for both in a line); while text steps are open the values are the frame's (its
    /// `prev` is brought up to date when they end)
    slots: Box<[TextSlot]>,
    /// bytes a step may write at most: its stamp and a line per variable
    need: usize,
    /// a text step is open: its stamp starts at `mark`, its lines at `start`
    open: bool,
    mark: usize,
    start: usize,
    /// the lowest position still allowed in the open step
    next: usize,
    /// a finished text step of this run changed a value (the writer's values are stale)
    dirty: bool,
    /// the `real` variables given in text steps ([`TextRun::real`]): their values as written
    /// (the writer's are brought up to date when the run ends) and, in the open step, whether
    /// given and changed
    reals: Vec<RealSlot>,
    /// the declaration index of the last real given in the open step (reals in increasing order)
    next_real: Option<u32>,
}

/// A `real` variable of a [`TextRun`] ([`TextRun::real`]).
#[derive(Clone, Copy)]
struct RealSlot {
    var: u32,
    value: f64,
    /// given in the open step, and changed in it
    given: bool,
    changed: bool,
}

/// A position of a [`TextRun`]'s frame: its value and its change line.
#[derive(Clone, Copy)]
struct TextSlot {
    prev: u64,
    line: ChangeLine,
}

/// One step of a [`TextRun`] ([`TextRun::step`]). It keeps the end of the text it writes as
/// its own field (two words: a caller that holds the step in a local variable keeps it in a
/// register from one line to the next). Each line stores the new end in the writer too, but
/// never loads it back: the next line starts from the step's own copy, not from a load that
/// waits for the store (the writer is up to date after every line, however the step ends).
pub struct TextStep<'s, 'a, W: Write> {
    run: &'s mut TextRun<'a, W>,
    /// the end of the text in the writer's buffer (equal to the writer's)
    pos: usize,
}

impl<W: Write> VcdWriter<W> {
    /// Lend the writer's text buffer to `frame` for a run of steps written at once
    /// ([`TextRun`]). Error: a frame of another writer.
    pub fn text_run<'a>(&'a mut self, frame: &'a mut Frame) -> Result<TextRun<'a, W>> {
        if frame.owner != self.owner || frame.id as usize >= self.frame_steps.len() {
            return Err(WriteError::UnknownFrame);
        }
        let eligible = frame.sorted
            && frame
                .idx
                .iter()
                .all(|&i| self.emitter.lines[i as usize].is_line());
        let need = (frame.idx.len() + 1) * SLACK;
        let e = &mut self.emitter;
        if eligible && e.buf.len() < need + SLACK {
            // a frame of thousands of variables: room for one whole step
            let mut buf = vec![0; VCD_BUFFER + need + SLACK].into_boxed_slice();
            buf[..e.pos].copy_from_slice(&e.buf[..e.pos]);
            e.buf = buf;
        }
        frame.nopen = 0;
        // (the values are taken from the frame when text steps start: `TextRun::step`)
        let slots = frame
            .idx
            .iter()
            .map(|&i| TextSlot {
                prev: 0,
                line: self.emitter.lines[i as usize],
            })
            .collect();
        Ok(TextRun {
            writer: self,
            frame,
            eligible,
            slots,
            need,
            open: false,
            mark: 0,
            start: 0,
            next: 0,
            dirty: false,
            reals: Vec::new(),
            next_real: None,
        })
    }
}

impl<'a, W: Write> TextRun<'a, W> {
    /// Start the frame's step at time `t`, after the writer's time: `None` when the step cannot
    /// be written at once (see [`TextRun`]; nothing is changed then, take the step through
    /// [`TextRun::frame_run`]). The first text step of a run (or the first after a
    /// [`TextRun::frame_run`]) checks that the frame holds the writer's values. Errors: `t`
    /// before the writer's time ([`WriteError::TimeBackwards`]), or at it after a text step
    /// ([`WriteError::DoubleChange`]: that step gave the frame's values at `t`).
    #[inline]
    pub fn step(&mut self, t: u64) -> Result<Option<TextStep<'_, 'a, W>>> {
        let w = &mut *self.writer;
        if t <= w.time {
            if t < w.time {
                return Err(WriteError::TimeBackwards {
                    requested: t,
                    current: w.time,
                });
            }
            if self.open {
                return Err(w.double_change(self.frame.idx[0] as usize));
            }
            return Ok(None);
        }
        if self.open {
            // the open step is final now: its text stays when it wrote a line
            for r in &mut self.reals {
                (r.given, r.changed) = (false, false);
            }
            self.next_real = None;
            let e = &mut w.emitter;
            if e.pos == self.start {
                e.pos = self.mark;
            } else {
                w.last_written = Some(w.time);
                self.dirty = true;
            }
            // nothing of it is taken back any more
            self.mark = e.pos;
            self.start = e.pos;
            if !w.in_window(t) {
                self.close();
                return Ok(None);
            }
        } else {
            if !(self.eligible && w.in_window(t)) {
                return Ok(None);
            }
            // the writer's step at its time (a frame run's last step, single changes; the
            // first dump) is written first, as `set_time` does
            w.flush_step()?;
            // `frame_prologue`'s checks (this frame or an overlapping one already stepped at
            // `t`, a single change at `t`) cannot fail: `t` is after the writer's time
            if !(w.dumped && self.frame.generation == w.generation)
                || self
                    .frame
                    .idx
                    .iter()
                    .any(|&i| !matches!(w.cur[i as usize], Stored::Int(_)))
            {
                return Ok(None);
            }
            // the text steps hold the frame's values from here until they end (`close`)
            for (s, &p) in self.slots.iter_mut().zip(&self.frame.prev) {
                s.prev = p;
            }
        }
        let e = &mut self.writer.emitter;
        if e.pos + self.need > e.buf.len() {
            if let Err(err) = e.out.write_all(&e.buf[..e.pos]) {
                self.close();
                return Err(err.into());
            }
            e.pos = 0;
        }
        let w = &mut *self.writer;
        if !self.open {
            // The writer's step number, and this frame's, once for the run's text steps: while
            // the run lasts nothing else assigns or steps, so every later step of it is this
            // frame's step at the writer's (new) time as well, and when the run ends the last
            // one is the frame's step at the writer's time, numbered after every earlier
            // assignment and frame step (as if numbered one by one).
            w.step += 1;
            w.frame_steps[self.frame.id as usize] = w.step;
        }
        self.open = true;
        w.time = t;
        let e = &mut w.emitter;
        self.mark = e.pos;
        e.stamp(t);
        let pos = e.pos;
        self.start = pos;
        self.next = 0;
        Ok(Some(TextStep { run: self, pos }))
    }

    /// The `real` variable `id` (declared after every variable of the frame) at the time of the
    /// last step, in the same step: written at once after the frame's lines when that step was
    /// a text step, through [`Writer::change_real`] otherwise (a step that went through
    /// [`TextRun::frame_run`], or none in this run). The same checks as `change_real`: a
    /// `real` variable, finite, given once per step; here in addition the reals of a step come
    /// in increasing declaration order ([`WriteError::FrameOrder`]). The file is the one of
    /// `dump_frame` and `change_real` at each step (tests/writer.rs).
    pub fn real(&mut self, id: SigId, v: f64) -> Result<()> {
        let i = self.writer.index(id)?;
        if !matches!(self.writer.vars[i].kind, Kind::Real) {
            return Err(self.writer.type_mismatch(i, "real"));
        }
        if !self.open {
            return self.change_real(id, v);
        }
        if self.frame.idx.last().is_some_and(|&last| i as u32 <= last) {
            return Err(order_error(
                i,
                self.frame.idx[self.frame.idx.len() - 1] as usize + 1,
            ));
        }
        if let Some(last) = self.next_real.filter(|&last| i as u32 <= last) {
            return Err(if last == i as u32 {
                self.writer.double_change(i)
            } else {
                order_error(i, last as usize + 1)
            });
        }
        if !v.is_finite() {
            return Err(WriteError::NotFinite {
                name: self.writer.vars[i].path.clone(),
                value: v,
            });
        }
        let v = v + 0.0;
        let k = match self.reals.iter().position(|r| r.var == i as u32) {
            Some(k) => k,
            None => {
                let Stored::Real(value) = self.writer.cur[i] else {
                    return Err(self.writer.type_mismatch(i, "real"));
                };
                // room for its line in every later step
                self.need += SLACK;
                self.reals.push(RealSlot {
                    var: i as u32,
                    value,
                    given: false,
                    changed: false,
                });
                self.reals.len() - 1
            }
        };
        self.next_real = Some(i as u32);
        self.next = self.slots.len();
        self.reals[k].given = true;
        if self.reals[k].value.to_bits() == v.to_bits() {
            return Ok(());
        }
        let e = &mut self.writer.emitter;
        let mut b = RealBuf::new();
        let text = real_text(v, &mut b);
        let code = &e.codes[i];
        let n = text.len() + code.len() + 3;
        if e.pos + n > e.buf.len() {
            // (only before the step reserved room for this real: take it through the writer)
            self.reals[k].given = false;
            self.next_real = None;
            self.close();
            return self.change_real(id, v);
        }
        real_line(&mut e.buf[e.pos..e.pos + n], &text, code);
        e.pos += n;
        self.reals[k].value = v;
        self.reals[k].changed = true;
        self.dirty = true;
        Ok(())
    }

    /// [`Writer::change_real`] of a real outside the frame: a frame that held the writer's
    /// values still does (so the next step may be a text step again).
    fn change_real(&mut self, id: SigId, v: f64) -> Result<()> {
        let current = self.frame.generation == self.writer.generation;
        self.writer.change_real(id, v)?;
        if current {
            self.frame.generation = self.writer.generation;
        }
        Ok(())
    }

    /// End the text steps and lend the writer to the frame as a [`FrameRun`] (for a step that
    /// [`TextRun::step`] cannot write at once); the text steps resume at the next
    /// [`TextRun::step`].
    pub fn frame_run(&mut self) -> Result<FrameRun<'_, VcdOut<W>>> {
        self.close();
        self.writer.frame_run(self.frame)
    }

    /// The writer takes over the frame's values: every variable of the frame its value, and
    /// the open step's changes (its text taken back out of the buffer) as its pending step.
    fn close(&mut self) {
        if !std::mem::replace(&mut self.open, false) {
            return;
        }
        let (w, f) = (&mut *self.writer, &mut *self.frame);
        for (p, s) in f.prev.iter_mut().zip(self.slots.iter()) {
            *p = s.prev;
        }
        // The open step's changes become the writer's pending step (its first text step
        // wrote the writer's own). They are read back from its text, which a step keeps whole:
        // its lines are in increasing positions, each ends with its variable's code.
        let (start, end) = (self.start, w.emitter.pos);
        let mut k = 0;
        let mut changed = false;
        // (the reals' lines, `r...`, follow the frame's: `TextRun::real`)
        for line in w.emitter.buf[start..end]
            .to_vec()
            .split_inclusive(|&b| b == b'\n')
            .take_while(|l| l.first() != Some(&b'r'))
        {
            while !self.slots[k].line.is_line_of(line) {
                k += 1;
            }
            w.push_pending(f.idx[k] as usize);
            changed = true;
            k += 1;
        }
        w.emitter.pos = self.mark;
        // The reals: the writer's values; those given in the open step are assigned in it.
        for r in self.reals.iter_mut() {
            w.cur[r.var as usize] = Stored::Real(r.value);
            if r.given {
                w.assigned[r.var as usize] = w.step;
                w.single_step = w.step;
            }
            if r.changed {
                w.push_pending(r.var as usize);
                changed = true;
            }
            (r.given, r.changed) = (false, false);
        }
        self.reals.clear();
        self.next_real = None;
        // a value changed in an earlier step of the run or in the open one
        if !std::mem::replace(&mut self.dirty, false) && !changed {
            return;
        }
        for (k, &i) in f.idx.iter().enumerate() {
            w.cur[i as usize] = Stored::Int(f.prev[k]);
        }
        w.generation += 1;
        f.generation = w.generation;
    }
}

impl<W: Write> Drop for TextRun<'_, W> {
    fn drop(&mut self) {
        self.close();
    }
}

impl<W: Write> TextStep<'_, '_, W> {
    /// The value `v` at position `k` of the frame, written at once when it changed. Positions
    /// increase within a step ([`WriteError::FrameOrder`]); a value too wide for its variable
    /// assigns nothing ([`WriteError::ValueTooWide`]), and the values before it in the step are
    /// assigned.
    #[inline(always)]
    pub fn line(&mut self, k: usize, v: u64) -> Result<()> {
        let r = &mut *self.run;
        if k < r.next {
            return Err(order_error(k, r.next));
        }
        let Some(slot) = r.slots.get_mut(k) else {
            return Err(position_error(r.frame, k));
        };
        if v == slot.prev {
            r.next = k + 1;
            return Ok(());
        }
        if v > r.frame.max[k] {
            return Err(too_wide(r.writer, r.frame, k, v));
        }
        self.write::<0>(k, v);
        Ok(())
    }

    /// The value `v` at position `k` of the frame, which the caller knows has changed and
    /// fits: written at once, as [`TextStep::line`] writes a changed value, without its three
    /// checks in release builds. The caller guarantees, and debug builds assert, that
    /// - `k` is after the positions given before in the step (the text stays sorted),
    /// - `v` differs from the frame's value at `k` (the caller keeps its own copy of the
    ///   values, which equals the frame's while a run of its steps lasts),
    /// - `v` fits the variable ([`Frame::max`]; checked once when the caller was declared,
    ///   against the widths of the values it gives).
    ///
    /// A position past the frame's end panics, in every build. For a tracer whose values come
    /// from typed registers (`pmu50::observers::tracer::CoreTracer`, which checks the frame's widths when
    /// it is created and is compared with [`Writer::dump_frame`] in its tests); any other
    /// caller, [`TextStep::line`].
    #[inline(always)]
    pub fn change(&mut self, k: usize, v: u64) {
        self.change_n::<0>(k, v);
    }

    /// [`TextStep::change`] for a variable the caller knows to be exactly `N` bits wide (its
    /// three guarantees, and this one, asserted in debug builds): the line is written by
    /// [`ChangeLine::write_w`], without the tests of a width known only at run time. For a
    /// caller that checked the frame's widths against its own when it was declared.
    #[inline(always)]
    pub fn change_w<const N: usize>(&mut self, k: usize, v: u64) {
        debug_assert!((1..=64).contains(&N), "change_w: a width of {N} bits");
        self.change_n::<N>(k, v);
    }

    /// [`TextStep::change`] (`N` = 0) and [`TextStep::change_w`]: the caller's guarantees
    /// asserted in debug builds, then the line.
    #[inline(always)]
    fn change_n<const N: usize>(&mut self, k: usize, v: u64) {
        let r = &*self.run;
        debug_assert!(
            k >= r.next,
            "change: position {k} after {} in one step",
            r.next
        );
        debug_assert!(r.slots[k].prev != v, "change: position {k} did not change");
        debug_assert!(
            v <= r.frame.max[k],
            "change: value {v:#x} too wide for position {k}"
        );
        debug_assert!(
            N == 0 || r.frame.max[k] == u64::MAX >> (64 - N),
            "change_w: position {k} is not {N} bits wide"
        );
        self.write::<N>(k, v);
    }

    /// The changed value `v` at position `k` (after the step's positions, fitting; `N` bits
    /// wide, or 0: the line's own width): the frame's value, the step's order mark, the line
    /// after the step's text, and the writer's end of text (stored, never loaded back: the next
    /// line starts from the step's copy).
    #[inline(always)]
    fn write<const N: usize>(&mut self, k: usize, v: u64) {
        let r = &mut *self.run;
        let slot = &mut r.slots[k];
        slot.prev = v;
        r.next = k + 1;
        let p = self.pos;
        let e = &mut r.writer.emitter;
        let out: &mut [u8; SLACK] = (&mut e.buf[p..p + SLACK])
            .try_into()
            .expect("room for a whole step, reserved when it began");
        self.pos = p + if N == 0 {
            slot.line.write(out, v)
        } else {
            slot.line.write_w::<N>(out, v)
        };
        e.pos = self.pos;
    }
}

/// Dumps value changes with every check of the module documentation; created by
/// [`VcdBuilder::start`] (VCD) or [`crate::fst::start_fst`] (FST). Call [`Writer::finish`] at
/// the end or the last time step is lost.
pub struct Writer<E: Emitter> {
    emitter: E,
    owner: u32,
    vars: Vec<VarDecl>,
    cur: Vec<Stored>,
    /// step number of the last individual assignment per variable (0 = never)
    assigned: Vec<u64>,
    /// step number of the last individual assignment of any variable (0 = never)
    single_step: u64,
    /// per variable: bit f set when frame f holds it
    var_frames: Vec<u32>,
    /// `pending[..npending]`: the variables whose value changed in the current step (each at
    /// most once: a second assignment in a step is an error, so `pending` has one slot per
    /// variable and a push never allocates)
    pending: Box<[u32]>,
    npending: usize,
    /// `pending[..npending]` is in increasing order (frames given in declaration order keep it
    /// so, and the step is then written without sorting)
    pending_sorted: bool,
    time: u64,
    step: u64,
    window: (u64, u64),
    dumped: bool,
    last_written: Option<u64>,
    /// incremented whenever a value of a frame's variable changes (frames use it to know their
    /// copy is current)
    generation: u64,
    /// per frame: step of its last dump (0 = never)
    frame_steps: Vec<u64>,
    /// per frame: bit g set when frame g shares a variable with it
    frame_overlap: Vec<u32>,
}

impl<E: Emitter> std::fmt::Debug for Writer<E> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Writer")
            .field("time", &self.time)
            .field("variables", &self.vars.len())
            .field("window", &self.window)
            .field("dumped", &self.dumped)
            .finish_non_exhaustive()
    }
}

impl<E: Emitter> Writer<E> {
    /// Current simulation time (timescale units).
    pub fn time(&self) -> u64 {
        self.time
    }

    /// GTKWave's name for a variable (see [`VcdBuilder::gtkwave_name`]).
    pub fn gtkwave_name(&self, id: SigId) -> Result<String> {
        let i = self.index(id)?;
        Ok(self.vars[i].gtkwave_name())
    }

    #[inline]
    fn index(&self, id: SigId) -> Result<usize> {
        if id.owner != self.owner || id.index as usize >= self.vars.len() {
            return Err(WriteError::UnknownId { id });
        }
        Ok(id.index as usize)
    }

    fn in_window(&self, t: u64) -> bool {
        t >= self.window.0 && t < self.window.1
    }

    /// Advance to time `t`. Equal time stays in the current step; an earlier
    /// time is an error.
    #[inline]
    pub fn set_time(&mut self, t: u64) -> Result<()> {
        if t == self.time {
            return Ok(());
        }
        if t < self.time {
            return Err(WriteError::TimeBackwards {
                requested: t,
                current: self.time,
            });
        }
        self.flush_step()?;
        let start = self.window.0;
        if !self.dumped && self.time < start && t > start && self.in_window(start) {
            self.write_dump(start)?;
        }
        self.time = t;
        self.step += 1;
        Ok(())
    }

    /// Change a one-bit variable (scalar or one-bit vector).
    pub fn change_bit(&mut self, id: SigId, v: Logic) -> Result<()> {
        let i = self.one_bit(id)?;
        self.assign(i, canon_bits(vec![v.as_byte()]))
    }

    /// Change a one-bit variable from a `bool`.
    pub fn change_bool(&mut self, id: SigId, v: bool) -> Result<()> {
        let i = self.one_bit(id)?;
        self.assign(i, Stored::Int(u64::from(v)))
    }

    /// The index of `id`, a one-bit variable (else a wrong width or type).
    fn one_bit(&self, id: SigId) -> Result<usize> {
        let i = self.index(id)?;
        match self.vars[i].kind {
            Kind::Bits { width: 1, .. } => Ok(i),
            Kind::Bits { width, .. } => Err(WriteError::WrongWidth {
                name: self.vars[i].path.clone(),
                expected: width,
                got: 1,
            }),
            Kind::Real => Err(self.type_mismatch(i, "bit")),
        }
    }

    /// Change a bit/vector variable to a two-state integer, which must fit the
    /// declared width.
    pub fn change_vector(&mut self, id: SigId, v: u64) -> Result<()> {
        let i = self.index(id)?;
        let width = match self.vars[i].kind {
            Kind::Bits { width, .. } => width,
            Kind::Real => return Err(self.type_mismatch(i, "integer")),
        };
        if v > max_for_width(width) {
            return Err(WriteError::ValueTooWide {
                name: self.vars[i].path.clone(),
                value: v,
                width,
                max: max_for_width(width),
            });
        }
        let s = if width <= 64 {
            Stored::Int(v)
        } else {
            canon_bits(int_to_bits(v, width))
        };
        self.assign(i, s)
    }

    /// Change a bit/vector variable to a four-state bit string, msb first,
    /// exactly as many characters as the declared width (`"01xz"`).
    pub fn change_bits(&mut self, id: SigId, bits: &str) -> Result<()> {
        let i = self.index(id)?;
        let width = match self.vars[i].kind {
            Kind::Bits { width, .. } => width,
            Kind::Real => return Err(self.type_mismatch(i, "bit-string")),
        };
        let mut out = Vec::with_capacity(bits.len());
        for (pos, ch) in bits.chars().enumerate() {
            let b = match ch {
                '0' => b'0',
                '1' => b'1',
                'x' | 'X' => b'x',
                'z' | 'Z' => b'z',
                _ => {
                    return Err(WriteError::InvalidBit {
                        name: self.vars[i].path.clone(),
                        ch,
                        pos,
                    })
                }
            };
            out.push(b);
        }
        if out.len() != width as usize {
            return Err(WriteError::WrongWidth {
                name: self.vars[i].path.clone(),
                expected: width,
                got: out.len(),
            });
        }
        self.assign(i, canon_bits(out))
    }

    /// Change a `real` variable. NaN and infinities are rejected; `-0.0` is
    /// written (and compared) as `0`.
    pub fn change_real(&mut self, id: SigId, v: f64) -> Result<()> {
        let i = self.index(id)?;
        if !matches!(self.vars[i].kind, Kind::Real) {
            return Err(self.type_mismatch(i, "real"));
        }
        if !v.is_finite() {
            return Err(WriteError::NotFinite {
                name: self.vars[i].path.clone(),
                value: v,
            });
        }
        self.assign(i, Stored::Real(v + 0.0))
    }

    /// Declare a frame: variables dumped together by [`Writer::dump_frame`] or
    /// [`Writer::frame_step`]. At least one; each must be a bit or vector variable of at most 64
    /// bits of this writer; a variable may appear once.
    pub fn frame(&mut self, ids: &[SigId]) -> Result<Frame> {
        let f = self.frame_steps.len();
        if f >= MAX_FRAMES {
            return Err(WriteError::TooManyFrames);
        }
        if ids.is_empty() {
            return Err(WriteError::EmptyFrame);
        }
        let bit = 1u32 << f;
        let mut idx = Vec::with_capacity(ids.len());
        let mut max = Vec::with_capacity(ids.len());
        let mut prev = Vec::with_capacity(ids.len());
        let mut seen = HashSet::new();
        for &id in ids {
            let i = self.index(id)?;
            let width = match self.vars[i].kind {
                Kind::Bits { width, .. } if width <= 64 => width,
                _ => return Err(self.type_mismatch(i, "frame value (integer of at most 64 bits)")),
            };
            if !seen.insert(i) {
                return Err(WriteError::Duplicate {
                    path: self.vars[i].path.clone(),
                });
            }
            idx.push(i as u32);
            max.push(max_for_width(width));
            prev.push(match self.cur[i] {
                Stored::Int(v) => v,
                _ => 0,
            });
        }
        let mut overlap = bit;
        for &i in &idx {
            overlap |= self.var_frames[i as usize];
        }
        for g in 0..f {
            if overlap & (1 << g) != 0 {
                self.frame_overlap[g] |= bit;
            }
        }
        for &i in &idx {
            self.var_frames[i as usize] |= bit;
        }
        self.frame_steps.push(0);
        self.frame_overlap.push(overlap);
        let seen = vec![0; idx.len().div_ceil(64)];
        Ok(Frame {
            owner: self.owner,
            id: f as u32,
            max,
            prev,
            generation: u64::MAX,
            seen,
            sorted: idx.windows(2).all(|p| p[0] < p[1]),
            open: vec![0; idx.len()].into_boxed_slice(),
            nopen: 0,
            idx,
        })
    }

    /// Advance to time `t` (as [`Writer::set_time`]) and assign every variable of the frame its
    /// value from `values` (same order and length as the frame). Equivalent to `set_time(t)` and
    /// one `change_vector` per variable, with the same checks: time never goes backwards, no
    /// variable is assigned twice in a step (by this frame, another frame or a single change),
    /// values fit their width. Only the values that changed are compared with their width and
    /// formatted. A time or double-assignment error assigns nothing; after a value that does not
    /// fit, the values before it in the frame are assigned.
    pub fn dump_frame(&mut self, frame: &mut Frame, t: u64, values: &[u64]) -> Result<()> {
        if frame.owner != self.owner || frame.id as usize >= self.frame_steps.len() {
            return Err(WriteError::UnknownFrame);
        }
        if values.len() != frame.idx.len() {
            return Err(WriteError::FrameLength {
                expected: frame.idx.len(),
                got: values.len(),
            });
        }
        self.frame_prologue(frame, t)?;
        let f = frame.id as usize;
        let step = self.step;
        let fast = frame.generation == self.generation;
        let mut changed = false;
        let n = values.len();
        // Chunks of eight: in the fast path a chunk whose values all equal the frame's copy is
        // passed with one OR of XORs, which the compiler vectorises (most of a frame is
        // unchanged in most steps); the values of the other chunks are compared one by one.
        let mut k = 0;
        while k < n {
            let end = (k + 8).min(n);
            if fast {
                let unchanged = match (
                    <&[u64; 8]>::try_from(&values[k..end]),
                    <&[u64; 8]>::try_from(&frame.prev[k..end]),
                ) {
                    (Ok(a), Ok(b)) => a.iter().zip(b).fold(0, |acc, (x, y)| acc | (x ^ y)) == 0,
                    _ => values[k..end] == frame.prev[k..end],
                };
                if unchanged {
                    k = end;
                    continue;
                }
            }
            // One position indexes four arrays (values, variable, last value, limit).
            #[allow(clippy::needless_range_loop)]
            for k in k..end {
                let v = values[k];
                let i = frame.idx[k] as usize;
                let same = if fast {
                    v == frame.prev[k]
                } else {
                    matches!(self.cur[i], Stored::Int(c) if c == v)
                };
                if same {
                    continue;
                }
                if v > frame.max[k] {
                    self.frame_steps[f] = step;
                    if changed {
                        self.generation += 1;
                    }
                    return Err(too_wide(self, frame, k, v));
                }
                frame.prev[k] = v;
                self.cur[i] = Stored::Int(v);
                self.push_pending(i);
                changed = true;
            }
            k = end;
        }
        if !fast {
            for (k, &i) in frame.idx.iter().enumerate() {
                if let Stored::Int(c) = self.cur[i as usize] {
                    frame.prev[k] = c;
                }
            }
        }
        self.frame_steps[f] = step;
        if changed {
            self.generation += 1;
        }
        frame.generation = self.generation;
        Ok(())
    }

    /// The checks and time advance that start a frame's step (shared by [`Writer::dump_frame`]
    /// and [`Writer::frame_step`]): the frame is this writer's, time does not go backwards, and
    /// no variable of the frame was assigned in the step at `t` yet (by an overlapping frame or
    /// a single change). Assigns nothing on error.
    #[inline]
    fn frame_prologue(&mut self, frame: &Frame, t: u64) -> Result<()> {
        if frame.owner != self.owner || frame.id as usize >= self.frame_steps.len() {
            return Err(WriteError::UnknownFrame);
        }
        self.set_time(t)?;
        let f = frame.id as usize;
        let step = self.step;
        // Double assignment: another (or the same) overlapping frame already dumped in this step.
        let ov = self.frame_overlap[f];
        let mut g = ov;
        while g != 0 {
            let k = g.trailing_zeros() as usize;
            g &= g - 1;
            if self.frame_steps[k] == step {
                let i = frame
                    .idx
                    .iter()
                    .map(|&i| i as usize)
                    .find(|&i| self.var_frames[i] & (1 << k) != 0)
                    .unwrap_or(frame.idx[0] as usize);
                return Err(self.double_change(i));
            }
        }
        if frame.generation != self.generation || self.single_step == step {
            // Values changed since this frame's last dump, or single assignments in this step
            // (one that kept a variable's value changes no generation): any of the frame's?
            if let Some(&i) = frame
                .idx
                .iter()
                .find(|&&i| self.assigned[i as usize] == step)
            {
                return Err(self.double_change(i as usize));
            }
        }
        Ok(())
    }

    /// Start a step of `frame` at time `t` in which only some of its values are given: the
    /// sparse form of [`Writer::dump_frame`], for callers that know which of their values may
    /// have changed (a struct equal to the last step's needs no value at all).
    ///
    /// The step assigns every variable of the frame at `t`, exactly as `dump_frame` with the
    /// values set through [`FrameStep::set`] and, at every other position, the value the
    /// variable has now. So it has every check of `dump_frame`: here time, foreign frames and
    /// double assignment by an overlapping frame or a single change; in `set` the position, a
    /// position set twice in the step, and the width of a value that changed. A single change of
    /// one of the frame's variables later in the same step is a double assignment.
    #[inline]
    fn frame_step<'a>(&'a mut self, frame: &'a mut Frame, t: u64) -> Result<FrameStep<'a, E>> {
        self.frame_prologue(frame, t)?;
        let current = frame.generation == self.generation;
        let mut slow = false;
        if !current {
            // The frame's copy is stale (single changes, or another frame): take the values now.
            for (k, &i) in frame.idx.iter().enumerate() {
                match self.cur[i as usize] {
                    Stored::Int(c) => frame.prev[k] = c,
                    // `x`/`z` from a single change: this step compares with the writer's value
                    _ => slow = true,
                }
            }
            frame.generation = if slow { u64::MAX } else { self.generation };
        }
        self.frame_steps[frame.id as usize] = self.step;
        // (the usual frame has at most 128 variables: no call to `memset`)
        match &mut frame.seen[..] {
            [a] => *a = 0,
            [a, b] => (*a, *b) = (0, 0),
            seen => seen.fill(0),
        }
        Ok(FrameStep {
            writer: self,
            frame,
            slow,
            current,
        })
    }

    /// Flush the last step, write a closing time stamp at the current time
    /// (if it lies in the window and is later than the last one written) and
    /// return the output.
    pub fn finish(mut self) -> Result<E::Output> {
        self.flush_step()?;
        let closing =
            if self.dumped && self.in_window(self.time) && self.last_written != Some(self.time) {
                Some(self.time)
            } else {
                None
            };
        self.emitter.finish(closing)
    }

    fn type_mismatch(&self, i: usize, given: &'static str) -> WriteError {
        WriteError::TypeMismatch {
            name: self.vars[i].path.clone(),
            declared: self.vars[i].describe(),
            given,
        }
    }

    fn assign(&mut self, i: usize, v: Stored) -> Result<()> {
        let mut frames = self.var_frames[i];
        let mut in_frame = false;
        while frames != 0 {
            let k = frames.trailing_zeros() as usize;
            frames &= frames - 1;
            in_frame |= self.frame_steps[k] == self.step;
        }
        if self.assigned[i] == self.step || in_frame {
            return Err(self.double_change(i));
        }
        self.assigned[i] = self.step;
        self.single_step = self.step;
        if self.cur[i] != v {
            self.cur[i] = v;
            self.push_pending(i);
            // A variable of no frame (a real, say) leaves every frame holding the writer's
            // values, so the next dump of a frame keeps its fast path.
            if self.var_frames[i] != 0 {
                self.generation += 1;
            }
        }
        Ok(())
    }

    fn flush_step(&mut self) -> Result<()> {
        let t = self.time;
        if self.in_window(t) {
            if !self.dumped {
                self.write_dump(t)?;
            } else if self.npending > 0 {
                let pending = &mut self.pending[..self.npending];
                if !self.pending_sorted {
                    pending.sort_unstable();
                }
                self.emitter.timestamp(t)?;
                for &i in pending.iter() {
                    self.emitter
                        .value(i as usize, self.cur[i as usize].as_ref())?;
                }
                self.last_written = Some(t);
            }
        }
        self.npending = 0;
        self.pending_sorted = true;
        Ok(())
    }

    /// The error of variable `i` assigned a second time in the current step.
    #[cold]
    #[inline(never)]
    fn double_change(&self, i: usize) -> WriteError {
        WriteError::DoubleChange {
            name: self.vars[i].path.clone(),
            time: self.time,
        }
    }

    /// Note that variable `i` changed in this step.
    #[inline]
    fn push_pending(&mut self, i: usize) {
        let i = i as u32;
        self.pending_sorted &= self.npending == 0 || self.pending[self.npending - 1] < i;
        self.pending[self.npending] = i;
        self.npending += 1;
    }

    fn write_dump(&mut self, t: u64) -> Result<()> {
        self.emitter.dump_begin(t)?;
        for i in 0..self.vars.len() {
            self.emitter.value(i, self.cur[i].as_ref())?;
        }
        self.emitter.dump_end()?;
        self.dumped = true;
        self.last_written = Some(t);
        Ok(())
    }
}

/// `vcd::Writer` cannot give its inner writer back, so the header is written into this slot
/// from which [`VcdBuilder::start`] takes it.
struct Slot(Option<Vec<u8>>);

impl Write for Slot {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        match &mut self.0 {
            Some(w) => w.write(buf),
            None => Err(std::io::Error::other("VCD header already taken")),
        }
    }

    fn flush(&mut self) -> std::io::Result<()> {
        Ok(())
    }
}

#[cfg(test)]
mod real_text_tests {
    use super::format_real;

    /// The text of a real as `std::fmt` writes it: plain for 1e-4 <= |v| < 1e16, `{:e}`
    /// otherwise, `0` for zero (the simpler reference of [`super::real_text`]).
    fn by_fmt(v: f64) -> String {
        if v == 0.0 {
            "0".to_string()
        } else if (1e-4..1e16).contains(&v.abs()) {
            format!("{v}")
        } else {
            format!("{v:e}")
        }
    }

    /// The text of a real by `ryu` alone, as the writer wrote it before its grid path.
    fn by_ryu(v: f64) -> String {
        let a = v.abs();
        if v == 0.0 {
            "0".to_string()
        } else if (1e-4..1e16).contains(&a) {
            let mut b = ryu::Buffer::new();
            let s = b.format_finite(v);
            s.strip_suffix(".0").unwrap_or(s).to_string()
        } else if (1e-5..1e-4).contains(&a) {
            format!("{v:e}")
        } else {
            ryu::Buffer::new().format_finite(v).to_string()
        }
    }

    /// `zmij` against `ryu` in plain notation: doubles whose exact value lies halfway between
    /// two 17-digit texts (m·2^-k with an 18-digit expansion ending in 5), and a spread of
    /// dyadic and random values.
    #[test]
    fn zmij_as_ryu_in_plain_notation() {
        let (mut r, mut z) = (ryu::Buffer::new(), zmij::Buffer::new());
        let mut s: u64 = 0x9E37_79B9_7F4A_7C15;
        let mut next = move || {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            s
        };
        let mut ties = 0;
        for k in 1..=25u32 {
            let p5 = 5u128.pow(k);
            let (lo, hi) = (
                10u128.pow(17).div_ceil(p5),
                (10u128.pow(18) / p5).min(1 << 53),
            );
            for _ in 0..4_000 {
                let m = if lo < hi {
                    (lo + u128::from(next()) % (hi - lo)) | 1
                } else {
                    1
                };
                let v = m as f64 * 2f64.powi(-(k as i32));
                if m < hi && (m * p5) % 10 == 5 && (1e-4..1e16).contains(&v) {
                    ties += 1;
                    assert_eq!(z.format_finite(v), r.format_finite(v), "k {k} m {m}");
                }
            }
        }
        assert!(ties > 10_000, "{ties} halfway cases");
        for _ in 0..200_000 {
            let b = next();
            for v in [
                f64::from_bits(b),
                (b >> 11) as f64 * 2f64.powi(-((b % 61) as i32)),
                ((b % 20_000_000) as f64 - 1e7) * [1e-3, 1e-4][(b >> 63) as usize],
            ] {
                if (1e-4..1e16).contains(&v.abs()) {
                    assert_eq!(z.format_finite(v), r.format_finite(v), "{v:e}");
                }
            }
        }
    }

    #[test]
    fn grid_edges_as_ryu() {
        for v in [
            1e-4,
            -1e-4,
            0.000_1 + 1e-6,
            1e9 - 1e-6,
            999_999_999.999_999,
            1e9,
            0.5,
            1.0,
            -1.0,
            10.0,
            100.001,
            0.1 * 3.0,
            123_456.000_001,
            0.000_123,
            7.0e-4,
            1e-6,
            1234.0 + 1.0 / 16384.0,
        ] {
            assert_eq!(format_real(v), by_ryu(v), "{v:e}");
        }
        for m in 1..200_000i64 {
            for q in [1e-3, 1e-4] {
                let v = m as f64 * q;
                assert_eq!(format_real(v), by_ryu(v), "{v:e}");
                assert_eq!(format_real(-v), by_ryu(-v), "{v:e}");
            }
        }
    }

    #[test]
    fn edges_of_the_notations() {
        // a short dyadic fraction: its exact value needs 18 digits
        assert_eq!(
            format_real(1234.0 + 1.0 / 16384.0).parse::<f64>(),
            Ok(1234.0 + 1.0 / 16384.0)
        );
        for v in [
            1e-4,
            9.99e-5,
            1e-5,
            1.5e-5,
            9.9e-6,
            1e16,
            1e15,
            37.0,
            -37.0,
            0.001,
            -0.0001,
            1e300,
            5e-324,
            -1.25e-7,
            123456.789,
            f64::MAX,
            f64::MIN_POSITIVE,
        ] {
            assert_eq!(format_real(v), by_fmt(v), "{v:e}");
        }
        assert_eq!(format_real(-0.0), "0");
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig { cases: 20_000, failure_persistence: None, ..Default::default() })]

        /// Any finite real reads back as itself, as short as `std::fmt`'s text and in the same
        /// notation; the texts differ only where the double's exact value lies halfway between
        /// two 17-digit texts (`ryu` and `std::fmt` break that tie differently).
        #[test]
        fn any_finite_real_as_std_fmt(bits in proptest::prelude::any::<u64>()) {
            let v = f64::from_bits(bits);
            if v.is_finite() {
                let (a, b) = (format_real(v), by_fmt(v));
                proptest::prop_assert_eq!(a.parse::<f64>().ok(), Some(v + 0.0), "{} for {:e}", a, v);
                proptest::prop_assert!(a == b || (a.len() == b.len() && a.contains('e') == b.contains('e')), "{} against {}", a, b);
            }
        }

        /// Values on and near the grid of 1e-6 that the writer formats without `ryu`: the
        /// same text as `ryu`'s (doubles nearest to n·10^-d, products n·q as the analog values
        /// are rounded, their neighbours one unit in the last place away, random doubles).
        #[test]
        fn grid_values_as_ryu(n in -999_999_999_999_999i64..999_999_999_999_999, d in 0u32..=9, q in 0usize..4, ulps in -2i64..=2, bits in proptest::prelude::any::<u64>()) {
            let p = 10f64.powi(d as i32);
            let on = n as f64 / p;
            let product = (n % 10_000_000_000) as f64 * [1e-3, 1e-4, 1e-6, 0.1][q];
            for v in [on, product, f64::from_bits((on.to_bits() as i64 + ulps) as u64), f64::from_bits((product.to_bits() as i64 + ulps) as u64), f64::from_bits(bits)] {
                if v.is_finite() {
                    proptest::prop_assert_eq!(format_real(v), by_ryu(v), "{:e}", v);
                }
            }
        }

        #[test]
        fn rounded_analog_values_as_std_fmt(n in -10_000_000i64..10_000_000, q in 0usize..2) {
            let v = ((n as f64 * [1e-3, 1e-4][q]) / [1e-3, 1e-4][q]).round() * [1e-3, 1e-4][q];
            proptest::prop_assert_eq!(format_real(v), by_fmt(v));
        }
    }
}

/// The frame steps that a frame run takes where it cannot be direct ([`Writer::frame_step`],
/// private: the library's callers step frames through `dump_frame`, `frame_run` and
/// `text_run`).
#[cfg(test)]
mod frame_step_tests {
    use super::{BitType, Logic, VcdBuilder, VcdWriter, WriteError};
    use crate::{TimeUnit, Timescale};

    fn text(w: VcdWriter<Vec<u8>>) -> String {
        String::from_utf8(w.finish().unwrap()).unwrap()
    }

    /// `pmu50.a` (a bit), `tmr` (16 bits), `w` (5 bits, 3), `wide` (64 bits), `z` (a bit, `x`).
    fn frame_builder() -> (VcdBuilder, Vec<super::SigId>) {
        let mut b = VcdBuilder::new(Timescale::new(1, TimeUnit::Us), "pmu50-waves test").unwrap();
        b.push_scope("pmu50").unwrap();
        let vectors = [
            (BitType::Reg, "tmr", 15, 0),
            (BitType::Reg, "w", 4, 3),
            (BitType::Wire, "wide", 63, 0),
        ];
        let mut ids = vec![b.add_bit(BitType::Wire, "a", Logic::Zero).unwrap()];
        ids.extend(
            vectors.map(|(ty, name, msb, init)| b.add_vector(ty, name, msb, 0, init).unwrap()),
        );
        ids.push(b.add_bit(BitType::Reg, "z", Logic::X).unwrap());
        b.pop_scope().unwrap();
        (b, ids)
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig { cases: 200, failure_persistence: None, ..Default::default() })]

        /// A frame step that sets some positions writes exactly what `dump_frame` writes with those
        /// values and the current value at every other position; a single change of a variable
        /// of no frame in between leaves the step current (only the first step is not).
        #[test]
        fn frame_steps_equal_dump_frame(steps in proptest::collection::vec((1u64..3, proptest::array::uniform4(proptest::option::of(0u64..4)), proptest::prelude::any::<bool>()), 0..60)) {
            let (b1, ids1) = frame_builder();
            let (b2, ids2) = frame_builder();
            let mut w1 = b1.start(Vec::new()).unwrap();
            let mut w2 = b2.start(Vec::new()).unwrap();
            let mut f1 = w1.frame(&ids1[..4]).unwrap();
            let mut f2 = w2.frame(&ids2[..4]).unwrap();
            let mut cur = [0u64, 0, 3, 0];
            let mut t = 0;
            let mut changed_outside = true;
            let mut zv = false;
            for (dt, set, z) in steps {
                t += dt;
                let mut s = w2.frame_step(&mut f2, t).unwrap();
                proptest::prop_assert_eq!(s.is_current(), !changed_outside);
                for (k, v) in set.iter().enumerate() {
                    if let Some(v) = v {
                        let v = [v & 1, v * 1000, v * 7, v << 60][k];
                        s.set(k, v).unwrap();
                        cur[k] = v;
                    }
                }
                w1.dump_frame(&mut f1, t, &cur).unwrap();
                // a change (the value alternates) of the variable of no frame
                changed_outside = false;
                if z {
                    zv = !zv;
                    w1.change_bool(ids1[4], zv).unwrap();
                    w2.change_bool(ids2[4], zv).unwrap();
                }
            }
            proptest::prop_assert_eq!(text(w1), text(w2));
        }
    }

    #[test]
    fn frame_steps_keep_every_check() {
        let (b, ids) = frame_builder();
        let mut w = b.start(Vec::new()).unwrap();
        let mut f = w.frame(&ids[..3]).unwrap();
        let mut g = w.frame(&ids[2..4]).unwrap();
        {
            let mut s = w.frame_step(&mut f, 1).unwrap();
            assert!(!s.is_current(), "a frame's first step is not current");
            s.set(1, 7).unwrap();
            // a position outside the frame, named with the frame's length
            let e = s.set(3, 1).unwrap_err();
            assert!(
                matches!(
                    e,
                    WriteError::FramePosition {
                        position: 3,
                        len: 3
                    }
                ),
                "{e}"
            );
            assert!(e.to_string().contains("0..3"), "{e}");
            // the same position twice in one step
            let e = s.set(1, 8).unwrap_err();
            assert!(
                matches!(&e, WriteError::DoubleChange { name, .. } if name == "pmu50.tmr"),
                "{e}"
            );
            // a changed value wider than the variable: 5-bit `w` takes at most 31, nothing assigned
            let e = s.set(2, 32).unwrap_err();
            assert!(
                matches!(
                    e,
                    WriteError::ValueTooWide {
                        value: 32,
                        max: 31,
                        ..
                    }
                ),
                "{e}"
            );
            // the refused position may still be given a value in the step (here its current one)
            s.set(2, 3).unwrap();
        }
        // a single change of a frame variable in the frame's step is a double assignment
        assert!(matches!(
            w.change_vector(ids[0], 1),
            Err(WriteError::DoubleChange { .. })
        ));
        // an overlapping frame in the same step
        assert!(matches!(
            w.frame_step(&mut g, 1),
            Err(WriteError::DoubleChange { .. })
        ));
        // time backwards
        assert!(matches!(
            w.frame_step(&mut f, 0),
            Err(WriteError::TimeBackwards { .. })
        ));
        // a single change first, then the frame, in one step
        w.set_time(2).unwrap();
        w.change_vector(ids[1], 9).unwrap();
        assert!(matches!(
            w.frame_step(&mut f, 2),
            Err(WriteError::DoubleChange { .. })
        ));
        // a frame of another writer
        let (b2, ids2) = frame_builder();
        let mut other = b2.start(Vec::new()).unwrap();
        let mut f2 = other.frame(&ids2[..1]).unwrap();
        assert!(matches!(
            w.frame_step(&mut f2, 3),
            Err(WriteError::UnknownFrame)
        ));
        // later steps: a step with nothing set keeps every value (and writes nothing)
        w.frame_step(&mut f, 3).unwrap();
        let mut s = w.frame_step(&mut f, 4).unwrap();
        assert!(s.is_current());
        s.set(0, 1).unwrap();
        let got = text(w);

        let (b, ids) = frame_builder();
        let mut r = b.start(Vec::new()).unwrap();
        for (t, ch) in [(1, vec![(1, 7)]), (2, vec![(1, 9)]), (4, vec![(0, 1)])] {
            r.set_time(t).unwrap();
            for (k, v) in ch {
                r.change_vector(ids[k], v).unwrap();
            }
        }
        let want = text(r);
        assert_eq!(got, want);
    }

    /// A frame variable that holds `x` from a single change: the next frame step compares with the
    /// writer's value, so setting the integer it had before is a change, not a repeat.
    #[test]
    fn frame_steps_after_four_state_values() {
        let (b, ids) = frame_builder();
        let mut w = b.start(Vec::new()).unwrap();
        let mut f = w.frame(&ids[..3]).unwrap();
        w.frame_step(&mut f, 1).unwrap().set(2, 5).unwrap();
        w.set_time(2).unwrap();
        w.change_bits(ids[2], "x0x0x").unwrap();
        let mut s = w.frame_step(&mut f, 3).unwrap();
        assert!(!s.is_current());
        s.set(2, 5).unwrap();
        // and a step that leaves it out keeps `x`
        w.set_time(4).unwrap();
        w.change_bits(ids[2], "xxxxx").unwrap();
        w.frame_step(&mut f, 5).unwrap().set(0, 1).unwrap();
        let vcd = text(w);
        assert!(
            vcd.contains("#2\nbx0x0x #\n#3\nb00101 #\n#4\nbxxxxx #\n#5\n1!\n"),
            "{vcd}"
        );
    }
}
