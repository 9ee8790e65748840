//! Golden snapshots (insta, stored in `golden/`) of the patent's FIG. 15A, 15B/15C and 16
//! sequences: a readable per-pulse event table and the VCD itself. Every VCD written here is read
//! back with an independent reader (wellen) and compared value by value with what the model
//! produced; GTKWave's own loader must read every shipped scenario's VCD without a warning; the
//! same scenario must give byte-identical files.
//!
//! Review changed snapshots with `make golden` (cargo insta review); never accept blindly: the
//! patent's numbers are asserted directly in tests/patent_sequences.rs as well.

use pmu50_testbench::output::{run_to_files, FileOptions};
use pmu50_testbench::scenario::Scenario;
use pmu50_testbench::sim::{Observer, SimError, TickView};
use pmu50_waves::reader::Waveform;
use pmu50_waves::Value;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

fn scenario(name: &str) -> Scenario {
    Scenario::load(
        &Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("scenarios")
            .join(format!("{name}.toml")),
    )
    .unwrap()
}

fn tmp(tag: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("pmu50-golden-{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Records what the model produced at every tick: every port and register by VCD path.
#[derive(Default)]
struct Recorder {
    /// (time in us, path -> value)
    rows: Vec<(u64, BTreeMap<String, u64>)>,
    cnt_width: u8,
    sync_depth: u8,
}

impl Recorder {
    fn record(&mut self, v: &TickView<'_>) {
        let s = pmu50_core::pmu50::Structural {
            sync_depth: self.sync_depth,
            cnt_width: self.cnt_width,
        };
        let mut m = BTreeMap::new();
        for (n, _, val) in v.ports.values(&s) {
            m.insert(format!("pmu50.{n}"), val);
        }
        for r in v.regs.values(&s) {
            m.insert(format!("pmu50.{}.{}", r.block, r.name), r.value);
        }
        self.rows.push((v.time_ns / 1000, m));
    }
}

impl Observer for Recorder {
    fn tick(&mut self, v: &TickView<'_>) -> Result<(), SimError> {
        self.record(v);
        Ok(())
    }
    fn finish(&mut self, v: &TickView<'_>) -> Result<(), SimError> {
        self.record(v);
        Ok(())
    }
}

fn bits_to_u64(v: &Value) -> u64 {
    match v {
        Value::Bits(b) => {
            u64::from_str_radix(b, 2).unwrap_or_else(|_| panic!("non-binary value {b}"))
        }
        other => panic!("expected bits, got {other:?}"),
    }
}

/// Run, read the VCD back with wellen, and compare every port and register at every tick.
fn run_and_read_back(name: &str) -> (String, String) {
    let sc = scenario(name);
    let dir = tmp(name);
    let mut rec = Recorder {
        cnt_width: sc.params.cnt_width,
        sync_depth: sc.params.sync_depth,
        ..Default::default()
    };
    let (res, w) = run_to_files(&sc, &dir, FileOptions::default(), &mut [&mut rec]).unwrap();
    assert!(res.passed(), "{:?}", res.checks);
    let wave = Waveform::open(&w.vcd).unwrap();
    assert_eq!(
        wave.timescale().map(|t| t.to_string()),
        Some("1 us".to_string())
    );
    let paths: Vec<String> = rec.rows[0].1.keys().cloned().collect();
    for path in &paths {
        let changes = wave.changes(path).unwrap_or_else(|e| panic!("{e}"));
        let mut i = 0;
        let mut cur = None;
        for (t, vals) in &rec.rows {
            while i < changes.len() && changes[i].0 <= *t {
                cur = Some(bits_to_u64(&changes[i].1));
                i += 1;
            }
            assert_eq!(
                cur,
                Some(vals[path]),
                "{name}: {path} at {t} us: VCD says {cur:?}, model produced {}",
                vals[path]
            );
        }
    }
    let vcd = std::fs::read_to_string(&w.vcd).unwrap();
    let gtkw = std::fs::read_to_string(&w.gtkw).unwrap();
    std::fs::remove_dir_all(&dir).ok();
    (res.pulse_table(), vcd + "\n---- gtkw ----\n" + &gtkw)
}

fn golden(name: &str) {
    let (table, vcd) = run_and_read_back(name);
    insta::with_settings!({ snapshot_path => "../golden", prepend_module_to_snapshot => false, omit_expression => true }, {
        insta::assert_snapshot!(format!("{name}_events"), table);
        insta::assert_snapshot!(format!("{name}_vcd"), vcd);
    });
}

#[test]
fn golden_fig15a() {
    golden("fig15a");
}

#[test]
fn golden_fig15b() {
    golden("fig15b");
}

#[test]
fn golden_fig16() {
    golden("fig16");
}

/// The timing diagram in the patent's FIG. 15/16 style (`pmu50 run --svg`): the SVG itself is the
/// snapshot, reviewed as a picture (render it with `rsvg-convert golden/..`), and its numbers are
/// checked against the event table: every detected change carries the patent's reference sign.
fn golden_svg(name: &str) {
    let sc = scenario(name);
    let dir = tmp(&format!("svg-{name}"));
    let (res, w) = pmu50_testbench::output::run_to_files(
        &sc,
        &dir,
        FileOptions {
            svg: true,
            ..FileOptions::default()
        },
        &mut [],
    )
    .unwrap();
    let ws = w.svg.unwrap();
    let svg = std::fs::read_to_string(&ws.svg).unwrap();
    let csv = std::fs::read_to_string(&ws.csv).unwrap();
    std::fs::remove_dir_all(&dir).ok();
    // one reference sign per rotation detected in the pulse table (FIG. 18 S23 / S28), at its time
    use pmu50_core::drive_interval_changing_56b::Fig18;
    let detected: Vec<String> = res
        .pulses
        .iter()
        .filter_map(|p| match p.fig18 {
            Fig18::S23DetectedCs => Some(format!("{:.3},100", p.time_ns as f64 / 1e6)),
            Fig18::S28DetectedCc => Some(format!("{:.3},101", p.time_ns as f64 / 1e6)),
            _ => None,
        })
        .collect();
    let signs: Vec<String> = csv
        .lines()
        .filter(|l| l.ends_with(",100") || l.ends_with(",101"))
        .map(|l| format!("{},{}", &l[..l.find(',').unwrap()], &l[l.len() - 3..]))
        .collect();
    assert!(!detected.is_empty(), "{name}: no rotation detected");
    assert_eq!(signs, detected, "{name}: {csv}");
    insta::with_settings!({ snapshot_path => "../golden", prepend_module_to_snapshot => false, omit_expression => true }, {
        insta::assert_snapshot!(format!("{name}_svg"), svg);
    });
}

#[test]
fn golden_svg_fig15a() {
    golden_svg("fig15a");
}

#[test]
fn golden_svg_fig15b() {
    golden_svg("fig15b");
}

#[test]
fn golden_svg_fig16() {
    golden_svg("fig16");
}

#[test]
fn same_scenario_gives_byte_identical_files() {
    let sc = scenario("fig15b");
    let (a, b) = (tmp("det-a"), tmp("det-b"));
    for d in [&a, &b] {
        run_to_files(
            &sc,
            d,
            FileOptions {
                log: true,
                ..FileOptions::default()
            },
            &mut [],
        )
        .unwrap();
    }
    for ext in ["vcd", "gtkw", "log"] {
        let fa = std::fs::read(a.join(format!("fig15b.{ext}"))).unwrap();
        let fb = std::fs::read(b.join(format!("fig15b.{ext}"))).unwrap();
        assert!(fa == fb, "fig15b.{ext} differs between two runs");
    }
    std::fs::remove_dir_all(&a).ok();
    std::fs::remove_dir_all(&b).ok();
}

fn tool(name: &str) -> Option<PathBuf> {
    std::env::var_os("PATH").and_then(|p| {
        std::env::split_paths(&p)
            .map(|d| d.join(name))
            .find(|f| f.is_file())
    })
}

/// GTKWave's loader (vcd2lxt2) reads every shipped scenario's VCD, full and windowed, with
/// nothing on stderr (the converters exit 0 on broken input, so stderr is what counts).
#[test]
fn gtkwave_loader_reads_every_shipped_vcd_without_a_warning() {
    let Some(conv) = tool("vcd2lxt2") else {
        assert!(
            std::env::var_os("PMU50_ALLOW_MISSING_TOOLS").is_some(),
            "vcd2lxt2 (Debian package gtkwave) is not installed; `make test` installs it"
        );
        return;
    };
    let dir = tmp("gtkwave");
    let scen = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenarios");
    let mut files: Vec<PathBuf> = std::fs::read_dir(&scen)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    files.sort();
    assert!(files.len() >= 7);
    for p in files {
        let sc = Scenario::load(&p).unwrap();
        if sc.ticks > 1_000_000_000 {
            // Days of parking have no VCD of every tick (docs/spec.md 5.1); tests/skip_ahead.rs checks them.
            continue;
        }
        let half = sc.ticks / 2;
        for (tag, window) in [("full", None), ("window", Some((half / 2, half)))] {
            let d = dir.join(tag);
            let (_, w) = run_to_files(
                &sc,
                &d,
                FileOptions {
                    window,
                    ..FileOptions::default()
                },
                &mut [],
            )
            .unwrap();
            let lxt = d.join(format!("{}.lxt", sc.name));
            let out = std::process::Command::new(&conv)
                .arg(&w.vcd)
                .arg(&lxt)
                .output()
                .unwrap();
            let stderr = String::from_utf8_lossy(&out.stderr);
            // The converter echoes the file names (one of which contains "error"): drop them first.
            let stdout = String::from_utf8_lossy(&out.stdout)
                .replace(&*w.vcd.to_string_lossy(), "VCD")
                .replace(&*lxt.to_string_lossy(), "LXT")
                .to_lowercase();
            assert!(
                out.status.success() && stderr.trim().is_empty(),
                "{}: vcd2lxt2 said: {stderr}",
                w.vcd.display()
            );
            assert!(
                !stdout.contains("warning") && !stdout.contains("error"),
                "{}: {stdout}",
                w.vcd.display()
            );
            assert!(std::fs::metadata(&lxt).unwrap().len() > 0);
        }
    }
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn windowed_vcd_holds_only_the_window() {
    let sc = scenario("fig16");
    let dir = tmp("win");
    let (_, w) = run_to_files(
        &sc,
        &dir,
        FileOptions {
            window: Some((5_000, 6_000)),
            ..FileOptions::default()
        },
        &mut [],
    )
    .unwrap();
    let wave = Waveform::open(&w.vcd).unwrap();
    let tmr = wave.changes("pmu50.timing_generator.tmr").unwrap();
    assert!(
        tmr.first().unwrap().0 >= 50_000 && tmr.last().unwrap().0 <= 60_000,
        "{:?}..{:?}",
        tmr.first(),
        tmr.last()
    );
    std::fs::remove_dir_all(&dir).ok();
}
