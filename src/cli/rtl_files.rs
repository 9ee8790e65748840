//! `pmu50 rtl-files`: an RTL's file list as the kit reads it (docs/hdl-guide.md "File lists"), for
//! the scripts and benches that build the RTL with another tool: the formal kit, the coverage
//! proofs, the gate-level flow, cocotb and UVM. One reader, so every tool sees the same RTL.

use super::error::{CmdResult, Outcome};
use super::io::out;
use pmu50_verif::filelist::FileList;
use std::path::PathBuf;

/// The options of `pmu50 rtl-files`.
#[derive(clap::Args)]
pub struct Args {
    /// The RTL's file list (`+incdir+`, `+define+`, `-f`/`-F`, `-y`, `+libext+`, `-v` and
    /// comments as docs/hdl-guide.md describes; paths relative to the list naming them).
    #[arg(long, value_name = "FILELIST")]
    pub rtl: PathBuf,
    /// Print JSON: `files`, `incdirs`, `defines` (name, value), `libdirs`, `libext`,
    /// `libfiles`, `lists` (every list read) and `content_hash`. Default: a flat list, one
    /// absolute entry per line, that any tool's `-f` reads.
    #[arg(long)]
    pub json: bool,
}

pub fn run(a: Args) -> CmdResult {
    let fl = FileList::read(&a.rtl)?;
    if a.json {
        let s =
            |v: &[PathBuf]| -> Vec<String> { v.iter().map(|p| p.display().to_string()).collect() };
        let defines: Vec<serde_json::Value> = fl
            .defines
            .iter()
            .map(|(n, v)| serde_json::json!({ "name": n, "value": v }))
            .collect();
        let j = serde_json::json!({
            "list": fl.list.display().to_string(),
            "files": s(&fl.files),
            "incdirs": s(&fl.incdirs),
            "defines": defines,
            "libdirs": s(&fl.libdirs),
            "libext": fl.libext,
            "libfiles": s(&fl.libfiles),
            "lists": s(&fl.lists),
            "content_hash": fl.content_hash()?,
        });
        out!("{}", serde_json::to_string_pretty(&j).unwrap_or_default());
    } else {
        for d in &fl.incdirs {
            out!("+incdir+{}", d.display());
        }
        for d in fl.define_args() {
            out!("+define+{d}");
        }
        for d in &fl.libdirs {
            out!("-y {}", d.display());
        }
        if !fl.libdirs.is_empty() {
            out!("+libext+{}", fl.libext.join("+"));
        }
        for f in &fl.libfiles {
            out!("-v {}", f.display());
        }
        for f in &fl.files {
            out!("{}", f.display());
        }
    }
    Ok(Outcome::Pass)
}
