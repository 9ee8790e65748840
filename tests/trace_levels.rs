//! Trace levels (docs/spec.md 6.1, "Trace levels"): `pmu50 run --trace ports|registers|all|none`
//! and `[vcd] trace`. Per level the waveform declares exactly its signals (same hierarchy, same
//! names), every shared signal has the values of the `all` file, the save file lists only
//! signals of the file; the default is chosen from the run's length; bad values are refused with
//! exit 2; the size estimate behind `--max-vcd-bytes` depends on the level and the format.

use pmu50_core::signals;
use pmu50_testbench::observers::waveform::{Level, WaveFormat};
use pmu50_testbench::output::{
    choose_trace, estimate_run_bytes, estimate_wave_bytes, parked_ticks, TraceFrom,
    DEFAULT_ALL_MAX_BYTES,
};
use pmu50_testbench::scenario::{Scenario, Trace};
use pmu50_waves::reader::Waveform;
use std::collections::BTreeSet;
use std::path::Path;

use crate::common;
use common::{expect, pmu50, s, text, tmp, write, KEY_ON_FAST};

/// The signal paths a waveform of `level` declares, from the signal table.
fn expected(level: Level) -> BTreeSet<String> {
    let mut v: BTreeSet<String> = signals::INPUTS
        .iter()
        .map(|s| format!("pmu50.{}", s.name))
        .collect();
    v.extend(signals::OUTPUTS.iter().map(|s| format!("pmu50.{}", s.name)));
    v.extend(
        [
            "theta_deg",
            "sin2_v",
            "cos2_v",
            "vs2_v",
            "vp_v",
            "vr_v",
            "theta1_deg",
            "theta_m_deg",
        ]
        .map(|n| format!("env.{n}")),
    );
    if level >= Level::Registers {
        v.extend(
            signals::REGISTERS
                .iter()
                .map(|s| format!("pmu50.{}.{}", s.scope, s.name)),
        );
    }
    if level == Level::All {
        v.extend(
            signals::INTERNALS
                .iter()
                .map(|s| format!("pmu50.internals.{}", s.name)),
        );
    }
    v
}

/// The signal names a GTKWave save file shows (one per trace line).
fn gtkw_traces(text: &str) -> Vec<String> {
    text.lines()
        .filter(|l| !l.is_empty() && !l.starts_with(['[', '*', '@', '-']))
        .map(str::to_string)
        .collect()
}

/// Run `fig15a` at every level in `format` (with `window` if given) and check each file against
/// the `all` one.
fn levels_against_all(format: &str, window: Option<[&str; 2]>) {
    let d = tmp(&format!("levels-{format}-{}", window.is_some()));
    let run = |level: &str| -> Waveform {
        let out = d.join(level);
        let mut args = vec![
            "run",
            "scenarios/fig15a.toml",
            "--trace",
            level,
            "--format",
            format,
            "--out-dir",
            s(&out),
        ];
        if let Some(w) = &window {
            args.extend(["--window", w[0], w[1]]);
        }
        expect(
            &pmu50(&args),
            0,
            &[&format!("trace = {level} (--trace)"), "wrote"],
        );
        let wave = Waveform::open(out.join(format!("fig15a.{format}"))).unwrap();
        // The save file lists only signals of the file, and every one of them.
        let gtkw = std::fs::read_to_string(out.join("fig15a.gtkw")).unwrap();
        let names: BTreeSet<String> = wave.signals().iter().map(|s| s.gtkwave_name()).collect();
        let shown = gtkw_traces(&gtkw);
        for t in &shown {
            assert!(
                names.contains(t),
                "{level}: the save file lists {t}, which the file lacks"
            );
        }
        assert_eq!(
            shown.iter().cloned().collect::<BTreeSet<_>>(),
            names,
            "{level}: the save file shows every signal of the file"
        );
        wave
    };
    let all = run("all");
    assert_eq!(
        all.signals()
            .iter()
            .map(|s| s.path.clone())
            .collect::<BTreeSet<_>>(),
        expected(Level::All)
    );
    for (word, level) in [("registers", Level::Registers), ("ports", Level::Ports)] {
        let w = run(word);
        let paths: Vec<String> = w.signals().iter().map(|s| s.path.clone()).collect();
        assert_eq!(
            paths.iter().cloned().collect::<BTreeSet<_>>(),
            expected(level),
            "{word}: declared signals"
        );
        assert_eq!(
            paths.len(),
            expected(level).len(),
            "{word}: each signal declared once"
        );
        assert_eq!(w.end_time(), all.end_time(), "{word}: same end time");
        if window.is_some() {
            // 20 ms to 30 ms in us: the last dumped tick starts at 29.99 ms.
            assert_eq!(w.end_time(), 29_990, "{word}: the window's end");
            // The first dump is at the window's start in both formats (the FST's header and first
            // block carry it: waves/src/fst.rs `set_start_time`).
            assert_eq!(
                w.changes_at(0).first().map(|c| c.0),
                Some(20_000),
                "{word}: the first dump is at the window's start"
            );
            assert!(
                w.changes_at(0)
                    .iter()
                    .all(|(t, _)| (20_000..30_000).contains(t)),
                "{word}: only the window is dumped: {:?}",
                w.changes_at(0)
            );
        }
        for (i, p) in paths.iter().enumerate() {
            let a = all
                .find(p)
                .unwrap_or_else(|| panic!("{p} is not in the all file"));
            assert_eq!(
                all.signals()[a].gtkwave_name(),
                w.signals()[i].gtkwave_name(),
                "{word}: {p} same name and width"
            );
            // Only changes are written: equal change lists are equal values at every tick.
            assert_eq!(w.changes_at(i), all.changes_at(a), "{word}: values of {p}");
        }
        // The same through `pmu50 diff`, the signals of `all` alone set aside.
        let file = |l: &str| d.join(l).join(format!("fig15a.{format}"));
        expect(
            &pmu50(&["diff", s(&file("all")), s(&file(word)), "--allow-unmatched"]),
            0,
            &[
                "waveform diff: EQUAL",
                "value mismatches: 0",
                "only in left: pmu50.internals.fig17[2:0]",
            ],
        );
    }
}

#[test]
fn each_vcd_level_declares_its_signals_with_the_values_of_all() {
    levels_against_all("vcd", None);
}

#[test]
fn each_fst_level_declares_its_signals_with_the_values_of_all() {
    levels_against_all("fst", None);
}

#[test]
fn every_level_takes_a_window() {
    levels_against_all("vcd", Some(["20 ms", "30 ms"]));
    levels_against_all("fst", Some(["20 ms", "30 ms"]));
}

#[test]
fn the_scenario_key_takes_every_level_and_the_flag_overrides_it() {
    let d = tmp("key");
    for level in ["ports", "registers", "all"] {
        let sc = d.join(format!("k_{level}.toml"));
        std::fs::write(
            &sc,
            format!("duration = \"5 ms\"\n[vcd]\ntrace = \"{level}\"\n"),
        )
        .unwrap();
        expect(
            &pmu50(&["run", s(&sc), "--out-dir", s(&d)]),
            0,
            &[&format!(
                "trace = {level} ([vcd] trace of the scenario; --trace overrides it)"
            )],
        );
        let w = Waveform::open(d.join(format!("k_{level}.vcd"))).unwrap();
        assert_eq!(
            w.signals().len(),
            expected(Trace::parse(level).unwrap().level().unwrap()).len(),
            "{level}"
        );
        expect(
            &pmu50(&["run", s(&sc), "--out-dir", s(&d), "--trace", "none"]),
            0,
            &["trace = none: no waveform"],
        );
    }
}

#[test]
fn a_short_run_defaults_to_all_and_says_why() {
    let d = tmp("short");
    let t = expect(&pmu50(&["run", "scenarios/fig15a.toml", "--out-dir", s(&d)]), 0, &["trace = all (chosen for this run: the VCD of every signal is at most about 553 kB, within the default's limit of 256 MiB; ask for less with --trace registers, ports or none"]);
    assert!(t.contains("wrote"), "{t}");
    assert_eq!(
        Waveform::open(d.join("fig15a.vcd"))
            .unwrap()
            .signals()
            .len(),
        expected(Level::All).len()
    );
}

fn parse(src: &str) -> Scenario {
    Scenario::parse(src, "t.toml", "t", Path::new("t.toml")).unwrap()
}

/// The key on all the time: every tick is active.
const ON: &str = "[[events]]\nat = \"0 ms\"\nig = true\n";

#[test]
fn the_default_is_all_up_to_the_threshold_and_ports_beyond() {
    // 10 us ticks with the key on: 160 bytes per tick of VCD `all` reach 256 MiB at 1 677 619
    // ticks (16.8 s); FST at 18 bytes per tick at 14.9 M ticks.
    let short = parse(&format!("duration = \"16 s\"\n{ON}"));
    let long = parse(&format!("duration = \"17 s\"\n{ON}"));
    assert_eq!(
        estimate_run_bytes(&long, None, Level::All, WaveFormat::Vcd),
        estimate_wave_bytes(long.ticks, Level::All, WaveFormat::Vcd),
        "all active"
    );
    let c = choose_trace(&short, None, None, WaveFormat::Vcd);
    assert_eq!(c.trace, Trace::ALL);
    let c = choose_trace(&long, None, None, WaveFormat::Vcd);
    assert_eq!(c.trace, Trace::Wave(Level::Ports));
    assert!(
        matches!(c.from, TraceFrom::Default { all_estimate } if all_estimate > DEFAULT_ALL_MAX_BYTES)
    );
    let line = c.describe(WaveFormat::Vcd);
    assert!(line.starts_with("trace = ports (chosen for this run: the VCD of every signal could reach about 272.0 MB, above the default's limit of 256 MiB; ask for more with --trace registers or all"), "{line}");
    // A window counts only the dumped ticks; the FST's bound is lower; flag and key win.
    assert_eq!(
        choose_trace(&long, None, Some((0, 100_000)), WaveFormat::Vcd).trace,
        Trace::ALL
    );
    assert_eq!(
        choose_trace(&long, None, None, WaveFormat::Fst).trace,
        Trace::ALL
    );
    assert_eq!(
        choose_trace(
            &parse(&format!("duration = \"180 s\"\n{ON}")),
            None,
            None,
            WaveFormat::Fst
        )
        .trace,
        Trace::Wave(Level::Ports)
    );
    assert_eq!(
        choose_trace(&long, Some(Trace::ALL), None, WaveFormat::Vcd).from,
        TraceFrom::Flag
    );
    let keyed = parse(&format!(
        "duration = \"17 s\"\n{ON}[vcd]\ntrace = \"registers\"\n"
    ));
    assert_eq!(
        choose_trace(&keyed, None, None, WaveFormat::Vcd),
        pmu50_testbench::output::TraceChoice {
            trace: Trace::Wave(Level::Registers),
            from: TraceFrom::Scenario
        }
    );
    // Parked (key off, shaft still) ticks cost less: 17 s parked stays `all`, a minute does not
    // (186 MB written, estimated at 82 bytes per tick).
    assert_eq!(
        choose_trace(&parse("duration = \"17 s\"\n"), None, None, WaveFormat::Vcd).trace,
        Trace::ALL
    );
    assert_eq!(
        choose_trace(&parse("duration = \"60 s\"\n"), None, None, WaveFormat::Vcd).trace,
        Trace::Wave(Level::Ports)
    );
    // Every shipped scenario either says `none` or stays within the threshold (its VCD keeps
    // every signal).
    for e in std::fs::read_dir(Path::new(env!("CARGO_MANIFEST_DIR")).join("scenarios")).unwrap() {
        let sc = Scenario::load(&e.unwrap().path()).unwrap();
        let c = choose_trace(&sc, None, None, WaveFormat::Vcd);
        assert!(
            c.trace == Trace::ALL || sc.trace == Some(Trace::None),
            "{}: {c:?}",
            sc.name
        );
    }
}

#[test]
fn parked_ticks_are_key_off_still_and_unfaulted() {
    // After power-on and after each key-off: sync_depth 2 + 2, Wt 22 and the sensor's settling
    // 24 ticks (11 x 21.7 us) stay active.
    let settle = 2 + 2 + 22 + 24;
    let sc = parse("duration = \"10 s\"\n");
    assert_eq!(parked_ticks(&sc, 0, sc.ticks), sc.ticks - settle);
    assert_eq!(parked_ticks(&sc, 10, 30), 0);
    assert_eq!(parked_ticks(&sc, 500, 700), 200);
    let sc = parse("duration = \"10 s\"\n[[events]]\nat = \"1 s\"\nig = true\n[[events]]\nat = \"2 s\"\nig = false\n");
    assert_eq!(
        parked_ticks(&sc, 0, sc.ticks),
        sc.ticks - settle - (100_000 + settle)
    );
    let sc = parse("duration = \"10 s\"\n[motor]\nsegments = [ { kind = \"hold\", duration = \"3 s\" }, { kind = \"move\", duration = \"1 s\", delta_deg = 10.0 } ]\n");
    assert_eq!(
        parked_ticks(&sc, 0, sc.ticks),
        sc.ticks - settle - (100_000 + 2),
        "a move and one tick either side"
    );
    let sc = parse("duration = \"10 s\"\n[[events]]\nat = \"1 s\"\nvs2_fault = true\n[[events]]\nat = \"2 s\"\nvs2_fault = false\n");
    assert_eq!(
        parked_ticks(&sc, 0, sc.ticks),
        sc.ticks - settle - (100_000 + settle)
    );
    let sc = parse("duration = \"10 s\"\n[[events]]\nat = \"1 s\"\nig = true\n");
    assert_eq!(
        parked_ticks(&sc, 0, sc.ticks),
        100_000 - settle,
        "key on to the end"
    );
    let sc = parse("duration = \"10 s\"\n[[events]]\nat = \"1 s\"\nig = true\n[[events]]\nat = \"1.5 s\"\nwrite = { reg = \"T2\", value = 110 }\n[[events]]\nat = \"2 s\"\nig = false\n");
    assert_eq!(
        parked_ticks(&sc, 0, sc.ticks),
        0,
        "a register write may change the key-off pulses"
    );
}

#[test]
fn parked_estimates_are_upper_bounds() {
    // Parks that pulse more than the defaults (testbench/src/output.rs `estimate_run_bytes` has 5 s
    // measurements of these and more): a fixed 1 ms cycle; a fast turn then a hold at a short
    // si_min; key on, a turn and a Vs2 fault in the middle of a park.
    let d = tmp("parked");
    let cases = [
        ("fixed", "duration = \"1 s\"\n[core]\nadaptive = false\nx = \"1 ms\"\nmin = \"1 ms\"\n"),
        ("turn", "duration = \"1 s\"\n[core]\nmin = \"0.5 ms\"\nt2 = \"0.01 ms\"\ncth = 255\n[motor]\nsegments = [ { kind = \"move\", duration = \"100 ms\", delta_deg = 900.0 }, { kind = \"hold\", duration = \"900 ms\" } ]\n"),
        ("mixed", "duration = \"1 s\"\n[motor]\nsegments = [ { kind = \"hold\", duration = \"200 ms\" }, { kind = \"move\", duration = \"200 ms\", delta_deg = 30.0 } ]\n[[events]]\nat = \"500 ms\"\nig = true\n[[events]]\nat = \"600 ms\"\nig = false\n[[events]]\nat = \"700 ms\"\nvs2_fault = true\n[[events]]\nat = \"750 ms\"\nvs2_fault = false\n"),
    ];
    for (name, src) in cases {
        let p = d.join(format!("{name}.toml"));
        std::fs::write(&p, src).unwrap();
        let sc = Scenario::load(&p).unwrap();
        assert!(
            parked_ticks(&sc, 0, sc.ticks) > sc.ticks / 2,
            "{name}: mostly parked"
        );
        for (f, format) in [("vcd", WaveFormat::Vcd), ("fst", WaveFormat::Fst)] {
            for (word, level) in [("all", Level::All), ("ports", Level::Ports)] {
                let out = d.join(format!("{f}-{word}"));
                expect(
                    &pmu50(&[
                        "run",
                        s(&p),
                        "--out-dir",
                        s(&out),
                        "--trace",
                        word,
                        "--format",
                        f,
                    ]),
                    0,
                    &[],
                );
                let size = std::fs::metadata(out.join(format!("{name}.{f}")))
                    .unwrap()
                    .len();
                let est = estimate_run_bytes(&sc, None, level, format);
                assert!(
                    size <= est,
                    "{name} {f} {word}: {size} bytes, estimate {est}"
                );
            }
        }
    }
}

#[test]
fn a_long_run_defaults_to_ports_and_its_refusal_says_level_and_format() {
    let d = tmp("long");
    let sc = d.join("long.toml");
    // The key on all the time (every tick active); a parked run: tests/cli_faults.rs.
    std::fs::write(&sc, format!("duration = \"1000 s\"\n{ON}")).unwrap();
    expect(&pmu50(&["run", s(&sc), "--out-dir", s(&d)]), 2, &["long.toml: the VCD at trace = ports would be about 11.5 GB (100000000 dumped ticks), above the limit of 2.0 GB; dump part of the run with --window START END, write the summary only with --trace none, write the compressed --format fst, or raise"]);
    expect(
        &pmu50(&["run", s(&sc), "--out-dir", s(&d), "--trace", "all"]),
        2,
        &[
            "the VCD at trace = all would be about 16.0 GB",
            "trace fewer signals with --trace ports (or none)",
        ],
    );
    // FST: its own estimate (18 bytes per tick), its own words.
    expect(&pmu50(&["run", s(&sc), "--out-dir", s(&d), "--format", "fst", "--max-vcd-bytes", "1000000000"]), 2, &["long.toml: the FST at trace = ports would be about 1.8 GB (100000000 dumped ticks), above the limit of 1.0 GB"]);
    let t = expect(
        &pmu50(&[
            "run",
            s(&sc),
            "--out-dir",
            s(&d),
            "--format",
            "fst",
            "--trace",
            "registers",
            "--max-vcd-bytes",
            "1000000000",
        ]),
        2,
        &["the FST at trace = registers would be about 1.8 GB"],
    );
    assert!(!t.contains("--format fst"), "{t}");
    std::fs::write(&sc, format!("duration = \"50 ms\"\n{ON}")).unwrap();
    expect(&pmu50(&["run", s(&sc), "--out-dir", s(&d), "--format", "fst", "--max-vcd-bytes", "50000"]), 2, &["the FST at trace = all would be about 106 kB (5000 dumped ticks), above the limit of 50 kB"]);
    expect(
        &pmu50(&[
            "run",
            s(&sc),
            "--out-dir",
            s(&d),
            "--format",
            "fst",
            "--max-vcd-bytes",
            "110000",
        ]),
        0,
        &["wrote"],
    );
}

#[test]
fn bad_levels_are_refused_with_the_valid_words() {
    let d = tmp("bad");
    let sc = write(
        &d,
        "bad.toml",
        "duration = \"5 ms\"\n[vcd]\ntrace = \"everything\"\n",
    );
    for cmd in ["check", "run"] {
        expect(
            &pmu50(&[cmd, s(&sc), "--out-dir", s(&d)][..if cmd == "check" { 2 } else { 4 }]),
            2,
            &["bad.toml:3: `vcd.trace`: `everything` is not a trace level; valid are \"ports\" (the core's inputs and outputs and the analog env values), \"registers\" (ports and every register), \"all\" (registers and the internals) and \"none\" (the summary only)"],
        );
    }
    expect(
        &pmu50(&[
            "run",
            "scenarios/fig15a.toml",
            "--out-dir",
            s(&d),
            "--trace",
            "regs",
        ]),
        2,
        &[
            "invalid value 'regs' for '--trace <TRACE>'",
            "[possible values: ports, registers, all, none]",
        ],
    );
    expect(&pmu50(&["run", "scenarios/fig15a.toml", "--out-dir", s(&d), "--trace", "none", "--window", "1 ms", "2 ms"]), 2, &["is run with trace = none, which writes no waveform; drop --window or run it with --trace ports, registers or all"]);
    let names: Vec<_> = std::fs::read_dir(&d)
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(names, ["bad.toml"], "nothing written");
}

#[test]
fn size_estimates_are_upper_bounds() {
    // The bounds (bytes per tick) against real runs: key on all the time with the shaft turning
    // fast (the worst case the bounds are set from) and a shipped key-off run turning fast.
    let d = tmp("est");
    let on = write(&d, "on.toml", KEY_ON_FAST);
    let fig = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenarios/too_fast.toml");
    // Two random scenarios of `pmu50 random` (the co-simulation's), the largest per tick of seeds 1-6.
    let mut runs = vec![(on.clone(), 5_000u64), (fig, 20_000)];
    for seed in ["4", "6"] {
        let p = d.join(format!("random{seed}.toml"));
        expect(&pmu50(&["random", "--seed", seed, "-o", s(&p)]), 0, &[]);
        runs.push((p.clone(), Scenario::load(&p).unwrap().ticks));
    }
    for (sc, ticks) in &runs {
        let (sc, ticks) = (sc.as_path(), *ticks);
        let name = Scenario::load(sc).unwrap().name;
        let name = name.as_str();
        for (f, format) in [("vcd", WaveFormat::Vcd), ("fst", WaveFormat::Fst)] {
            for (word, level) in [
                ("all", Level::All),
                ("registers", Level::Registers),
                ("ports", Level::Ports),
            ] {
                let out = d.join(format!("{f}-{word}"));
                // A random scenario may fail a check or see a write refused (exit 1): its files are written.
                let o = pmu50(&[
                    "run",
                    s(sc),
                    "--out-dir",
                    s(&out),
                    "--trace",
                    word,
                    "--format",
                    f,
                ]);
                assert!(matches!(o.status.code(), Some(0 | 1)), "{}", text(&o));
                let size = std::fs::metadata(out.join(format!("{name}.{f}")))
                    .unwrap()
                    .len();
                let est = estimate_wave_bytes(ticks, level, format);
                assert!(
                    size <= est,
                    "{name} {f} {word}: {size} bytes, estimate {est}"
                );
                if name == "on" {
                    // The worst case: the bound is not far above it.
                    assert!(
                        est <= 2 * size,
                        "{name} {f} {word}: {size} bytes, estimate {est}"
                    );
                }
            }
        }
    }
}
