//! Reading Verilator's counts: a point's key (file, line, kind, the signal of a toggle bit),
//! numbered once per process, and a seed's counts read from its `coverage.dat`.

use std::collections::HashMap;
use std::path::Path;
use std::sync::{Arc, Mutex, OnceLock};

/// The first line of a Verilator coverage file.
pub(super) const DAT_HEADER: &str = "# SystemC::Coverage-3";
/// The changes Verilator (before 5.038) counts for one rise-and-fall of a bit (a toggle point's
/// count in the folder is a seed's changes divided by this, summed over the seeds; a newer
/// Verilator counts rises and falls apart, and the count is the smaller of the two).
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

/// A key as the folder keeps it, one point per source construct whatever the build that
/// counted it: its `f` field relative to `base` (the file list's folder, so that the keys of one
/// RTL are the same on every machine); its `page` cut to the kind (`v_line`, `v_branch`,
/// `v_toggle`, `v_expr`), without the module Verilator names the page after, whose name carries
/// the parameters of the copy (`pmu_regbank__S1_Cc_CBz1`, `updown_counter__C10`, `m__pi3`,
/// `m__Dz2`, a generate block's copy); and without the instance (`h`). A point is so the file,
/// line, column, kind and comment (the block kind, the signal and bit of a toggle, the
/// condition of an expression term) Verilator gives it, with the source lines it covers (`S`).
pub fn normalise(key: &str, base: Option<&Path>) -> String {
    key.split('\u{1}')
        .filter(|field| !field.starts_with("h\u{2}"))
        .map(|field| {
            if let Some(f) = field.strip_prefix("f\u{2}") {
                if let Some(rel) = base.and_then(|b| Path::new(f).strip_prefix(b).ok()) {
                    return format!("f\u{2}{}", rel.display());
                }
            } else if let Some(page) = field.strip_prefix("page\u{2}") {
                return format!("page\u{2}{}", page_kind(page));
            }
            field.to_string()
        })
        .collect::<Vec<_>>()
        .join("\u{1}")
}

/// `v_line/m__S1_Cc` is `v_line`.
pub(super) fn page_kind(page: &str) -> &str {
    page.split_once('/').map_or(page, |(k, _)| k)
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
    // the records of several instances, and of several copies of a module, fold into one point
    let mut v: std::collections::BTreeMap<u32, u64> = std::collections::BTreeMap::new();
    // a Verilator from 5.038 counts a bit's rises and falls apart (`o` = `cnt[3]:0->1`,
    // `cnt[3]:1->0`): by instance record, (rises, falls)
    let mut directed: std::collections::BTreeMap<String, (u64, u64)> =
        std::collections::BTreeMap::new();
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
        // a toggle point: rise-and-fall pairs of one instance's bit, not changes (the DUT
        // writes a record per instance)
        let c = if k.contains("\u{1}page\u{2}v_toggle") {
            if let Some((bit, rise)) = direction(k) {
                let e = directed.entry(bit).or_insert((0, 0));
                if rise {
                    e.0 = e.0.saturating_add(c);
                } else {
                    e.1 = e.1.saturating_add(c);
                }
                continue;
            }
            c / TOGGLE_CHANGES
        } else {
            c
        };
        let e = v.entry(intern(&normalise(k, base))).or_insert(0);
        *e = e.saturating_add(c);
    }
    for (k, (rise, fall)) in directed {
        let e = v.entry(intern(&normalise(&k, base))).or_insert(0);
        *e = e.saturating_add(rise.min(fall));
    }
    Ok(v.into_iter().collect())
}

/// A toggle record of one direction (`o` = `cnt[3]:0->1` or `cnt[3]:1->0`): the key of the bit
/// (`o` = `cnt[3]`) and whether it counts rises.
pub(super) fn direction(key: &str) -> Option<(String, bool)> {
    let mut rise = None;
    let fields: Vec<String> = key
        .split('\u{1}')
        .map(|f| {
            if let Some(o) = f.strip_prefix("o\u{2}") {
                if let Some(b) = o.strip_suffix(":0->1") {
                    rise = Some(true);
                    return format!("o\u{2}{b}");
                }
                if let Some(b) = o.strip_suffix(":1->0") {
                    rise = Some(false);
                    return format!("o\u{2}{b}");
                }
            }
            f.to_string()
        })
        .collect();
    rise.map(|r| (fields.join("\u{1}"), r))
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
    /// One term of an expression's truth table (`v_expr`, Verilator's `--coverage-expr`): the
    /// inputs' values that decide the result, and the result.
    Expr,
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
                    p.kind = match page_kind(value) {
                        "v_line" => Kind::Line,
                        "v_branch" => Kind::Branch,
                        "v_toggle" => Kind::Toggle,
                        "v_expr" => Kind::Expr,
                        _ => Kind::Other,
                    }
                }
                "o" => p.comment = value.to_string(),
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn copies_and_instances_of_a_module_fold_into_one_point() {
        let k = |page: &str, h: &str| {
            format!("\u{1}f\u{2}/r/m.sv\u{1}l\u{2}40\u{1}n\u{2}3\u{1}page\u{2}{page}\u{1}o\u{2}cnt[3]\u{1}h\u{2}{h}")
        };
        let base = Some(Path::new("/r"));
        let want =
            "\u{1}f\u{2}m.sv\u{1}l\u{2}40\u{1}n\u{2}3\u{1}page\u{2}v_toggle\u{1}o\u{2}cnt[3]";
        for page in [
            "v_toggle/m",
            "v_toggle/m__S1_Cc_CBz1",
            "v_toggle/m__C10",
            "v_toggle/m__pi3",
            "v_toggle/m__Dz2",
        ] {
            assert_eq!(normalise(&k(page, "top.u_a"), base), want, "{page}");
        }
        assert_eq!(normalise(&k("v_toggle/m", "top.g[1].u_b"), base), want);
    }

    #[test]
    fn toggles_are_paired_per_instance_record() {
        let dir = tempfile::tempdir().unwrap();
        let rec = |o: &str, h: &str, n: u64| {
            format!("C '\u{1}f\u{2}m.sv\u{1}l\u{2}4\u{1}page\u{2}v_toggle/m\u{1}o\u{2}{o}\u{1}h\u{2}{h}' {n}\n")
        };
        // instance a only rises, instance b only falls: no toggle, though the module's bit
        // rose and fell; instance c rose twice and fell once: one
        let text = format!(
            "{DAT_HEADER}\n{}{}{}{}{}{}",
            rec("x:0->1", "t.a", 1),
            rec("x:1->0", "t.a", 0),
            rec("x:0->1", "t.b", 0),
            rec("x:1->0", "t.b", 1),
            rec("y", "t.a", 1),
            rec("y", "t.b", 1),
        ) + &rec("z:0->1", "t.c", 2)
            + &rec("z:1->0", "t.c", 1);
        let p = dir.path().join("c.dat");
        std::fs::write(&p, text).unwrap();
        let got: std::collections::BTreeMap<String, u64> = read_counts(&p, None)
            .unwrap()
            .into_iter()
            .map(|(id, n)| (Point::parse(&key_of(id)).comment, n))
            .collect();
        assert_eq!(got["x"], 0);
        assert_eq!(
            got["y"], 0,
            "a change in each of two instances is no toggle"
        );
        assert_eq!(got["z"], 1);
    }
}
