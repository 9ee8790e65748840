//! The waveform of a shrunk failure: the model's VCD of every signal of the repro, with a
//! GTKWave save file zoomed on the first divergence and a named marker there.

use super::check::Failure;
use super::RegressError;
use crate::output::{run_to_batch_focused, FileOptions, Focus};
use crate::scenario::Scenario;
use crate::waveform::{Level, WaveFormat};
use std::path::Path;

/// Write `repro.vcd` and `repro.gtkw` into `folder` from the repro's TOML text.
pub fn write(folder: &Path, toml: &str, name: &str, f: &Failure) -> Result<(), RegressError> {
    let path = folder.join("repro.toml");
    let mut sc = Scenario::parse(toml, &path.display().to_string(), name, &path).map_err(|e| RegressError::File { path: path.clone(), reason: e.to_string() })?;
    sc.name = "repro".into();
    let fo = FileOptions { level: Level::All, ..FileOptions::default() };
    // The marker sits on the edge that diverged (tick k: the end of bench tick k - 1).
    let focus = Focus { tick: f.tick.min(sc.ticks), name: format!("first divergence: {}", f.signal.trim_start_matches("pmu50.")).to_lowercase(), before: 60, after: 20 };
    let (_, _, batch) = run_to_batch_focused(&sc, folder, fo, WaveFormat::Vcd, &mut [], Some(&focus)).map_err(|e| RegressError::File { path: folder.join("repro.vcd"), reason: e.to_string() })?;
    batch.commit()?;
    Ok(())
}
