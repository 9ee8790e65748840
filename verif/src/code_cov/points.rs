//! Reading Verilator's counts: a point's key (file, line, kind, the signal of a toggle bit),
//! numbered once per process, and a seed's counts read from its `coverage.dat`.

use std::collections::HashMap;
use std::path::Path;
use std::sync::{Arc, Mutex, OnceLock};

/// The first line of a Verilator coverage file.
pub(super) const DAT_HEADER: &str = "# SystemC::Coverage-3";
/// The changes Verilator counts for one rise-and-fall of a bit (a toggle point's count in the
/// folder is a seed's changes divided by this, summed over the seeds).
pub const TOGGLE_CHANGES: u64 = 2;

/// The point keys of this process, each numbered once: a seed's counts are (number, count).
pub(super) struct Interner {
    pub(super) ids: HashMap<Arc<str>, u32>,
    pub(super) keys: Vec<Arc<str>>,
}

pub(super) fn interner() -> &'static Mutex<Interner> {
    static I: OnceLock<Mutex<Interner>> = OnceLock::new();
    I.get_or_init(|| {
        Mutex::new(Interner {
            ids: HashMap::new(),
            keys: Vec::new(),
        })
    })
}

pub(super) fn intern(key: &str) -> u32 {
    let mut i = interner().lock().unwrap_or_else(|e| e.into_inner());
    if let Some(&id) = i.ids.get(key) {
        return id;
    }
    let k: Arc<str> = Arc::from(key);
    let id = i.keys.len() as u32;
    i.keys.push(k.clone());
    i.ids.insert(k, id);
    id
}

pub(super) fn key_of(id: u32) -> Arc<str> {
    let i = interner().lock().unwrap_or_else(|e| e.into_inner());
    i.keys
        .get(id as usize)
        .cloned()
        .unwrap_or_else(|| Arc::from(""))
}

/// The code coverage of one seed's RTL run: its nonzero counts and every point of its build.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SeedCode {
    /// (point, count), count > 0.
    pub counts: Vec<(u32, u64)>,
    /// Every point of the library the seed ran on, hit or not.
    pub points: Arc<Vec<u32>>,
}

/// A key as the folder keeps it: its `f` field relative to `base` (the file list's folder, so
/// that the keys of one RTL are the same on every machine), and its `page`
/// without the suffix Verilator gives a module per parameter set (`updown_counter_58cd__C10`,
/// `register_file__pi1`), so that a source line's point is one point whatever the parameters
/// of the build that counted it.
pub fn normalise(key: &str, base: Option<&Path>) -> String {
    key.split('\u{1}')
        .map(|field| {
            if let Some(f) = field.strip_prefix("f\u{2}") {
                if let Some(rel) = base.and_then(|b| Path::new(f).strip_prefix(b).ok()) {
                    return format!("f\u{2}{}", rel.display());
                }
            } else if let Some(page) = field.strip_prefix("page\u{2}") {
                return format!("page\u{2}{}", strip_param_suffix(page));
            }
            field.to_string()
        })
        .collect::<Vec<_>>()
        .join("\u{1}")
}

/// `v_line/m__C10` and `v_line/m__pi3` are `v_line/m`.
pub(super) fn strip_param_suffix(page: &str) -> &str {
    if let Some(i) = page.rfind("__") {
        let tail = &page[i + 2..];
        let param = tail
            .strip_prefix("pi")
            .filter(|t| !t.is_empty() && t.chars().all(|c| c.is_ascii_digit()))
            .is_some()
            || tail
                .strip_prefix('C')
                .filter(|t| !t.is_empty() && t.chars().all(|c| c.is_ascii_alphanumeric()))
                .is_some();
        if param {
            return &page[..i];
        }
    }
    page
}

/// One line of a coverage.dat: `C '<key>' <count>`.
pub(super) fn dat_line(line: &str) -> Option<(&str, u64)> {
    let rest = line.strip_prefix("C '")?;
    let end = rest.rfind('\'')?;
    let count = rest[end + 1..].trim().parse().ok()?;
    Some((&rest[..end], count))
}

/// The counts of a Verilator coverage.dat a worker wrote: (point, count) for every point, the
/// points' files relative to `base` ([`normalise`]).
pub fn read_counts(path: &Path, base: Option<&Path>) -> Result<Vec<(u32, u64)>, String> {
    let text = std::fs::read_to_string(path).map_err(|e| {
        format!(
            "the code coverage of the RTL's run ({}): {e}",
            path.display()
        )
    })?;
    let mut v = Vec::new();
    for (n, l) in text.lines().enumerate() {
        if l.is_empty() || l.starts_with('#') {
            continue;
        }
        let (k, c) = dat_line(l).ok_or_else(|| {
            format!(
                "{}:{}: not a line of a Verilator coverage file",
                path.display(),
                n + 1
            )
        })?;
        // a toggle point: rise-and-fall pairs, not changes
        let c = if k.contains("\u{1}page\u{2}v_toggle/") {
            c / TOGGLE_CHANGES
        } else {
            c
        };
        v.push((intern(&normalise(k, base)), c));
    }
    Ok(v)
}

/// The kind of a point (its `page`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Kind {
    /// A block (`v_line`).
    Line,
    /// An `if`/`else`/`case` branch (`v_branch`).
    Branch,
    /// One bit of a signal (`v_toggle`).
    Toggle,
    /// Anything else (user coverage): counted in coverage.dat, not in the figures.
    Other,
}

/// A name as the RTL spells it: Verilator writes a character other than a letter, a digit or
/// `_` of a name as `__0` and two hex digits (a netlist's `\\drive_interval.si` is
/// `drive_interval__02esi`).
pub fn demangle(name: &str) -> String {
    let b = name.as_bytes();
    let mut out = String::with_capacity(name.len());
    let mut i = 0;
    while i < b.len() {
        if b[i..].starts_with(b"__0") && i + 5 <= b.len() {
            if let Ok(c) = u8::from_str_radix(&name[i + 3..i + 5], 16) {
                if c.is_ascii_graphic() {
                    out.push(char::from(c));
                    i += 5;
                    continue;
                }
            }
        }
        out.push(char::from(b[i]));
        i += 1;
    }
    out
}

/// A point's key, read.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Point {
    pub file: String,
    pub line: u32,
    pub kind: Kind,
    /// The block kind (`block`, `if`, `else`, `case`) or the signal and bit (`cnt[3]`).
    pub comment: String,
    /// The instance.
    pub hier: String,
    /// The source lines of a block (`S`), as ranges; the point's line when absent.
    pub lines: Vec<(u32, u32)>,
}

impl Point {
    pub fn parse(key: &str) -> Point {
        let mut p = Point {
            file: String::new(),
            line: 0,
            kind: Kind::Other,
            comment: String::new(),
            hier: String::new(),
            lines: Vec::new(),
        };
        for field in key.split('\u{1}') {
            let Some((name, value)) = field.split_once('\u{2}') else {
                continue;
            };
            match name {
                "f" => p.file = value.to_string(),
                "l" => p.line = value.parse().unwrap_or(0),
                "page" => {
                    p.kind = if value.starts_with("v_line/") {
                        Kind::Line
                    } else if value.starts_with("v_branch/") {
                        Kind::Branch
                    } else if value.starts_with("v_toggle/") {
                        Kind::Toggle
                    } else {
                        Kind::Other
                    }
                }
                "o" => p.comment = value.to_string(),
                "h" => p.hier = value.to_string(),
                "S" => {
                    p.lines = value
                        .split(',')
                        .filter_map(|r| match r.split_once('-') {
                            Some((a, b)) => Some((a.parse().ok()?, b.parse().ok()?)),
                            None => r.parse().ok().map(|a| (a, a)),
                        })
                        .collect()
                }
                _ => {}
            }
        }
        if p.lines.is_empty() && p.line > 0 {
            p.lines.push((p.line, p.line));
        }
        p
    }

    /// A line or branch point.
    pub fn is_line(&self) -> bool {
        matches!(self.kind, Kind::Line | Kind::Branch)
    }

    /// Whether `count` covers this point (a toggle point's count is rise-and-fall pairs).
    pub fn covered(&self, count: u64) -> bool {
        count > 0
    }

    /// A toggle point's signal and bit: `cnt[3]` is (`cnt`, Some(3)).
    pub fn signal(&self) -> (&str, Option<u32>) {
        let c = self.comment.as_str();
        if let Some(open) = c.rfind('[') {
            if let Some(bit) = c[open + 1..].strip_suffix(']').and_then(|b| b.parse().ok()) {
                return (&c[..open], Some(bit));
            }
        }
        (c, None)
    }
}
