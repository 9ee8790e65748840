//! `pmu50 diff` on bad input, run as a user would: exit code 2 with one clear line naming the file
//! and the line, never a panic message or backtrace; 0/1 only for a real comparison. The exit
//! codes come from the waves diff API (`DiffReport::exit_code`, `DiffError::exit_code`).

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

use pmu50_waves::fuzzing::{MALFORMED, VALID_SAMPLE};

use crate::common;
use common::{exited, tmp, write};

/// Runs `pmu50 args`, killing it after 20 s (a FIFO must never block it).
fn pmu50(args: &[&Path]) -> Output {
    let mut child = Command::new(env!("CARGO_BIN_EXE_pmu50"))
        .arg("diff")
        .args(args)
        .env("RUST_BACKTRACE", "1")
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let start = Instant::now();
    while child.try_wait().unwrap().is_none() {
        if start.elapsed() > Duration::from_secs(20) {
            child.kill().unwrap();
            panic!("pmu50 diff {args:?} did not finish in 20 s");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    child.wait_with_output().unwrap()
}

fn pmu50_args(args: &[&str]) -> Output {
    let paths: Vec<PathBuf> = args.iter().map(PathBuf::from).collect();
    let refs: Vec<&Path> = paths.iter().map(PathBuf::as_path).collect();
    pmu50(&refs)
}

/// Exit 2, nothing on stdout, exactly one line on stderr containing `want`, no panic text.
fn bad_input(o: &Output, want: &str) {
    let out = String::from_utf8_lossy(&o.stdout);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "stdout: {out}\nstderr: {err}");
    assert!(out.is_empty(), "nothing on stdout, got: {out}");
    assert!(
        !err.contains("panicked") && !err.contains("backtrace") && !err.contains("RUST_BACKTRACE"),
        "{err}"
    );
    assert_eq!(err.lines().count(), 1, "one line: {err}");
    assert!(
        err.starts_with("error: ") && err.contains(want),
        "`{want}` not in: {err}"
    );
}

#[test]
fn every_malformed_shape_exits_2_with_file_and_line_and_no_panic_text() {
    let d = tmp("shapes");
    let good = write(&d, "good.vcd", VALID_SAMPLE);
    for m in MALFORMED {
        let bad = write(&d, &format!("{}.vcd", m.name), m.vcd);
        let o = pmu50(&[&bad, &good]);
        bad_input(
            &o,
            &format!(
                "cannot read left waveform: {}:{}: malformed VCD: ",
                bad.display(),
                m.line
            ),
        );
        bad_input(&o, m.says);
        let o = pmu50(&[&good, &bad]);
        bad_input(
            &o,
            &format!("cannot read right waveform: {}:{}: ", bad.display(), m.line),
        );
    }
}

#[test]
fn width_4294967295_is_refused_before_allocating() {
    let d = tmp("width");
    let huge = b"$timescale 1 ns $end\n$scope module t $end\n$var wire 4294967295 ! a $end\n$upscope $end\n$enddefinitions $end\n#0\nb1 !\n";
    let f = write(&d, "huge.vcd", huge);
    let t = Instant::now();
    let o = pmu50(&[&f, &f]);
    bad_input(&o, &format!("{}:3: malformed VCD: variable `a` is declared with 4294967295 bits; the limit is 65536 bits", f.display()));
    assert!(t.elapsed() < Duration::from_secs(10));
}

#[test]
fn rnan_against_itself_is_equal_exit_0() {
    let d = tmp("nan");
    let v = b"$timescale 1 ns $end\n$scope module t $end\n$var real 64 ! v $end\n$upscope $end\n$enddefinitions $end\n#0\nrnan !\n#5\nr1 !\n#9\nrnan !\n";
    let f = write(&d, "nan.vcd", v);
    let o = pmu50(&[&f, &f]);
    let out = exited(&o, 0);
    assert!(out.starts_with("waveform diff: EQUAL"), "{out}");
}

#[test]
fn time_going_backwards_exits_2_not_equal() {
    let d = tmp("back");
    let head = "$timescale 1 ns $end\n$scope module t $end\n$var wire 1 ! a $end\n$upscope $end\n$enddefinitions $end\n#0\n0!\n#10\n1!\n";
    let back = write(&d, "back.vcd", format!("{head}#5\n0!\n").as_bytes());
    let plain = write(&d, "plain.vcd", head.as_bytes());
    let o = pmu50(&[&back, &plain]);
    bad_input(
        &o,
        &format!(
            "{}:10: malformed VCD: time goes backwards: #5 after #10 (line 8)",
            back.display()
        ),
    );
}

#[test]
fn fifo_directory_and_device_exit_2_without_blocking() {
    let d = tmp("special");
    let good = write(&d, "good.vcd", VALID_SAMPLE);
    let fifo = d.join("fifo.vcd");
    assert!(Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .unwrap()
        .success());
    for (p, kind) in [
        (fifo.as_path(), "FIFO"),
        (&*d, "directory"),
        (Path::new("/dev/zero"), "character device"),
    ] {
        bad_input(
            &pmu50(&[p, &good]),
            &format!(
                "cannot read left waveform: {} is a {kind}, not a regular file",
                p.display()
            ),
        );
        bad_input(
            &pmu50(&[&good, p]),
            &format!(
                "cannot read right waveform: {} is a {kind}, not a regular file",
                p.display()
            ),
        );
    }
}

#[test]
fn files_over_max_bytes_exit_2_and_the_limit_is_an_option() {
    let d = tmp("size");
    let f = write(&d, "f.vcd", VALID_SAMPLE);
    let n = VALID_SAMPLE.len();
    let fs = f.to_str().unwrap();
    let small = (n - 1).to_string();
    let o = pmu50_args(&[fs, fs, "--max-bytes", &small]);
    bad_input(&o, &format!("{fs} is {n} bytes, more than the limit of {} bytes; raise the limit (`pmu50 diff --max-bytes N`)", n - 1));
    let exact = n.to_string();
    assert_eq!(
        pmu50_args(&[fs, fs, "--max-bytes", &exact]).status.code(),
        Some(0)
    );
}

#[test]
fn missing_file_exits_2() {
    let o = pmu50_args(&["/nonexistent/a.vcd", "/nonexistent/b.vcd"]);
    bad_input(&o, "cannot open waveform file /nonexistent/a.vcd");
}

#[test]
fn equal_is_0_and_differ_is_1() {
    let d = tmp("codes");
    let a = write(&d, "a.vcd", VALID_SAMPLE);
    let mut changed = VALID_SAMPLE.to_vec();
    let at = changed.windows(5).position(|w| w == b"b101 ").unwrap();
    changed[at + 3] = b'0';
    let b = write(&d, "b.vcd", &changed);
    assert_eq!(pmu50(&[&a, &a]).status.code(), Some(0));
    let o = pmu50(&[&a, &b]);
    let out = exited(&o, 1);
    assert!(
        out.contains("t=1 (x 10 ns)  top.cnt[7:0]: left=00000101 right=00000100"),
        "{out}"
    );
}
