//! Read a VCD back with `wellen`, independently of [`crate::writer`].
//!
//! Every input first passes [`crate::validate`] (one streaming pass): a file
//! `wellen` would panic on, warn about or silently misread is refused with its
//! line ([`ReadError::Malformed`]). [`Waveform::open_with`] also refuses
//! anything but a regular file and files over [`ReadLimits::max_file_bytes`]
//! (2 GiB by default); `$var` sizes above [`ReadLimits::max_var_width`] (65 536
//! bits) are refused before anything is allocated for them. FST is read too: a
//! file whose first byte is FST's header block type (0, `FST_BL_HDR`) and that
//! wellen's own detection calls FST skips the VCD validator and goes straight to
//! wellen (GHW is not read). wellen runs single-threaded
//! under a panic guard, so even a validator gap prints nothing and becomes
//! [`ReadError::ParserPanicked`].
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

use std::io::{Cursor, Read};
use std::path::{Path, PathBuf};

use std::collections::HashMap;
use thiserror::Error;
use wellen::{
    Hierarchy, LoadOptions, Signal, SignalEncoding, SignalRef, SignalSource, SignalValueRef,
};

use crate::guard::quietly;
use crate::time::{TimeUnit, Timescale};
use crate::validate::{validate, ValidateError};

/// Default bound on the size of a waveform file: 2 GiB.
pub const DEFAULT_MAX_FILE_BYTES: u64 = 2 << 30;

/// Default bound on a declared `$var` size: 65 536 bits (IEEE 1364-2005 §6.1.1
/// lets tools limit vectors to 2^16 bits; no file of this project comes near).
pub const DEFAULT_MAX_VAR_WIDTH: u32 = 1 << 16;

/// What the reader refuses before it allocates anything in proportion to a
/// declaration: files larger than `max_file_bytes`, `$var` sizes above
/// `max_var_width`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ReadLimits {
    /// Largest file accepted, in bytes ([`DEFAULT_MAX_FILE_BYTES`]).
    pub max_file_bytes: u64,
    /// Largest declared width accepted, in bits ([`DEFAULT_MAX_VAR_WIDTH`]).
    pub max_var_width: u32,
}

impl Default for ReadLimits {
    fn default() -> Self {
        ReadLimits {
            max_file_bytes: DEFAULT_MAX_FILE_BYTES,
            max_var_width: DEFAULT_MAX_VAR_WIDTH,
        }
    }
}

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
    /// File could not be opened or read.
    #[error("cannot open waveform file {path}: {source}")]
    Open {
        /// the path
        path: PathBuf,
        /// the I/O error
        source: std::io::Error,
    },
    /// The path is a directory, FIFO, device or socket.
    #[error("{path} is a {kind}, not a regular file; give the path of a VCD file")]
    NotRegular {
        /// the path
        path: PathBuf,
        /// what it is instead (`directory`, `FIFO`, `character device`, ...)
        kind: &'static str,
    },
    /// The input is larger than [`ReadLimits::max_file_bytes`].
    #[error("{origin} is {size} bytes, more than the limit of {limit} bytes; raise the limit (`pmu50 diff --max-bytes N`) if the file really is this large")]
    TooLarge {
        /// file path or `<memory>`
        origin: String,
        /// its size in bytes (at least; a growing file may be larger)
        size: u64,
        /// the limit
        limit: u64,
    },
    /// The validator refused the file: what is wrong and on which line.
    #[error("{origin}:{line}: malformed VCD: {what}")]
    Malformed {
        /// file path or `<memory>`
        origin: String,
        /// 1-based line
        line: u64,
        /// what is wrong
        what: String,
    },
    /// wellen rejected a file the validator accepted.
    #[error("cannot parse waveform {origin}: {message} (expected a VCD file with $timescale, $scope/$var declarations and $enddefinitions)")]
    Parse {
        /// file path or `<memory>`
        origin: String,
        /// wellen's message
        message: String,
    },
    /// An FST (first byte 0) that wellen cannot read, or panicked on: damaged or unfinished.
    #[error("cannot read FST {origin}: {message} (the file is damaged or was not finished; an FST is complete only when the run that wrote it ended)")]
    BadFst {
        /// file path or `<memory>`
        origin: String,
        /// wellen's message, on one line
        message: String,
    },
    /// wellen panicked on an FST that passed [`crate::fst_check`] (a gap in the checks: the
    /// fuzz target `fst_read` treats this as a failure); the panic was caught and printed nothing.
    #[error("cannot read FST {origin}: the FST reader failed ({message}); the file is damaged (please report this with the file)")]
    FstReaderPanicked {
        /// file path or `<memory>`
        origin: String,
        /// the panic message, on one line
        message: String,
    },
    /// wellen panicked on a file the validator accepted (a validator gap: the
    /// fuzz targets treat this as a failure).
    #[error("{origin}: the VCD parser failed on a file that passed validation ({message}); please report this with the file")]
    ParserPanicked {
        /// file path or `<memory>`
        origin: String,
        /// the panic message
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

/// The FST's hierarchy against its checked geometry: every variable's handle exists, its width
/// is the geometry's, within the limit the check applied.
fn check_fst_hierarchy(h: &Hierarchy, layout: &crate::fst_check::FstLayout) -> Result<(), String> {
    for vr in h.all_vars() {
        let v = &h[vr];
        let handle = v.signal_ref().index();
        let name = v.full_name(h);
        let Some(&geo) = layout.widths.get(handle) else {
            return Err(format!(
                "variable {name} has signal handle {}, the geometry declares {}",
                handle + 1,
                layout.widths.len()
            ));
        };
        match (v.signal_encoding(h), geo) {
            (SignalEncoding::BitVector(w), Some(g)) if w == g => {}
            (SignalEncoding::Real, None) | (SignalEncoding::String, Some(0)) => {}
            (enc, g) => {
                let geo = g.map_or("a real".to_string(), |g| format!("{g} bits"));
                let hier = match enc {
                    SignalEncoding::BitVector(w) => format!("{w} bits"),
                    SignalEncoding::Real => "a real".into(),
                    SignalEncoding::String => "a string".into(),
                };
                return Err(format!("variable {name} is {hier} in the hierarchy but {geo} in the geometry (signal handle {})", handle + 1));
            }
        }
    }
    Ok(())
}

/// A fully loaded waveform file.
pub struct Waveform {
    origin: String,
    data: HashMap<SignalRef, Signal>,
    time_table: Vec<u64>,
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

/// True when `bytes` start like an FST file: the first block is the header block, block type 0
/// (`FST_BL_HDR`). Text (VCD) never starts with a NUL byte.
pub fn is_fst(bytes: &[u8]) -> bool {
    bytes.first() == Some(&0)
}

/// What a path is, when it is not a regular file.
fn file_kind(ft: std::fs::FileType) -> &'static str {
    use std::os::unix::fs::FileTypeExt;
    if ft.is_dir() {
        "directory"
    } else if ft.is_fifo() {
        "FIFO"
    } else if ft.is_char_device() {
        "character device"
    } else if ft.is_block_device() {
        "block device"
    } else if ft.is_socket() {
        "socket"
    } else {
        "special file"
    }
}

impl Waveform {
    /// Read a VCD file with the default [`ReadLimits`].
    pub fn open(path: impl AsRef<Path>) -> Result<Self, ReadError> {
        Self::open_with(path, &ReadLimits::default())
    }

    /// Read a VCD file. Refuses anything but a regular file (checked before
    /// opening, so a FIFO never blocks) and files over `limits.max_file_bytes`.
    pub fn open_with(path: impl AsRef<Path>, limits: &ReadLimits) -> Result<Self, ReadError> {
        let path = path.as_ref();
        let open_err = |source| ReadError::Open {
            path: path.to_path_buf(),
            source,
        };
        let not_regular = |ft| ReadError::NotRegular {
            path: path.to_path_buf(),
            kind: file_kind(ft),
        };
        let origin = path.display().to_string();
        let too_large = |size| ReadError::TooLarge {
            origin: origin.clone(),
            size,
            limit: limits.max_file_bytes,
        };
        let meta = std::fs::metadata(path).map_err(open_err)?;
        if !meta.is_file() {
            return Err(not_regular(meta.file_type()));
        }
        if meta.len() > limits.max_file_bytes {
            return Err(too_large(meta.len()));
        }
        let file = std::fs::File::open(path).map_err(open_err)?;
        // the path may have been replaced between the two looks
        let meta = file.metadata().map_err(open_err)?;
        if !meta.is_file() {
            return Err(not_regular(meta.file_type()));
        }
        if meta.len() > limits.max_file_bytes {
            return Err(too_large(meta.len()));
        }
        let mut bytes = Vec::with_capacity(usize::try_from(meta.len()).unwrap_or(0));
        file.take(limits.max_file_bytes.saturating_add(1))
            .read_to_end(&mut bytes)
            .map_err(open_err)?;
        if bytes.len() as u64 > limits.max_file_bytes {
            return Err(too_large(bytes.len() as u64));
        }
        Self::load(bytes, origin, limits)
    }

    /// Read a VCD held in memory with the default [`ReadLimits`].
    pub fn from_bytes(bytes: Vec<u8>) -> Result<Self, ReadError> {
        Self::from_bytes_with(bytes, &ReadLimits::default())
    }

    /// Read a VCD held in memory.
    pub fn from_bytes_with(bytes: Vec<u8>, limits: &ReadLimits) -> Result<Self, ReadError> {
        if bytes.len() as u64 > limits.max_file_bytes {
            return Err(ReadError::TooLarge {
                origin: "<memory>".into(),
                size: bytes.len() as u64,
                limit: limits.max_file_bytes,
            });
        }
        Self::load(bytes, "<memory>".to_string(), limits)
    }

    fn load(bytes: Vec<u8>, origin: String, limits: &ReadLimits) -> Result<Self, ReadError> {
        // An FST starts with its header block, block type 0 (FST_BL_HDR); a VCD is text and never
        // starts with a NUL byte. FST goes to wellen directly (under the panic guard below), once
        // wellen's own detection agrees that it is an FST.
        if is_fst(&bytes) {
            // Sizes and counts first: fst-reader allocates whatever a block declares, and its
            // format detection alone loops for minutes on a damaged header length.
            let layout =
                crate::fst_check::check(&bytes, limits.max_file_bytes, limits.max_var_width)
                    .map_err(|p| ReadError::BadFst {
                        origin: origin.clone(),
                        message: p.to_string(),
                    })?;
            let fst = quietly(|| {
                wellen::viewers::detect_file_format(&mut Cursor::new(bytes.as_slice()))
                    == wellen::FileFormat::Fst
            });
            if fst != Ok(true) {
                return Err(ReadError::BadFst { origin, message: "it starts like an FST (block type 0, FST_BL_HDR) but its header block is not valid".into() });
            }
            // wellen sizes a table by the largest signal handle of the hierarchy (an alias may
            // name any handle): every handle must be one the geometry declares.
            let handles = layout.widths.len();
            let hier = quietly(|| -> Result<Option<String>, String> {
                let mut r = fst_reader::FstReader::open(Cursor::new(bytes.as_slice()))
                    .map_err(|e| e.to_string())?;
                let mut bad = None;
                r.read_hierarchy(|e| {
                    if let fst_reader::FstHierarchyEntry::Var { handle, name, .. } = e {
                        if bad.is_none() && handle.get_index() >= handles {
                            bad = Some(format!("variable {name} has signal handle {}, the geometry declares {handles}", handle.get_index() as u64 + 1));
                        }
                    }
                })
                .map_err(|e| e.to_string())?;
                Ok(bad)
            });
            match hier {
                Ok(Ok(None)) => {}
                Ok(Ok(Some(message))) | Ok(Err(message)) => {
                    return Err(ReadError::BadFst {
                        origin,
                        message: message.split_whitespace().collect::<Vec<_>>().join(" "),
                    })
                }
                Err(message) => {
                    return Err(ReadError::FstReaderPanicked {
                        origin,
                        message: message.split_whitespace().collect::<Vec<_>>().join(" "),
                    })
                }
            }
            Self::parse(bytes, origin, Some(&layout))
        } else {
            Self::validate_vcd(&bytes, &origin, limits)?;
            Self::parse(bytes, origin, None)
        }
    }

    fn validate_vcd(bytes: &[u8], origin: &str, limits: &ReadLimits) -> Result<(), ReadError> {
        let origin = origin.to_string();
        match validate(bytes, limits.max_var_width) {
            Ok(_) => Ok(()),
            Err(ValidateError::Malformed(p)) => Err(ReadError::Malformed {
                origin,
                line: p.line,
                what: p.what,
            }),
            Err(ValidateError::Io(e)) => Err(ReadError::Parse {
                origin,
                message: e.to_string(),
            }),
        }
    }

    /// Reads `bytes` with wellen; `fst` is the checked layout of an FST (None for a VCD).
    fn parse(
        bytes: Vec<u8>,
        origin: String,
        fst: Option<&crate::fst_check::FstLayout>,
    ) -> Result<Self, ReadError> {
        let layout = fst;
        let fst = fst.is_some();
        // wellen's FST messages span lines; an error is one line.
        let bad_fst = |message: String| ReadError::BadFst {
            origin: origin.clone(),
            message: message.split_whitespace().collect::<Vec<_>>().join(" "),
        };
        let parse_err = |message: String| {
            if fst {
                bad_fst(message)
            } else {
                ReadError::Parse {
                    origin: origin.clone(),
                    message,
                }
            }
        };
        let panicked = |message: String| {
            if fst {
                ReadError::FstReaderPanicked {
                    origin: origin.clone(),
                    message: message.split_whitespace().collect::<Vec<_>>().join(" "),
                }
            } else {
                ReadError::ParserPanicked {
                    origin: origin.clone(),
                    message,
                }
            }
        };
        // One thread: a panic on a rayon worker would be printed by a hook we do not guard.
        let options = LoadOptions {
            multi_thread: false,
            remove_scopes_with_empty_name: false,
        };
        let read = quietly(
            move || -> Result<(Hierarchy, SignalSource, Vec<u64>), String> {
                let header = wellen::viewers::read_header(Cursor::new(bytes), &options)
                    .map_err(|e| e.to_string())?;
                // The hierarchy's widths are what wellen sizes its signals by, the geometry's what
                // fst-reader decodes by: they must agree (a hierarchy width of 54 for a 1-bit
                // signal panics in wellen's signal/mod.rs), and stay within the width limit.
                if let Some(layout) = layout {
                    check_fst_hierarchy(&header.hierarchy, layout)?;
                }
                let body = wellen::viewers::read_body(header.body, &header.hierarchy, None)
                    .map_err(|e| e.to_string())?;
                Ok((header.hierarchy, body.source, body.time_table))
            },
        );
        let (h, mut source, time_table) = match read {
            Ok(Ok(w)) => w,
            Ok(Err(e)) => return Err(parse_err(e)),
            Err(p) => return Err(panicked(p)),
        };
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
        let listed = quietly(|| {
            for vr in h.all_vars() {
                let v = &h[vr];
                let (kind, width) = match v.signal_encoding(&h) {
                    SignalEncoding::BitVector(w) => (SignalKind::Bits, w),
                    SignalEncoding::Real => (SignalKind::Real, 64),
                    SignalEncoding::String => (SignalKind::Text, 0),
                };
                signals.push(SignalInfo {
                    path: v.full_name(&h),
                    index: v.index().map(|i| (i.msb(), i.lsb())),
                    width,
                    kind,
                    var_type: format!("{:?}", v.var_type()).to_lowercase(),
                });
                refs.push(v.signal_ref());
            }
        });
        listed.map_err(panicked)?;
        let mut unique = refs.clone();
        unique.sort_unstable();
        unique.dedup();
        let loaded = quietly(|| source.load_signals(&unique, &h, false)).map_err(panicked)?;
        let data = loaded.into_iter().map(|s| (s.signal_ref(), s)).collect();
        let w = Waveform {
            origin: origin.clone(),
            data,
            time_table,
            signals,
            refs,
            timescale,
        };
        if fst {
            // Every value once, under the guard: wellen decodes values lazily, and a damaged
            // FST that slipped through would otherwise panic later, in changes_at.
            // A real that is not a number cannot equal itself: refused, as in a VCD.
            let nan = quietly(|| {
                for i in 0..w.refs.len() {
                    if let Some((t, v)) = w
                        .changes_at(i)
                        .into_iter()
                        .find(|(_, v)| matches!(v, Value::Real(r) if !r.is_finite()))
                    {
                        return Some(format!(
                            "real value {v} of {} at time {t} is not a finite number",
                            w.signals[i].path
                        ));
                    }
                }
                None
            })
            .map_err(panicked)?;
            if let Some(message) = nan {
                return Err(bad_fst(message));
            }
        }
        Ok(w)
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
        self.time_table.last().copied().unwrap_or(0)
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
        let Some(sig) = self.data.get(r) else {
            return Vec::new();
        };
        let tt = &self.time_table;
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
