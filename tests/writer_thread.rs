//! The waveform written on a thread of its own (`VcdObserver`, `pmu50_testbench::observers::thread`) is the
//! one written on the bench's thread, byte for byte, for the shipped scenarios in both formats
//! at every trace level; and an observer's error or panic on its thread ends the run with that
//! error.

use pmu50_testbench::observers::markers::MarkerObserver;
use pmu50_testbench::observers::thread::{Threaded, BATCH};
use pmu50_testbench::observers::waveform::{Level, VcdObserver, WaveFormat};
use pmu50_testbench::scenario::Scenario;
use pmu50_testbench::sim::{
    run, run_with, Observer, OnBegin, SimError, SimOptions, Stepping, TickView,
};
use std::path::Path;

/// The waveform of `sc` (with the markers' observer beside it, as `pmu50 run`), written on its
/// own thread or on the bench's.
fn wave(sc: &Scenario, format: WaveFormat, level: Level, own_thread: bool) -> Vec<u8> {
    let dir = tempfile::tempdir().unwrap();
    let core = pmu50_core::Pmu50::new(sc.params).unwrap();
    let mut vcd = OnBegin::new(|init: &TickView<'_>| {
        VcdObserver::create(
            dir.path(),
            &sc.name,
            &core,
            sc.clock_ns(),
            sc.vcd_window,
            format,
            level,
            init,
        )
        .map(|o| o.on_own_thread(own_thread))
    });
    let mut marks = MarkerObserver::new(sc.clock_ns());
    run(sc, SimOptions::default(), &mut [&mut vcd, &mut marks]).unwrap();
    let (file, gtkw) = vcd.into_inner().unwrap().into_outputs();
    assert!(gtkw.is_some(), "{}: no save file", sc.name);
    std::fs::read(file.unwrap().temp_path()).unwrap()
}

fn shipped(name: &str) -> Scenario {
    Scenario::load(
        &Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("scenarios")
            .join(format!("{name}.toml")),
    )
    .unwrap()
}

fn same_both_ways(name: &str, formats: &[WaveFormat], levels: &[Level]) {
    let sc = shipped(name);
    for &format in formats {
        for &level in levels {
            let a = wave(&sc, format, level, false);
            let b = wave(&sc, format, level, true);
            assert!(
                a.len() > 1000,
                "{name} {format:?} {level:?}: only {} bytes",
                a.len()
            );
            if a != b {
                let at = a
                    .iter()
                    .zip(&b)
                    .position(|(x, y)| x != y)
                    .unwrap_or(a.len().min(b.len()));
                panic!("{name} {format:?} {level:?}: the threaded writer's file differs at byte {at} of {} / {}", a.len(), b.len());
            }
        }
    }
}

const FORMATS: [WaveFormat; 2] = [WaveFormat::Vcd, WaveFormat::Fst];
const LEVELS: [Level; 3] = [Level::Ports, Level::Registers, Level::All];

/// Key-off sampling with the shaft turning (8 MB of VCD at level all; thousands of batches).
#[test]
fn keyoff_turns_is_the_same_on_its_own_thread() {
    same_both_ways("keyoff_turns", &FORMATS, &LEVELS);
}

/// Key on and off with the MPU's read-outs, and a window.
#[test]
fn figures_are_the_same_on_their_own_thread() {
    for name in [
        "fig15a",
        "fig16",
        "first_embodiment",
        "threshold_error",
        "too_fast",
    ] {
        same_both_ways(name, &FORMATS, &LEVELS);
    }
}

/// Parked: the bench skips whole key-off periods and the writer replays them (the bench asks
/// the thread whether it can: `Observer::can_replay`).
#[test]
fn replayed_periods_are_the_same_on_their_own_thread() {
    for name in ["park_bumps", "park_still"] {
        same_both_ways(name, &FORMATS, &[Level::All]);
    }
}

/// Fails at tick `at` (or panics there).
struct Failing {
    at: u64,
    panic: bool,
    ticks: u64,
}

impl Observer for Failing {
    fn tick(&mut self, v: &TickView<'_>) -> Result<(), SimError> {
        self.ticks += 1;
        if v.tick == self.at {
            if self.panic {
                panic!("planted panic at tick {}", v.tick);
            }
            return Err(SimError::observer(
                "planted.vcd",
                format!("planted error at tick {}", v.tick),
            ));
        }
        Ok(())
    }
}

fn short() -> Scenario {
    let text = "name = \"short\"\nduration = \"200 ms\"\n";
    Scenario::parse(text, "short.toml", "short", Path::new("short.toml")).unwrap()
}

/// An observer's error on its thread ends the run with that error, whether it comes in the
/// middle of a batch, or in the last batch (at `finish`).
#[test]
fn an_error_on_the_thread_ends_the_run() {
    let sc = short();
    assert!(
        sc.ticks > 4 * BATCH as u64,
        "the scenario is too short for the test: {} ticks",
        sc.ticks
    );
    for at in [3, BATCH as u64 + 7, sc.ticks - 2] {
        let mut t = Threaded::spawn(
            Failing {
                at,
                panic: false,
                ticks: 0,
            },
            "planted.vcd",
        )
        .unwrap_or_else(|_| panic!("no thread"));
        let e = run_with(&sc, Stepping::EveryTick, &mut [&mut t]).unwrap_err();
        assert!(
            e.to_string()
                .contains(&format!("planted error at tick {at}")),
            "{e}"
        );
        assert!(e.to_string().starts_with("planted.vcd"), "{e}");
    }
}

/// A panic on the thread is an error of the run that says so.
#[test]
fn a_panic_on_the_thread_is_an_error() {
    let sc = short();
    let mut t = Threaded::spawn(
        Failing {
            at: 100,
            panic: true,
            ticks: 0,
        },
        "planted.vcd",
    )
    .unwrap_or_else(|_| panic!("no thread"));
    let e = run_with(&sc, Stepping::EveryTick, &mut [&mut t]).unwrap_err();
    let s = e.to_string();
    assert!(
        s.contains("panicked") && s.contains("planted panic at tick 100"),
        "{s}"
    );
}

/// Every tick reaches the observer on its thread, in order, and it comes back after `finish`.
#[test]
fn every_tick_reaches_the_thread() {
    let sc = short();
    let mut t = Threaded::spawn(
        Failing {
            at: u64::MAX,
            panic: false,
            ticks: 0,
        },
        "count",
    )
    .unwrap_or_else(|_| panic!("no thread"));
    run_with(&sc, Stepping::EveryTick, &mut [&mut t]).unwrap();
    assert_eq!(t.into_inner().map(|f| f.ticks), Some(sc.ticks));
}
