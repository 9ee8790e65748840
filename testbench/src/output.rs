//! Running a scenario to files (VCD, GTKWave save file, change log) and the text summary.
//!
//! Every file goes through [`crate::atomic_file`]: written beside its final path, renamed into place
//! when the run is complete, the `.gtkw` last.

use crate::atomic_file::{self, AtomicFile, Batch, OutputError};
use crate::observers::changelog::ChangeLog;
use crate::observers::markers::MarkerObserver;
use crate::observers::waveform::{timescale_for, Level, VcdObserver, WaveFormat};
use crate::scenario::{Scenario, Trace};
use crate::sim::{self, Observer, RunResult, SimError, SimOptions, TickView};
use pmu50_core::pmu50::Structural;
use pmu50_core::Pmu50;
use std::io::BufWriter;
use std::path::{Path, PathBuf};

/// First line of a change log (to recognise a stale `.log` of an earlier run).
pub const LOG_HEADER: &str = "# tick      time_us  register";

/// What to write besides the VCD and its save file.
#[derive(Clone, Copy, Debug, Default)]
pub struct FileOptions {
    /// Also write `<name>.log`, one line per register change.
    pub log: bool,
    /// Dump window in ticks (overrides the scenario's `[vcd] window`).
    pub window: Option<(u64, u64)>,
    /// Also write `<name>.svg`, a timing diagram in the style of the patent's FIG. 15/16 of the
    /// whole run or of the window, with its numbers in `<name>_timing.csv` (testbench/src/observers/timing.rs).
    pub svg: bool,
    /// The signals of the waveform (`--trace`, `[vcd] trace`; default `all`).
    pub level: Level,
}

/// Paths written by [`run_to_files`].
#[derive(Clone, Debug)]
pub struct Written {
    pub vcd: PathBuf,
    pub gtkw: PathBuf,
    pub log: Option<PathBuf>,
    pub svg: Option<WrittenSvg>,
}

/// A run failed: the model or an observer, or an output file.
#[derive(Debug, thiserror::Error)]
pub enum RunError {
    #[error(transparent)]
    Sim(#[from] SimError),
    #[error(transparent)]
    Output(#[from] OutputError),
    #[error("{}: save file: {source}", path.display())]
    Gtkw {
        path: PathBuf,
        #[source]
        source: pmu50_waves::gtkw::GtkwError,
    },
    #[error("{}: the {what} was not finished by the run (internal error)", path.display())]
    Unfinished { path: PathBuf, what: &'static str },
}

/// The files a run writes, for `dir` and scenario `name` (to detect two scenarios writing the
/// same file before anything runs).
pub fn output_paths(dir: &Path, name: &str, log: bool) -> Vec<PathBuf> {
    let mut v = vec![
        dir.join(format!("{name}.vcd")),
        dir.join(format!("{name}.gtkw")),
    ];
    if log {
        v.push(dir.join(format!("{name}.log")));
    }
    let svg = svg_paths(dir, name);
    v.extend([svg.svg, svg.csv]);
    v
}

fn svg_paths(dir: &Path, name: &str) -> WrittenSvg {
    WrittenSvg {
        svg: dir.join(format!("{name}.svg")),
        csv: dir.join(format!("{name}_timing.csv")),
    }
}

/// Estimated size in bytes of the VCD of every signal (`trace = all`) for `ticks` dumped ticks:
/// [`estimate_wave_bytes`] at `Level::All`, `WaveFormat::Vcd`.
pub fn estimate_vcd_bytes(ticks: u64) -> u64 {
    estimate_wave_bytes(ticks, Level::All, WaveFormat::Vcd)
}

/// Estimated size in bytes of the waveform of `ticks` dumped ticks at `level` in `format`: an
/// upper bound per tick plus the header. The bounds are measured, not derived: the worst case is a
/// run with the key on all the time and the shaft turning fast (bus polling, every analog value
/// moving every tick); key-off runs write far less (test `size_estimates_are_upper_bounds` in
/// tests/trace_levels.rs checks both ends). Bytes per tick, VCD / FST, measured with
/// target/release/pmu50 (`pmu50 run FILE --trace LEVEL --format F`, file size / ticks): `on` is the
/// test's 50 ms key-on run turning 2000 deg; `keyoff 1 min` is 10 ms of key-on then a minute of
/// key-off, the shaft still:
///
/// | level | on | too_fast | keyoff_turns | threshold_error | keyoff 1 min |
/// |---|---|---|---|---|---|
/// | all | 135.0 / 12.1 | 47.8 / 3.0 | 41.1 / 1.36 | 41.5 / 2.08 | 31.0 / 0.017 |
/// | registers | 134.3 / 12.1 | 47.6 / 3.0 | 40.9 / 1.36 | 41.4 / 2.08 | 30.9 / 0.017 |
/// | ports | 96.8 / 11.8 | 21.2 / 2.8 | 13.4 / 1.32 | 15.5 / 2.04 | 1.5 / 0.003 |
///
/// Six random scenarios of `pmu50 random --seed 1..6` (key on and off, turning) write 57-91 / 4.2-9.6
/// bytes per tick at `all` and 29-55 / 4.1-9.5 at `ports`.
///
/// The bound is the key-on figure with about 20 % margin for the VCD (text: the same values give
/// the same bytes) and 50 % for the FST (its compression depends on how the values repeat). The
/// internals change rarely, so `registers` is bounded like `all`; in the FST the analog reals,
/// which every level has, dominate the worst case, so the levels share one bound.
pub fn estimate_wave_bytes(ticks: u64, level: Level, format: WaveFormat) -> u64 {
    let per_tick = match (format, level) {
        (WaveFormat::Vcd, Level::All | Level::Registers) => 160,
        (WaveFormat::Vcd, Level::Ports) => 115,
        (WaveFormat::Fst, _) => 18,
    };
    WAVE_HEADER_BYTES + ticks.saturating_mul(per_tick)
}

/// Estimated size in bytes of the waveform of a run of `sc` dumping the ticks of `window` (else
/// the scenario's window, else the whole run) at `level` in `format`: [`estimate_wave_bytes`]
/// for the active ticks, and a lower bound per tick for the parked ones ([`parked_ticks`]).
///
/// A parked tick (key off, shaft still, no fault) changes only what a key-off output pulse
/// changes, plus the free-running timer `tmr` every tick at `registers` and `all`. Pulses come at
/// most every `si_min` ticks (the drive interval never goes below it, [0228]) and each changes
/// values for at most its window Wt = Pw + Pi + Ps and the settling of the second sensor after it
/// (11 time constants from 5 V to the 0.1 mV the VCD rounds to). So a parked tick costs at most
/// the base (`tmr`'s 20-byte value line and a time stamp of up to 18 bytes: 48 bytes of VCD; 1 of
/// FST) plus the active bound times the busy share (Wt + settling) / si_min, at most 1. With the
/// defaults (Wt 22 ticks, settling 24, si_min 220) that is 82 / 25 bytes per tick of VCD at
/// `all` / `ports` and 4.8 of FST, against 31 / 1.5 / 0.017 measured for a minute of key-off
/// (README). Parks measured against it (5 s, release build, real / estimate): a fixed 1 ms cycle
/// 18.2 / 56.8 MB (`all` VCD), 4.7 / 27.0 MB (`ports` VCD), 18 kB / 4.7 MB (`all` FST); a 300 us
/// sensor time constant, 15.0 / 100 MB and 0.75 / 58 MB; a fast turn then a hold at a 0.5 ms
/// si_min, 15.4 / 93 MB and 1.4 / 54 MB; a 2.5 ms output window, 15.3 / 93 MB and 0.96 / 53 MB
/// (estimates with a 40-byte base; tests/trace_levels.rs `parked_estimates_are_upper_bounds`).
pub fn estimate_run_bytes(
    sc: &Scenario,
    window: Option<(u64, u64)>,
    level: Level,
    format: WaveFormat,
) -> u64 {
    let (a, z) = window.or(sc.vcd_window).unwrap_or((0, sc.ticks));
    let z = z.min(sc.ticks);
    let dumped = z.saturating_sub(a);
    let parked = parked_ticks(sc, a, z);
    let active = estimate_wave_bytes(dumped - parked, level, format);
    let p = &sc.params;
    let settle = (PARK_SETTLE_TAUS * sc.env.sensor2.tau_us * 1e3 / sc.clock_ns() as f64)
        .ceil()
        .max(0.0) as u64;
    let busy = u64::from(p.pw) + u64::from(p.pi) + u64::from(p.ps) + settle;
    let si_min = u64::from(p.si_min).max(1);
    let rate = estimate_wave_bytes(1, level, format) - WAVE_HEADER_BYTES;
    let base = match (format, level) {
        (_, Level::Ports) => 1,
        (WaveFormat::Vcd, _) => 48,
        (WaveFormat::Fst, _) => 1,
    };
    // Bytes per 1000 parked ticks, rounded up.
    let per_kilotick = base * 1000 + (rate * 1000 * busy.min(si_min)).div_ceil(si_min);
    active.saturating_add(parked.saturating_mul(per_kilotick).div_ceil(1000))
}

/// Time constants of the second sensor's settling counted after an output pulse (e^-11 of 5 V is
/// below the 0.1 mV the waveform rounds to).
const PARK_SETTLE_TAUS: f64 = 11.0;

/// Ticks of [a, z) that are parked: the key off (from the tick after `ig` falls plus the
/// synchroniser, one output window and the sensor's settling, until `ig` rises), the shaft
/// still (outside every move segment, one tick either side) and no Vs2 fault injected; none in a
/// scenario that writes a register. Every other tick is active, bounded by [`estimate_wave_bytes`].
pub fn parked_ticks(sc: &Scenario, a: u64, z: u64) -> u64 {
    use crate::scenario::Action;
    // A register write (key on) may change Pw, Pi, Ps or si_min for the parks after it: then no
    // tick counts as parked.
    if z <= a
        || sc
            .events
            .iter()
            .any(|e| matches!(e.action, Action::Write { .. }))
    {
        return 0;
    }
    let clk = sc.clock_ns().max(1);
    let p = &sc.params;
    let settle = (PARK_SETTLE_TAUS * sc.env.sensor2.tau_us * 1e3 / clk as f64)
        .ceil()
        .max(0.0) as u64;
    let after_off =
        u64::from(p.sync_depth) + 2 + u64::from(p.pw) + u64::from(p.pi) + u64::from(p.ps) + settle;
    // Active intervals [from, to) in ticks.
    let mut active: Vec<(u64, u64)> = Vec::new();
    // Before the first event the key is off since power-on; the reset itself is a key-off edge.
    active.push((0, after_off));
    // (on, since) of the key and of the Vs2 fault: a stretch of either is active from its start
    // to `after_off` past its end.
    let (mut ig, mut fault) = ((false, 0u64), (false, 0u64));
    let mut switch = |state: &mut (bool, u64), on: bool, tick: u64| {
        if on == state.0 {
            return;
        }
        if on {
            state.1 = tick;
        } else {
            active.push((state.1, tick.saturating_add(after_off)));
        }
        state.0 = on;
    };
    for e in &sc.events {
        match e.action {
            Action::Ig(on) => switch(&mut ig, on, e.tick),
            Action::Vs2Fault(on) => switch(&mut fault, on, e.tick),
            _ => {}
        }
    }
    for (on, since) in [ig, fault] {
        if on {
            active.push((since, u64::MAX));
        }
    }
    let mut t_ns = 0u64;
    for seg in sc.motor.segments() {
        let d = seg.duration_ns();
        if matches!(seg, pmu50_env::Segment::Move { .. }) {
            active.push((
                (t_ns / clk).saturating_sub(1),
                (t_ns.saturating_add(d)).div_ceil(clk).saturating_add(1),
            ));
        }
        t_ns = t_ns.saturating_add(d);
    }
    active.sort_unstable();
    // Length of the union of the active intervals within [a, z).
    let mut busy = 0u64;
    let mut reach = a;
    for (from, to) in active {
        let (from, to) = (from.max(reach), to.min(z));
        if to > from {
            busy += to - from;
            reach = to;
        }
    }
    (z - a) - busy
}

/// Header of either format (declarations, save-file-independent), rounded up.
const WAVE_HEADER_BYTES: u64 = 16 * 1024;

/// The largest estimated `all` waveform a run writes when neither `--trace` nor `[vcd] trace`
/// says a level: above it the run writes `ports`. 256 MiB: GTKWave loads a VCD of that size in
/// seconds and it fits any disk; with the bounds of [`estimate_wave_bytes`] that is 1.68 M ticks
/// (16.8 s at the default 10 us clock) in VCD, 14.9 M ticks in FST. Every shipped scenario that
/// writes a waveform (3.6 s at most) stays below it and keeps its VCD of every signal. A minute
/// of key-off writes 186 MB of `all` VCD (31 bytes per tick, the timer `tmr` every tick) but 8.9
/// MB of `ports`.
pub const DEFAULT_ALL_MAX_BYTES: u64 = 256 << 20;

/// Where the trace level of a run comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TraceFrom {
    /// `--trace` on the command line.
    Flag,
    /// `[vcd] trace` in the scenario.
    Scenario,
    /// Neither: chosen from the estimated size of the `all` waveform of the dumped ticks.
    Default { all_estimate: u64 },
}

/// The trace level of a run and why ([`choose_trace`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TraceChoice {
    pub trace: Trace,
    pub from: TraceFrom,
}

/// Ticks dumped by a run of `sc` with the dump window `window` (else the scenario's, else all).
pub fn dumped_ticks(sc: &Scenario, window: Option<(u64, u64)>) -> u64 {
    let (a, z) = window.or(sc.vcd_window).unwrap_or((0, sc.ticks));
    z.min(sc.ticks).saturating_sub(a)
}

/// The trace level of a run of `sc`: `flag` (`--trace`) if given, else the scenario's
/// `[vcd] trace`, else `all` when the estimated `all` waveform ([`estimate_run_bytes`] of the
/// dumped ticks of `window`, in `format`) is at most [`DEFAULT_ALL_MAX_BYTES`], otherwise `ports`.
pub fn choose_trace(
    sc: &Scenario,
    flag: Option<Trace>,
    window: Option<(u64, u64)>,
    format: WaveFormat,
) -> TraceChoice {
    if let Some(trace) = flag {
        return TraceChoice {
            trace,
            from: TraceFrom::Flag,
        };
    }
    if let Some(trace) = sc.trace {
        return TraceChoice {
            trace,
            from: TraceFrom::Scenario,
        };
    }
    let all_estimate = estimate_run_bytes(sc, window, Level::All, format);
    let level = if all_estimate <= DEFAULT_ALL_MAX_BYTES {
        Level::All
    } else {
        Level::Ports
    };
    TraceChoice {
        trace: Trace::Wave(level),
        from: TraceFrom::Default { all_estimate },
    }
}

/// A size for messages: `58.0 MB`, `1.2 GB`, `900 kB`.
pub fn human_bytes(bytes: u64) -> String {
    let b = bytes as f64;
    if b >= 1e9 {
        format!("{:.1} GB", b / 1e9)
    } else if b >= 1e6 {
        format!("{:.1} MB", b / 1e6)
    } else {
        format!("{:.0} kB", b / 1e3)
    }
}

impl TraceChoice {
    /// One line for the run summary: the level, why, and how to ask for another.
    pub fn describe(&self, format: WaveFormat) -> String {
        let name = self.trace.name();
        let ext = format.ext().to_uppercase();
        match self.from {
            TraceFrom::Flag => format!("trace = {name} (--trace)"),
            TraceFrom::Scenario => format!("trace = {name} ([vcd] trace of the scenario; --trace overrides it)"),
            TraceFrom::Default { all_estimate } if self.trace == Trace::ALL => format!(
                "trace = all (chosen for this run: the {ext} of every signal is at most about {}, within the default's limit of {} MiB; ask for less with --trace registers, ports or none, or [vcd] trace in the scenario)",
                human_bytes(all_estimate),
                DEFAULT_ALL_MAX_BYTES >> 20
            ),
            TraceFrom::Default { all_estimate } => format!(
                "trace = {name} (chosen for this run: the {ext} of every signal could reach about {}, above the default's limit of {} MiB; ask for more with --trace registers or all, or [vcd] trace in the scenario, and --window START END for a part of the run)",
                human_bytes(all_estimate),
                DEFAULT_ALL_MAX_BYTES >> 20
            ),
        }
    }
}

/// Run `sc` and stage its files (temporary files, not yet in place); the returned batch renames
/// them into place. `extra` observers (a progress bar, a vector writer) see every tick as well.
pub fn run_to_batch(
    sc: &Scenario,
    dir: &Path,
    fo: FileOptions,
    extra: &mut [&mut dyn Observer],
) -> Result<(RunResult, Written, Batch), RunError> {
    run_to_batch_as(sc, dir, fo, WaveFormat::Vcd, extra)
}

/// [`run_to_batch`] with the waveform in `format` (`<name>.vcd` or `<name>.fst`; the `.gtkw`
/// points at it).
pub fn run_to_batch_as(
    sc: &Scenario,
    dir: &Path,
    fo: FileOptions,
    format: WaveFormat,
    extra: &mut [&mut dyn Observer],
) -> Result<(RunResult, Written, Batch), RunError> {
    run_to_batch_focused(sc, dir, fo, format, extra, None)
}

/// A tick the save file zooms on, marked with a name (a regression's first divergence).
#[derive(Clone, Debug)]
pub struct Focus {
    pub tick: u64,
    pub name: String,
    /// Ticks shown before and after the focus.
    pub before: u64,
    pub after: u64,
}

/// [`run_to_batch_as`] with the save file zoomed on `focus` and a named marker there (ahead of
/// the scenario's own markers).
pub fn run_to_batch_focused(
    sc: &Scenario,
    dir: &Path,
    fo: FileOptions,
    format: WaveFormat,
    extra: &mut [&mut dyn Observer],
    focus: Option<&Focus>,
) -> Result<(RunResult, Written, Batch), RunError> {
    atomic_file::create_dir(dir)?;
    let s = Structural {
        sync_depth: sc.params.sync_depth,
        cnt_width: sc.params.cnt_width,
    };
    let window = fo.window.or(sc.vcd_window);
    // The VCD declares every signal with its reset value: built when the bench begins.
    let core = Pmu50::new(sc.params).map_err(|source| SimError::Core {
        scenario: sc.name.clone(),
        source,
    })?;
    let mut vcd = sim::OnBegin::new(|init: &TickView<'_>| {
        VcdObserver::create(
            dir,
            &sc.name,
            &core,
            sc.clock_ns(),
            window,
            format,
            fo.level,
            init,
        )
    });
    let log_path = dir.join(format!("{}.log", sc.name));
    let mut log = if fo.log {
        let f = AtomicFile::stage(&log_path)?;
        Some(ChangeLog::new(BufWriter::new(f), s, sc.clock_ns())?)
    } else {
        None
    };
    let mut marks = MarkerObserver::new(sc.clock_ns());
    let mut timing = crate::observers::timing::TimingRecorder::new(sc.clock_ns(), window);
    let res = {
        let mut obs: Vec<&mut dyn Observer> = vec![&mut vcd, &mut marks];
        if fo.svg {
            obs.push(&mut timing);
        }
        if let Some(l) = log.as_mut() {
            obs.push(l);
        }
        for e in extra.iter_mut() {
            obs.push(&mut **e);
        }
        sim::run(sc, SimOptions::default(), &mut obs)?
    };
    let vcd_path = dir.join(format!("{}.{}", sc.name, format.ext()));
    let gtkw_path = dir.join(format!("{}.gtkw", sc.name));
    let mut batch = Batch::new();
    let missing = |what| RunError::Unfinished {
        path: vcd_path.clone(),
        what,
    };
    let (vcd_file, gtkw) = vcd
        .into_inner()
        .ok_or_else(|| missing("VCD"))?
        .into_outputs();
    batch.add(vcd_file.ok_or_else(|| missing("VCD"))?);
    match log {
        Some(l) => batch.add(
            l.into_inner()
                .into_inner()
                .map_err(|e| OutputError::Write {
                    path: log_path.clone(),
                    source: e.into_error(),
                })?,
        ),
        None => {
            // A log of an earlier `--log` run would no longer match the VCD beside it.
            if std::fs::read(&log_path).is_ok_and(|b| b.starts_with(LOG_HEADER.as_bytes())) {
                batch.remove_stale(log_path.clone());
            }
        }
    }
    let svg = if fo.svg {
        let title = if sc.description.is_empty() {
            sc.name.clone()
        } else {
            format!("{}: {}", sc.name, sc.description)
        };
        let ws = svg_paths(dir, &sc.name);
        batch.add(atomic_file::write_atomic(
            &ws.svg,
            timing.svg(&title).as_bytes(),
        )?);
        batch.add(atomic_file::write_atomic(&ws.csv, timing.csv().as_bytes())?);
        Some(ws)
    } else {
        None
    };
    let mut gtkw = gtkw.ok_or_else(|| missing("save file"))?;
    let (_, unit_ns) = timescale_for(sc.clock_ns());
    let to_units = |tick: u64| tick * sc.clock_ns() / unit_ns;
    let (a, z) = window.unwrap_or((0, sc.ticks));
    let gerr = |source| RunError::Gtkw {
        path: gtkw_path.clone(),
        source,
    };
    match focus {
        Some(f) => {
            gtkw.fit(
                to_units(f.tick.saturating_sub(f.before).max(a)),
                to_units((f.tick + f.after).min(z).min(sc.ticks)),
            );
            gtkw.marker(to_units(f.tick), &f.name).map_err(gerr)?;
        }
        None => {
            gtkw.fit(to_units(a), to_units(z.min(sc.ticks)));
        }
    }
    let (mut markers, left_out) = marks.markers(Some((a, z)));
    if let Some(f) = focus {
        // the focus marker names that instant; the scenario's own markers fill the other 25
        markers.retain(|m| m.tick != f.tick);
        markers.truncate(markers.len().min(25));
    }
    for m in &markers {
        gtkw.marker(to_units(m.tick), &m.name).map_err(gerr)?;
    }
    if left_out > 0 {
        gtkw.note(&format!(
            "{left_out} more key events than GTKWave's 26 named markers are not marked"
        ))
        .map_err(gerr)?;
    }
    let text = gtkw.render().map_err(gerr)?;
    batch.set_last(atomic_file::write_atomic(&gtkw_path, text.as_bytes())?);
    Ok((
        res,
        Written {
            vcd: vcd_path,
            gtkw: gtkw_path,
            log: fo.log.then_some(log_path),
            svg,
        },
        batch,
    ))
}

/// Run `sc`, writing `<dir>/<name>.vcd`, `.gtkw` and optionally `.log` (each renamed into
/// place when complete; a stale `.log` is removed when none is written).
pub fn run_to_files(
    sc: &Scenario,
    dir: &Path,
    fo: FileOptions,
    extra: &mut [&mut dyn Observer],
) -> Result<(RunResult, Written), RunError> {
    let (res, w, batch) = run_to_batch(sc, dir, fo, extra)?;
    batch.commit()?;
    Ok((res, w))
}

/// Paths of the timing diagram (`FileOptions::svg`).
#[derive(Clone, Debug)]
pub struct WrittenSvg {
    pub svg: PathBuf,
    pub csv: PathBuf,
}

/// Distinct drive intervals listed in full in a summary; more are shortened.
const SI_SEQ_SHOWN: usize = 200;

/// A time in a summary: `12.345 ms` up to 100 s (what every shipped short scenario prints), and
/// beyond that also in days, hours, minutes and seconds (`2591999001.020 ms (29 d 23:59:59.001)`).
fn at_ms(ns: u64) -> String {
    let ms = format!("{:.3} ms", ns as f64 / 1e6);
    if ns < 100_000_000_000 {
        return ms;
    }
    let s = ns / 1_000_000_000;
    format!(
        "{ms} ({} d {:02}:{:02}:{:02}.{:03})",
        s / 86_400,
        s / 3_600 % 24,
        s / 60 % 60,
        s % 60,
        ns / 1_000_000 % 1_000
    )
}

/// Human summary of a run: counts, read-outs against the true angle, diagnosis, Vs2 duty,
/// average key-off current, checks.
pub fn summary(sc: &Scenario, r: &RunResult) -> String {
    let mut s = String::new();
    let w = r.cnt_width;
    let sx = |v: u16| pmu50_core::updown_counter_58cd::sext(v, w);
    s += &format!("== {}: {}\n", sc.name, sc.description);
    s += &format!(
        "   simulated {} ({} ticks of {} ns), {} key-off pulses\n",
        at_ms(r.ticks * r.clock_ns),
        r.ticks,
        r.clock_ns,
        r.pulses.len()
    );
    let p = &r.final_ports;
    s += &format!(
        "   final: cnt_s={} cnt_c={} (CNT={}) si={:.1} ms cnt_r={} hist_s={} hist_c={} diag={} quadrant_skip={}\n",
        sx(p.cnt_s),
        sx(p.cnt_c),
        sx(p.cnt_s) + sx(p.cnt_c),
        f64::from(p.si) * r.clock_ns as f64 / 1e6,
        p.cnt_r,
        u8::from(p.hist_s),
        u8::from(p.hist_c),
        u8::from(p.diag),
        u8::from(p.quadrant_skip)
    );
    let seq: Vec<String> = r
        .si_sequence_ms()
        .iter()
        .map(|v| format!("{v:.1}"))
        .collect();
    if seq.len() > SI_SEQ_SHOWN {
        // Days of parking: the first and the last changes, and how many there were.
        let head = seq[..SI_SEQ_SHOWN / 2].join(" -> ");
        let tail = seq[seq.len() - SI_SEQ_SHOWN / 2..].join(" -> ");
        s += &format!("   drive interval at key-off pulses (ms): {head} -> ... ({} intervals in all) ... -> {tail}\n", seq.len());
    } else if !seq.is_empty() {
        s += &format!(
            "   drive interval at key-off pulses (ms): {}\n",
            seq.join(" -> ")
        );
    }
    for k in &r.keyons {
        let ro = &k.readout;
        s += &format!(
            "   key-on read-out at {}: CNTs={} CNTc={} CNT={} Q1={} Q2={} diff={} ({:?}) CNTa={} Nr={} theta1={:.2} -> theta_m={:.2} deg, true {:.2} deg, error {:+.3} deg; theta_o={:.3} theta_i={:.3} deg; diag={} theta1/theta2 abnormal={}\n",
            at_ms(k.time_ns), ro.cnt_s, ro.cnt_c, ro.cnt, ro.q1, ro.q2, ro.quadrant_diff, ro.equation, ro.cnt_a, ro.nr, ro.theta1_deg, ro.theta_m_deg, k.true_deg, k.error_deg, k.angles.theta_o_deg, k.angles.theta_i_deg, u8::from(k.diag), u8::from(k.theta_abnormal)
        );
    }
    for k in &r.keyoffs {
        s += &format!("   key-off at {}: tracked theta_m={:.2} deg (theta_o={:.3}, theta_i={:.3}), true {:.2} deg\n", at_ms(k.tick * r.clock_ns), k.theta_m_deg, k.angles.theta_o_deg, k.angles.theta_i_deg, k.true_deg);
    }
    let d = &r.dark;
    if d.key_off_ns > 0 {
        let duty = d
            .vs2_duty
            .map_or("-".into(), |v| format!("{:.2} %", v * 100.0));
        let cur = d
            .avg_current_ua
            .map_or("-".into(), |v| format!("{v:.1} uA"));
        s += &format!(
            "   key off for {}: Vs2 duty {duty}, average key-off current {cur}\n",
            at_ms(d.key_off_ns)
        );
    }
    for c in &r.checks {
        s += &format!(
            "   check {:<20} {}  {}\n",
            c.name,
            if c.ok { "PASS" } else { "FAIL" },
            c.detail
        );
    }
    s
}
