//! Read a VCD back with `wellen`, independently of [`crate::writer`].
//!
//! [`Waveform`] lists every variable by full hierarchical path with width and
//! kind, gives the file's timescale, and returns each signal's value changes
//! as `(time, Value)` in file time units, in file order. wellen drops a value
//! that repeats the signal's previous value, so the list holds changes only;
//! it cannot be used to check that a file contains no redundant value lines.
//!
//! ```
//! use pmu50_waves::reader::Waveform;
//! use pmu50_waves::Value;
//!
//! let vcd = "$timescale 1 us $end\n$scope module top $end\n\
//!            $var wire 4 ! cnt [3:0] $end\n$upscope $end\n$enddefinitions $end\n\
//!            #0\nb0011 !\n#5\nb0100 !\n";
//! let wave = Waveform::from_bytes(vcd.as_bytes().to_vec()).unwrap();
//! assert_eq!(wave.signals()[0].gtkwave_name(), "top.cnt[3:0]");
//! let ch = wave.changes("top.cnt").unwrap();
//! assert_eq!(ch[1], (5, Value::Bits("0100".into())));
//! ```

use std::io::Cursor;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::{Path, PathBuf};

use thiserror::Error;
use wellen::{SignalEncoding, SignalRef, SignalValueRef};

use crate::time::{TimeUnit, Timescale};

/// One value of a signal.
#[derive(Debug, Clone, PartialEq)]
pub enum Value {
    /// Bit-vector value, one character per bit, msb first (`0 1 x z`; VHDL
    /// files may also contain `h u w l -`). Single-bit signals have one character.
    Bits(String),
    /// `real` value.
    Real(f64),
    /// `string` variable value (never produced by [`crate::writer`]).
    Text(String),
}

impl std::fmt::Display for Value {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Value::Bits(b) => f.write_str(b),
            Value::Real(r) => write!(f, "{r}"),
            Value::Text(s) => write!(f, "{s:?}"),
        }
    }
}

/// What kind of values a signal carries.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum SignalKind {
    /// bit or bit vector (`Value::Bits`)
    Bits,
    /// real (`Value::Real`)
    Real,
    /// string (`Value::Text`)
    Text,
}

impl std::fmt::Display for SignalKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            SignalKind::Bits => "bit vector",
            SignalKind::Real => "real",
            SignalKind::Text => "string",
        })
    }
}

/// One declared variable.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SignalInfo {
    /// Full dotted path without bit range (`pmu50.drive_interval.si`).
    pub path: String,
    /// Declared `[msb:lsb]` (or `[i]` as `(i, i)`), if any.
    pub index: Option<(i64, i64)>,
    /// Width in bits (64 for reals, 0 for strings).
    pub width: u32,
    /// Kind of values.
    pub kind: SignalKind,
    /// Declared type keyword in lower case (`wire`, `reg`, `real`, `integer`, ...).
    pub var_type: String,
}

impl SignalInfo {
    /// GTKWave's name: the path plus `[msb:lsb]` for vectors (`[i]` for bit selects).
    pub fn gtkwave_name(&self) -> String {
        match self.index {
            Some((m, l)) if m == l => format!("{}[{}]", self.path, m),
            Some((m, l)) => format!("{}[{}:{}]", self.path, m, l),
            None => self.path.clone(),
        }
    }
}

/// Errors while reading a waveform.
#[derive(Debug, Error)]
pub enum ReadError {
    /// File could not be opened.
    #[error("cannot open waveform file {path}: {source}")]
    Open {
        /// the path
        path: PathBuf,
        /// the I/O error
        source: std::io::Error,
    },
    /// wellen rejected the input.
    #[error("cannot parse waveform {origin}: {message} (expected a VCD file with $timescale, $scope/$var declarations and $enddefinitions)")]
    Parse {
        /// file path or `<memory>`
        origin: String,
        /// wellen's message
        message: String,
    },
    /// The file declares a unit outside s..fs.
    #[error("{origin} declares an unsupported timescale unit ({unit}); supported: s, ms, us, ns, ps, fs")]
    UnsupportedTimescale {
        /// file path or `<memory>`
        origin: String,
        /// the unit as wellen reported it
        unit: String,
    },
    /// `changes` was asked for a name the file does not declare.
    #[error("no signal named `{name}` in {origin}; use the full dotted path (e.g. `top.sub.sig`) or GTKWave's name with range (`top.sub.vec[7:0]`)")]
    UnknownSignal {
        /// the requested name
        name: String,
        /// file path or `<memory>`
        origin: String,
    },
}

/// A fully loaded waveform file.
pub struct Waveform {
    origin: String,
    inner: wellen::simple::Waveform,
    signals: Vec<SignalInfo>,
    refs: Vec<SignalRef>,
    timescale: Option<Timescale>,
}

impl std::fmt::Debug for Waveform {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Waveform")
            .field("origin", &self.origin)
            .field("timescale", &self.timescale)
            .field("signals", &self.signals.len())
            .finish_non_exhaustive()
    }
}

fn panic_message(p: Box<dyn std::any::Any + Send>) -> String {
    if let Some(s) = p.downcast_ref::<&str>() {
        format!("parser panicked: {s}")
    } else if let Some(s) = p.downcast_ref::<String>() {
        format!("parser panicked: {s}")
    } else {
        "parser panicked".to_string()
    }
}

impl Waveform {
    /// Read a waveform file (VCD; wellen also accepts FST and GHW).
    pub fn open(path: impl AsRef<Path>) -> Result<Self, ReadError> {
        let path = path.as_ref();
        let bytes = std::fs::read(path).map_err(|source| ReadError::Open {
            path: path.to_path_buf(),
            source,
        })?;
        Self::load(bytes, path.display().to_string())
    }

    /// Read a waveform held in memory.
    pub fn from_bytes(bytes: Vec<u8>) -> Result<Self, ReadError> {
        Self::load(bytes, "<memory>".to_string())
    }

    fn load(bytes: Vec<u8>, origin: String) -> Result<Self, ReadError> {
        let parse_err = |message: String| ReadError::Parse {
            origin: origin.clone(),
            message,
        };
        let read = catch_unwind(AssertUnwindSafe(|| {
            wellen::simple::read_from_reader(Cursor::new(bytes))
        }));
        let mut inner = match read {
            Ok(Ok(w)) => w,
            Ok(Err(e)) => return Err(parse_err(e.to_string())),
            Err(p) => return Err(parse_err(panic_message(p))),
        };
        let h = inner.hierarchy();
        let timescale = match h.timescale() {
            None => None,
            Some(ts) => {
                let unit = ts
                    .unit
                    .to_exponent()
                    .and_then(|e| TimeUnit::from_exponent(i32::from(e)))
                    .ok_or_else(|| ReadError::UnsupportedTimescale {
                        origin: origin.clone(),
                        unit: format!("{:?}", ts.unit),
                    })?;
                Some(Timescale::new(ts.factor, unit))
            }
        };
        let mut signals = Vec::new();
        let mut refs = Vec::new();
        for vr in h.all_vars() {
            let v = &h[vr];
            let (kind, width) = match v.signal_encoding(h) {
                SignalEncoding::BitVector(w) => (SignalKind::Bits, w),
                SignalEncoding::Real => (SignalKind::Real, 64),
                SignalEncoding::String => (SignalKind::Text, 0),
            };
            signals.push(SignalInfo {
                path: v.full_name(h),
                index: v.index().map(|i| (i.msb(), i.lsb())),
                width,
                kind,
                var_type: format!("{:?}", v.var_type()).to_lowercase(),
            });
            refs.push(v.signal_ref());
        }
        let mut unique = refs.clone();
        unique.sort_unstable();
        unique.dedup();
        let loaded = catch_unwind(AssertUnwindSafe(|| inner.load_signals(&unique)));
        if let Err(p) = loaded {
            return Err(parse_err(panic_message(p)));
        }
        Ok(Waveform {
            origin,
            inner,
            signals,
            refs,
            timescale,
        })
    }

    /// The file's `$timescale`, or `None` if it declares none.
    pub fn timescale(&self) -> Option<Timescale> {
        self.timescale
    }

    /// All variables in declaration order.
    pub fn signals(&self) -> &[SignalInfo] {
        &self.signals
    }

    /// Last time stamp in the file (0 for a file without time stamps).
    pub fn end_time(&self) -> u64 {
        self.inner.time_table().last().copied().unwrap_or(0)
    }

    /// Index into [`Waveform::signals`] of `name`, given as full path
    /// (`top.sig`) or as GTKWave name with range (`top.vec[7:0]`).
    pub fn find(&self, name: &str) -> Option<usize> {
        self.signals
            .iter()
            .position(|s| s.path == name)
            .or_else(|| self.signals.iter().position(|s| s.gtkwave_name() == name))
    }

    /// Value changes of `name` (see [`Waveform::find`]) in file order, with
    /// times in file timescale units.
    pub fn changes(&self, name: &str) -> Result<Vec<(u64, Value)>, ReadError> {
        match self.find(name) {
            Some(i) => Ok(self.changes_at(i)),
            None => Err(ReadError::UnknownSignal {
                name: name.to_string(),
                origin: self.origin.clone(),
            }),
        }
    }

    /// Value changes of the `i`-th signal of [`Waveform::signals`]; empty if
    /// `i` is out of range.
    pub fn changes_at(&self, i: usize) -> Vec<(u64, Value)> {
        let Some(r) = self.refs.get(i) else {
            return Vec::new();
        };
        let Some(sig) = self.inner.get_signal(*r) else {
            return Vec::new();
        };
        let tt = self.inner.time_table();
        let mut out = Vec::with_capacity(sig.time_indices().len());
        for (ti, v) in sig.iter_changes() {
            let Some(t) = tt.get(ti as usize) else {
                continue;
            };
            let value = match v {
                SignalValueRef::BitVec(_) => {
                    Value::Bits(v.to_bit_string().unwrap_or_default().to_ascii_lowercase())
                }
                SignalValueRef::Real(r) => Value::Real(r),
                SignalValueRef::String(s) => Value::Text(s.to_string()),
                SignalValueRef::Event => Value::Bits("1".to_string()),
            };
            out.push((*t, value));
        }
        out
    }

    /// Where the waveform came from (file path or `<memory>`), for messages.
    pub fn origin(&self) -> &str {
        &self.origin
    }
}
