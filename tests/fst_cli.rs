//! `pmu50 run --format fst`: the FST of a scenario holds the same waveform as its VCD (`pmu50
//! diff` says EQUAL, exit 0), its `.gtkw` points at the `.fst`, no `.vcd` is written beside it,
//! reruns are byte-identical, and a damaged FST makes `pmu50 diff` exit 2 with one line and no
//! panic text. With `--window A B` the FST and the VCD of the same run are EQUAL too (the FST
//! starts at the window start), and a different window is not.

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};

fn pmu50(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_pmu50"))
        .args(args)
        .env("RUST_BACKTRACE", "1")
        .stdin(Stdio::null())
        .output()
        .unwrap()
}

fn tmp(tag: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("pmu50-fst-cli-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn scenario(name: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("scenarios").join(format!("{name}.toml")).display().to_string()
}

fn run(name: &str, dir: &Path, format: Option<&str>) {
    run_with(name, dir, format, &[]);
}

fn run_with(name: &str, dir: &Path, format: Option<&str>, extra: &[&str]) {
    let sc = scenario(name);
    let d = dir.display().to_string();
    let mut args = vec!["run", sc.as_str(), "--out-dir", d.as_str()];
    if let Some(f) = format {
        args.extend(["--format", f]);
    }
    args.extend(extra);
    let o = pmu50(&args);
    assert!(o.status.success(), "pmu50 {args:?}: {}", String::from_utf8_lossy(&o.stderr));
}

#[test]
fn fst_run_equals_vcd_run_and_gtkw_points_at_it() {
    let d = tmp("equal");
    let (v, f, f2) = (d.join("v"), d.join("f"), d.join("f2"));
    run("fig15b", &v, None);
    run("fig15b", &f, Some("fst"));
    run("fig15b", &f2, Some("fst"));
    let fst = f.join("fig15b.fst");
    assert!(!f.join("fig15b.vcd").exists(), "--format fst also wrote a VCD");
    let bytes = std::fs::read(&fst).unwrap();
    assert_eq!(bytes[0], 0, "an FST starts with its header block (type 0)");
    assert_eq!(bytes, std::fs::read(f2.join("fig15b.fst")).unwrap(), "FST reruns differ");
    let gtkw = std::fs::read_to_string(f.join("fig15b.gtkw")).unwrap();
    assert!(gtkw.contains("[dumpfile] \"fig15b.fst\""), "{gtkw}");
    let vcd_gtkw = std::fs::read_to_string(v.join("fig15b.gtkw")).unwrap();
    assert!(vcd_gtkw.contains("[dumpfile] \"fig15b.vcd\""), "{vcd_gtkw}");

    let vcd = v.join("fig15b.vcd").display().to_string();
    let fst = fst.display().to_string();
    let o = pmu50(&["diff", &vcd, &fst]);
    let out = String::from_utf8_lossy(&o.stdout);
    assert_eq!(o.status.code(), Some(0), "{out}{}", String::from_utf8_lossy(&o.stderr));
    assert!(out.contains("EQUAL") && out.contains("value mismatches: 0"), "{out}");
    // and a different scenario's FST is not equal: the comparison can fail
    run("fig15a", &f, Some("fst"));
    let other = f.join("fig15a.fst").display().to_string();
    let o = pmu50(&["diff", &vcd, &other]);
    assert_eq!(o.status.code(), Some(1), "{}", String::from_utf8_lossy(&o.stdout));
    std::fs::remove_dir_all(&d).unwrap();
}

/// Regression: the windowed FST had its window-start values at time 0 (and the window start in
/// the header's time-zero field), so the diff said DIFFER with a mismatch per signal at 0 us.
#[test]
fn windowed_fst_run_equals_windowed_vcd_run() {
    let d = tmp("window");
    let (v, f, g) = (d.join("v"), d.join("f"), d.join("g"));
    run_with("fig15a", &v, None, &["--window", "10 ms", "30 ms"]);
    run_with("fig15a", &f, Some("fst"), &["--window", "10 ms", "30 ms"]);
    run_with("fig15a", &g, Some("fst"), &["--window", "12 ms", "30 ms"]);
    let vcd = v.join("fig15a.vcd").display().to_string();
    let fst = f.join("fig15a.fst").display().to_string();
    for (l, r) in [(&vcd, &fst), (&fst, &vcd)] {
        let o = pmu50(&["diff", l, r]);
        let out = String::from_utf8_lossy(&o.stdout);
        assert_eq!(o.status.code(), Some(0), "{out}{}", String::from_utf8_lossy(&o.stderr));
        assert!(out.contains("EQUAL") && out.contains("value mismatches: 0"), "{out}");
    }
    let later = g.join("fig15a.fst").display().to_string();
    let o = pmu50(&["diff", &vcd, &later]);
    let out = String::from_utf8_lossy(&o.stdout);
    assert_eq!(o.status.code(), Some(1), "{out}");
    assert!(out.contains("(first at 10000 us)"), "{out}");
    std::fs::remove_dir_all(&d).unwrap();
}

#[test]
fn damaged_fst_exits_2_with_one_line() {
    let d = tmp("bad");
    run("fig15b", &d, Some("fst"));
    let good = std::fs::read(d.join("fig15b.fst")).unwrap();
    let vcd_dir = d.join("v");
    run("fig15b", &vcd_dir, None);
    let vcd = vcd_dir.join("fig15b.vcd").display().to_string();
    for (k, cut) in [3, 20, good.len() / 3, good.len() - 10].into_iter().enumerate() {
        let bad = d.join(format!("bad{k}.fst"));
        std::fs::write(&bad, &good[..cut]).unwrap();
        let o = pmu50(&["diff", &vcd, &bad.display().to_string()]);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "cut {cut}: {err}");
        assert!(o.stdout.is_empty(), "cut {cut}: {}", String::from_utf8_lossy(&o.stdout));
        assert_eq!(err.trim_end().lines().count(), 1, "cut {cut}: {err}");
        assert!(err.contains("bad") && err.contains("FST"), "cut {cut}: {err}");
        assert!(!err.contains("panick") && !err.contains("backtrace") && !err.contains("RUST_BACKTRACE"), "cut {cut}: {err}");
    }
    std::fs::remove_dir_all(&d).unwrap();
}
