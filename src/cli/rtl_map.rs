//! `pmu50 rtl-map`: a proposed map for an RTL, found by running it beside the model, for review.

use super::common::write_file;
use super::error::{CmdResult, Outcome};
use super::io::out;
use pmu50_verif::behaviour;
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
    let (m, found) = behaviour::propose(&a.rtl)?;
    let text = behaviour::proposal_toml(&m, &found);
    match &a.output {
        Some(path) => {
            write_file(path, &text)?;
            out!(
                "wrote {} ({} of {} entries)",
                path.display(),
                m.registers.len() + m.internals.len(),
                pmu50_core::signals::N_REGISTERS + pmu50_core::signals::N_INTERNALS
            );
        }
        None => out!("{}", text.trim_end()),
    }
    Ok(Outcome::Pass)
}
