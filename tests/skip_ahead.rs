//! The skipping bench against the per-tick bench (docs/spec.md 5.1).
//!
//! - every shipped scenario, run both ways, gives the same summary (every figure: counters,
//!   intervals, read-outs, key-off current), the same table rows, read-outs, final registers and
//!   dark-current times; the parked 30-day scenario is compared on a half-day copy (a day in
//!   `make test-long`);
//! - proptest over random park scenarios (random core configuration, key-off for seconds with
//!   bumps and turns at random times, key-on read-out) compares the two on every output;
//! - the 30-day park passes its checks with a bounded table (run-length rows);
//! - with a waveform (VCD or FST, whole run or `--window`), the skipping bench replays the
//!   skipped periods to the writer: the file is byte-identical to the one of the per-tick bench,
//!   on the shipped parks and in a proptest over random parks (with the GTKWave markers, the
//!   change log of `--log` and the timing diagram of `--svg`, which replay too).
//!
//! The per-tick reference of the shortened copy uses the idle-gap fast-forward
//! ([`Stepping::IdleGaps`]), itself proven equal to stepping every tick in tests/properties.rs
//! and below: stepping every one of its 8.6e9 ticks would take CI an hour.

use pmu50_core::pmu50::Structural;
use pmu50_testbench::observers::changelog::ChangeLog;
use pmu50_testbench::observers::markers::{Marker, MarkerObserver};
use pmu50_testbench::observers::timing::TimingRecorder;
use pmu50_testbench::observers::waveform::{Level, VcdObserver, WaveFormat};
use pmu50_testbench::output::summary;
use pmu50_testbench::scenario::Scenario;
use pmu50_testbench::sim::{run_with, OnBegin, RunResult, Stepping, TickView};
use proptest::prelude::*;
use std::fmt::Write;
use std::path::{Path, PathBuf};

fn scenarios_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("scenarios")
}

fn parse(text: &str, name: &str) -> Scenario {
    Scenario::parse(
        text,
        &format!("{name}.toml"),
        name,
        Path::new("inline.toml"),
    )
    .unwrap_or_else(|e| panic!("{e}\n{text}"))
}

/// Every output of two runs, equal (the table row by row only when `rows`).
fn same(sc: &Scenario, a: &RunResult, b: &RunResult, rows: bool) -> Result<(), TestCaseError> {
    prop_assert_eq!(summary(sc, a), summary(sc, b));
    prop_assert_eq!(a.ticks, b.ticks);
    prop_assert_eq!(a.pulses.len(), b.pulses.len());
    if rows {
        prop_assert!(a.pulses.iter().eq(b.pulses.iter()), "pulse tables differ");
    } else {
        prop_assert_eq!(a.pulses.runs(), b.pulses.runs());
    }
    prop_assert_eq!(a.si_sequence_ms(), b.si_sequence_ms());
    prop_assert_eq!(&a.keyons, &b.keyons);
    prop_assert_eq!(&a.keyoffs, &b.keyoffs);
    prop_assert_eq!(a.final_regs, b.final_regs);
    prop_assert_eq!(a.final_ports, b.final_ports);
    prop_assert_eq!(a.dark, b.dark);
    prop_assert_eq!(&a.checks, &b.checks);
    Ok(())
}

fn assert_same(sc: &Scenario, a: &RunResult, b: &RunResult, rows: bool) {
    if let Err(e) = same(sc, a, b, rows) {
        panic!("{}: {e}", sc.name);
    }
}

/// `sc` stepped every tick and with period skips, the two runs checked equal ([`assert_same`],
/// rows included): (every tick, skipping).
fn tick_and_skip(sc: &Scenario) -> (RunResult, RunResult) {
    let tick = run_with(sc, Stepping::EveryTick, &mut []).unwrap();
    let skip = run_with(sc, Stepping::Periods, &mut []).unwrap();
    assert_same(sc, &tick, &skip, true);
    (tick, skip)
}

#[test]
fn every_shipped_scenario_gives_the_same_summary_skipping_and_per_tick() {
    let mut files: Vec<PathBuf> = std::fs::read_dir(scenarios_dir())
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    files.sort();
    let mut n = 0;
    for p in files {
        let sc = Scenario::load(&p).unwrap();
        if sc.ticks > 1_000_000_000 {
            continue; // the parked days: compared on a shortened copy below
        }
        let tick = run_with(&sc, Stepping::EveryTick, &mut []).unwrap();
        let gaps = run_with(&sc, Stepping::IdleGaps, &mut []).unwrap();
        let skip = run_with(&sc, Stepping::Periods, &mut []).unwrap();
        assert_same(&sc, &tick, &gaps, true);
        assert_same(&sc, &tick, &skip, true);
        assert_eq!(tick.evaluated_ticks, sc.ticks);
        n += 1;
    }
    assert!(n >= 7);
}

/// The shipped 30-day park shortened to half a day (one day with PMU50_TEST_LONG=1, as
/// `make test-long` runs it): the same disturbances every 6 h, key-on one second before the end.
fn park_short() -> (Scenario, u64) {
    let secs: u64 = if std::env::var_os("PMU50_TEST_LONG").is_some() {
        86_400
    } else {
        43_200
    };
    let text = std::fs::read_to_string(scenarios_dir().join("park_30d.toml")).unwrap();
    assert!(text.contains("duration = \"30 d\"") && text.contains("at = \"2591999 s\""));
    let text = text
        .replace("duration = \"30 d\"", &format!("duration = \"{secs} s\""))
        .replace("at = \"2591999 s\"", &format!("at = \"{} s\"", secs - 1))
        .replace("name = \"park_30d\"", "name = \"park_short\"");
    (parse(&text, "park_short"), secs)
}

#[test]
fn a_parked_half_day_skipping_equals_per_tick() {
    let (sc, secs) = park_short();
    let skip = run_with(&sc, Stepping::Periods, &mut []).unwrap();
    let gaps = run_with(&sc, Stepping::IdleGaps, &mut []).unwrap();
    assert_same(&sc, &gaps, &skip, false);
    assert!(skip.passed(), "{:?}", skip.checks);
    assert_eq!(skip.keyons.len(), 2);
    // Most of the park is skipped; the table holds a few runs per disturbance.
    assert!(
        skip.skipped_ticks * 100 > sc.ticks * 99,
        "skipped {} of {}",
        skip.skipped_ticks,
        sc.ticks
    );
    assert!(
        skip.pulses.runs().len() < 1_000,
        "{} runs",
        skip.pulses.runs().len()
    );
    // about one pulse every 6.6 ms
    assert!(
        skip.pulses.len() > secs * 1000 / 7,
        "{} pulses",
        skip.pulses.len()
    );
}

#[test]
fn thirty_parked_days_pass_their_checks_with_a_bounded_table() {
    let sc = Scenario::load(&scenarios_dir().join("park_30d.toml")).unwrap();
    assert_eq!(sc.ticks, 30 * 86_400 * 100_000);
    let r = run_with(&sc, Stepping::Periods, &mut []).unwrap();
    assert!(r.passed(), "{:?}", r.checks);
    assert_eq!(r.keyons.len(), 2);
    let k = &r.keyons[1];
    // 30 days of +4 +360 -3 -270 deg a day from 37 deg.
    assert!(
        (k.true_deg - (r.keyons[0].true_deg + 30.0 * 91.0)).abs() < 1e-6,
        "{k:?}"
    );
    assert!(
        k.error_deg.abs() <= 0.05 && !k.diag && !k.theta_abnormal,
        "{k:?}"
    );
    assert!(
        r.pulses.runs().len() < 30 * 4 * 100,
        "{} runs",
        r.pulses.runs().len()
    );
    assert!(
        r.evaluated_ticks < 20_000_000,
        "evaluated {}",
        r.evaluated_ticks
    );
    // The interval settles back to x = 6.6 ms after every disturbance: the key-off current is
    // close to the settled one (duty 220 us / 6.6 ms).
    let duty = r.dark.vs2_duty.unwrap();
    assert!(duty > 1.0 / 30.0 && duty < 1.0 / 29.0, "duty {duty}");
}

/// A random parked car: core configuration, a short drive, key off for seconds with bumps and
/// turns by hand at random times, key on and read out at the end.
#[derive(Clone, Debug)]
struct Park {
    adaptive: bool,
    /// x = 2.2 ms times this (1..=3).
    x_ms: u64,
    cth: u8,
    start: f64,
    /// (hold before, in 10 us ticks; move duration in ticks; delta deg)
    moves: Vec<(u64, u64, f64)>,
    fault: Option<(u64, u64)>,
    keyoff_ticks: u64,
}

fn park_toml(p: &Park) -> String {
    let mut t = String::new();
    let off = 20_000u64; // key off at 200 ms
    let on = off + p.keyoff_ticks;
    let end = on + 30_000;
    let _ = writeln!(t, "duration = \"{} us\"", end * 10);
    let x = ["2.2", "4.4", "6.6"][(p.x_ms - 1) as usize];
    let _ = writeln!(
        t,
        "[core]\nadaptive = {}\nx = \"{x} ms\"\ncth = {}",
        p.adaptive, p.cth
    );
    let _ = writeln!(t, "[motor]\nstart_deg = {}\nsegments = [", p.start);
    for (hold, dur, delta) in &p.moves {
        let _ = writeln!(
            t,
            "  {{ kind = \"hold\", duration = \"{} us\" }},",
            hold * 10
        );
        let _ = writeln!(
            t,
            "  {{ kind = \"move\", duration = \"{} us\", delta_deg = {delta} }},",
            dur * 10
        );
    }
    t += "]\n";
    let mut ev: Vec<(u64, String)> = vec![
        (0, "ig = true".into()),
        (off, "ig = false".into()),
        (on, "ig = true".into()),
    ];
    if let Some((a, b)) = p.fault {
        // Both fault edges inside the run: a scenario refuses events at or after its end.
        let a = a % p.keyoff_ticks;
        let b = b.min(end - 1 - off - a).max(1);
        ev.push((off + a, "vs2_fault = true".into()));
        ev.push((off + a + b, "vs2_fault = false".into()));
    }
    ev.sort_by_key(|e| e.0);
    for (tick, what) in ev {
        let _ = writeln!(t, "[[events]]\nat = \"{} us\"\n{what}", tick * 10);
    }
    t
}

fn park() -> impl Strategy<Value = Park> {
    let mv = (1_000u64..150_000, 50u64..20_000, -400.0f64..400.0);
    (
        any::<bool>(),
        1u64..=3,
        1u8..6,
        0.0f64..360.0,
        prop::collection::vec(mv, 0..5),
        prop::option::of((0u64..300_000, 1u64..50_000)),
        200_000u64..600_000,
    )
        .prop_map(
            |(adaptive, x, cth, start, moves, fault, keyoff_ticks)| Park {
                adaptive,
                x_ms: x,
                cth,
                start: (start * 10.0).round() / 10.0,
                // At most 10 deg/ms: never a skipped quadrant at any interval up to 6.6 ms.
                moves: moves
                    .into_iter()
                    .map(|(h, d, a)| {
                        (
                            h,
                            d,
                            ((a.clamp(-(d as f64) / 10.0, d as f64 / 10.0)) * 100.0).round()
                                / 100.0,
                        )
                    })
                    .collect(),
                fault,
                keyoff_ticks,
            },
        )
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 24, ..ProptestConfig::default() })]

    /// Random parks: skipping whole periods equals stepping every tick, on every output.
    #[test]
    fn random_parks_skipping_equals_every_tick(p in park()) {
        let sc = parse(&park_toml(&p), "park");
        let tick = run_with(&sc, Stepping::EveryTick, &mut []).unwrap();
        let skip = run_with(&sc, Stepping::Periods, &mut []).unwrap();
        same(&sc, &tick, &skip, true)?;
        prop_assert!(skip.evaluated_ticks <= tick.evaluated_ticks);
    }
}

#[test]
fn a_still_park_skips_almost_everything() {
    let p = Park {
        adaptive: true,
        x_ms: 3,
        cth: 4,
        start: 100.0,
        moves: vec![],
        fault: None,
        keyoff_ticks: 600_000,
    };
    let sc = parse(&park_toml(&p), "still");
    let (_, skip) = tick_and_skip(&sc);
    assert!(
        skip.skipped_ticks * 10 > 9 * 600_000,
        "skipped {}",
        skip.skipped_ticks
    );
}

/// An observer that does not need every tick: it gets the reset state at `begin` and the final
/// state at `finish`, and the bench still skips.
#[derive(Default)]
struct Ends {
    begin: Option<(u64, pmu50_core::Regs)>,
    ticks: u64,
    finish: Option<(u64, pmu50_core::Regs)>,
}

impl pmu50_testbench::sim::Observer for Ends {
    fn begin(
        &mut self,
        v: &pmu50_testbench::sim::TickView<'_>,
    ) -> Result<(), pmu50_testbench::sim::SimError> {
        self.begin = Some((v.tick, *v.regs));
        Ok(())
    }
    fn tick(
        &mut self,
        _: &pmu50_testbench::sim::TickView<'_>,
    ) -> Result<(), pmu50_testbench::sim::SimError> {
        self.ticks += 1;
        Ok(())
    }
    fn finish(
        &mut self,
        v: &pmu50_testbench::sim::TickView<'_>,
    ) -> Result<(), pmu50_testbench::sim::SimError> {
        self.finish = Some((v.tick, *v.regs));
        Ok(())
    }
    fn needs_every_tick(&self) -> bool {
        false
    }
}

#[test]
fn observers_begin_with_the_reset_state_and_may_let_the_bench_skip() {
    let (sc, _) = park_short();
    let mut o = Ends::default();
    let r = run_with(&sc, Stepping::Periods, &mut [&mut o]).unwrap();
    assert_eq!(o.begin, Some((0, pmu50_core::pmu50::reset(&sc.params))));
    assert_eq!(o.finish, Some((sc.ticks, r.final_regs)));
    assert_eq!(o.ticks, r.evaluated_ticks);
    assert!(r.skipped_ticks > 0);
}

#[test]
fn sim_errors_are_typed_with_their_source() {
    let mut sc = parse("duration = \"1 ms\"\n", "bad");
    sc.params.si_min = 0; // not legal: the core refuses it
    let e = run_with(&sc, Stepping::Periods, &mut []).unwrap_err();
    assert!(
        matches!(e, pmu50_testbench::sim::SimError::Core { .. }),
        "{e:?}"
    );
    let src = std::error::Error::source(&e).expect("a source");
    assert!(src.downcast_ref::<pmu50_core::ParamError>().is_some());
    assert!(e.to_string().contains("scenario bad"), "{e}");
}

/// A run writing the waveform of `sc` (with the GTKWave markers' observer, as `pmu50 run`, the
/// change log of `--log` and the timing diagram of `--svg`): its result, the waveform file's
/// bytes, the markers, and the log followed by the diagram's CSV.
fn traced(
    sc: &Scenario,
    stepping: Stepping,
    format: WaveFormat,
    window: Option<(u64, u64)>,
) -> (RunResult, Vec<u8>, Vec<Marker>, Vec<u8>) {
    traced_level(sc, stepping, format, window, Level::All)
}

/// [`traced`] with the signals of a trace level.
fn traced_level(
    sc: &Scenario,
    stepping: Stepping,
    format: WaveFormat,
    window: Option<(u64, u64)>,
    level: Level,
) -> (RunResult, Vec<u8>, Vec<Marker>, Vec<u8>) {
    let dir = tempfile::tempdir().unwrap();
    let s = Structural {
        sync_depth: sc.params.sync_depth,
        cnt_width: sc.params.cnt_width,
    };
    let core = pmu50_core::Pmu50::new(sc.params).unwrap();
    let mut vcd = OnBegin::new(|init: &TickView<'_>| {
        VcdObserver::create(
            dir.path(),
            &sc.name,
            &core,
            sc.clock_ns(),
            window,
            format,
            level,
            init,
        )
    });
    let mut marks = MarkerObserver::new(sc.clock_ns());
    let mut log = ChangeLog::new(Vec::new(), s, sc.clock_ns()).unwrap();
    let mut timing = TimingRecorder::new(sc.clock_ns(), window);
    let r = run_with(
        sc,
        stepping,
        &mut [&mut vcd, &mut marks, &mut log, &mut timing],
    )
    .unwrap();
    let mut log = log.into_inner();
    // The timing diagram of `--svg`, as its CSV (every row and mark, and the end).
    log.extend_from_slice(timing.csv().as_bytes());
    let (file, _) = vcd.into_inner().unwrap().into_outputs();
    let file = file.unwrap();
    let bytes = std::fs::read(file.temp_path()).unwrap();
    (r, bytes, marks.markers(None).0, log)
}

/// The waveform of the skipping bench equals the per-tick one byte for byte, and so does
/// everything else; returns the ticks skipped.
fn same_waves(
    sc: &Scenario,
    format: WaveFormat,
    window: Option<(u64, u64)>,
) -> Result<u64, TestCaseError> {
    let (tick, a, ma, la) = traced(sc, Stepping::EveryTick, format, window);
    let (skip, b, mb, lb) = traced(sc, Stepping::Periods, format, window);
    prop_assert_eq!(tick.evaluated_ticks, sc.ticks);
    same(sc, &tick, &skip, true)?;
    prop_assert_eq!(ma, mb);
    prop_assert!(la.len() > 100);
    prop_assert!(
        la == lb,
        "{}: the change logs or timing diagrams differ:\n{}\n----\n{}",
        sc.name,
        String::from_utf8_lossy(&la),
        String::from_utf8_lossy(&lb)
    );
    prop_assert!(a.len() > 100);
    if a != b {
        let at = a
            .iter()
            .zip(&b)
            .position(|(x, y)| x != y)
            .unwrap_or(a.len().min(b.len()));
        let from = at.saturating_sub(200);
        return Err(TestCaseError::fail(format!(
            "{} {format:?} window {window:?}: waveforms differ at byte {at} of {} / {}\nper tick: {:?}\nskipping: {:?}",
            sc.name,
            a.len(),
            b.len(),
            String::from_utf8_lossy(&a[from..(at + 200).min(a.len())]),
            String::from_utf8_lossy(&b[from..(at + 200).min(b.len())]),
        )));
    }
    Ok(skip.skipped_ticks)
}

/// The other shipped scenarios (figures, turns, faults) have key-off stretches too: their
/// waveforms (in their own window, as `pmu50 run` writes them) are the same skipping.
#[test]
fn shipped_scenarios_write_the_same_waveform_skipping_and_per_tick() {
    let mut skipped = 0;
    for name in [
        "fig15a",
        "fig15b",
        "fig16",
        "first_embodiment",
        "keyoff_turns",
        "threshold_error",
        "too_fast",
    ] {
        let sc = Scenario::load(&scenarios_dir().join(format!("{name}.toml"))).unwrap();
        skipped +=
            same_waves(&sc, WaveFormat::Vcd, sc.vcd_window).unwrap_or_else(|e| panic!("{e}"));
    }
    assert!(skipped > 0);
}

#[test]
fn shipped_parks_write_the_same_waveform_skipping_and_per_tick() {
    // Each park in both formats, with and without its window (two runs each: the per-tick
    // reference writes 300 000 ticks).
    for (name, vcd_windowed) in [
        ("park_still", false),
        ("park_bumps", true),
        ("park_ferry", false),
    ] {
        let sc = Scenario::load(&scenarios_dir().join(format!("{name}.toml"))).unwrap();
        assert!(
            sc.vcd_window.is_some(),
            "{name}: the shipped parks have a window"
        );
        let runs = if vcd_windowed {
            [(WaveFormat::Vcd, sc.vcd_window), (WaveFormat::Fst, None)]
        } else {
            [(WaveFormat::Vcd, None), (WaveFormat::Fst, sc.vcd_window)]
        };
        for (format, window) in runs {
            let skipped = same_waves(&sc, format, window).unwrap_or_else(|e| panic!("{e}"));
            if name == "park_still" {
                assert!(
                    skipped * 10 > sc.ticks * 8,
                    "{name}: skipped {skipped} of {}",
                    sc.ticks
                );
            }
        }
    }
}

/// The lower trace levels replay too: `ports` (no timer: a few changes per period) and
/// `registers`, in both formats, give the same bytes skipping as per tick.
#[test]
fn lower_trace_levels_write_the_same_waveform_skipping_and_per_tick() {
    let sc = Scenario::load(&scenarios_dir().join("park_bumps.toml")).unwrap();
    for (level, format) in [
        (Level::Ports, WaveFormat::Vcd),
        (Level::Ports, WaveFormat::Fst),
        (Level::Registers, WaveFormat::Vcd),
    ] {
        let (tick, a, _, _) = traced_level(&sc, Stepping::EveryTick, format, None, level);
        let (skip, b, _, _) = traced_level(&sc, Stepping::Periods, format, None, level);
        assert_same(&sc, &tick, &skip, true);
        assert!(
            skip.skipped_ticks * 2 > sc.ticks,
            "{level:?} {format:?}: skipped only {} of {}",
            skip.skipped_ticks,
            sc.ticks
        );
        assert!(
            a.len() > 100 && a == b,
            "{level:?} {format:?}: the waveforms differ ({} / {} bytes)",
            a.len(),
            b.len()
        );
    }
}

/// A random park of 0.5 to 1.5 s key-off (shorter than [`park`]: the per-tick reference
/// writes every tick), a waveform format and an optional window (fractions of the run).
fn traced_park() -> impl Strategy<Value = (Park, WaveFormat, Option<(f64, f64)>)> {
    let shorter = park().prop_map(|mut p| {
        p.keyoff_ticks /= 4;
        p.moves.iter_mut().for_each(|m| m.0 /= 2);
        p
    });
    (
        shorter,
        prop_oneof![Just(WaveFormat::Vcd), Just(WaveFormat::Fst)],
        prop::option::of((0.0f64..1.0, 0.0f64..1.0)),
    )
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 8, ..ProptestConfig::default() })]

    /// Random parks with a waveform: the skipping bench (replaying the skipped periods to the
    /// writer) writes the same bytes as the per-tick bench, whole run or window.
    #[test]
    fn random_parks_write_the_same_waveform_skipping_and_per_tick((p, format, w) in traced_park()) {
        let sc = parse(&park_toml(&p), "park");
        let window = w.map(|(x, y)| {
            let (a, z) = ((x.min(y) * sc.ticks as f64) as u64, (x.max(y) * sc.ticks as f64) as u64);
            (a, z.max(a + 1))
        });
        same_waves(&sc, format, window)?;
    }
}

/// A window that starts and ends inside skipped stretches, off any period boundary: the
/// replay writes its first dump and its last change exactly where stepping does.
#[test]
fn a_window_inside_a_skipped_stretch_gives_the_same_waveform() {
    let p = Park {
        adaptive: true,
        x_ms: 3,
        cth: 4,
        start: 100.0,
        moves: vec![(30_000, 2_000, 20.0)],
        fault: None,
        keyoff_ticks: 100_000,
    };
    let sc = parse(&park_toml(&p), "still");
    for (format, window) in [
        (WaveFormat::Vcd, (60_007, 90_013)),
        (WaveFormat::Fst, (60_007, 90_013)),
        (WaveFormat::Vcd, (75_001, 75_002)),
    ] {
        let skipped = same_waves(&sc, format, Some(window)).unwrap_or_else(|e| panic!("{e}"));
        assert!(skipped > 60_000, "skipped {skipped}");
    }
}

/// An observer that needs every tick and replays, but declines the first offers: the bench
/// then steps on (and finds the repeat again), and every tick reaches the observer exactly once,
/// stepped or replayed, in order.
struct Picky {
    next: u64,
    offers: u32,
    decline: u32,
    replayed: u64,
}

impl pmu50_testbench::sim::Observer for Picky {
    fn tick(&mut self, v: &TickView<'_>) -> Result<(), pmu50_testbench::sim::SimError> {
        assert_eq!(
            v.tick, self.next,
            "ticks in order, none twice, none left out"
        );
        self.next += 1;
        Ok(())
    }
    fn finish(&mut self, v: &TickView<'_>) -> Result<(), pmu50_testbench::sim::SimError> {
        assert_eq!(v.tick, self.next);
        Ok(())
    }
    fn replays_periods(&self) -> bool {
        true
    }
    fn can_replay(&self, k: u64, _len: u64) -> bool {
        assert_eq!(k, self.next);
        // Boundaries seen so far (a skip is offered at a boundary).
        self.offers > self.decline
    }
    fn period_boundary(&mut self, _k: u64) -> Result<(), pmu50_testbench::sim::SimError> {
        self.offers += 1;
        Ok(())
    }
    fn replay(
        &mut self,
        k: u64,
        periods: u64,
        len: u64,
    ) -> Result<(), pmu50_testbench::sim::SimError> {
        assert_eq!(k, self.next);
        assert!(periods > 0 && len > 0);
        self.next += periods * len;
        self.replayed += periods * len;
        Ok(())
    }
}

#[test]
fn a_declined_replay_steps_on_and_every_tick_is_seen_once() {
    let p = Park {
        adaptive: true,
        x_ms: 1,
        cth: 2,
        start: 10.0,
        moves: vec![(40_000, 3_000, 30.0)],
        fault: Some((90_000, 5_000)),
        keyoff_ticks: 150_000,
    };
    let sc = parse(&park_toml(&p), "picky");
    let tick = run_with(&sc, Stepping::EveryTick, &mut []).unwrap();
    for decline in [0, 5, 40, u32::MAX] {
        let mut o = Picky {
            next: 0,
            offers: 0,
            decline,
            replayed: 0,
        };
        let r = run_with(&sc, Stepping::Periods, &mut [&mut o]).unwrap();
        assert_same(&sc, &tick, &r, true);
        assert_eq!(o.next, sc.ticks);
        assert_eq!(o.replayed, r.skipped_ticks, "decline {decline}");
        assert_eq!(
            r.evaluated_ticks + r.skipped_ticks,
            sc.ticks,
            "no idle gap is fast-forwarded past a waveform"
        );
        if decline == u32::MAX {
            assert_eq!(r.skipped_ticks, 0);
        } else {
            assert!(
                r.skipped_ticks > 50_000,
                "decline {decline}: skipped {}",
                r.skipped_ticks
            );
        }
    }
}

/// With the key on and the shaft still, the bench repeats every on-key sampling period that
/// starts a round of the MPU's polling: such periods are skipped too, with the same summary,
/// read-outs, registers and waveform as stepping every tick. Two key-on stretches (one with
/// smp_on and the poll round coprime, one with a turn at its end), key-off between them.
#[test]
fn key_on_periods_skip_exactly() {
    let text = r#"
duration = "3.2 s"
[core]
smp_on = "70 us"
[motor]
start_deg = 100.0
segments = [
  { kind = "hold", duration = "2.0 s" },
  { kind = "move", duration = "50 ms", delta_deg = 95.0 },
]
[[events]]
at = "0 ms"
ig = true
[[events]]
at = "1.5 s"
ig = false
[[events]]
at = "1.6 s"
ig = true
[[events]]
at = "3.0 s"
ig = false
"#;
    let sc = parse(text, "key_on_still");
    let (every, skip) = tick_and_skip(&sc);
    assert_eq!(every.keyons.len(), 2);
    assert!(
        skip.evaluated_ticks * 10 < sc.ticks,
        "key-on periods were skipped: {} of {} ticks evaluated",
        skip.evaluated_ticks,
        sc.ticks
    );
    // and the waveform of every signal (the writer replays the skipped periods)
    let short = parse(
        &text
            .replace("3.2 s", "0.9 s")
            .replace("1.5 s", "0.5 s")
            .replace("1.6 s", "0.6 s")
            .replace("3.0 s", "0.8 s")
            .replace("2.0 s", "0.7 s"),
        "key_on_still_short",
    );
    let skipped = same_waves(&short, WaveFormat::Vcd, None).unwrap_or_else(|e| panic!("{e}"));
    assert!(skipped > 10_000, "skipped {skipped}");
}

/// A key-on stretch with the Vs2 rail dead: the powered-off sensor is in one state from the
/// start, so key-on periods (here 18 ticks: smp_on = 2 ticks) repeat at once, but the MPU's read-out (due a fixed time after the
/// key edge) must not be skipped over.
#[test]
fn a_key_on_period_skip_never_jumps_over_the_read_out() {
    let text = r#"
duration = "1.5 s"
[core]
smp_on = "20 us"
[motor]
start_deg = 10.0
segments = [ { kind = "hold", duration = "1 ms" } ]
[[events]]
at = "0 ms"
ig = false
[[events]]
at = "400 ms"
vs2_fault = true
[[events]]
at = "1000 ms"
ig = true
"#;
    let sc = parse(text, "key_on_dead_rail");
    let (every, skip) = tick_and_skip(&sc);
    assert_eq!(every.keyons.len(), 1);
    assert!(
        skip.skipped_ticks > 40_000,
        "skipped {}",
        skip.skipped_ticks
    );
}
