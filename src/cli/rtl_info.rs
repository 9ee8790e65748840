//! `pmu50 rtl-info`: what the regression reads of an RTL, as JSON.

use super::error::{CmdResult, Outcome};
use super::io::out;
use pmu50_verif::dut::Dut;
use std::path::PathBuf;

/// The options of `pmu50 rtl-info`.
#[derive(clap::Args)]
pub struct Args {
    /// The RTL's Verilog file list (top `pmu50` with the contract ports).
    #[arg(long, value_name = "FILELIST")]
    pub rtl: PathBuf,
}

pub fn run(a: Args) -> CmdResult {
    let d = pmu50_verif::dut::VerilatorDut::prepare(&a.rtl, None, Default::default())?;
    let fixed: serde_json::Map<String, serde_json::Value> = d
        .fixed()
        .values
        .iter()
        .map(|(n, v)| (n.clone(), serde_json::Value::from(*v)))
        .collect();
    let info = serde_json::json!({ "rtl": a.rtl.display().to_string(), "parameters": d.top_param_names(), "fixed": fixed, "contract": "ok" });
    out!(
        "{}",
        serde_json::to_string_pretty(&info).unwrap_or_default()
    );
    Ok(Outcome::Pass)
}
