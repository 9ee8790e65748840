//! The generator draws the corners of the register ranges that the twin's code coverage needs
//! (docs/verification.md, "Code coverage of the RTL under test"): durations up to the 16-bit top
//! of each register, Cth from 64 to 255, and reads of bus addresses outside the register map.
//! Each test fails when the generator stops drawing its corner: the model runs the seeds and
//! every bit of each register must rise and fall within one seed's run, as Verilator's toggle
//! coverage counts it. And the regression reaches every reachable bin by itself, the port-level
//! ones (raw bus writes, a leaking power-good) included, with no witness file.

use pmu50_core::register_file::MAP;
use pmu50_core::Regs;
use pmu50_testbench::scenario::{self, Scenario};
use pmu50_testbench::sim::{self, Observer, SimError, Stepping, TickView};
use pmu50_verif::gen::{Action, Bias, Knob, Stimulus, KNOBS};
use pmu50_verif::lockstep::InputRecorder;
use std::collections::BTreeMap;
use std::path::Path;

/// Seeds a regression draws the corners within (the default of `make signoff`).
const SEEDS: u64 = 400;

fn parse(s: &Stimulus) -> Scenario {
    let text = s.to_toml("t");
    Scenario::parse(&text, "t", "t", Path::new("t.toml"))
        .unwrap_or_else(|e| panic!("seed {}: {e}\n{text}", s.seed))
}

/// The reads of a scenario: (tick, bus address).
fn reads_of(sc: &Scenario) -> Vec<(u64, u8)> {
    sc.events
        .iter()
        .filter_map(|e| match e.action {
            scenario::Action::Read { addr } => Some((e.tick, addr)),
            _ => None,
        })
        .collect()
}

/// The registers whose every bit must toggle, by name, with their width.
fn registers(r: &Regs) -> [(&'static str, u16, u32); 11] {
    let f = &r.register_file;
    [
        ("register_file.pw", f.pw, 16),
        ("register_file.pi", f.pi, 16),
        ("register_file.ps", f.ps, 16),
        ("register_file.si_max", f.si_max, 16),
        ("register_file.si_min", f.si_min, 16),
        ("register_file.t1", f.t1, 16),
        ("register_file.t2", f.t2, 16),
        ("register_file.smp_on", f.smp_on, 16),
        ("register_file.cth", u16::from(f.cth), 8),
        ("timing_generator.tmr", r.timing_generator.tmr, 16),
        ("drive_interval.si", r.drive_interval.si, 16),
    ]
}

/// The bits of each register that rose and fell within one run (toggle coverage's rule: a seed
/// adds its changes halved), over several runs.
#[derive(Default)]
struct Toggles {
    /// register -> (rose, fell) in this run
    run: BTreeMap<&'static str, (u16, u16)>,
    /// register -> bits that rose and fell within one run, over the runs
    both: BTreeMap<&'static str, u16>,
}

impl Toggles {
    fn end_run(&mut self) {
        for (name, (rose, fell)) in std::mem::take(&mut self.run) {
            *self.both.entry(name).or_default() |= rose & fell;
        }
    }

    /// The bits of each register that never toggled.
    fn missing(&self) -> Vec<String> {
        let mut out = Vec::new();
        for (name, _, width) in registers(&pmu50_core::pmu50::reset(&Default::default())) {
            let all = ((1u32 << width) - 1) as u16;
            let got = self.both.get(name).copied().unwrap_or(0);
            if got != all {
                out.push(format!("{name}: bits {:#06x} never toggle", all & !got));
            }
        }
        out
    }
}

impl Observer for Toggles {
    fn tick(&mut self, v: &TickView<'_>) -> Result<(), SimError> {
        for ((name, a, _), (_, b, _)) in registers(v.regs).into_iter().zip(registers(v.after)) {
            let e = self.run.entry(name).or_default();
            e.0 |= !a & b;
            e.1 |= a & !b;
        }
        Ok(())
    }
}

/// The seeds of 1..=SEEDS (uniform draws) that draw `knob`.
fn drawing(knob: Knob) -> Vec<Stimulus> {
    (1..=SEEDS)
        .map(|s| Stimulus::generate(s, &Bias::uniform()))
        .filter(|s| s.knobs.contains(&knob))
        .collect()
}

/// Durations up to the 16-bit top, and Cth from 64 to 255: run on the model, the seeds that
/// draw them toggle every bit of every duration register, of Cth, of the timing generator's
/// count and of the drive interval. Without them (a regression's other seeds) the high bits
/// stay still.
#[test]
fn long_durations_and_a_high_cth_toggle_every_register_bit() {
    let mut seeds = drawing(Knob::LongDurations);
    seeds.extend(drawing(Knob::CthTop));
    assert!(seeds.len() >= 20, "{} seeds draw the corners", seeds.len());
    let mut t = Toggles::default();
    for s in &seeds {
        let sc = parse(s);
        let p = &sc.params;
        p.validate().unwrap();
        sim::run_with(&sc, Stepping::Periods, &mut [&mut t]).unwrap();
        t.end_run();
    }
    assert_eq!(t.missing(), Vec::<String>::new());
    // the other seeds of the regression keep to short durations: the high bits are these knobs'
    let mut rest = Toggles::default();
    for s in (1..=40).map(|s| Stimulus::generate(s, &Bias::uniform())) {
        if s.knobs.contains(&Knob::LongDurations)
            || s.knobs.contains(&Knob::CthTop)
            || s.knobs.contains(&Knob::LongQuiet)
        {
            continue;
        }
        sim::run_with(&parse(&s), Stepping::Periods, &mut [&mut rest]).unwrap();
        rest.end_run();
    }
    assert_eq!(
        rest.both.get("register_file.pw").copied().unwrap_or(0) & 0x8000,
        0
    );
}

/// Reads outside the register map: the seeds that draw them read holes of the map and
/// addresses of 0x20 and above (bus_addr bits 5-7 rise, and fall at the next poll), never a
/// mapped address, only while the key is on (the scenario check refuses the rest), and the
/// model's bus carries the address in the read's tick.
#[test]
fn unmapped_reads_reach_every_address_bit() {
    let seeds = drawing(Knob::UnmappedReads);
    assert!(
        seeds.len() >= 10,
        "{} seeds read unmapped addresses",
        seeds.len()
    );
    let mapped = |a: u8| MAP.iter().any(|m| m.1 == a);
    let (mut holes, mut high) = (0, 0u8);
    for s in &seeds {
        let sc = parse(s);
        let reads = reads_of(&sc);
        let mut rec = InputRecorder::default();
        sim::run_with(&sc, Stepping::Periods, &mut [&mut rec]).unwrap();
        for &(tick, addr) in &reads {
            assert!(!mapped(addr), "seed {}: read of mapped {addr:#04x}", s.seed);
            // the recorded input word: bus_we in bit 4, bus_addr in bits 8-15
            let w = rec.inputs[tick as usize];
            assert_eq!((w >> 8) as u8, addr, "seed {} tick {tick}", s.seed);
            assert_eq!(
                w >> 4 & 1,
                0,
                "seed {} tick {tick}: a read is no write",
                s.seed
            );
            if addr < 0x20 {
                holes += 1;
            }
            high |= addr & 0xE0;
        }
    }
    assert!(holes > 0, "no read of a hole of the map");
    assert_eq!(high, 0xE0, "bus_addr bits 5-7 are not all read");
}

/// The corner knobs draw from streams of their own: a seed that draws none of them has the
/// scenario it had before they existed (the other knobs' draws are untouched), so the mutants'
/// catching seeds and the cached RTL builds of those seeds stay.
#[test]
fn the_corner_knobs_leave_the_other_seeds_alone() {
    let corners = [
        Knob::LongDurations,
        Knob::CthTop,
        Knob::UnmappedReads,
        Knob::PortLevel,
    ];
    let without = Bias {
        percent: KNOBS
            .iter()
            .copied()
            .filter(|(k, _)| !corners.contains(k))
            .collect(),
        ..Bias::uniform()
    };
    let mut same = 0;
    for seed in 1..=200 {
        let a = Stimulus::generate(seed, &Bias::uniform());
        if a.knobs.iter().any(|k| corners.contains(k)) {
            continue;
        }
        assert_eq!(a, Stimulus::generate(seed, &without), "seed {seed}");
        same += 1;
    }
    assert!(same > 100, "{same} seeds compared");
    // and generation is a pure function of the seed
    for seed in 1..=50 {
        assert_eq!(
            Stimulus::generate(seed, &Bias::uniform()),
            Stimulus::generate(seed, &Bias::uniform())
        );
    }
}

/// A generated read goes through the TOML and back as the same event.
#[test]
fn a_read_round_trips_through_the_scenario_file() {
    let s = drawing(Knob::UnmappedReads)
        .into_iter()
        .find(|s| s.events.iter().any(|e| matches!(e.1, Action::Read { .. })))
        .expect("a seed with a read");
    let sc = parse(&s);
    let want: Vec<(u64, u8)> = s
        .events
        .iter()
        .filter_map(|(t, a)| match a {
            Action::Read { addr } => Some((*t, *addr)),
            _ => None,
        })
        .collect();
    let got = reads_of(&sc);
    assert_eq!(want, got);
}

/// Every bin of coverage.json that is not declared unreachable and has no hit.
fn empty_bins(dir: &Path) -> Vec<String> {
    let c: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("coverage.json")).unwrap()).unwrap();
    c["bins"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|b| b.get("unreachable").is_none() && b["hits"].as_u64() == Some(0))
        .map(|b| b["name"].as_str().unwrap().to_string())
        .collect()
}

fn regress(dir: &Path, args: &[&str]) {
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_pmu50"))
        .args([
            "regress",
            "--directed",
            "--iterations",
            "400",
            "--jobs",
            "2",
        ])
        .args(args)
        .arg("--out")
        .arg(dir)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .unwrap();
    assert!(
        o.status.success(),
        "{}{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    );
}

/// 400 directed seeds hit every reachable bin by themselves, port-level bins included, drawing
/// their parameters from the default pool of an RTL run (`--param-sets 10`). On the model here;
/// on the twin and hdl/alt_sv with `PMU50_TEST_LONG=1`.
#[test]
fn a_directed_regression_reaches_every_reachable_bin_by_itself() {
    let t = std::env::temp_dir().join(format!("pmu50-reach-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&t);
    regress(&t.join("model"), &["--param-sets", "10"]);
    assert_eq!(empty_bins(&t.join("model")), Vec::<String>::new());
    // regress.json and the report list the pool the seeds drew from
    let rec: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(t.join("model/regress.json")).unwrap())
            .unwrap();
    let pool = rec["pool"].as_array().expect("regress.json lists the pool");
    assert!(!pool.is_empty() && pool.len() <= 10, "{pool:?}");
    let report = std::fs::read_to_string(t.join("model/report.html")).unwrap();
    assert!(
        report.contains(&format!("parameter sets: a pool of {}", pool.len())),
        "the report does not list the pool"
    );
    if std::env::var_os("PMU50_TEST_LONG").is_some() {
        for (name, rtl) in [("twin", "hdl/pmu50.f"), ("alt", "hdl/alt_sv/pmu50_alt.f")] {
            regress(&t.join(name), &["--dut", "verilator", "--rtl", rtl]);
            assert_eq!(empty_bins(&t.join(name)), Vec::<String>::new(), "{name}");
        }
    }
    let _ = std::fs::remove_dir_all(&t);
}

/// The port-level stimuli run on an RTL unlike the twin and on the twin, in lockstep: the
/// refusals of read-only and unmapped addresses, a CTH word with high bits (0x0100 refused,
/// 0x0105 taken as 5) and a leaking power-good (Sr stays 0) agree with the model.
#[test]
fn port_level_stimuli_agree_on_the_twin_and_an_rtl_unlike_it() {
    let t = std::env::temp_dir().join(format!("pmu50-port-{}", std::process::id()));
    std::fs::create_dir_all(&t).unwrap();
    let sc = t.join("port.toml");
    std::fs::write(
        &sc,
        r#"name = "port"
description = "port-level stimuli"
duration = "60 ms"
[core]
clock = "10 us"
[motor]
start_deg = 10.0
segments = [{ kind = "move", duration = "60 ms", delta_deg = 200.0 }]
[[events]]
at = "0 ms"
vs2_pg_leak = true
[[events]]
at = "5 ms"
vs2_pg_leak = false
[[events]]
at = "6 ms"
ig = true
[[events]]
at = "6 ms"
bus_write = { addr = 0x10, data = 0x1234 }
[[events]]
at = "7 ms"
bus_write = { addr = 0x00, data = 0xFFFF }
[[events]]
at = "7.01 ms"
bus_write = { addr = 0x7F, data = 0x0001 }
[[events]]
at = "7.02 ms"
bus_write = { addr = 0x0A, data = 0x0100 }
[[events]]
at = "7.03 ms"
bus_write = { addr = 0x0A, data = 0x0105 }
[[events]]
at = "7.04 ms"
read = 0x0A
[[events]]
at = "20 ms"
ig = false
[[events]]
at = "21 ms"
vs2_pg_leak = true
"#,
    )
    .unwrap();
    for rtl in ["hdl/pmu50.f", "hdl/alt_sv/pmu50_alt.f"] {
        let o = std::process::Command::new(env!("CARGO_BIN_EXE_pmu50"))
            .args(["regress", "--dut", "verilator", "--rtl", rtl, "--repro"])
            .arg(&sc)
            .current_dir(env!("CARGO_MANIFEST_DIR"))
            .output()
            .unwrap();
        let text = format!(
            "{}{}",
            String::from_utf8_lossy(&o.stdout),
            String::from_utf8_lossy(&o.stderr)
        );
        assert!(o.status.success() && text.contains("PASS"), "{rtl}: {text}");
    }
    // and the model hits the port-level bins on it
    let s = Scenario::load(&sc).unwrap();
    let (checks, _) = pmu50_verif::run_model(&s, false, &mut []).unwrap();
    let l = pmu50_coverage::layout();
    for name in [
        "bus.write_reg.read_only",
        "bus.write_reg.unmapped",
        "bus.write_outcome.refused_not_writable",
        "bus.illegal_rule.cth_zero_high_bits",
        "faults.pg_unpowered.high",
    ] {
        let i = l.bins.iter().position(|b| b.name == name).unwrap();
        assert!(checks.coverage.hits()[i] > 0, "{name} not hit");
    }
    let _ = std::fs::remove_dir_all(&t);
}
