//! The waveform of a shrunk failure: the model's VCD of every signal of the repro around the
//! first divergence, with a GTKWave save file zoomed there and a named marker on it.

use crate::check::Failure;
use crate::error::RegressError;
use pmu50_testbench::observers::waveform::{Level, WaveFormat};
use pmu50_testbench::output::{run_to_batch_focused, FileOptions, Focus};
use pmu50_testbench::scenario::Scenario;
use std::path::Path;

/// Write `repro.vcd` and `repro.gtkw` into `folder` from the repro's TOML text.
pub fn write(folder: &Path, toml: &str, name: &str, f: &Failure) -> Result<(), RegressError> {
    let path = folder.join("repro.toml");
    let mut sc = Scenario::parse(toml, &path.display().to_string(), name, &path).map_err(|e| {
        RegressError::File {
            path: path.clone(),
            reason: e.to_string(),
        }
    })?;
    sc.name = "repro".into();
    // The marker sits on the edge that diverged (tick k: the end of bench tick k - 1). The file
    // holds the 400 ticks before it and 40 after (GTKWave opens a file at its first time).
    let tick = f.tick.min(sc.ticks);
    let window = (
        tick.saturating_sub(400),
        (tick + 40).min(sc.ticks).max(tick.saturating_sub(400) + 1),
    );
    let fo = FileOptions {
        level: Level::All,
        window: Some(window),
        ..FileOptions::default()
    };
    let focus = Focus {
        tick,
        name: format!(
            "first divergence: {}",
            f.signal.trim_start_matches("pmu50.")
        )
        .to_lowercase(),
        before: 400,
        after: 40,
    };
    let (_, _, batch) =
        run_to_batch_focused(&sc, folder, fo, WaveFormat::Vcd, &mut [], Some(&focus)).map_err(
            |e| RegressError::File {
                path: folder.join("repro.vcd"),
                reason: e.to_string(),
            },
        )?;
    batch.commit()?;
    Ok(())
}
