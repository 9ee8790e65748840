//! Waivers of code coverage points (`waivers.toml`): what each waives, why, its claim, and its
//! review ([`crate::waiver::Review`]: kind, reviewer, the checksum of the lines it covers).

use super::points::*;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// A waivers file that is not valid: where, which field, what is valid.
#[derive(Debug, thiserror::Error)]
pub enum WaiverError {
    #[error("{}: {reason}", path.display())]
    File { path: PathBuf, reason: String },
    #[error("{}:{line}: field `{field}`: {reason}", path.display())]
    Field {
        path: PathBuf,
        line: usize,
        field: &'static str,
        reason: String,
    },
}

/// What a waiver excludes.
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Target {
    /// The line and branch points starting on these lines (first, last).
    Lines(u32, u32),
    /// The toggle points of a signal, all its bits or bits `lo..=hi`.
    Signal {
        name: String,
        bits: Option<(u32, u32)>,
    },
    /// The expression terms (`v_expr`) of these lines (first, last); with a pattern (`term`),
    /// only the terms whose text, as Verilator writes it and the report lists it, matches it
    /// (`*` stands for any characters).
    Expr(u32, u32, Option<String>),
}

/// One waiver.
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
pub struct Waiver {
    /// The RTL file: its path as the file list names it, or a trailing part of it.
    pub file: String,
    pub target: Target,
    pub reason: String,
    /// The claim behind the reason as a Verilog expression over the file's module (`holds`):
    /// an invariant of every reachable state after reset, which `make coverage-proofs` proves
    /// on the twin (hdl/formal/coverage.py). `$past(x)` names the value one edge before.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub holds: Option<String>,
    /// Its line in the waivers file.
    pub at: usize,
    /// Kind, reviewer and the checksum of its lines as reviewed.
    pub review: crate::waiver::Review,
}

impl Waiver {
    /// The source lines it covers in `source` (its file): its lines, or those naming its signal.
    pub fn lines(&self, source: &str) -> Vec<u32> {
        match &self.target {
            Target::Lines(a, b) | Target::Expr(a, b, _) => (*a..=*b).collect(),
            Target::Signal { name, .. } => crate::waiver::lines_naming(source, name),
        }
    }

    /// The target as written: `line 40`, `lines 40-45`, `expr 52`, `expr 52 term (a==0) => *`,
    /// `signal cnt`, `signal cnt[15:4]`.
    pub fn what(&self) -> String {
        match &self.target {
            Target::Lines(a, b) if a == b => format!("line {a}"),
            Target::Lines(a, b) => format!("lines {a}-{b}"),
            Target::Expr(a, b, term) => {
                let lines = if a == b {
                    format!("expr {a}")
                } else {
                    format!("expr {a}-{b}")
                };
                match term {
                    Some(t) => format!("{lines} term {t}"),
                    None => lines,
                }
            }
            Target::Signal { name, bits: None } => format!("signal {name}"),
            Target::Signal {
                name,
                bits: Some((lo, hi)),
            } if lo == hi => format!("signal {name}[{lo}]"),
            Target::Signal {
                name,
                bits: Some((lo, hi)),
            } => format!("signal {name}[{hi}:{lo}]"),
        }
    }

    /// Whether this waiver excludes point `p`.
    pub fn covers(&self, p: &Point) -> bool {
        if !file_matches(&p.file, &self.file) {
            return false;
        }
        match &self.target {
            Target::Lines(a, b) => p.is_line() && (*a..=*b).contains(&p.line),
            Target::Expr(a, b, term) => {
                p.kind == Kind::Expr
                    && (*a..=*b).contains(&p.line)
                    && term.as_deref().is_none_or(|t| glob(t, &p.comment))
            }
            Target::Signal { name, bits } => {
                if p.kind != Kind::Toggle {
                    return false;
                }
                let (sig, bit) = p.signal();
                (sig == name || demangle(sig) == *name)
                    && match (bits, bit) {
                        (None, _) => true,
                        (Some((lo, hi)), Some(b)) => (*lo..=*hi).contains(&b),
                        (Some(_), None) => false,
                    }
            }
        }
    }
}

/// Whether `text` matches `pattern`, whose `*` stands for any characters (none included) and
/// every other character for itself.
pub(super) fn glob(pattern: &str, text: &str) -> bool {
    let parts: Vec<&str> = pattern.split('*').collect();
    let (first, rest) = (parts[0], &parts[1..]);
    let Some(mut left) = text.strip_prefix(first) else {
        return false;
    };
    let Some((last, middle)) = rest.split_last() else {
        return left.is_empty();
    };
    for m in middle {
        match left.find(m) {
            Some(i) => left = &left[i + m.len()..],
            None => return false,
        }
    }
    left.len() >= last.len() && left.ends_with(last)
}

/// Whether `path` is `file` or ends with it on a folder boundary.
pub(super) fn file_matches(path: &str, file: &str) -> bool {
    path == file || path.ends_with(&format!("/{file}"))
}

/// The waivers of a run: `hdl/coverage-waivers.toml` for the twin, `--waivers FILE` for any RTL.
#[derive(Clone, Debug, Default)]
pub struct Waivers {
    pub list: Vec<Waiver>,
    /// The file's text (kept in the folder as `code/waivers.toml`).
    pub text: String,
    /// Where it was read from.
    pub origin: String,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawFile {
    #[serde(default)]
    pub(super) waiver: Vec<toml::Spanned<RawWaiver>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawWaiver {
    pub(super) file: Option<toml::Spanned<String>>,
    pub(super) line: Option<toml::Spanned<toml::Value>>,
    pub(super) signal: Option<toml::Spanned<String>>,
    pub(super) reason: Option<toml::Spanned<String>>,
    pub(super) holds: Option<toml::Spanned<String>>,
    pub(super) expr: Option<toml::Spanned<toml::Value>>,
    pub(super) term: Option<toml::Spanned<String>>,
    pub(super) kind: Option<toml::Spanned<String>>,
    pub(super) reviewer: Option<toml::Spanned<String>>,
    pub(super) checksum: Option<toml::Spanned<String>>,
}

/// The line (from 1) of byte `at` of `text`.
pub(super) fn line_at(text: &str, at: usize) -> usize {
    text.as_bytes()[..at.min(text.len())]
        .iter()
        .filter(|b| **b == b'\n')
        .count()
        + 1
}

/// `name`, `name[3]` or `name[15:4]`.
pub(super) fn parse_signal(s: &str) -> Option<(String, Option<(u32, u32)>)> {
    let ident = |n: &str| {
        !n.is_empty()
            && n.chars()
                .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '$' || c == '.')
            && !n.starts_with(|c: char| c.is_ascii_digit())
    };
    match s.split_once('[') {
        None => ident(s).then(|| (s.to_string(), None)),
        Some((n, rest)) => {
            let inner = rest.strip_suffix(']')?;
            let bits = match inner.split_once(':') {
                Some((hi, lo)) => {
                    let (hi, lo): (u32, u32) = (hi.trim().parse().ok()?, lo.trim().parse().ok()?);
                    (lo.min(hi), lo.max(hi))
                }
                None => {
                    let b: u32 = inner.trim().parse().ok()?;
                    (b, b)
                }
            };
            ident(n).then(|| (n.to_string(), Some(bits)))
        }
    }
}

impl Waivers {
    /// Read and check a waivers file. With `rtl` (the file list's files), each waiver's file
    /// must name exactly one of them, its lines must be in that file and its signal must appear
    /// in it.
    pub fn read(path: &Path, rtl: Option<&[PathBuf]>) -> Result<Waivers, WaiverError> {
        let text = std::fs::read_to_string(path).map_err(|e| WaiverError::File {
            path: path.to_path_buf(),
            reason: e.to_string(),
        })?;
        Waivers::parse(&text, path, rtl)
    }

    pub fn parse(text: &str, path: &Path, rtl: Option<&[PathBuf]>) -> Result<Waivers, WaiverError> {
        let raw: RawFile = toml::from_str(text).map_err(|e| match e.span() {
            Some(s) => WaiverError::Field {
                path: path.to_path_buf(),
                line: line_at(text, s.start),
                field: "waiver",
                reason: e.message().to_string(),
            },
            None => WaiverError::File {
                path: path.to_path_buf(),
                reason: e.message().to_string(),
            },
        })?;
        let mut list = Vec::new();
        for w in raw.waiver {
            let at = line_at(text, w.span().start);
            let w = w.into_inner();
            let field_err = |line: usize, field: &'static str, reason: String| WaiverError::Field {
                path: path.to_path_buf(),
                line,
                field,
                reason,
            };
            let file = w
                .file
                .ok_or_else(|| field_err(at, "file", "missing: the RTL file the waiver is in (its path as the file list names it, or the end of it)".into()))?;
            let file_line = line_at(text, file.span().start);
            let file = file.into_inner();
            if file.trim().is_empty() {
                return Err(field_err(
                    file_line,
                    "file",
                    "empty: name the RTL file".into(),
                ));
            }
            let reason = w.reason.ok_or_else(|| {
                field_err(
                    at,
                    "reason",
                    "missing: every waiver says why the point cannot or need not be covered".into(),
                )
            })?;
            let reason_line = line_at(text, reason.span().start);
            let reason = reason.into_inner();
            if reason.trim().len() < 10 {
                return Err(field_err(reason_line, "reason", format!("`{reason}` is too short: say why the point cannot or need not be covered (at least 10 characters)")));
            }
            let target_line;
            let (line_field, is_expr) = match (w.line, w.expr) {
                (Some(_), Some(e)) => {
                    return Err(field_err(
                        line_at(text, e.span().start),
                        "expr",
                        "a waiver has one of `line`, `expr` or `signal`".into(),
                    ))
                }
                (Some(l), None) => (Some(l), false),
                (None, Some(e)) => (Some(e), true),
                (None, None) => (None, false),
            };
            if let (Some(t), false) = (&w.term, is_expr) {
                return Err(field_err(
                    line_at(text, t.span().start),
                    "term",
                    "a pattern of expression terms goes with `expr` (the lines of the terms), not with `line` or `signal`".into(),
                ));
            }
            let target = match (line_field, w.signal) {
                (Some(_), Some(s)) => {
                    return Err(field_err(
                        line_at(text, s.span().start),
                        "signal",
                        "a waiver has one of `line`, `expr` or `signal`".into(),
                    ))
                }
                (None, None) => {
                    return Err(field_err(at, "line", "missing: give `line` (a line, 42, or a range, \"40-45\"), `expr` (the expression terms of a line or range) or `signal` (a toggled signal, \"cnt\" or \"cnt[15:4]\")".into()))
                }
                (Some(l), None) => {
                    let ll = line_at(text, l.span().start);
                    target_line = ll;
                    let bad = || {
                        field_err(
                            ll,
                            "line",
                            format!("{}: valid is a line number (42) or a range (\"40-45\") from 1", l.get_ref()),
                        )
                    };
                    let (a, b) = match l.get_ref() {
                        toml::Value::Integer(n) if *n >= 1 && *n <= i64::from(u32::MAX) => {
                            (*n as u32, *n as u32)
                        }
                        toml::Value::String(s) => {
                            let (a, b) = s.split_once('-').unwrap_or((s, s));
                            let a: u32 = a.trim().parse().map_err(|_| bad())?;
                            let b: u32 = b.trim().parse().map_err(|_| bad())?;
                            if a == 0 || b < a {
                                return Err(bad());
                            }
                            (a, b)
                        }
                        _ => return Err(bad()),
                    };
                    if is_expr {
                        let term = match w.term {
                            Some(t) if t.get_ref().trim().is_empty() => {
                                return Err(field_err(
                                    line_at(text, t.span().start),
                                    "term",
                                    "empty: give the pattern of the terms waived, as the report lists them (`*` for any characters), or leave the field out".into(),
                                ))
                            }
                            Some(t) => Some(t.into_inner().trim().to_string()),
                            None => None,
                        };
                        Target::Expr(a, b, term)
                    } else {
                        Target::Lines(a, b)
                    }
                }
                (None, Some(s)) => {
                    let sl = line_at(text, s.span().start);
                    target_line = sl;
                    let (name, bits) = parse_signal(s.get_ref()).ok_or_else(|| {
                        field_err(
                            sl,
                            "signal",
                            format!(
                                "`{}`: valid is a signal name, with a bit (\"cnt[3]\") or bits (\"cnt[15:4]\")",
                                s.get_ref()
                            ),
                        )
                    })?;
                    Target::Signal { name, bits }
                }
            };
            if let Some(files) = rtl {
                let matching: Vec<&PathBuf> = files
                    .iter()
                    .filter(|f| file_matches(&f.display().to_string(), &file))
                    .collect();
                let src = match matching.as_slice() {
                    [one] => *one,
                    [] => {
                        return Err(field_err(
                            file_line,
                            "file",
                            format!(
                                "`{file}` is none of the RTL's files ({})",
                                files
                                    .iter()
                                    .filter_map(|f| f.file_name())
                                    .map(|n| n.to_string_lossy().into_owned())
                                    .collect::<Vec<_>>()
                                    .join(", ")
                            ),
                        ))
                    }
                    many => {
                        return Err(field_err(
                            file_line,
                            "file",
                            format!(
                                "`{file}` names {} of the RTL's files ({}): give more of its path",
                                many.len(),
                                many.iter()
                                    .map(|f| f.display().to_string())
                                    .collect::<Vec<_>>()
                                    .join(", ")
                            ),
                        ))
                    }
                };
                let source = std::fs::read_to_string(src).unwrap_or_default();
                match &target {
                    Target::Lines(_, b) | Target::Expr(_, b, _) => {
                        let n = source.lines().count() as u32;
                        if *b > n {
                            return Err(field_err(
                                target_line,
                                "line",
                                format!(
                                    "line {b} is past the end of {} ({n} lines)",
                                    src.display()
                                ),
                            ));
                        }
                    }
                    Target::Signal { name, .. } => {
                        // a name, or a netlist's escaped one (`\\drive_interval.si `)
                        let word = |t: &str| {
                            t.split(|c: char| !(c.is_ascii_alphanumeric() || "_$.\\".contains(c)))
                                .any(|w| w == name || w.trim_start_matches(['\\', '.']) == name)
                        };
                        if !word(&source) {
                            return Err(field_err(
                                target_line,
                                "signal",
                                format!("`{name}` does not appear in {}", src.display()),
                            ));
                        }
                    }
                }
            }
            let holds = match w.holds {
                Some(h) if h.get_ref().trim().is_empty() => {
                    return Err(field_err(
                        line_at(text, h.span().start),
                        "holds",
                        "empty: give the claim as a Verilog expression over the file's module (\"t[17:16] == 2'b00\"), or leave the field out".into(),
                    ))
                }
                Some(h) => Some(h.into_inner().trim().to_string()),
                None => None,
            };
            let kind = w.kind.ok_or_else(|| {
                field_err(
                    at,
                    "kind",
                    format!(
                        "missing: the kind of waiver, one of {}",
                        crate::waiver::Kind::ALL
                            .map(crate::waiver::Kind::name)
                            .join(", ")
                    ),
                )
            })?;
            let kind = crate::waiver::Kind::parse(kind.get_ref())
                .map_err(|e| field_err(line_at(text, kind.span().start), "kind", e))?;
            let reviewer = w
                .reviewer
                .map(|r| r.into_inner().trim().to_string())
                .filter(|r| !r.is_empty())
                .ok_or_else(|| {
                    field_err(
                        at,
                        "reviewer",
                        "missing: who reviewed the waiver (a name or a handle)".into(),
                    )
                })?;
            let checksum = w
                .checksum
                .map(|c| c.into_inner().trim().to_string())
                .unwrap_or_default();
            list.push(Waiver {
                file,
                target,
                reason: reason.trim().to_string(),
                holds,
                at,
                review: crate::waiver::Review {
                    kind,
                    reason: reason.trim().to_string(),
                    reviewer,
                    checksum,
                },
            });
        }
        Ok(Waivers {
            list,
            text: text.to_string(),
            origin: path.display().to_string(),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn term(line: u32, text: &str) -> Point {
        Point {
            file: "rtl/count_diagnosis.v".into(),
            line,
            kind: Kind::Expr,
            comment: text.into(),
            lines: Vec::new(),
        }
    }

    fn parse(text: &str) -> Result<Waivers, WaiverError> {
        Waivers::parse(text, Path::new("w.toml"), None)
    }

    const HEAD: &str = "[[waiver]]\nfile = \"rtl/count_diagnosis.v\"\nreason = \"a reason long enough\"\nkind = \"UNR\"\nreviewer = \"me\"\n";

    #[test]
    fn a_glob_matches_the_whole_text_with_a_star_for_any_characters() {
        assert!(glob("* => 0", "((d == 0)==0 && (d == 1)==0) => 0"));
        assert!(!glob("* => 0", "((d == 0)==1) => 1"));
        assert!(glob("(a==0) => 1", "(a==0) => 1"));
        assert!(!glob("(a==0) => 1", "(a==0) => 1 "));
        assert!(glob(
            "((d == {*1'h1}})==1) => *",
            "((d == {32'h1{1'h1}})==1) => 1"
        ));
        assert!(!glob("a*b*c", "acb"));
        assert!(glob("a*b*c", "abbc"));
        assert!(glob("*", ""));
        assert!(
            !glob("ab*ba", "aba"),
            "the prefix and the suffix do not share characters"
        );
    }

    #[test]
    fn an_expr_waiver_with_a_term_waives_only_the_terms_it_matches() {
        let w = parse(&format!("{HEAD}expr = 27\nterm = \"* => 0\"\n")).unwrap();
        let w = &w.list[0];
        assert_eq!(w.what(), "expr 27 term * => 0");
        assert!(w.covers(&term(27, "((d == 0)==0 && (d == 1)==0) => 0")));
        assert!(
            !w.covers(&term(27, "((d == 0)==1) => 1")),
            "a term it does not match"
        );
        assert!(!w.covers(&term(36, "(x==0) => 0")), "another line");
        // without a term: every term of the lines
        let all = parse(&format!("{HEAD}expr = \"27-28\"\n")).unwrap();
        assert_eq!(all.list[0].what(), "expr 27-28");
        assert!(all.list[0].covers(&term(28, "((d == 0)==1) => 1")));
    }

    #[test]
    fn a_term_without_expr_or_empty_is_refused_at_its_line() {
        let e = parse(&format!("{HEAD}line = 27\nterm = \"* => 0\"\n"))
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("w.toml:7: field `term`: a pattern of expression terms goes with `expr`"),
            "{e}"
        );
        let e = parse(&format!("{HEAD}expr = 27\nterm = \" \"\n"))
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("w.toml:7: field `term`: empty"), "{e}");
    }
}
