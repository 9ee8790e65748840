//! Bad input, refused writes and safe outputs at the command line (README "Exit codes"): each
//! case with its exit code and message.
//! (Interruptions and disk full: tests/interrupt.rs.)

use std::path::Path;
use std::process::{Command, Stdio};

use crate::common;
use common::{expect, expect_code, pmu50, s, text, tmp, write, BIN, KEY_ON_FAST};

fn names(d: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(d)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

const SHORT: &str = "duration = \"5 ms\"\n";

// ------------------------------------------------------------------ section 1 ----

#[test]
fn a_symlink_at_the_output_path_is_replaced_not_followed() {
    let d = tmp("link");
    let precious = write(&d, "precious.txt", "not a waveform");
    let out = d.join("out");
    std::fs::create_dir_all(&out).unwrap();
    for ext in ["vcd", "gtkw", "log"] {
        std::os::unix::fs::symlink(&precious, out.join(format!("v.{ext}"))).unwrap();
    }
    let sc = write(&d, "v.toml", SHORT);
    expect(
        &pmu50(&["run", s(&sc), "--log", "--out-dir", s(&out)]),
        0,
        &["wrote"],
    );
    assert_eq!(
        std::fs::read_to_string(&precious).unwrap(),
        "not a waveform"
    );
    for ext in ["vcd", "gtkw", "log"] {
        let m = std::fs::symlink_metadata(out.join(format!("v.{ext}"))).unwrap();
        assert!(m.file_type().is_file(), "v.{ext} is a regular file now");
    }
    assert_eq!(
        names(&out),
        ["v.gtkw", "v.log", "v.vcd"],
        "no temporary file left"
    );
}

#[test]
fn two_scenarios_writing_the_same_file_exit_2_before_simulating() {
    let d = tmp("same");
    let (a, b) = (d.join("a.toml"), d.join("b.toml"));
    std::fs::write(&a, format!("name = \"twin\"\n{SHORT}")).unwrap();
    std::fs::write(&b, format!("name = \"twin\"\n{SHORT}")).unwrap();
    let out = d.join("out");
    let o = pmu50(&["run", s(&a), s(&b), "--out-dir", s(&out)]);
    expect(
        &o,
        2,
        &[
            "twin.vcd would be written by two scenarios",
            "a.toml",
            "b.toml",
            "nothing was run",
        ],
    );
    assert!(
        !out.exists() || names(&out).is_empty(),
        "nothing was simulated or written"
    );
}

#[test]
fn bad_files_are_all_reported_the_good_ones_run_and_the_worst_code_wins() {
    let d = tmp("many");
    let (a, bad, bad2, c) = (
        d.join("a.toml"),
        d.join("bad.toml"),
        d.join("bad2.toml"),
        d.join("c.toml"),
    );
    std::fs::write(&a, SHORT).unwrap();
    std::fs::write(&bad, "duration = \"5 ms\"\n[core]\nt2 = \"1.105 ms\"\n").unwrap();
    std::fs::write(&bad2, "duration = 3\n").unwrap();
    std::fs::write(&c, format!("{SHORT}[expect]\nsi_sequence_ms = [2.2]\n")).unwrap();
    let out = d.join("out");
    let o = pmu50(&["run", s(&a), s(&bad), s(&bad2), s(&c), "--out-dir", s(&out)]);
    expect(
        &o,
        2,
        &[
            "bad.toml:3: `core.t2`",
            "bad2.toml:1:",
            "== a:",
            "== c:",
            "check si_sequence_ms       FAIL",
        ],
    );
    assert_eq!(names(&out), ["a.gtkw", "a.vcd", "c.gtkw", "c.vcd"]);
    // Without the bad files the worst is the failed check: 1.
    expect(
        &pmu50(&["run", s(&a), s(&c), "--out-dir", s(&out)]),
        1,
        &["== a:", "== c:"],
    );
}

#[test]
fn a_stale_log_is_removed_when_the_new_run_writes_none() {
    let d = tmp("stale");
    let sc = write(&d, "v.toml", SHORT);
    let out = d.join("out");
    expect(
        &pmu50(&["run", s(&sc), "--log", "--out-dir", s(&out)]),
        0,
        &["v.log"],
    );
    assert_eq!(names(&out), ["v.gtkw", "v.log", "v.vcd"]);
    // A file of the user's that merely has the name is not a change log: it stays.
    expect(
        &pmu50(&["run", s(&sc), "--out-dir", s(&out)]),
        0,
        &["wrote"],
    );
    assert_eq!(names(&out), ["v.gtkw", "v.vcd"]);
    std::fs::write(out.join("v.log"), "my notes\n").unwrap();
    expect(
        &pmu50(&["run", s(&sc), "--out-dir", s(&out)]),
        0,
        &["wrote"],
    );
    assert_eq!(
        std::fs::read_to_string(out.join("v.log")).unwrap(),
        "my notes\n"
    );
}

#[test]
fn closed_or_full_streams_exit_2_without_panic_text() {
    // stdout on a full device
    let o = Command::new(BIN)
        .args(["list", "scenarios"])
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .stdout(std::fs::File::create("/dev/full").unwrap())
        .output()
        .unwrap();
    expect(&o, 2, &[]);
    assert!(
        o.stderr.is_empty(),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    // stderr on a full device (the error message cannot be written)
    let o = Command::new(BIN)
        .args(["check", "no/such.toml"])
        .stderr(std::fs::File::create("/dev/full").unwrap())
        .output()
        .unwrap();
    expect(&o, 2, &[]);
    // clap's help and usage errors too
    let o = Command::new(BIN)
        .arg("--help")
        .stdout(std::fs::File::create("/dev/full").unwrap())
        .output()
        .unwrap();
    expect(&o, 2, &[]);
    let o = Command::new(BIN).arg("--help").output().unwrap();
    expect(&o, 0, &["Usage: pmu50"]);
    let o = Command::new(BIN).args(["run", "--bogus"]).output().unwrap();
    expect(&o, 2, &["unexpected argument '--bogus'"]);
    // stdout a closed pipe: the reader went away before the summary
    let d = tmp("pipe");
    let mut child = Command::new(BIN)
        .args(["run", "scenarios/fig15a.toml", "--out-dir", s(&d)])
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    drop(child.stdout.take());
    let o = child.wait_with_output().unwrap();
    expect(&o, 2, &[]);
}

// ------------------------------------------------------------------ section 2 ----

#[test]
fn refused_writes_are_reported_with_file_line_and_reason_and_exit_1() {
    let d = tmp("refused");
    let sc = d.join("w.toml");
    std::fs::write(
        &sc,
        "duration = \"10 ms\"\n[[events]]\nat = \"0 ms\"\nig = true\n[[events]]\nat = \"0 ms\"\nwrite = { reg = \"T2\", value = 100 }\n\
         [[events]]\nat = \"5 ms\"\nwrite = { reg = \"SI_MIN\", value = 700 }\n[[events]]\nat = \"6 ms\"\nwrite = { reg = \"T1\", value = 100 }\n",
    )
    .unwrap();
    let o = pmu50(&["run", s(&sc), "--out-dir", s(&d)]);
    expect(
        &o,
        1,
        &[
            "w.toml:7: write T2 = 100 at 0.000 ms refused by the chip (bus_err set): the chip's synchronised key signal sig is still 0",
            "w.toml:10: write SI_MIN = 700 at 5.000 ms refused by the chip (bus_err set): the parameter set would become illegal: core.min (700 ticks) is above core.x (660 ticks)",
        ],
    );
    assert!(
        !text(&o).contains("w.toml:13"),
        "the legal T1 write is not reported:\n{}",
        text(&o)
    );
    // `check` validates statically; it cannot know the chip's state, and says the file is ok.
    expect(&pmu50(&["check", s(&sc)]), 0, &["ok"]);
}

#[test]
fn the_model_refuses_exactly_the_writes_reported() {
    // Cross-check with the waveform: bus_err rises right after the first refused write.
    let d = tmp("buserr");
    let sc = write(&d, "w.toml", "duration = \"2 ms\"\n[[events]]\nat = \"0 ms\"\nig = true\n[[events]]\nat = \"1 ms\"\nwrite = { reg = \"CTH\", value = 0 }\n");
    let o = pmu50(&["run", s(&sc), "--log", "--out-dir", s(&d)]);
    expect(
        &o,
        1,
        &[
            "w.toml:7: write CTH = 0 at 1.000 ms refused",
            "core.cth = 0 is out of range",
        ],
    );
    let log = std::fs::read_to_string(d.join("w.log")).unwrap();
    let line = log
        .lines()
        .find(|l| l.contains("register_file.bus_err"))
        .expect("bus_err changes in the log");
    assert!(
        line.trim_start().starts_with("101 "),
        "bus_err rises at edge 101 (write at tick 100): {line}"
    );
}

#[test]
fn a_window_outside_the_run_exits_2() {
    let d = tmp("window");
    let o = pmu50(&[
        "run",
        "scenarios/fig15a.toml",
        "--window",
        "40 ms",
        "50 ms",
        "--out-dir",
        s(&d),
    ]);
    expect(
        &o,
        2,
        &["--window 40 ms 50 ms is outside the run of scenarios/fig15a.toml (0 to 48 ms)"],
    );
    let sc = write(
        &d,
        "w.toml",
        "duration = \"10 ms\"\n[vcd]\nwindow = [\"12 ms\", \"20 ms\"]\n",
    );
    expect(
        &pmu50(&["check", s(&sc)]),
        2,
        &[
            "w.toml:3: `vcd.window[1]`",
            "after the end of the run (duration = 10 ms)",
        ],
    );
    assert_eq!(names(&d), ["w.toml"], "nothing written");
}

#[test]
fn a_vcd_over_the_limit_is_refused_unless_windowed_or_allowed() {
    let d = tmp("big");
    let sc = write(&d, "long.toml", "duration = \"1000 s\"\n");
    let o = pmu50(&["run", s(&sc), "--out-dir", s(&d)]);
    expect(&o, 2, &["long.toml: the VCD at trace = ports would be about 2.5 GB (100000000 dumped ticks), above the limit of 2.0 GB", "--window", "--max-vcd-bytes"]);
    let o = pmu50(&[
        "run",
        s(&sc),
        "--out-dir",
        s(&d),
        "--max-vcd-bytes",
        "1000000000",
    ]);
    expect(&o, 2, &["above the limit of 1.0 GB"]);
    // A small explicit limit applies to short runs too; a window brings the estimate down.
    std::fs::write(&sc, "duration = \"50 ms\"\n").unwrap();
    expect(
        &pmu50(&[
            "run",
            s(&sc),
            "--out-dir",
            s(&d),
            "--max-vcd-bytes",
            "100000",
        ]),
        2,
        &["about 428 kB (5000 dumped ticks)"],
    );
    expect(
        &pmu50(&[
            "run",
            s(&sc),
            "--out-dir",
            s(&d),
            "--max-vcd-bytes",
            "100000",
            "--window",
            "0 ms",
            "0.5 ms",
        ]),
        0,
        &["wrote"],
    );
}

#[test]
fn vcd_size_estimate_is_an_upper_bound() {
    // The estimate (160 bytes per tick) against real runs: key off (shipped) and key on all the time.
    let d = tmp("est");
    let on = write(&d, "on.toml", KEY_ON_FAST);
    let fig = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenarios/too_fast.toml");
    for (sc, name, ticks) in [
        (on.as_path(), "on", 5_000u64),
        (fig.as_path(), "too_fast", 20_000),
    ] {
        expect(&pmu50(&["run", s(sc), "--out-dir", s(&d)]), 0, &[]);
        let size = std::fs::metadata(d.join(format!("{name}.vcd")))
            .unwrap()
            .len();
        let est = pmu50_testbench::output::estimate_vcd_bytes(ticks);
        assert!(
            size <= est && est <= 4 * size,
            "{name}: {size} bytes, estimate {est}"
        );
    }
}

#[test]
fn list_never_blocks_on_a_fifo_and_check_refuses_non_regular_and_huge_files() {
    let d = tmp("fifo");
    let fifo = d.join("pipe.toml");
    let st = Command::new("mkfifo").arg(&fifo).status().unwrap();
    assert!(st.success(), "mkfifo");
    std::fs::write(d.join("ok.toml"), SHORT).unwrap();
    std::fs::create_dir(d.join("dir.toml")).unwrap();
    let mut child = Command::new(BIN)
        .args(["list", s(&d)])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let t0 = std::time::Instant::now();
    while child.try_wait().unwrap().is_none() {
        if t0.elapsed() > std::time::Duration::from_secs(20) {
            child.kill().ok();
            panic!("`pmu50 list` blocked on a FIFO");
        }
        std::thread::sleep(std::time::Duration::from_millis(10));
    }
    let o = child.wait_with_output().unwrap();
    expect(
        &o,
        0,
        &[
            "pipe.toml: is a FIFO (named pipe), not a regular file",
            "dir.toml: is a folder",
            "ok ",
        ],
    );
    expect(
        &pmu50(&["check", s(&fifo)]),
        2,
        &["pipe.toml: is a FIFO (named pipe), not a regular file; a scenario is a TOML file"],
    );
    expect(
        &pmu50(&["check", "/dev/null"]),
        2,
        &["/dev/null: is a device, not a regular file"],
    );
    let huge = write(
        &d,
        "huge.toml",
        format!("{SHORT}{}", "# padding\n".repeat(120_000)),
    );
    expect(
        &pmu50(&["check", s(&huge)]),
        2,
        &["huge.toml: 1200018 bytes is larger than a scenario can be (1048576 bytes at most)"],
    );
}

// ------------------------------------------------------------------ section 5 ----

#[test]
fn the_save_file_opens_on_the_whole_run_with_named_markers() {
    let d = tmp("gtkw");
    expect(
        &pmu50(&["run", "scenarios/fig16.toml", "--out-dir", s(&d)]),
        0,
        &[],
    );
    let g = std::fs::read_to_string(d.join("fig16.gtkw")).unwrap();
    // 110 ms = 110000 us in GTKWave's wave pane (about 800 px of the 1400 px window); GTKWave
    // shows 2^-zoom / 200 us per pixel.
    assert!(g.contains("[timestart] 0\n"), "{g}");
    let star = g.lines().find(|l| l.starts_with('*')).unwrap();
    let f: Vec<&str> = star.split(' ').collect();
    assert_eq!(f[0], "*-14.747144", "{star}");
    let us_per_px = 2f64.powf(14.747144) / 200.0;
    assert!(
        (110_000.0..110_100.0).contains(&(us_per_px * 800.0)),
        "{us_per_px}"
    );
    assert_eq!(f.len(), 2 + 26);
    // FIG. 16: Cs then Cc rotation (each with its shortening), then the climb 3.3 .. 6.6 ms.
    let names: Vec<&str> = g
        .lines()
        .filter_map(|l| l.strip_prefix("[markername] "))
        .collect();
    assert_eq!(
        names,
        [
            "Arotation cs, si 4.4 ms",
            "Brotation cc, si 2.2 ms",
            "Csi 3.3 ms",
            "Dsi 4.4 ms",
            "Esi 5.5 ms",
            "Fsi 6.6 ms"
        ]
    );
    assert_eq!(
        &f[2..4],
        ["26620", "39820"],
        "the FIG. 15A edges of the README walk-through"
    );
    assert!(f[8..].iter().all(|m| *m == "-1"));
}

#[test]
fn a_windowed_save_file_opens_on_the_window_with_its_markers_only() {
    let d = tmp("gtkww");
    expect(
        &pmu50(&[
            "run",
            "scenarios/fig16.toml",
            "--window",
            "30 ms",
            "50 ms",
            "--out-dir",
            s(&d),
        ]),
        0,
        &[],
    );
    let g = std::fs::read_to_string(d.join("fig16.gtkw")).unwrap();
    assert!(g.contains("[timestart] 30000\n"), "{g}");
    let names: Vec<&str> = g
        .lines()
        .filter_map(|l| l.strip_prefix("[markername] "))
        .collect();
    assert_eq!(names, ["Arotation cc, si 2.2 ms"], "{g}");
}

#[test]
fn vectors_and_random_outputs_are_atomic_too() {
    let d = tmp("vecatomic");
    let vec = write(&d, "f.vec", "previous vectors\n");
    // The VCD folder is a file: the run fails after the vectors were written to their temporary
    // file; the previous vector file stays and no temporary file is left.
    let blocker = write(&d, "not_a_dir", "x");
    let o = pmu50(&[
        "vectors",
        "scenarios/fig15a.toml",
        "-o",
        s(&vec),
        "--vcd-dir",
        s(&blocker),
    ]);
    expect(&o, 2, &["not_a_dir: cannot create the output folder"]);
    assert_eq!(std::fs::read_to_string(&vec).unwrap(), "previous vectors\n");
    assert_eq!(names(&d), ["f.vec", "not_a_dir"]);
    // Vectors written over the model's own VCD: refused before running.
    let o = pmu50(&[
        "vectors",
        "scenarios/fig15a.toml",
        "-o",
        s(&d.join("fig15a.vcd")),
        "--vcd-dir",
        s(&d),
    ]);
    expect(
        &o,
        2,
        &["fig15a.vcd is also the model's", "written into --vcd-dir"],
    );
    assert_eq!(names(&d), ["f.vec", "not_a_dir"]);
    // A symlink at the output of `random` is replaced, its target untouched.
    let target = write(&d, "target.txt", "keep");
    let link = d.join("r.toml");
    std::os::unix::fs::symlink(&target, &link).unwrap();
    expect(&pmu50(&["random", "--seed", "3", "-o", s(&link)]), 0, &[]);
    assert_eq!(std::fs::read_to_string(&target).unwrap(), "keep");
    assert!(std::fs::read_to_string(&link).unwrap().contains("random_3"));
    // An output folder that does not exist is an error naming it, exit 2.
    expect(
        &pmu50(&["random", "--seed", "3", "-o", s(&d.join("no/such/r.toml"))]),
        2,
        &["no/such/r.toml: cannot create a temporary file beside it"],
    );
}

// ------------------------------------------- device nodes, FIFOs, `-o -`, own input ----

/// An output path that exists and is a character device, a FIFO or a symlink to one
/// (`/dev/null`, `/proc/self/fd/1`) is refused with exit 2 and left exactly as it was; as root,
/// a character device made with mknod too. Before, `random` and `vectors` replaced the node by a
/// regular file and said nothing.
#[test]
fn device_nodes_fifos_and_links_to_them_are_never_replaced() {
    use std::os::unix::fs::FileTypeExt;
    let d = tmp("nodes");
    let fifo = d.join("fifo");
    assert!(
        Command::new("mkfifo")
            .arg(&fifo)
            .status()
            .unwrap()
            .success(),
        "mkfifo"
    );
    let null_link = d.join("null");
    std::os::unix::fs::symlink("/dev/null", &null_link).unwrap();
    let fd1 = d.join("fd1");
    std::os::unix::fs::symlink("/proc/self/fd/1", &fd1).unwrap();
    let mut nodes = vec![
        (fifo.clone(), "is a FIFO"),
        (null_link.clone(), "is a character device"),
        (fd1.clone(), "not a regular file"),
    ];
    let dev = d.join("dev");
    // SAFETY: mknod with a valid C string and mode; it fails (and the case is left out) unless root.
    let made = unsafe {
        let c = std::ffi::CString::new(s(&dev)).unwrap();
        libc::mknod(c.as_ptr(), libc::S_IFCHR | 0o666, libc::makedev(1, 3)) == 0
    };
    if made {
        nodes.push((dev.clone(), "is a character device"));
    }
    for (node, says) in &nodes {
        let kind = |p: &std::path::Path| {
            let (l, m) = (
                std::fs::symlink_metadata(p).unwrap().file_type(),
                std::fs::metadata(p).map(|m| m.file_type()),
            );
            (
                l.is_symlink(),
                l.is_fifo(),
                l.is_char_device(),
                m.map(|t| (t.is_fifo(), t.is_char_device())).ok(),
            )
        };
        let before = kind(node);
        // stdout a pipe: /proc/self/fd/1 of the child is a FIFO
        let random = Command::new(BIN)
            .args(["random", "--seed", "1", "-o", s(node)])
            .stdin(Stdio::null())
            .output()
            .unwrap();
        expect(
            &random,
            2,
            &[
                says,
                "an output file never replaces it",
                "or - for standard output",
            ],
        );
        assert!(
            random.stdout.is_empty(),
            "nothing written to standard output"
        );
        let vectors = pmu50(&["vectors", "scenarios/fig15a.toml", "-o", s(node)]);
        expect(&vectors, 2, &[says, "an output file never replaces it"]);
        assert_eq!(kind(node), before, "{} was replaced", node.display());
    }
    assert_eq!(
        names(&d).len(),
        nodes.len(),
        "no temporary file left: {:?}",
        names(&d)
    );
}

/// `-o -` is standard output: the same bytes as the file, streamed, and the vectors' "wrote"
/// note goes to stderr so that stdout holds the vectors only.
#[test]
fn dash_is_standard_output() {
    let d = tmp("dash");
    let f = d.join("r.toml");
    expect(&pmu50(&["random", "--seed", "3", "-o", s(&f)]), 0, &[]);
    let o = pmu50(&["random", "--seed", "3", "-o", "-"]);
    expect_code(&o, 0);
    assert_eq!(o.stdout, std::fs::read(&f).unwrap());
    let v = d.join("v.txt");
    expect(
        &pmu50(&["vectors", "scenarios/fig15a.toml", "-o", s(&v)]),
        0,
        &["wrote"],
    );
    let o = pmu50(&["vectors", "scenarios/fig15a.toml", "-o", "-"]);
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    assert_eq!(
        o.stdout,
        std::fs::read(&v).unwrap(),
        "stdout holds exactly the vector file"
    );
    assert!(String::from_utf8_lossy(&o.stderr)
        .contains("wrote the vectors to standard output (4800 ticks)"));
    assert!(
        !d.join("-").exists()
            && !std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
                .join("-")
                .exists()
    );
}

/// `vectors x.toml -o x.toml` (or through a link) is refused and the scenario is kept.
#[test]
fn vectors_never_overwrite_their_own_scenario() {
    let d = tmp("self");
    let x = write(&d, "x.toml", SHORT);
    let link = d.join("y.toml");
    std::os::unix::fs::symlink(&x, &link).unwrap();
    for out in [&x, &link] {
        expect(
            &pmu50(&["vectors", s(&x), "-o", s(out)]),
            2,
            &["is the scenario file itself", "choose another name"],
        );
        assert_eq!(std::fs::read_to_string(&x).unwrap(), SHORT);
    }
    assert!(std::fs::symlink_metadata(&link)
        .unwrap()
        .file_type()
        .is_symlink());
}

/// `diff --allow-unmatched` of two files with no signal in common compares nothing: exit 2 with
/// the reason, not EQUAL (0 compared).
#[test]
fn allow_unmatched_with_nothing_in_common_is_an_error() {
    let d = tmp("nothing");
    let vcd = |name: &str| {
        format!("$timescale 1 us $end\n$scope module top $end\n$var wire 1 ! {name} $end\n$upscope $end\n$enddefinitions $end\n#0\n1!\n#5\n0!\n")
    };
    let (a, b) = (d.join("a.vcd"), d.join("b.vcd"));
    std::fs::write(&a, vcd("alpha")).unwrap();
    std::fs::write(&b, vcd("beta")).unwrap();
    let o = pmu50(&["diff", s(&a), s(&b), "--allow-unmatched"]);
    expect(
        &o,
        2,
        &[
            "no signal of",
            "a.vcd",
            "b.vcd",
            "nothing would be compared",
            "--map",
        ],
    );
    assert!(!text(&o).contains("EQUAL"));
    // without the flag the files simply differ; with a common signal the flag still works
    expect(&pmu50(&["diff", s(&a), s(&b)]), 1, &["DIFFER"]);
    std::fs::write(
        &b,
        vcd("alpha").replace("$upscope", "$var wire 1 \" beta $end\n$upscope"),
    )
    .unwrap();
    expect(
        &pmu50(&["diff", s(&a), s(&b), "--allow-unmatched"]),
        0,
        &["EQUAL", "signals compared: 1"],
    );
}

// ------------------------------------------------------------------ bounded work ----

/// Work above its default limit is refused before it starts, naming the option that raises it:
/// simulated key-on ticks (`run`, `budget`: `--max-ticks`), the vector file (`--max-vector-bytes`),
/// speed-limit points (`--max-points`; a step of 1e-300 or a `--to` of 1e308 panicked with
/// "capacity overflow", 0.0003 grew to 1.6 GB before refusing). A month of parking with
/// `--trace none` stays allowed: the exact skip makes it cheap.
#[test]
fn unbounded_work_is_refused_before_it_starts() {
    let d = tmp("bounds");
    let long_on = write(
        &d,
        "long_on.toml",
        "duration = \"100000 d\"\n[[events]]\nat = \"1 ms\"\nig = true\n",
    );
    let o = pmu50(&["run", s(&long_on), "--trace", "none"]);
    expect(
        &o,
        2,
        &[
            "long_on.toml: the simulation of its key-on ticks would be about 863999999999950 ticks",
            "above the limit of 1000000000 ticks",
            "--max-ticks",
        ],
    );
    let hour = write(&d, "hour.toml", "duration = \"2 h\"\n[[events]]\nat = \"1 ms\"\nig = true\n[[events]]\nat = \"1 h\"\nig = false\n");
    expect(
        &pmu50(&["budget", s(&hour), "--out-dir", s(&d)]),
        2,
        &[
            "hour.toml: 3 simulations of its key-on ticks",
            "--max-ticks",
        ],
    );
    // the limit is the option's: a short key-on run above a small limit, below a large one
    let short_on = write(
        &d,
        "short_on.toml",
        "duration = \"10 ms\"\n[[events]]\nat = \"1 ms\"\nig = true\n",
    );
    expect(
        &pmu50(&["run", s(&short_on), "--trace", "none", "--max-ticks", "100"]),
        2,
        &["above the limit of 100 ticks"],
    );
    expect(
        &pmu50(&[
            "run",
            s(&short_on),
            "--trace",
            "none",
            "--max-ticks",
            "1000",
        ]),
        0,
        &["trace = none"],
    );
    // parked: 259 200 000 000 ticks, a few hundred thousand evaluated
    expect(
        &pmu50(&["run", "scenarios/park_30d.toml", "--trace", "none"]),
        0,
        &["ticks evaluated, the rest skipped exactly"],
    );
    let v = d.join("v.txt");
    expect(
        &pmu50(&["vectors", "scenarios/park_30d.toml", "-o", s(&v)]),
        2,
        &[
            "park_30d.toml: the vector file (259200000000 lines) would be about",
            "above the limit of 2.0 GB",
            "--max-vector-bytes",
        ],
    );
    assert!(!v.exists());
    expect(
        &pmu50(&[
            "vectors",
            "scenarios/fig15a.toml",
            "-o",
            s(&v),
            "--max-vector-bytes",
            "1000",
        ]),
        2,
        &["--max-vector-bytes"],
    );
    expect(
        &pmu50(&[
            "vectors",
            "scenarios/fig15a.toml",
            "-o",
            s(&v),
            "--max-vector-bytes",
            "1000000",
        ]),
        0,
        &["wrote"],
    );
    for args in [
        ["--step", "1e-300"],
        ["--to", "1e308"],
        ["--step", "0.0003"],
    ] {
        let t = std::time::Instant::now();
        let o = pmu50(&["speed-limit", args[0], args[1], "--out-dir", s(&d)]);
        expect(
            &o,
            2,
            &[
                "speed sweep",
                "above the limit of 2000 points",
                "--max-points",
            ],
        );
        assert!(
            t.elapsed().as_secs() < 10,
            "{args:?} took {:?}",
            t.elapsed()
        );
    }
    expect(
        &pmu50(&[
            "speed-limit",
            "--step",
            "1",
            "--from",
            "1000",
            "--to",
            "2000",
            "--max-points",
            "5000",
            "--out-dir",
            s(&d),
        ]),
        2,
        &["--max-ticks", "each point runs 90 deg / step"],
    );
}
