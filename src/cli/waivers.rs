//! `pmu50 waivers refresh`: re-check waivers and write the checksum of their source lines again
//! for those checked again, and only those (docs/verification.md "Waivers"). A code-coverage
//! waiver is checked again when the coverage proofs given prove its claim (`holds`) on the RTL
//! as it is; a lint or X waiver when the report given (`pmu50 lint` / `pmu50 xprop` of the RTL
//! as it is) has the very finding it waives, at its rule, file, line and signal. The others keep
//! their checksum and stay stale; each is listed with why.

use super::error::{CliError, CmdResult, Outcome};
use super::io::out;
use pmu50_verif::filelist::FileList;
use pmu50_verif::waiver::{checksum, ends_with_path, set_checksum, SiteWaivers};
use std::path::{Path, PathBuf};

#[derive(clap::Args)]
pub struct Args {
    #[command(subcommand)]
    pub cmd: Sub,
}

#[derive(clap::Subcommand)]
pub enum Sub {
    /// Rewrite the checksums of the waivers checked again (the file rewritten in place, its
    /// comments kept). Exit 0 every waiver current, 1 some left stale, 2 bad input.
    Refresh(RefreshArgs),
}

#[derive(clap::Args)]
pub struct RefreshArgs {
    /// The waivers file.
    #[arg(long, value_name = "FILE.toml")]
    pub waivers: PathBuf,
    /// The RTL's file list.
    #[arg(long, value_name = "FILELIST")]
    pub rtl: PathBuf,
    /// Code-coverage waivers: the coverage proofs of the RTL as it is (`make coverage-proofs`'
    /// coverage.json).
    #[arg(long, value_name = "FILE.json", conflicts_with = "report")]
    pub proofs: Option<PathBuf>,
    /// Lint or X waivers: the report of the RTL as it is (`pmu50 lint` / `pmu50 xprop`).
    #[arg(long, value_name = "FILE.json")]
    pub report: Option<PathBuf>,
}

pub fn run(a: Args) -> CmdResult {
    match a.cmd {
        Sub::Refresh(r) => refresh(r),
    }
}

fn read_json(p: &Path) -> Result<serde_json::Value, CliError> {
    let t =
        std::fs::read_to_string(p).map_err(|e| CliError::Usage(format!("{}: {e}", p.display())))?;
    serde_json::from_str(&t)
        .map_err(|e| CliError::Usage(format!("{}:{}: {e}", p.display(), e.line())))
}

fn source(files: &[PathBuf], file: &str) -> Result<String, CliError> {
    let f = files
        .iter()
        .find(|f| ends_with_path(&f.display().to_string(), file))
        .ok_or_else(|| CliError::Usage(format!("`{file}` is none of the RTL's files")))?;
    std::fs::read_to_string(f).map_err(|e| CliError::Usage(format!("{}: {e}", f.display())))
}

fn refresh(a: RefreshArgs) -> CmdResult {
    let fl = FileList::read(&a.rtl)?;
    let text = std::fs::read_to_string(&a.waivers)
        .map_err(|e| CliError::Usage(format!("{}: {e}", a.waivers.display())))?;
    // (line of the table, new checksum) for those checked again; (what, why) for the others
    let mut set: Vec<(usize, String)> = Vec::new();
    let mut left: Vec<String> = Vec::new();
    let mut current = 0;
    if let Some(p) = &a.proofs {
        let w = pmu50_verif::code_cov::Waivers::read(&a.waivers, Some(&fl.files))
            .map_err(|e| CliError::Usage(e.to_string()))?;
        let proofs = read_json(p)?;
        let verdicts = proofs
            .get("waivers")
            .and_then(|v| v.as_array())
            .cloned()
            .unwrap_or_default();
        for x in &w.list {
            let src = source(&fl.files, &x.file)?;
            let now = checksum(&src, &x.lines(&src));
            let name = format!("{}:{} ({} {})", a.waivers.display(), x.at, x.file, x.what());
            let Some(h) = &x.holds else {
                left.push(format!("{name}: states no claim (holds) to prove"));
                continue;
            };
            let proven = verdicts.iter().any(|v| {
                v.get("file").and_then(|f| f.as_str()) == Some(x.file.as_str())
                    && v.get("what").and_then(|f| f.as_str()) == Some(x.what().as_str())
                    && v.get("holds").and_then(|f| f.as_str()) == Some(h.as_str())
                    && v.get("status").and_then(|f| f.as_str()) == Some("proven")
            });
            if !proven {
                left.push(format!(
                    "{name}: its claim `{h}` is not proven in {}",
                    p.display()
                ));
            } else if x.review.checksum == now {
                current += 1;
            } else {
                set.push((x.at, now));
            }
        }
    } else if let Some(p) = &a.report {
        let w = SiteWaivers::read(&a.waivers).map_err(CliError::Usage)?;
        let report = read_json(p)?;
        let findings: Vec<pmu50_verif::waiver::Finding> = report
            .get("unwaived")
            .cloned()
            .map(serde_json::from_value)
            .transpose()
            .map_err(|e| CliError::Usage(format!("{}: field `unwaived`: {e}", p.display())))?
            .unwrap_or_default();
        let uses: Vec<pmu50_verif::waiver::SiteUse> = report
            .get("waivers")
            .cloned()
            .map(serde_json::from_value)
            .transpose()
            .map_err(|e| CliError::Usage(format!("{}: field `waivers`: {e}", p.display())))?
            .unwrap_or_default();
        for x in &w.list {
            let src = source(&fl.files, &x.file)?;
            let now = checksum(&src, &[x.line]);
            let name = format!(
                "{}:{} ({} {}:{})",
                a.waivers.display(),
                x.at,
                x.rule,
                x.file,
                x.line
            );
            let found = findings.iter().any(|f| {
                f.rule == x.rule
                    && f.line == x.line
                    && ends_with_path(&f.file, &x.file)
                    && (x.signal.is_empty() || x.signal == f.signal)
            }) || uses.iter().any(|u| u.waiver.at == x.at && u.waived > 0);
            if !found {
                left.push(format!("{name}: {} has no such finding", p.display()));
            } else if x.review.checksum == now {
                current += 1;
            } else {
                set.push((x.at, now));
            }
        }
    } else {
        return Err(CliError::Usage(
            "give --proofs FILE.json (code-coverage waivers) or --report FILE.json (lint or X waivers): what checks the waivers again".into(),
        ));
    }
    let mut new = text.clone();
    for (at, sum) in &set {
        new = set_checksum(&new, *at, sum);
    }
    if new != text {
        super::common::write_file(&a.waivers, &new)?;
    }
    for l in &left {
        out!("waivers: not refreshed: {l}");
    }
    out!(
        "waivers: {} checksum(s) written, {} current, {} not checked again ({})",
        set.len(),
        current,
        left.len(),
        a.waivers.display()
    );
    Ok(Outcome::of(left.is_empty()))
}
