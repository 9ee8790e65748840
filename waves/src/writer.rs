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
use vcd::{IdCode, ReferenceIndex, SimulationCommand, VarType};

use crate::time::Timescale;

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
    /// Underlying I/O failure.
    #[error("I/O error while writing the VCD: {0}")]
    Io(#[from] std::io::Error),
}

type Result<T> = std::result::Result<T, WriteError>;

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
pub(crate) fn format_real(v: f64) -> String {
    if v == 0.0 {
        return "0".to_string();
    }
    let a = v.abs();
    if (1e-4..1e16).contains(&a) {
        format!("{v}")
    } else {
        format!("{v:e}")
    }
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

    /// Write the header to `out` and switch to the value-change phase.
    pub fn start<W: Write>(self, out: W) -> Result<VcdWriter<W>> {
        if !self.stack.is_empty() {
            return Err(WriteError::UnclosedScopes {
                open: self.stack.len(),
                innermost: self.scope_path(),
            });
        }
        if self.vars.is_empty() {
            return Err(WriteError::NoVariables);
        }
        let mut w = vcd::Writer::new(Slot(Some(std::io::BufWriter::new(out))));
        w.version(&self.version)?;
        w.timescale(self.timescale.factor, self.timescale.unit.to_vcd())?;
        let mut codes = vec![IdCode::FIRST; self.vars.len()];
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
                    codes[*i] = next;
                    next = next.next();
                }
            }
        }
        w.enddefinitions()?;
        let n = self.vars.len();
        Ok(VcdWriter {
            w,
            owner: self.owner,
            vars: self.vars,
            codes,
            cur: self.init,
            assigned: vec![0; n],
            pending: Vec::new(),
            time: 0,
            step: 1,
            window: self.window,
            dumped: false,
            last_written: None,
        })
    }
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

/// Dumps value changes; created by [`VcdBuilder::start`]. Call
/// [`VcdWriter::finish`] at the end or the last time step is lost.
/// Output is buffered internally; pass a plain `File`.
pub struct VcdWriter<W: Write> {
    w: vcd::Writer<Slot<W>>,
    owner: u32,
    vars: Vec<VarDecl>,
    codes: Vec<IdCode>,
    cur: Vec<Stored>,
    /// step number of the last assignment per variable (0 = never)
    assigned: Vec<u64>,
    /// variables whose value changed in the current step
    pending: Vec<usize>,
    time: u64,
    step: u64,
    window: (u64, u64),
    dumped: bool,
    last_written: Option<u64>,
}

impl<W: Write> std::fmt::Debug for VcdWriter<W> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("VcdWriter")
            .field("time", &self.time)
            .field("variables", &self.vars.len())
            .field("window", &self.window)
            .field("dumped", &self.dumped)
            .finish_non_exhaustive()
    }
}

impl<W: Write> VcdWriter<W> {
    /// Current simulation time (timescale units).
    pub fn time(&self) -> u64 {
        self.time
    }

    /// GTKWave's name for a variable (see [`VcdBuilder::gtkwave_name`]).
    pub fn gtkwave_name(&self, id: SigId) -> Result<String> {
        let i = self.index(id)?;
        Ok(self.vars[i].gtkwave_name())
    }

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
    pub fn set_time(&mut self, t: u64) -> Result<()> {
        if t < self.time {
            return Err(WriteError::TimeBackwards {
                requested: t,
                current: self.time,
            });
        }
        if t == self.time {
            return Ok(());
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
        let i = self.index(id)?;
        match self.vars[i].kind {
            Kind::Bits { width: 1, .. } => self.assign(i, canon_bits(vec![v.as_byte()])),
            Kind::Bits { width, .. } => Err(WriteError::WrongWidth {
                name: self.vars[i].path.clone(),
                expected: width,
                got: 1,
            }),
            Kind::Real => Err(self.type_mismatch(i, "bit")),
        }
    }

    /// Change a one-bit variable from a `bool`.
    pub fn change_bool(&mut self, id: SigId, v: bool) -> Result<()> {
        self.change_bit(id, Logic::from(v))
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

    /// Flush the last step, write a closing time stamp at the current time
    /// (if it lies in the window and is later than the last one written) and
    /// return the output.
    pub fn finish(mut self) -> Result<W> {
        self.flush_step()?;
        if self.dumped && self.in_window(self.time) && self.last_written != Some(self.time) {
            self.w.timestamp(self.time)?;
        }
        self.w.flush()?;
        match self.w.writer().0.take() {
            Some(buf) => buf.into_inner().map_err(|e| WriteError::Io(e.into_error())),
            None => Err(WriteError::Io(std::io::Error::other(
                "VCD output already taken",
            ))),
        }
    }

    fn type_mismatch(&self, i: usize, given: &'static str) -> WriteError {
        WriteError::TypeMismatch {
            name: self.vars[i].path.clone(),
            declared: self.vars[i].describe(),
            given,
        }
    }

    fn assign(&mut self, i: usize, v: Stored) -> Result<()> {
        if self.assigned[i] == self.step {
            return Err(WriteError::DoubleChange {
                name: self.vars[i].path.clone(),
                time: self.time,
            });
        }
        self.assigned[i] = self.step;
        if self.cur[i] != v {
            self.cur[i] = v;
            self.pending.push(i);
        }
        Ok(())
    }

    fn flush_step(&mut self) -> Result<()> {
        let t = self.time;
        if self.in_window(t) {
            if !self.dumped {
                self.write_dump(t)?;
            } else if !self.pending.is_empty() {
                self.pending.sort_unstable();
                self.w.timestamp(t)?;
                for k in 0..self.pending.len() {
                    let i = self.pending[k];
                    self.write_value(i)?;
                }
                self.last_written = Some(t);
            }
        }
        self.pending.clear();
        Ok(())
    }

    fn write_dump(&mut self, t: u64) -> Result<()> {
        self.w.timestamp(t)?;
        self.w.begin(SimulationCommand::Dumpvars)?;
        for i in 0..self.vars.len() {
            self.write_value(i)?;
        }
        self.w.end()?;
        self.dumped = true;
        self.last_written = Some(t);
        Ok(())
    }

    fn write_value(&mut self, i: usize) -> Result<()> {
        let code = self.codes[i];
        let width = self.vars[i].width();
        let is_real = matches!(self.vars[i].kind, Kind::Real);
        let out = self.w.writer();
        match &self.cur[i] {
            Stored::Real(v) => writeln!(out, "r{} {}", format_real(*v), code)?,
            Stored::Int(v) if width == 1 && !is_real => writeln!(out, "{}{}", v & 1, code)?,
            Stored::Int(v) => {
                let bits = int_to_bits(*v, width);
                out.write_all(b"b")?;
                out.write_all(&bits)?;
                writeln!(out, " {code}")?;
            }
            Stored::Bits(bits) if width == 1 => {
                out.write_all(bits)?;
                writeln!(out, "{code}")?;
            }
            Stored::Bits(bits) => {
                out.write_all(b"b")?;
                out.write_all(bits)?;
                writeln!(out, " {code}")?;
            }
        }
        Ok(())
    }
}

/// `vcd::Writer` cannot give its inner writer back, so it writes into this
/// buffered slot from which [`VcdWriter::finish`] takes the output.
struct Slot<W: Write>(Option<std::io::BufWriter<W>>);

impl<W: Write> Write for Slot<W> {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        match &mut self.0 {
            Some(w) => w.write(buf),
            None => Err(std::io::Error::other("VCD output already taken")),
        }
    }

    fn write_all(&mut self, buf: &[u8]) -> std::io::Result<()> {
        match &mut self.0 {
            Some(w) => w.write_all(buf),
            None => Err(std::io::Error::other("VCD output already taken")),
        }
    }

    fn flush(&mut self) -> std::io::Result<()> {
        match &mut self.0 {
            Some(w) => w.flush(),
            None => Ok(()),
        }
    }
}
