//! `pmu50 hdl`: the HDL kit this binary carries: written out for a team's repository, and the
//! coverage monitor generated from the coverage model.

use super::error::{CliError, CmdResult, Outcome};
use super::io::{err, out};
use clap::Subcommand;
use pmu50_testbench::atomic_file::{self, Batch};
use std::path::{Path, PathBuf};

/// The options of `pmu50 hdl`.
#[derive(clap::Args)]
pub struct Args {
    #[command(subcommand)]
    pub cmd: HdlCmd,
}

#[derive(Subcommand)]
pub enum HdlCmd {
    /// Write the kit into DIR, for an HDL team to take into its own repository. Refuses a DIR
    /// that holds files unless --force.
    Export {
        dir: PathBuf,
        #[arg(long)]
        force: bool,
    },
    /// Write the coverage model as a Verilog monitor: DIR/pmu50_cov.sv (module pmu50_cov, one
    /// hit_<bin> wire per bin), DIR/pmu50_cov_top.sv (the twin with the monitor bound to it) and
    /// DIR/pmu50_cov.json (the bins and their wires); and the top's contract
    /// DIR/pmu50_contract.json (its ports and parameters). The repository keeps them in
    /// hdl/formal.
    CoverageMonitor {
        /// Folder to write into (made if missing).
        #[arg(long, default_value = "hdl/formal")]
        dir: PathBuf,
        /// Write nothing: exit 1 if a file in DIR differs from what would be written.
        #[arg(long)]
        check: bool,
    },
}

pub fn run(a: Args) -> CmdResult {
    match a.cmd {
        HdlCmd::Export { dir, force } => export(&dir, force),
        HdlCmd::CoverageMonitor { dir, check } => coverage_monitor(&dir, check),
    }
}

/// `pmu50 hdl export DIR`.
fn export(dir: &Path, force: bool) -> CmdResult {
    if let Some(kind) = atomic_file::special_kind(dir) {
        return Err(CliError::Usage(format!(
            "{}: is {kind}, not a folder",
            dir.display()
        )));
    }
    if dir.exists() && !dir.is_dir() {
        return Err(CliError::Usage(format!(
            "{}: is a file, not a folder",
            dir.display()
        )));
    }
    if !force
        && std::fs::read_dir(dir)
            .map(|mut d| d.next().is_some())
            .unwrap_or(false)
    {
        return Err(CliError::Usage(format!("{}: the folder holds files; give --force to write the kit into it (files of the kit are replaced, others kept)", dir.display())));
    }
    let n = pmu50_verif::hdl_kit::write(dir)?;
    out!("wrote the HDL kit ({n} files) into {}: the twin (pmu50.f), its map, the testbenches, the FuseSoC core pmu50.core, the formal kit", dir.display());
    Ok(Outcome::Pass)
}

/// `pmu50 hdl coverage-monitor`: the monitor generated from the coverage model.
fn coverage_monitor(dir: &Path, check: bool) -> CmdResult {
    let files = pmu50_coverage::monitor::files();
    if check {
        let stale: Vec<String> = files
            .iter()
            .filter(|(n, text)| std::fs::read_to_string(dir.join(n)).ok().as_deref() != Some(text))
            .map(|(n, _)| dir.join(n).display().to_string())
            .collect();
        if stale.is_empty() {
            out!("the coverage monitor in {} is up to date", dir.display());
            return Ok(Outcome::Pass);
        }
        err!(
            "the coverage monitor is stale: {} (run `pmu50 hdl coverage-monitor --dir {}`)",
            stale.join(", "),
            dir.display()
        );
        return Ok(Outcome::Fail);
    }
    std::fs::create_dir_all(dir)
        .map_err(|e| CliError::Usage(format!("{}: cannot make the folder: {e}", dir.display())))?;
    // the files renamed into place together
    let mut batch = Batch::default();
    for (name, text) in &files {
        batch.add(atomic_file::write_atomic(&dir.join(name), text.as_bytes())?);
    }
    batch.commit()?;
    out!(
        "wrote the coverage monitor ({} bins) into {}: {}",
        pmu50_coverage::layout().bins.len(),
        dir.display(),
        files.map(|(n, _)| n).join(", ")
    );
    Ok(Outcome::Pass)
}
