//! What every waiver has, whatever it waives (code coverage points, lint warnings, flip-flops
//! without a reset): a kind from a fixed list (OpenTitan's exclusion kinds), a reason, who
//! reviewed it, and the checksum of the RTL source lines it covers. A waiver whose lines have
//! changed since its review no longer applies: it is stale, and the row that reads it says which
//! and where; `pmu50 waivers refresh` writes the checksum again once the waiver is checked again.

use crate::digest::sha256_hex;
use serde::{Deserialize, Serialize};

/// The kind of a waiver.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Serialize, Deserialize)]
pub enum Kind {
    /// Unreachable: no input sequence reaches it (proven, or constant by construction).
    #[serde(rename = "UNR")]
    Unr,
    /// Not RTL of the design: a testbench or debug construct.
    #[serde(rename = "NON_RTL")]
    NonRtl,
    /// The tool does not support the construct.
    #[serde(rename = "UNSUPPORTED")]
    Unsupported,
    /// Covered elsewhere: by another block's verification, or by the system.
    #[serde(rename = "EXTERNAL")]
    External,
    /// Reviewed and accepted as a low risk.
    #[serde(rename = "LOW_RISK")]
    LowRisk,
}

impl Kind {
    pub const ALL: [Kind; 5] = [
        Kind::Unr,
        Kind::NonRtl,
        Kind::Unsupported,
        Kind::External,
        Kind::LowRisk,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Kind::Unr => "UNR",
            Kind::NonRtl => "NON_RTL",
            Kind::Unsupported => "UNSUPPORTED",
            Kind::External => "EXTERNAL",
            Kind::LowRisk => "LOW_RISK",
        }
    }

    /// `UNR`... : the kind; else what is valid.
    pub fn parse(s: &str) -> Result<Kind, String> {
        Kind::ALL
            .into_iter()
            .find(|k| k.name() == s)
            .ok_or_else(|| {
                format!(
                    "`{s}` is not a kind of waiver; valid: {}",
                    Kind::ALL.map(Kind::name).join(", ")
                )
            })
    }
}

/// The review of a waiver: its kind, reason, reviewer and the checksum of its lines.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Review {
    pub kind: Kind,
    pub reason: String,
    pub reviewer: String,
    /// `sha256:<16 hex>` of the lines it covers ([`checksum`]), as reviewed; empty when never
    /// written (a new waiver: `pmu50 waivers refresh` writes it).
    pub checksum: String,
}

/// The checksum of source lines `lines` (from 1) of `source`: `sha256:` and the first 16 hex
/// digits of the SHA-256 of the lines, each without its end-of-line spaces, joined by `\n`.
/// Lines past the end count as empty.
pub fn checksum(source: &str, lines: &[u32]) -> String {
    let all: Vec<&str> = source.lines().collect();
    let mut text = String::new();
    for &l in lines {
        let t = all
            .get((l as usize).wrapping_sub(1))
            .map_or("", |t| t.trim_end());
        text.push_str(&format!("{l}:{t}\n"));
    }
    format!("sha256:{}", &sha256_hex(text.as_bytes())[..16])
}

/// The lines (from 1) of `source` where `name` appears as a word (a signal's declaration, its
/// drivers and readers): what a waiver of that signal covers.
pub fn lines_naming(source: &str, name: &str) -> Vec<u32> {
    source
        .lines()
        .enumerate()
        .filter(|(_, t)| {
            t.split(|c: char| !(c.is_ascii_alphanumeric() || c == '_' || c == '$'))
                .any(|w| w == name)
        })
        .map(|(i, _)| i as u32 + 1)
        .collect()
}

/// Whether a reviewed waiver still applies: its checksum is that of its lines now. `Err` says
/// why not (stale, or never reviewed).
pub fn current(r: &Review, source: &str, lines: &[u32]) -> Result<(), String> {
    let now = checksum(source, lines);
    if r.checksum.is_empty() {
        return Err(format!(
            "no checksum (never reviewed on this source; its lines now {now}): check it and run `pmu50 waivers refresh`"
        ));
    }
    if r.checksum != now {
        return Err(format!(
            "stale: its lines changed since its review (checksum {} reviewed, {now} now)",
            r.checksum
        ));
    }
    Ok(())
}

/// Lines as ranges: `12-14,40`.
pub fn ranges(lines: &[u32]) -> String {
    let mut out: Vec<String> = Vec::new();
    let mut i = 0;
    while i < lines.len() {
        let mut j = i;
        while j + 1 < lines.len() && lines[j + 1] == lines[j] + 1 {
            j += 1;
        }
        out.push(if i == j {
            lines[i].to_string()
        } else {
            format!("{}-{}", lines[i], lines[j])
        });
        i = j + 1;
    }
    out.join(",")
}

/// Set the `checksum = "..."` of the `[[waiver]]` table that starts at line `at` (from 1) of a
/// waivers file's `text` (written after its `reason` when it has none); the rest of the text,
/// comments included, kept.
pub fn set_checksum(text: &str, at: usize, sum: &str) -> String {
    let lines: Vec<&str> = text.split_inclusive('\n').collect();
    let start = at.saturating_sub(1).min(lines.len());
    let end = (start + 1..lines.len())
        .find(|&i| lines[i].trim_start().starts_with('['))
        .unwrap_or(lines.len());
    let new_line = format!("checksum = \"{sum}\"\n");
    let mut out: Vec<String> = lines.iter().map(|l| l.to_string()).collect();
    if let Some(i) = (start..end).find(|&i| lines[i].trim_start().starts_with("checksum")) {
        out[i] = new_line;
    } else {
        // after the last key line of the table
        let last = (start..end)
            .rev()
            .find(|&i| lines[i].contains('=') && !lines[i].trim_start().starts_with('#'))
            .unwrap_or(start);
        let mut l = new_line;
        if !out[last].ends_with('\n') {
            l.insert(0, '\n');
        }
        out.insert(last + 1, l);
    }
    out.concat()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_checksum_changes_with_its_lines_only() {
        let a = "module m;\n  reg [3:0] t;\n  assign x = t;\nendmodule\n";
        let b = "module m;\n  reg [3:0] t;\n  assign x = ~t;\nendmodule\n";
        let c = "module m;  \n  reg [3:0] t;\n  assign x = t;\nendmodule\n";
        assert_ne!(checksum(a, &[3]), checksum(b, &[3]));
        assert_eq!(checksum(a, &[2]), checksum(b, &[2]));
        assert_eq!(checksum(a, &[1, 2]), checksum(c, &[1, 2]), "end spaces");
        assert_eq!(lines_naming(a, "t"), vec![2, 3]);
        assert_eq!(ranges(&[1, 2, 3, 7, 9, 10]), "1-3,7,9-10");
    }

    #[test]
    fn kinds_are_a_fixed_list() {
        assert_eq!(Kind::parse("UNR"), Ok(Kind::Unr));
        let e = Kind::parse("unr").unwrap_err();
        assert!(
            e.contains("UNR, NON_RTL, UNSUPPORTED, EXTERNAL, LOW_RISK"),
            "{e}"
        );
    }

    #[test]
    fn a_checksum_is_written_into_its_own_table() {
        let t = "# c\n[[waiver]]\nfile = \"a\"\nreason = \"r\"\n\n[[waiver]]\nfile = \"b\"\nchecksum = \"old\"\n";
        let u = set_checksum(t, 2, "sha256:1");
        assert_eq!(
            u,
            "# c\n[[waiver]]\nfile = \"a\"\nreason = \"r\"\nchecksum = \"sha256:1\"\n\n[[waiver]]\nfile = \"b\"\nchecksum = \"old\"\n"
        );
        let v = set_checksum(&u, 7, "sha256:2");
        assert!(
            v.ends_with("file = \"b\"\nchecksum = \"sha256:2\"\n"),
            "{v}"
        );
    }
}

/// A finding a check reports at a place of the RTL: a lint warning, a flip-flop without reset.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Finding {
    /// The check's rule (`UNUSEDSIGNAL`, `yosys-check`, `no-reset`).
    pub rule: String,
    /// The RTL file (absolute, or as the tool gave it); empty when the tool gives none.
    pub file: String,
    /// Its line (from 1); 0 when the tool gives none.
    pub line: u32,
    /// The signal or register it is about, when the check names one.
    #[serde(default)]
    pub signal: String,
    pub message: String,
}

/// Findings in order of place: file, line, rule, signal, message.
impl PartialOrd for Finding {
    fn partial_cmp(&self, o: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(o))
    }
}
impl Ord for Finding {
    fn cmp(&self, o: &Self) -> std::cmp::Ordering {
        (
            &self.file,
            self.line,
            &self.rule,
            &self.signal,
            &self.message,
        )
            .cmp(&(&o.file, o.line, &o.rule, &o.signal, &o.message))
    }
}

/// A waiver of findings at one place (a lint or X waivers file, `[[waiver]]` tables): `rule`,
/// `file`, `line`, optional `signal`, and the review (`kind`, `reason`, `reviewer`, `checksum`
/// of its line).
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct SiteWaiver {
    pub rule: String,
    pub file: String,
    pub line: u32,
    #[serde(default)]
    pub signal: String,
    /// Its line in the waivers file.
    pub at: usize,
    pub review: Review,
}

/// A waivers file of [`SiteWaiver`]s.
#[derive(Clone, Debug, Default)]
pub struct SiteWaivers {
    pub list: Vec<SiteWaiver>,
    pub path: String,
    pub text: String,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawSites {
    #[serde(default)]
    waiver: Vec<toml::Spanned<RawSite>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawSite {
    rule: String,
    file: String,
    line: u32,
    #[serde(default)]
    signal: String,
    reason: String,
    kind: String,
    reviewer: String,
    #[serde(default)]
    checksum: String,
}

/// A waiver applied to findings: which it waived, or why it does not apply.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct SiteUse {
    pub waiver: SiteWaiver,
    /// Findings it waived.
    pub waived: u64,
    /// Why it does not apply (stale, no checksum), naming where.
    pub stale: Option<String>,
    /// Its line's checksum now.
    pub checksum: String,
}

impl SiteWaivers {
    /// Read a waivers file: `[[waiver]]` tables with rule, file, line, reason, kind, reviewer
    /// and checksum (signal where the check names one).
    pub fn read(path: &std::path::Path) -> Result<SiteWaivers, String> {
        let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
        let line_at = |at: usize| text[..at.min(text.len())].matches('\n').count() + 1;
        let raw: RawSites = toml::from_str(&text).map_err(|e| {
            format!(
                "{}:{}: {}; valid: [[waiver]] tables with rule, file, line, reason, kind ({}), reviewer, checksum (and signal)",
                path.display(),
                e.span().map_or(1, |s| line_at(s.start)),
                e.message(),
                Kind::ALL.map(Kind::name).join(", ")
            )
        })?;
        let mut list = Vec::new();
        for w in raw.waiver {
            let at = line_at(w.span().start);
            let w = w.into_inner();
            let kind = Kind::parse(&w.kind)
                .map_err(|e| format!("{}:{at}: field `kind`: {e}", path.display()))?;
            if w.reason.trim().len() < 10 {
                return Err(format!(
                    "{}:{at}: field `reason`: say why the finding is accepted (at least 10 characters)",
                    path.display()
                ));
            }
            if w.reviewer.trim().is_empty() {
                return Err(format!(
                    "{}:{at}: field `reviewer`: who reviewed the waiver",
                    path.display()
                ));
            }
            list.push(SiteWaiver {
                rule: w.rule,
                file: w.file,
                line: w.line,
                signal: w.signal,
                at,
                review: Review {
                    kind,
                    reason: w.reason.trim().to_string(),
                    reviewer: w.reviewer.trim().to_string(),
                    checksum: w.checksum,
                },
            });
        }
        Ok(SiteWaivers {
            list,
            path: path.display().to_string(),
            text,
        })
    }

    /// The findings no waiver that applies waives, and each waiver's use. A waiver applies while
    /// the checksum of its line in `files` (the RTL's files) is the reviewed one.
    pub fn apply(
        &self,
        findings: &[Finding],
        files: &[std::path::PathBuf],
    ) -> (Vec<Finding>, Vec<SiteUse>) {
        let mut uses: Vec<SiteUse> = self
            .list
            .iter()
            .map(|w| {
                let src = files
                    .iter()
                    .find(|f| ends_with_path(&f.display().to_string(), &w.file));
                let (stale, checksum) = match src.and_then(|f| std::fs::read_to_string(f).ok()) {
                    None => (
                        Some(format!("stale: {} is none of the RTL's files", w.file)),
                        String::new(),
                    ),
                    Some(s) => (
                        current(&w.review, &s, &[w.line])
                            .err()
                            .map(|e| format!("{e}; line {} of {}", w.line, w.file)),
                        checksum(&s, &[w.line]),
                    ),
                };
                SiteUse {
                    waiver: w.clone(),
                    waived: 0,
                    stale,
                    checksum,
                }
            })
            .collect();
        let mut left = Vec::new();
        for f in findings {
            let by = uses.iter_mut().find(|u| {
                u.stale.is_none()
                    && u.waiver.rule == f.rule
                    && u.waiver.line == f.line
                    && ends_with_path(&f.file, &u.waiver.file)
                    && (u.waiver.signal.is_empty() || u.waiver.signal == f.signal)
            });
            match by {
                Some(u) => u.waived += 1,
                None => left.push(f.clone()),
            }
        }
        (left, uses)
    }
}

/// Whether `path` is `file` or ends with it on a folder boundary.
pub fn ends_with_path(path: &str, file: &str) -> bool {
    !file.is_empty() && (path == file || path.ends_with(&format!("/{file}")))
}
