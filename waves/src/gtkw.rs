//! GTKWave save files (`.gtkw`).
//!
//! The flag words follow GTKWave's `TraceEntFlagBits` (`src/analyzer.h`) and
//! the line syntax follows `write_save_helper` (`src/savefile.c`):
//!
//! | bit | flag | used for |
//! |-----|------|----------|
//! | 0x1 | `TR_HIGHLIGHT` | – |
//! | 0x2 | `TR_HEX` | [`Format::Hex`] |
//! | 0x4 | `TR_DEC` | [`Format::Decimal`] |
//! | 0x8 | `TR_BIN` | [`Format::Binary`] |
//! | 0x20 | `TR_RJUSTIFY` | every trace |
//! | 0x200 | `TR_BLANK` | group begin/end lines |
//! | 0x400 | `TR_SIGNED` | [`Format::SignedDecimal`] |
//! | 0x1000 | `TR_COLLAPSED` | closed group end |
//! | 0x8000 | `TR_ANALOG_STEP` | [`Analog::Step`] |
//! | 0x10000 | `TR_ANALOG_INTERPOLATED` | [`Analog::Interpolated`] |
//! | 0x20000 | `TR_ANALOG_BLANK_STRETCH` | extra analog height rows |
//! | 0x400000 | `TR_CLOSED` | closed groups |
//! | 0x800000 | `TR_GRP_BEGIN` | group begin (`@800200`) |
//! | 0x1000000 | `TR_GRP_END` | group end (`@1000200`) |
//!
//! A `@flags` line is written only when the flags differ from the previous
//! trace's, exactly like GTKWave does. Trace names are GTKWave's names for VCD
//! variables: the full dotted path, plus `[msb:lsb]` for vectors
//! (`pmu50.drive_interval.si[15:0]`); get them from
//! [`crate::writer::VcdWriter::gtkwave_name`] or
//! [`crate::reader::SignalInfo::gtkwave_name`].
//!
//! Output is deterministic: no date, no window position, no file mtime/size.
//!
//! ```
//! use pmu50_waves::gtkw::{Analog, Format, GtkwSave, Trace};
//!
//! let mut s = GtkwSave::new("run.vcd").unwrap();
//! s.begin_group("drive", false).unwrap();
//! s.trace(Trace::new("pmu50.drive_interval.si[15:0]").format(Format::SignedDecimal)).unwrap();
//! s.trace(Trace::new("pmu50.vout").analog(Analog::Step, 3)).unwrap();
//! s.end_group().unwrap();
//! let text = s.render().unwrap();
//! assert!(text.contains("@800200\n-drive\n@420\npmu50.drive_interval.si[15:0]\n"));
//! assert!(text.contains("@8028\npmu50.vout\n@20000\n-\n-\n@1000200\n-drive\n"));
//! ```

use std::fmt::Write as _;
use std::path::Path;

use thiserror::Error;

use crate::reader::Waveform;

// GTKWave's trace flags (the TR_* bits of its analyzer.h), by their GTKWave names.
const TR_HEX: u64 = 1 << 1;
const TR_DEC: u64 = 1 << 2;
const TR_BIN: u64 = 1 << 3;
const TR_RJUSTIFY: u64 = 1 << 5;
const TR_BLANK: u64 = 1 << 9;
const TR_SIGNED: u64 = 1 << 10;
const TR_COLLAPSED: u64 = 1 << 12;
const TR_ANALOG_STEP: u64 = 1 << 15;
const TR_ANALOG_INTERPOLATED: u64 = 1 << 16;
const TR_ANALOG_BLANK_STRETCH: u64 = 1 << 17;
const TR_CLOSED: u64 = 1 << 22;
const TR_GRP_BEGIN: u64 = 1 << 23;
const TR_GRP_END: u64 = 1 << 24;

/// Number of named markers (a..z) GTKWave 3.3 writes on the `*` zoom line.
const NAMED_MARKERS: usize = 26;

/// Number display format of a trace.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum Format {
    /// binary (`@28`); GTKWave's own default for VCD traces it adds
    #[default]
    Binary,
    /// hexadecimal (`@22`)
    Hex,
    /// unsigned decimal (`@24`)
    Decimal,
    /// two's complement signed decimal (`@420`)
    SignedDecimal,
}

impl Format {
    fn flags(self) -> u64 {
        match self {
            Format::Binary => TR_BIN,
            Format::Hex => TR_HEX,
            Format::Decimal => TR_DEC,
            Format::SignedDecimal => TR_SIGNED,
        }
    }
}

/// Analog rendering of a vector or real trace.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Analog {
    /// sample-and-hold steps (`TR_ANALOG_STEP`)
    Step,
    /// linear interpolation (`TR_ANALOG_INTERPOLATED`)
    Interpolated,
}

/// Trace colour (`[color] n`, GTKWave's rainbow indices 1..=7).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Color {
    /// 1
    Red,
    /// 2
    Orange,
    /// 3
    Yellow,
    /// 4
    Green,
    /// 5
    Blue,
    /// 6
    Indigo,
    /// 7
    Violet,
}

impl Color {
    fn index(self) -> u8 {
        match self {
            Color::Red => 1,
            Color::Orange => 2,
            Color::Yellow => 3,
            Color::Green => 4,
            Color::Blue => 5,
            Color::Indigo => 6,
            Color::Violet => 7,
        }
    }
}

/// One signal trace.
#[derive(Debug, Clone, PartialEq)]
pub struct Trace {
    name: String,
    format: Format,
    analog: Option<(Analog, u32)>,
    color: Option<Color>,
    alias: Option<String>,
}

impl Trace {
    /// Trace of GTKWave signal `name` (full path, `[msb:lsb]` for vectors),
    /// binary format, digital, default colour.
    pub fn new(name: impl Into<String>) -> Self {
        Trace {
            name: name.into(),
            format: Format::Binary,
            analog: None,
            color: None,
            alias: None,
        }
    }

    /// The name GTKWave shows for the trace instead of the signal's (`+{alias} name`), e.g.
    /// `model si` and `RTL si` for two signals both called `si`. One line, without `{` or `}`.
    pub fn alias(mut self, alias: impl Into<String>) -> Self {
        self.alias = Some(alias.into());
        self
    }

    /// Number format (for `real` variables GTKWave always shows the real value).
    pub fn format(mut self, format: Format) -> Self {
        self.format = format;
        self
    }

    /// Draw as analog waveform, `rows` trace rows high (1 = normal height;
    /// each extra row is an `@20000` blank-stretch line).
    pub fn analog(mut self, mode: Analog, rows: u32) -> Self {
        self.analog = Some((mode, rows));
        self
    }

    /// Trace colour.
    pub fn color(mut self, color: Color) -> Self {
        self.color = Some(color);
        self
    }

    /// GTKWave flag word of this trace.
    pub fn flags(&self) -> u64 {
        let analog = match self.analog {
            Some((Analog::Step, _)) => TR_ANALOG_STEP,
            Some((Analog::Interpolated, _)) => TR_ANALOG_INTERPOLATED,
            None => 0,
        };
        self.format.flags() | TR_RJUSTIFY | analog
    }
}

/// Errors building a save file.
#[derive(Debug, Error)]
pub enum GtkwError {
    /// A name or path that cannot be written on one save-file line.
    #[error("invalid {what} {text:?}: {why}")]
    InvalidText {
        /// "dump file path", "group name" or "trace name"
        what: &'static str,
        /// the rejected text
        text: String,
        /// what is valid
        why: &'static str,
    },
    /// Analog trace with zero rows.
    #[error("analog trace `{name}` has height 0 rows: the height must be at least 1")]
    ZeroHeight {
        /// trace name
        name: String,
    },
    /// Zoom that is NaN or infinite.
    #[error("zoom {0} is not finite: GTKWave zoom is a finite (usually negative) number")]
    BadZoom(f64),
    /// `end_group` without `begin_group`.
    #[error("end_group called with no open group")]
    NoOpenGroup,
    /// `render` with groups still open.
    #[error("group `{0}` is still open: call end_group for every begin_group before rendering")]
    UnclosedGroup(String),
    /// Traces naming signals the VCD does not have.
    #[error("{} trace name(s) not found in {origin}: {}; GTKWave names are full dotted paths with `[msb:lsb]` for vectors, e.g. {example}", missing.len(), missing.join(", "))]
    UnknownSignals {
        /// the names not found
        missing: Vec<String>,
        /// waveform origin
        origin: String,
        /// an existing name to show the expected form
        example: String,
    },
    /// More named markers than GTKWave has (A-Z).
    #[error("marker `{name}`: GTKWave has {max} named markers (A-Z), all in use")]
    TooManyMarkers {
        /// the marker that did not fit
        name: String,
        /// GTKWave's number of named markers
        max: usize,
    },
    /// Writing the file failed.
    #[error("cannot write save file {path}: {source}")]
    Io {
        /// the path
        path: String,
        /// the I/O error
        source: std::io::Error,
    },
}

#[derive(Debug, Clone, PartialEq)]
enum Entry {
    GroupBegin { name: String, closed: bool },
    GroupEnd { name: String, closed: bool },
    Trace(Trace),
}

/// A GTKWave save file under construction.
#[derive(Debug, Clone, PartialEq)]
pub struct GtkwSave {
    dumpfile: String,
    timestart: u64,
    size: (u32, u32),
    zoom: f64,
    entries: Vec<Entry>,
    open: Vec<(String, bool)>,
    markers: Vec<(u64, String)>,
    notes: Vec<String>,
}

fn check_line(what: &'static str, text: &str, allow_empty: bool) -> Result<(), GtkwError> {
    if !allow_empty && text.is_empty() {
        return Err(GtkwError::InvalidText {
            what,
            text: text.into(),
            why: "it must not be empty",
        });
    }
    if text.chars().any(|c| c.is_control()) {
        return Err(GtkwError::InvalidText {
            what,
            text: text.into(),
            why: "it must fit on one line (no newline or other control characters)",
        });
    }
    Ok(())
}

impl GtkwSave {
    /// Save file that opens `dumpfile` (written as `[dumpfile] "dumpfile"`;
    /// relative paths are resolved by GTKWave relative to its working directory).
    pub fn new(dumpfile: &str) -> Result<Self, GtkwError> {
        check_line("dump file path", dumpfile, false)?;
        if dumpfile.contains('"') {
            return Err(GtkwError::InvalidText {
                what: "dump file path",
                text: dumpfile.into(),
                why: "it must not contain a double quote",
            });
        }
        Ok(GtkwSave {
            dumpfile: dumpfile.to_string(),
            timestart: 0,
            size: (1400, 800),
            zoom: 0.0,
            entries: Vec::new(),
            open: Vec::new(),
            markers: Vec::new(),
            notes: Vec::new(),
        })
    }

    /// `[timestart]`: first time shown, in VCD time units (default 0).
    pub fn timestart(&mut self, t: u64) -> &mut Self {
        self.timestart = t;
        self
    }

    /// `[size]`: window size in pixels (default 1400 × 800).
    pub fn size(&mut self, width: u32, height: u32) -> &mut Self {
        self.size = (width, height);
        self
    }

    /// Zoom level of the `*` line (GTKWave shows 2^-zoom time units per pixel;
    /// default 0).
    pub fn zoom(&mut self, zoom: f64) -> Result<&mut Self, GtkwError> {
        if !zoom.is_finite() {
            return Err(GtkwError::BadZoom(zoom));
        }
        self.zoom = zoom;
        Ok(self)
    }

    /// Set `[timestart]` to `start` and the zoom that shows `[start, end]` across the wave pane
    /// of the configured window width. GTKWave shows 2^-zoom / 200 time units per pixel (its
    /// "zoom best fit" sets zoom = -log2(span / pane · 200)); the pane is taken as the window
    /// width less 600 pixels for the signal tree and the name column, so the span fits with a
    /// small margin.
    pub fn fit(&mut self, start: u64, end: u64) -> &mut Self {
        self.timestart = start;
        let pane = f64::from(self.size.0.saturating_sub(600).max(100));
        let span = end.saturating_sub(start).max(1) as f64;
        // Rounded down to the 6 decimals written, so that the whole span stays visible.
        self.zoom = (-(span * 200.0 / pane).log2() * 1e6).floor() / 1e6;
        if self.zoom == 0.0 {
            self.zoom = 0.0; // no "-0"
        }
        self
    }

    /// Add a named marker at time `t` (VCD time units): GTKWave's markers A, B, ... in the order
    /// added, shown with `name` above the waves (`[markername]`). The name must fit on one line
    /// and must not start with an upper-case letter (GTKWave would read it as part of the
    /// marker's letter).
    pub fn marker(&mut self, t: u64, name: &str) -> Result<(), GtkwError> {
        check_line("marker name", name, false)?;
        if name.starts_with(|c: char| c.is_ascii_uppercase()) {
            return Err(GtkwError::InvalidText {
                what: "marker name",
                text: name.into(),
                why: "it must not start with an upper-case letter A-Z",
            });
        }
        if self.markers.len() >= NAMED_MARKERS {
            return Err(GtkwError::TooManyMarkers {
                name: name.into(),
                max: NAMED_MARKERS,
            });
        }
        self.markers.push((t, name.to_string()));
        Ok(())
    }

    /// A comment line (`[*] text`) in the header.
    pub fn note(&mut self, text: &str) -> Result<(), GtkwError> {
        check_line("note", text, false)?;
        self.notes.push(text.to_string());
        Ok(())
    }

    /// Start a (possibly closed) group named `name` (`@800200` / `-name`).
    pub fn begin_group(&mut self, name: &str, closed: bool) -> Result<(), GtkwError> {
        check_line("group name", name, false)?;
        self.entries.push(Entry::GroupBegin {
            name: name.to_string(),
            closed,
        });
        self.open.push((name.to_string(), closed));
        Ok(())
    }

    /// End the innermost open group (`@1000200` / `-name`).
    pub fn end_group(&mut self) -> Result<(), GtkwError> {
        let (name, closed) = self.open.pop().ok_or(GtkwError::NoOpenGroup)?;
        self.entries.push(Entry::GroupEnd { name, closed });
        Ok(())
    }

    /// Add a trace.
    pub fn trace(&mut self, trace: Trace) -> Result<(), GtkwError> {
        check_line("trace name", &trace.name, false)?;
        let first = trace.name.chars().next().unwrap_or(' ');
        if trace.name.chars().any(char::is_whitespace) || "@-*[#:+(>^!?%".contains(first) {
            return Err(GtkwError::InvalidText {
                what: "trace name",
                text: trace.name.clone(),
                why: "it must be a GTKWave signal name: no whitespace and not starting with one of @ - * [ # : + ( > ^ ! ? %",
            });
        }
        if let Some(a) = &trace.alias {
            check_line("trace alias", a, false)?;
            if a.contains(['{', '}']) {
                return Err(GtkwError::InvalidText {
                    what: "trace alias",
                    text: a.clone(),
                    why: "it must not contain `{` or `}`",
                });
            }
        }
        if let Some((_, 0)) = trace.analog {
            return Err(GtkwError::ZeroHeight {
                name: trace.name.clone(),
            });
        }
        self.entries.push(Entry::Trace(trace));
        Ok(())
    }

    /// Check that every trace names a signal of `wave` (by GTKWave name).
    pub fn check_names(&self, wave: &Waveform) -> Result<(), GtkwError> {
        let known: std::collections::HashSet<String> =
            wave.signals().iter().map(|s| s.gtkwave_name()).collect();
        let missing: Vec<String> = self
            .entries
            .iter()
            .filter_map(|e| match e {
                Entry::Trace(t) if !known.contains(&t.name) => Some(t.name.clone()),
                _ => None,
            })
            .collect();
        if missing.is_empty() {
            return Ok(());
        }
        let example = wave
            .signals()
            .iter()
            .map(|s| s.gtkwave_name())
            .find(|n| n.ends_with(']'))
            .or_else(|| wave.signals().first().map(|s| s.gtkwave_name()))
            .unwrap_or_else(|| "top.sig[7:0]".to_string());
        Err(GtkwError::UnknownSignals {
            missing,
            origin: wave.origin().to_string(),
            example,
        })
    }

    /// The save file text.
    pub fn render(&self) -> Result<String, GtkwError> {
        if let Some((name, _)) = self.open.last() {
            return Err(GtkwError::UnclosedGroup(name.clone()));
        }
        let mut s = String::new();
        // writing to a String cannot fail
        let _ = self.render_into(&mut s);
        Ok(s)
    }

    fn render_into(&self, s: &mut String) -> std::fmt::Result {
        writeln!(s, "[*]")?;
        writeln!(s, "[*] pmu50-waves GTKWave save file")?;
        for n in &self.notes {
            writeln!(s, "[*] {n}")?;
        }
        writeln!(s, "[*]")?;
        writeln!(s, "[dumpfile] \"{}\"", self.dumpfile)?;
        writeln!(s, "[timestart] {}", self.timestart)?;
        writeln!(s, "[size] {} {}", self.size.0, self.size.1)?;
        write!(s, "*{:.6} -1", self.zoom)?;
        for i in 0..NAMED_MARKERS {
            match self.markers.get(i) {
                Some((t, _)) => write!(s, " {t}")?,
                None => write!(s, " -1")?,
            }
        }
        writeln!(s)?;
        for (i, (_, name)) in self.markers.iter().enumerate() {
            // `i < NAMED_MARKERS` (checked in `marker`), so this is one letter A-Z.
            let letter = char::from(b'A' + i as u8);
            writeln!(s, "[markername] {letter}{name}")?;
        }
        let mut prev: Option<u64> = None;
        let mut set_flags = |s: &mut String, flags: u64| -> std::fmt::Result {
            if prev != Some(flags) {
                writeln!(s, "@{flags:x}")?;
                prev = Some(flags);
            }
            Ok(())
        };
        for e in &self.entries {
            match e {
                Entry::GroupBegin { name, closed } => {
                    let f = TR_GRP_BEGIN | TR_BLANK | if *closed { TR_CLOSED } else { 0 };
                    set_flags(s, f)?;
                    writeln!(s, "-{name}")?;
                }
                Entry::GroupEnd { name, closed } => {
                    let f =
                        TR_GRP_END | TR_BLANK | if *closed { TR_CLOSED | TR_COLLAPSED } else { 0 };
                    set_flags(s, f)?;
                    writeln!(s, "-{name}")?;
                }
                Entry::Trace(t) => {
                    set_flags(s, t.flags())?;
                    if let Some(c) = t.color {
                        writeln!(s, "[color] {}", c.index())?;
                    }
                    if let Some(a) = &t.alias {
                        write!(s, "+{{{a}}} ")?;
                    }
                    writeln!(s, "{}", t.name)?;
                    if let Some((_, rows)) = t.analog {
                        for _ in 1..rows {
                            set_flags(s, TR_ANALOG_BLANK_STRETCH)?;
                            writeln!(s, "-")?;
                        }
                    }
                }
            }
        }
        Ok(())
    }

    /// Render and write to `path`: to a temporary file beside it, renamed into place when
    /// complete (an interrupted write never leaves a cut save file; a symlink at `path` is
    /// replaced, not followed). The `pmu50` CLI stages its save files with its own output batch
    /// instead (testbench/src/atomic_file.rs), so that the `.gtkw` lands after the VCD.
    pub fn write(&self, path: impl AsRef<Path>) -> Result<(), GtkwError> {
        let text = self.render()?;
        let path = path.as_ref();
        let io = |source| GtkwError::Io {
            path: path.display().to_string(),
            source,
        };
        let name = path
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default();
        let tmp = path.with_file_name(format!(".{name}.{}.tmp", std::process::id()));
        std::fs::write(&tmp, text).map_err(io)?;
        std::fs::rename(&tmp, path).map_err(|e| {
            let _ = std::fs::remove_file(&tmp);
            io(e)
        })
    }
}
