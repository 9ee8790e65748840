//! `pmu50 seal`: the provenance and digest of a JSON file of evidence, written by the kit's one
//! implementation (verif/src/provenance.rs) for the scripts that make such files (the formal
//! kit, the coverage proofs); `--check` verifies one.

use super::common::write_file;
use super::error::{CliError, CmdResult, Outcome};
use super::io::out;
use pmu50_verif::filelist::FileList;
use pmu50_verif::provenance::{self, Provenance, RtlId, Seeds};
use std::path::PathBuf;

/// The options of `pmu50 seal`.
#[derive(clap::Args)]
pub struct Args {
    /// The JSON file (an object), rewritten in place with `provenance` and `digest`.
    pub file: PathBuf,
    /// Verify the file instead: its digest matches and it has a provenance; print the
    /// provenance. Exit 2 when it was edited or has none.
    #[arg(long, conflicts_with_all = ["made_by", "rtl", "dut", "seeds"])]
    pub check: bool,
    /// What made the file (`hdl/formal/run.py`).
    #[arg(long, required_unless_present = "check")]
    pub made_by: Option<String>,
    /// The RTL the evidence is about (its file list; its content hash is recorded).
    #[arg(long, value_name = "FILELIST")]
    pub rtl: Option<PathBuf>,
    /// The DUT or engine (`formal`, `verilator`).
    #[arg(long, default_value = "formal")]
    pub dut: String,
    /// The seed range, `START:COUNT`.
    #[arg(long)]
    pub seeds: Option<String>,
}

pub fn run(a: Args) -> CmdResult {
    let text = std::fs::read_to_string(&a.file)
        .map_err(|e| CliError::Usage(format!("{}: {e}", a.file.display())))?;
    if a.check {
        let (_, p) = provenance::open(&a.file, &text, "the command that makes it")
            .map_err(|e| CliError::Usage(e.to_string()))?;
        out!("{}", serde_json::to_string_pretty(&p).unwrap_or_default());
        return Ok(Outcome::Pass);
    }
    let v: serde_json::Value = serde_json::from_str(&text)
        .map_err(|e| CliError::Usage(format!("{}:{}: {e}", a.file.display(), e.line())))?;
    let serde_json::Value::Object(m) = v else {
        return Err(CliError::Usage(format!(
            "{}: not a JSON object",
            a.file.display()
        )));
    };
    let rtl = match &a.rtl {
        Some(l) => {
            let fl = FileList::read(l)?;
            Some(RtlId {
                list: l.display().to_string(),
                hash: fl.content_hash()?,
            })
        }
        None => None,
    };
    let seeds = match &a.seeds {
        Some(s) => {
            let bad = || CliError::Usage(format!("--seeds {s}: valid is START:COUNT"));
            let (x, n) = s.split_once(':').ok_or_else(bad)?;
            Some(Seeds {
                start: x.parse().map_err(|_| bad())?,
                count: n.parse().map_err(|_| bad())?,
            })
        }
        None => None,
    };
    let p = Provenance::now(a.made_by.as_deref().unwrap_or(""), rtl, &a.dut, seeds);
    write_file(&a.file, &provenance::seal(m, &p))?;
    Ok(Outcome::Pass)
}
