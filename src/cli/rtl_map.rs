//! `pmu50 rtl-map`: a proposed map for an RTL, for review.

use super::common::write_file;
use super::error::{CliError, CmdResult, Outcome};
use super::io::out;
use pmu50_verif::{map, rtl as r};
use std::path::PathBuf;

/// The options of `pmu50 rtl-map`.
#[derive(clap::Args)]
pub struct Args {
    /// The RTL's Verilog file list (top `pmu50` with the contract ports).
    #[arg(long, value_name = "FILELIST")]
    pub rtl: PathBuf,
    /// Write the map here (default: standard output).
    #[arg(short, long)]
    pub output: Option<PathBuf>,
}

pub fn run(a: Args) -> CmdResult {
    let fl = r::FileList::read(&a.rtl)?;
    let work =
        tempfile::tempdir().map_err(|e| CliError::Usage(format!("a scratch folder: {e}")))?;
    let d = r::elaborate(&fl, &[], work.path())?;
    let p = pmu50_core::Params::default();
    let s = pmu50_core::pmu50::Structural {
        sync_depth: d.param("SYNC_DEPTH").map_or(p.sync_depth, |v| v as u8),
        cnt_width: d.param("CNT_W").map_or_else(
            || d.port_width("cnt_s").map_or(p.cnt_width, |w| w as u8),
            |v| v as u8,
        ),
    };
    d.check_contract(&s)?;
    let (m, props) = map::propose(&d, &s);
    let text = map::proposal_toml(&m, &props);
    match &a.output {
        Some(path) => {
            write_file(path, &text)?;
            out!("wrote {}", path.display());
        }
        None => out!("{}", text.trim_end()),
    }
    Ok(Outcome::Pass)
}
