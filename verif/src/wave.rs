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
        tick.saturating_sub(BEFORE),
        (tick + AFTER)
            .min(sc.ticks)
            .max(tick.saturating_sub(BEFORE) + 1),
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
        before: BEFORE,
        after: AFTER,
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

/// Ticks of `repro.vcd` and `rtl.vcd` before and after the divergence.
const BEFORE: u64 = 400;
const AFTER: u64 = 40;
/// Ticks of `compare.vcd` before and after the divergence: what GTKWave shows when it opens
/// (it opens a file at its first time, whatever the save file's `[timestart]` says).
const COMPARE_BEFORE: u64 = 40;
const COMPARE_AFTER: u64 = 8;

/// The window of ticks of a failure's `repro.vcd` and of the RTL's own `rtl.vcd`.
pub fn rtl_window(tick: u64, ticks: u64) -> (u64, u64) {
    let from = tick.saturating_sub(BEFORE);
    (from, (tick + AFTER).min(ticks).max(from))
}

/// The window of ticks of a failure's `compare.vcd` (and of the DUT's trace it is drawn from).
pub fn compare_window(tick: u64, ticks: u64) -> (u64, u64) {
    let from = tick.saturating_sub(COMPARE_BEFORE);
    (from, (tick + COMPARE_AFTER).min(ticks).max(from))
}

/// Write `compare.vcd` and `compare.gtkw`: the inputs, the register bus whenever the run uses
/// it, and each signal that differs at the failing tick as the model has it (`model.<name>`)
/// beside the RTL's (`rtl.<name>`, from the DUT's trace), one sample a tick at k x the clock
/// period, in the time unit of `repro.vcd`; GTKWave opens on the divergence with a marker.
pub fn write_compare(
    folder: &Path,
    sc: &Scenario,
    f: &Failure,
    trace: Option<&crate::dut::DutTrace>,
) -> Result<(), RegressError> {
    use pmu50_waves::gtkw::{Color, Format, GtkwSave, Trace};
    use pmu50_waves::writer::{BitType, Logic, VcdBuilder};
    use pmu50_waves::{TimeUnit, Timescale};
    let err = |path: &str, e: String| RegressError::File {
        path: folder.join(path),
        reason: e,
    };
    let (from, to) = compare_window(f.tick, sc.ticks);
    let cap = crate::picture::Capture::run(sc, from, to)
        .map_err(|e| err("compare.vcd", e.to_string()))?;
    // time as in repro.vcd: microseconds when the clock period is a whole number of them
    let (unit, ns) = if sc.clock_ns().is_multiple_of(1000) && sc.clock_ns() > 0 {
        (TimeUnit::Us, sc.clock_ns() / 1000)
    } else {
        (TimeUnit::Ns, sc.clock_ns().max(1))
    };
    // rows: (scope, name, width, values)
    let mut rows: Vec<(&str, String, u8, Vec<Option<u64>>)> = Vec::new();
    let mut inputs = vec!["ig", "vs2_ok", "cmp_s", "cmp_c"];
    if cap.uses_bus() {
        inputs.extend(["bus_we", "bus_addr", "bus_wdata"]);
    }
    for n in inputs {
        if let Some((b, v)) = cap.values(&format!("in {n}")) {
            rows.push(("inputs", n.to_string(), b, v));
        }
    }
    let mut pairs = crate::picture::diverging(f);
    if cap.uses_bus() && !pairs.iter().any(|p| p == "bus_rdata") {
        pairs.push("bus_rdata".into());
    }
    for p in &pairs {
        let Some((b, v)) = cap.values(p) else {
            continue;
        };
        let name = p.replace('.', "_");
        rows.push(("model", name.clone(), b, v));
        if let Some(d) = trace.and_then(|t| crate::picture::dut_values(t, p, from, to)) {
            rows.push(("rtl", name, b, d));
        }
    }
    let ts = Timescale::new(1, unit);
    let mut b = VcdBuilder::new(ts, "pmu50 regress: the model and the RTL of a failure")
        .map_err(|e| err("compare.vcd", e.to_string()))?;
    b.window(from * ns, (to + 1) * ns)
        .map_err(|e| err("compare.vcd", e.to_string()))?;
    let mut ids = Vec::new();
    let mut names = Vec::new();
    for scope in ["inputs", "model", "rtl"] {
        if !rows.iter().any(|r| r.0 == scope) {
            continue;
        }
        b.push_scope(scope)
            .map_err(|e| err("compare.vcd", e.to_string()))?;
        for (k, r) in rows.iter().enumerate().filter(|(_, r)| r.0 == scope) {
            let init = r.3.first().copied().flatten().unwrap_or(0);
            let id = if r.2 <= 1 {
                b.add_bit(BitType::Wire, &r.1, Logic::from(init != 0))
            } else {
                b.add_vector(BitType::Wire, &r.1, u32::from(r.2) - 1, 0, init)
            }
            .map_err(|e| err("compare.vcd", e.to_string()))?;
            names.push((
                k,
                b.gtkwave_name(id)
                    .map_err(|e| err("compare.vcd", e.to_string()))?,
            ));
            ids.push((k, id));
        }
        b.pop_scope()
            .map_err(|e| err("compare.vcd", e.to_string()))?;
    }
    let mut w = b
        .start(Vec::new())
        .map_err(|e| err("compare.vcd", e.to_string()))?;
    for (c, e) in (from..=to).enumerate() {
        w.set_time(e * ns)
            .map_err(|e| err("compare.vcd", e.to_string()))?;
        for (k, id) in &ids {
            if let Some(v) = rows[*k].3.get(c).copied().flatten() {
                if c > 0 && rows[*k].3.get(c - 1).copied().flatten() == Some(v) {
                    continue;
                }
                if rows[*k].2 <= 1 {
                    w.change_bool(*id, v != 0)
                } else {
                    w.change_vector(*id, v)
                }
                .map_err(|e| err("compare.vcd", e.to_string()))?;
            }
        }
    }
    let vcd = w.finish().map_err(|e| err("compare.vcd", e.to_string()))?;
    // the save file: the inputs, then each signal's model and RTL rows together
    let gerr = |e: pmu50_waves::gtkw::GtkwError| err("compare.gtkw", e.to_string());
    let mut g = GtkwSave::new("compare.vcd").map_err(gerr)?;
    let name_of = |k: usize| names.iter().find(|(j, _)| *j == k).map(|(_, n)| n.clone());
    let trace_of = |k: usize, colour: Option<Color>| -> Option<Trace> {
        let mut t = Trace::new(name_of(k)?);
        if crate::picture::is_bus(&rows[k].1) {
            t = t.format(Format::Hex);
        } else if rows[k].2 > 1 {
            t = t.format(Format::Decimal);
        }
        if let Some(c) = colour {
            t = t.color(c);
        }
        Some(t)
    };
    g.begin_group("inputs", false).map_err(gerr)?;
    for (k, _) in rows.iter().enumerate().filter(|(_, r)| r.0 == "inputs") {
        if let Some(t) = trace_of(k, None) {
            g.trace(t).map_err(gerr)?;
        }
    }
    g.end_group().map_err(gerr)?;
    for p in &pairs {
        let name = p.replace('.', "_");
        g.begin_group(&format!("{p}: model / RTL"), false)
            .map_err(gerr)?;
        for (k, _) in rows
            .iter()
            .enumerate()
            .filter(|(_, r)| r.0 != "inputs" && r.1 == name)
        {
            // both rows of a pair are called `<p>` in the VCD: the alias says whose it is
            let (colour, side) = if rows[k].0 == "model" {
                (Color::Green, "model")
            } else {
                (Color::Red, "RTL")
            };
            if let Some(t) = trace_of(k, Some(colour)) {
                g.trace(t.alias(format!("{side} {p}"))).map_err(gerr)?;
            }
        }
        g.end_group().map_err(gerr)?;
    }
    let tick = f.tick.clamp(from, to);
    g.fit(from * ns, to.max(from + 1) * ns);
    g.marker(
        tick * ns,
        &format!("divergence at tick {}: {}", f.tick, pairs_text(f)),
    )
    .map_err(gerr)?;
    let gtkw = g.render().map_err(gerr)?;
    let mut batch = pmu50_testbench::atomic_file::Batch::new();
    batch.add(pmu50_testbench::atomic_file::write_atomic(
        &folder.join("compare.vcd"),
        &vcd,
    )?);
    batch.add(pmu50_testbench::atomic_file::write_atomic(
        &folder.join("compare.gtkw"),
        gtkw.as_bytes(),
    )?);
    batch.commit()?;
    Ok(())
}

/// `si, bus_err` for a marker.
fn pairs_text(f: &Failure) -> String {
    crate::picture::diverging(f).join(", ").to_lowercase()
}
