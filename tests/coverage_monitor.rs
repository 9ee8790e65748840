//! The generated coverage monitor (hdl/formal/pmu50_cov.sv) over the twin, on Verilator, hits
//! exactly the bins the Rust sampler hits, edge by edge: on the shipped scenarios' stimuli
//! (`pmu50 vectors`, every tick, nothing skipped) and on random port stimuli of random legal
//! parameter sets (bus writes of every address, key edges inside the synchronizer, dead Vs2).
//! Needs verilator (`make deps`). The long scenarios run whole in `make test-long`
//! (PMU50_TEST_LONG=1), their first 20000 ticks otherwise; the 30-day park is left out (its
//! vector file would hold 260 million ticks).

use pmu50_core::rng::{ParamRanges, SplitMix64};
use pmu50_core::{Inputs, Params, Pmu50};
use pmu50_coverage::{layout, Coverage};
use std::collections::hash_map::DefaultHasher;
use std::hash::{Hash, Hasher};
use std::io::{BufRead, BufReader, Write};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

const ROOT: &str = env!("CARGO_MANIFEST_DIR");

/// One tick's inputs in the columns of a vector file.
type Row = [u32; 7];

/// The Verilator build of pmu50_cov_top for these parameters and clock period (cached by the
/// sources' text).
fn harness(p: &Params, clock_ns: u64) -> PathBuf {
    let hdl = Path::new(ROOT).join("hdl");
    let mut sources: Vec<PathBuf> = vec![hdl.join("pmu50.v")];
    let mut rtl: Vec<PathBuf> = std::fs::read_dir(hdl.join("rtl"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "v"))
        .collect();
    rtl.sort();
    sources.extend(rtl);
    sources.push(hdl.join("formal/pmu50_cov.sv"));
    sources.push(hdl.join("formal/pmu50_cov_top.sv"));
    let main = hdl.join("tb/coverage/cov_main.cpp");
    let mut h = DefaultHasher::new();
    for f in sources.iter().chain([&main]) {
        std::fs::read(f).unwrap().hash(&mut h);
    }
    p.hdl_parameters().hash(&mut h);
    clock_ns.hash(&mut h);
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("cov_monitor")
        .join(format!("{:016x}", h.finish()));
    let exe = dir.join("obj/Vpmu50_cov_top");
    if exe.exists() {
        return exe;
    }
    std::fs::create_dir_all(&dir).unwrap();
    let mut cmd = Command::new("verilator");
    cmd.current_dir(&dir).args([
        "--cc",
        "--exe",
        "--build",
        "-O1",
        "-j",
        "1",
        "-Wno-fatal",
        "-Wno-lint",
        "-Wno-style",
        "--top-module",
        "pmu50_cov_top",
        "-Mdir",
        "obj",
        "-CFLAGS",
        "-O1",
        "-CFLAGS",
    ]);
    cmd.arg(format!("-DHITS_BITS={}", layout().bins.len()));
    for (k, v) in p.hdl_parameters() {
        cmd.arg(format!("-G{k}={v}"));
    }
    cmd.arg(format!("-GCLOCK_NS={clock_ns}"));
    cmd.args(&sources).arg(&main);
    let out = cmd
        .output()
        .expect("verilator runs (make deps installs it)");
    assert!(
        out.status.success() && exe.exists(),
        "verilator build of the monitor failed:\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    exe
}

/// The monitor's hits before each edge, as bin indices.
fn monitor_hits(exe: &Path, rows: &[Row]) -> Vec<Vec<usize>> {
    let mut child = Command::new(exe)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .spawn()
        .unwrap();
    let mut stdin = child.stdin.take().unwrap();
    let text: String = rows
        .iter()
        .map(|r| {
            format!(
                "{:x} {:x} {:x} {:x} {:x} {:02x} {:04x}\n",
                r[0], r[1], r[2], r[3], r[4], r[5], r[6]
            )
        })
        .collect();
    let writer = std::thread::spawn(move || {
        stdin.write_all(text.as_bytes()).unwrap();
    });
    let n = layout().bins.len();
    let mut all = Vec::with_capacity(rows.len());
    for line in BufReader::new(child.stdout.take().unwrap()).lines() {
        let line = line.unwrap();
        let digits: Vec<u32> = line
            .chars()
            .rev()
            .map(|c| c.to_digit(16).unwrap())
            .collect();
        all.push(
            (0..n)
                .filter(|&i| digits.get(i / 4).is_some_and(|d| (d >> (i % 4)) & 1 == 1))
                .collect(),
        );
    }
    writer.join().unwrap();
    assert!(child.wait().unwrap().success());
    all
}

/// The Rust sampler's hits at each edge (the configuration sampled at the start counts at the
/// first edge), with the non-skipping step.
fn model_hits(p: &Params, clock_ns: u64, rows: &[Row]) -> Vec<Vec<usize>> {
    let mut core = Pmu50::new(*p).unwrap();
    let mut cov = Coverage::new(p, clock_ns);
    let mut last = vec![0u64; cov.hits().len()];
    let mut all = Vec::with_capacity(rows.len());
    for r in rows {
        let i = Inputs {
            ig: r[0] & 1 == 1,
            vs2_ok: r[1] & 1 == 1,
            cmp_s: r[2] & 1 == 1,
            cmp_c: r[3] & 1 == 1,
            bus_we: r[4] & 1 == 1,
            bus_addr: r[5] as u8,
            bus_wdata: r[6] as u16,
        };
        cov.step(&mut core, &i);
        let now = cov.hits();
        all.push((0..now.len()).filter(|&k| now[k] != last[k]).collect());
        last.copy_from_slice(now);
    }
    all
}

/// Both, edge by edge; returns the bins hit.
fn compare(what: &str, p: &Params, clock_ns: u64, rows: &[Row]) -> Vec<bool> {
    let exe = harness(p, clock_ns);
    let rtl = monitor_hits(&exe, rows);
    let model = model_hits(p, clock_ns, rows);
    assert_eq!(
        rtl.len(),
        rows.len(),
        "{what}: the monitor answered every tick"
    );
    let names = &layout().bins;
    let mut hit = vec![false; names.len()];
    for (k, (a, b)) in rtl.iter().zip(&model).enumerate() {
        if a != b {
            let only = |x: &Vec<usize>, y: &Vec<usize>| {
                x.iter()
                    .filter(|i| !y.contains(i))
                    .map(|&i| names[i].name.as_str())
                    .collect::<Vec<_>>()
            };
            panic!(
                "{what}: edge {k} (inputs {:?}): the monitor hit {:?} that the sampler did not, the sampler {:?} that the monitor did not",
                rows[k],
                only(a, b),
                only(b, a)
            );
        }
        for &i in a {
            hit[i] = true;
        }
    }
    hit
}

/// (parameters, clock, inputs) of a vector file.
fn read_vec(path: &Path) -> (Params, u64, Vec<Row>) {
    let text = std::fs::read_to_string(path).unwrap();
    let mut p = Params::DEFAULT;
    let mut clock = 10_000;
    let mut rows = Vec::new();
    for line in text.lines() {
        if let Some(rest) = line.strip_prefix("// param ") {
            let mut f = rest.split_whitespace();
            let (k, v) = (f.next().unwrap(), f.next().unwrap().parse().unwrap());
            p.set_hdl_parameter(k, v).unwrap();
        } else if let Some(rest) = line.strip_prefix("// clock_ns ") {
            clock = rest.trim().parse().unwrap();
        } else if !line.starts_with("//") && !line.trim().is_empty() {
            let f: Vec<u32> = line
                .split_whitespace()
                .take(7)
                .map(|x| u32::from_str_radix(x, 16).unwrap())
                .collect();
            rows.push([f[0], f[1], f[2], f[3], f[4], f[5], f[6]]);
        }
    }
    (p, clock, rows)
}

/// (parameters, clock, inputs) of a scenario's vectors (`pmu50 vectors`).
fn vectors(name: &str) -> (Params, u64, Vec<Row>) {
    let src = Path::new(ROOT).join(name);
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("cov_monitor");
    std::fs::create_dir_all(&dir).unwrap();
    let vec = dir.join(format!(
        "{}.vec",
        src.file_stem().unwrap().to_string_lossy()
    ));
    let out = Command::new(env!("CARGO_BIN_EXE_pmu50"))
        .args(["vectors"])
        .arg(&src)
        .arg("-o")
        .arg(&vec)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "pmu50 vectors {name}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    read_vec(&vec)
}

fn scenario(name: &str, max_ticks: Option<usize>) -> Vec<bool> {
    let (p, clock, mut rows) = vectors(name);
    if let Some(n) = max_ticks {
        rows.truncate(n);
    }
    compare(name, &p, clock, &rows)
}

/// Random port stimuli: key toggles (some shorter than the synchronizer), comparators, Vs2
/// dropouts, bus writes of every address with data near the legality limits, reads.
fn random_rows(seed: u64, ticks: usize) -> Vec<Row> {
    let mut r = SplitMix64::new(seed);
    let (mut ig, mut s, mut c) = (0u32, 0u32, 0u32);
    let mut rows = Vec::with_capacity(ticks);
    let mut hold = 0u32;
    for _ in 0..ticks {
        if hold == 0 && r.percent(1) {
            ig ^= 1;
            hold = if r.percent(30) { 1 } else { 40 };
        }
        hold = hold.saturating_sub(1);
        if r.percent(6) {
            s ^= 1;
        }
        if r.percent(6) {
            c ^= 1;
        }
        let we = u32::from(r.percent(4));
        let addr = if r.percent(85) {
            r.range(0x02, 0x0B) as u32
        } else {
            r.range(0, 0x1F) as u32
        };
        let data = match r.range(0, 3) {
            0 => r.range(0, 3),
            1 => r.range(0, 40),
            2 => r.range(0, 0x2FF) | (r.range(0, 1) << 9),
            _ => r.next() & 0xFFFF,
        } as u32;
        rows.push([ig, u32::from(!r.percent(4)), s, c, we, addr, data]);
    }
    rows
}

const SHORT: ParamRanges = ParamRanges {
    pw: 2,
    pi: 2,
    ps: 2,
    si_min_over_wt: 4,
    si_max_over_min: 12,
    narrow_cnt: (1, 1),
    narrow_cnt_max: 5,
    adaptive: (4, 5),
    t1: 8,
    t2: 8,
    cth: 4,
    smp_on: 4,
};

#[test]
fn monitor_matches_the_sampler_on_random_stimuli() {
    let names = &layout().bins;
    let mut hit = vec![false; names.len()];
    for seed in 1..=3u64 {
        let p = SplitMix64::new(seed * 7919).legal_params(&SHORT);
        let rows = random_rows(seed, 60_000);
        for (i, h) in compare(&format!("random seed {seed} ({p:?})"), &p, 10_000, &rows)
            .into_iter()
            .enumerate()
        {
            hit[i] |= h;
        }
    }
    // the comparison saw the rare bins too, not only quiet edges
    let n = hit.iter().filter(|&&h| h).count();
    assert!(n > 250, "random stimuli hit only {n} bins");
    for must in [
        "faults.sync_glitch.short_high",
        "bus.illegal_rule.window_too_long",
        "counter.wrap.cnt_s_up",
        "interval.shorten_to.min_clamped",
        "bus.write_outcome.refused_not_writable",
    ] {
        let i = names.iter().position(|b| b.name == must).unwrap();
        assert!(hit[i], "random stimuli never hit {must}");
    }
}

#[test]
fn monitor_matches_the_sampler_on_the_short_scenarios() {
    for s in [
        "scenarios/fig15a.toml",
        "scenarios/fig15b.toml",
        "scenarios/fig16.toml",
        "scenarios/too_fast.toml",
        "hdl/scenarios/hdl_bus.toml",
    ] {
        scenario(s, None);
    }
}

#[test]
fn monitor_matches_the_sampler_on_the_long_scenarios() {
    let max = if std::env::var_os("PMU50_TEST_LONG").is_some() {
        None
    } else {
        Some(20_000)
    };
    for s in [
        "scenarios/first_embodiment.toml",
        "scenarios/keyoff_turns.toml",
        "scenarios/park_bumps.toml",
        "scenarios/park_ferry.toml",
        "scenarios/park_still.toml",
        "scenarios/threshold_error.toml",
    ] {
        scenario(s, max);
    }
}

/// The witness scenarios of hdl/formal/deep, which decide the bins deeper than the coverage
/// proofs' bounded search (docs/verification.md section 2), hit the bins they are for on the
/// model; in `make test-long` the monitor over the twin agrees with the sampler edge by edge on
/// them too (their clocks of 5 and 20 us included). A scenario of the folder missing here fails.
#[test]
fn the_witness_scenarios_hit_the_bins_they_decide() {
    let wraps = |w: &str| -> Vec<String> {
        ["cnt_s_up", "cnt_s_down", "cnt_c_up", "cnt_c_down"]
            .iter()
            .map(|d| format!("cross.wrap_x_cnt_w.{d}*{w}"))
            .collect()
    };
    let sat = |b: &[&str]| -> Vec<String> {
        b.iter()
            .map(|s| format!("cross.fig17_x_cnt_r.{s}*saturated"))
            .collect()
    };
    let mut table: Vec<(&str, Vec<String>)> = vec![
        ("wrap_w4_clock5us", wraps("3_7")),
        ("wrap_w8_clock20us", wraps("8_15")),
        ("wrap_w16", wraps("16")),
        ("cnt_r_sat_at_min", sat(&["s5_at_min"])),
        (
            "cnt_r_sat_expanding",
            sat(&["s10_expand", "s7_at_max", "s6_shorten"]),
        ),
    ];
    table[0].1.push("config.clock.below_10us".into());
    table[1].1.push("config.clock.above_10us".into());
    table[3].1.push("cnt_r.before.saturated".into());
    table[4].1.push("cnt_r.value.saturated".into());
    let mut on_disk: Vec<String> = std::fs::read_dir(Path::new(ROOT).join("hdl/formal/deep"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .map(|p| p.file_stem().unwrap().to_string_lossy().into_owned())
        .collect();
    on_disk.sort();
    let mut named: Vec<String> = table.iter().map(|(n, _)| n.to_string()).collect();
    named.sort();
    assert_eq!(on_disk, named, "every witness scenario has its bins here");
    let long = std::env::var_os("PMU50_TEST_LONG").is_some();
    let names = &layout().bins;
    for (name, bins) in &table {
        let path = format!("hdl/formal/deep/{name}.toml");
        let (p, clock, rows) = vectors(&path);
        let hit = if long {
            compare(&path, &p, clock, &rows)
        } else {
            let mut hit = vec![false; names.len()];
            for edge in model_hits(&p, clock, &rows) {
                for i in edge {
                    hit[i] = true;
                }
            }
            hit
        };
        for b in bins {
            let i = names
                .iter()
                .position(|x| &x.name == b)
                .unwrap_or_else(|| panic!("{b} is no bin of the model"));
            assert!(hit[i], "{path} no longer hits {b}");
        }
    }
}
