//! The `pmu50` command line: exit codes (0 ok, 1 a check failed / waveforms differ, 2 bad
//! input), the summary, the change log, vectors, random scenarios and the waveform diff.

use crate::common;
use common::{expect_code, pmu50, text, tmp, write};
use std::path::{Path, PathBuf};

#[test]
fn run_prints_the_summary_and_writes_vcd_gtkw_log() {
    let d = tmp("run");
    let o = pmu50(&[
        "run",
        "scenarios/threshold_error.toml",
        "--out-dir",
        d.to_str().unwrap(),
        "--log",
    ]);
    let t = text(&o);
    assert_eq!(o.status.code(), Some(0), "{t}");
    for want in [
        "key-on read-out",
        "CNTa=6",
        "theta_m=543.00 deg, true 543.00 deg",
        "theta_o=27.150 theta_i=28.650",
        "Vs2 duty",
        "average key-off current",
        "check readout_within_deg   PASS",
    ] {
        assert!(t.contains(want), "summary lacks `{want}`:\n{t}");
    }
    for ext in ["vcd", "gtkw", "log"] {
        assert!(d.join(format!("threshold_error.{ext}")).is_file());
    }
    let log = std::fs::read_to_string(d.join("threshold_error.log")).unwrap();
    let line = log
        .lines()
        .find(|l| l.contains("pmu50.drive_interval.si "))
        .expect("si changes are logged");
    let f: Vec<&str> = line.split_whitespace().collect();
    assert_eq!(f.len(), 6, "tick time register old -> new: {line}");
    assert_eq!(f[4], "->");
    let tick: u64 = f[0].parse().unwrap();
    let time_us: f64 = f[1].parse().unwrap();
    assert_eq!(tick * 10, time_us as u64, "time = tick * 10 us");
    assert!(
        !log.contains("timing_generator.tmr"),
        "the free-running timer is not logged"
    );
}

#[test]
fn failing_check_exits_1() {
    let d = tmp("fail");
    let sc = write(
        &d,
        "wrong.toml",
        "duration = \"30 ms\"\n[expect]\nsi_sequence_ms = [2.2]\n",
    );
    let o = pmu50(&[
        "run",
        sc.to_str().unwrap(),
        "--out-dir",
        d.to_str().unwrap(),
    ]);
    expect_code(&o, 1);
    assert!(text(&o).contains("check si_sequence_ms       FAIL"));
}

#[test]
fn bad_input_exits_2_with_file_line_field() {
    let d = tmp("bad");
    let sc = write(
        &d,
        "bad.toml",
        "duration = \"30 ms\"\n[core]\nt2 = \"1.105 ms\"\n",
    );
    let (sc, dir) = (sc.to_str().unwrap(), d.to_str().unwrap());
    for args in [vec!["run", sc, "--out-dir", dir], vec!["check", sc]] {
        let o = pmu50(&args);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", text(&o));
        assert!(text(&o).contains("bad.toml:3: `core.t2`"), "{}", text(&o));
    }
    let o = pmu50(&[
        "run",
        "scenarios/fig15a.toml",
        "--window",
        "5 ms",
        "1 ms",
        "--out-dir",
        dir,
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert_eq!(pmu50(&["run"]).status.code(), Some(2));
    assert_eq!(pmu50(&["check", "no/such.toml"]).status.code(), Some(2));
}

#[test]
fn list_shows_every_shipped_scenario() {
    let o = pmu50(&["list"]);
    let t = text(&o);
    for n in [
        "fig15a",
        "fig15b",
        "fig16",
        "keyoff_turns",
        "threshold_error",
        "first_embodiment",
        "too_fast",
    ] {
        assert!(t.contains(n), "{t}");
    }
    assert!(!t.contains("INVALID"));
}

#[test]
fn vectors_have_the_documented_header_and_one_line_per_tick() {
    let d = tmp("vec");
    let f = d.join("fig15a.vec");
    let o = pmu50(&[
        "vectors",
        "scenarios/fig15a.toml",
        "-o",
        f.to_str().unwrap(),
    ]);
    expect_code(&o, 0);
    let v = std::fs::read_to_string(&f).unwrap();
    assert!(v.starts_with("// pmu50 vectors v1\n// scenario fig15a\n// clock_ns 10000\n"));
    assert!(v.contains("// param SI_MAX 660\n") && v.contains("// fields 30\n"));
    let data: Vec<&str> = v.lines().filter(|l| !l.starts_with("//")).collect();
    assert_eq!(data.len(), 4800, "48 ms at 10 us");
    assert!(data
        .iter()
        .all(|l| l.split(' ').count() == 30
            && l.split(' ').all(|x| u32::from_str_radix(x, 16).is_ok())));
    // Line 0: inputs of edge 1 (key off, Vs2 on at reset) and the outputs after it.
    let f0: Vec<&str> = data[0].split(' ').collect();
    assert_eq!(
        &f0[..2],
        ["0", "1"],
        "ig = 0, vs2_ok = 1 during the first window"
    );
}

#[test]
fn random_is_deterministic_and_loadable() {
    let d = tmp("rnd");
    let (a, b) = (d.join("a.toml"), d.join("b.toml"));
    for p in [&a, &b] {
        assert_eq!(
            pmu50(&["random", "--seed", "42", "-o", p.to_str().unwrap()])
                .status
                .code(),
            Some(0)
        );
    }
    assert_eq!(std::fs::read(&a).unwrap(), std::fs::read(&b).unwrap());
    assert_eq!(
        pmu50(&["check", a.to_str().unwrap()]).status.code(),
        Some(0)
    );
}

fn run_vcd(d: &Path, sc: &Path) -> PathBuf {
    let o = pmu50(&[
        "run",
        sc.to_str().unwrap(),
        "--out-dir",
        d.to_str().unwrap(),
    ]);
    assert!(
        o.status.code() == Some(0) || o.status.code() == Some(1),
        "{}",
        text(&o)
    );
    d.join(format!("{}.vcd", sc.file_stem().unwrap().to_string_lossy()))
}

#[test]
fn diff_equal_differ_and_bad_input() {
    let d = tmp("diff");
    let (a, b) = (d.join("a"), d.join("b"));
    let fig = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenarios/fig15a.toml");
    let va = run_vcd(&a, &fig);
    let vb = run_vcd(&b, &fig);
    let o = pmu50(&["diff", va.to_str().unwrap(), vb.to_str().unwrap()]);
    expect_code(&o, 0);
    // Same scenario with T1 = 1.1 ms: the interval differs after the first change.
    let src = std::fs::read_to_string(&fig)
        .unwrap()
        .replace("[motor]", "[core]\nt1 = \"1.1 ms\"\n\n[motor]")
        .replace("si_sequence_ms = [6.6, 4.4, 2.2]", "");
    let c = d.join("c");
    std::fs::create_dir_all(&c).unwrap();
    let fc = write(&c, "fig15a.toml", src);
    let vc = run_vcd(&c, &fc);
    let o = pmu50(&[
        "diff",
        va.to_str().unwrap(),
        vc.to_str().unwrap(),
        "--max",
        "3",
    ]);
    let t = text(&o);
    assert_eq!(o.status.code(), Some(1), "{t}");
    assert!(
        t.contains("pmu50.register_file.t1"),
        "the first difference is the T1 register itself: {t}"
    );
    let o = pmu50(&[
        "diff",
        va.to_str().unwrap(),
        vc.to_str().unwrap(),
        "--map",
        "pmu50.drive_interval=pmu50.drive_interval",
    ]);
    let t = text(&o);
    assert_eq!(o.status.code(), Some(1), "{t}");
    assert!(
        t.contains("26620") && t.contains("pmu50.drive_interval.si"),
        "si first differs at the first shortening, 26.62 ms: {t}"
    );
    assert_eq!(
        pmu50(&["diff", va.to_str().unwrap(), "missing.vcd"])
            .status
            .code(),
        Some(2)
    );
    assert_eq!(
        pmu50(&[
            "diff",
            va.to_str().unwrap(),
            vb.to_str().unwrap(),
            "--map",
            "nonsense"
        ])
        .status
        .code(),
        Some(2)
    );
}

#[test]
fn key_on_polling_exercises_the_registered_read_path() {
    let d = tmp("poll");
    let f = d.join("k.vec");
    assert_eq!(
        pmu50(&[
            "vectors",
            "scenarios/first_embodiment.toml",
            "-o",
            f.to_str().unwrap()
        ])
        .status
        .code(),
        Some(0)
    );
    let v = std::fs::read_to_string(&f).unwrap();
    let mut seen = std::collections::BTreeMap::new();
    for l in v.lines().filter(|l| !l.starts_with("//")) {
        let x: Vec<u32> = l
            .split(' ')
            .map(|h| u32::from_str_radix(h, 16).unwrap())
            .collect();
        // Line k: bus_addr (field 5) of edge k+1, and bus_rdata (field 7 + 21) after it.
        seen.entry(x[5]).or_insert_with(Vec::new).push(x[28]);
    }
    assert!(seen[&0x00].iter().all(|&r| r == 0x5050), "ID");
    assert!(seen[&0x01].iter().all(|&r| r == 0x0001), "VERSION");
    assert!(
        seen[&0x0C].iter().all(|&r| r == 0x1002),
        "CFG: cnt_width 16, sync_depth 2"
    );
    assert!(seen[&0x06].iter().all(|&r| r == 660), "SI_MAX");
    assert!(seen[&0x02].iter().all(|&r| r == 0), "CTRL: adaptive off");
    assert!(
        seen.contains_key(&0x10) && seen.contains_key(&0x14),
        "counts and STATUS are polled"
    );
}

/// `PMU50_SYNC=0` leaves out the flush before the renames and nothing else: the same files,
/// every old file replaced; any other value than 0 or 1 is refused before anything runs.
#[test]
fn without_the_flush_the_files_are_the_same() {
    let d = tmp("nosync");
    let synced = d.join("synced");
    let unsynced = d.join("unsynced");
    std::fs::create_dir_all(&unsynced).unwrap();
    for ext in ["vcd", "gtkw", "log"] {
        std::fs::write(unsynced.join(format!("threshold_error.{ext}")), "old").unwrap();
    }
    let run = |dir: &Path, sync: &str| {
        std::process::Command::new(env!("CARGO_BIN_EXE_pmu50"))
            .args([
                "run",
                "scenarios/threshold_error.toml",
                "--trace",
                "all",
                "--log",
            ])
            .arg("--out-dir")
            .arg(dir)
            .env("PMU50_SYNC", sync)
            .current_dir(env!("CARGO_MANIFEST_DIR"))
            .output()
            .unwrap()
    };
    expect_code(&run(&synced, "1"), 0);
    expect_code(&run(&unsynced, "0"), 0);
    for ext in ["vcd", "gtkw", "log"] {
        let name = format!("threshold_error.{ext}");
        let a = std::fs::read(synced.join(&name)).unwrap();
        assert!(a.len() > 100, "{name} written");
        assert!(
            a == std::fs::read(unsynced.join(&name)).unwrap(),
            "{name} differs"
        );
    }
    let names: Vec<String> = std::fs::read_dir(&unsynced)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(names.len(), 3, "no temporary file is left: {names:?}");
    let bad = run(&d.join("bad"), "yes");
    expect_code(&bad, 2);
    let t = text(&bad);
    assert!(
        t.contains("PMU50_SYNC=\"yes\"") && t.contains("use 1"),
        "{t}"
    );
    assert!(!d.join("bad").exists(), "nothing ran");
}
