//! The files of a regression folder as a careless or hostile user leaves them, read back by
//! `pmu50 regress --resume`, `pmu50 merge` and `pmu50 closure`: each bad case is refused with
//! exit 2 and a message naming the file, the line or field, and what is valid; nothing is lost
//! or written outside the folder. Also: a merge of adjacent seed ranges, merge's output folder,
//! the repro folders a merge carries, the scheduler's variables and the flags `--resume` takes.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::time::{Duration, Instant};

use crate::common;
use common::{expect, pmu50, s, tmp};

/// `pmu50 regress` of `n` seeds from `start` into `dir` (the model; no triage), checked to pass.
fn regress(dir: &Path, start: u64, n: u64) {
    let o = pmu50(&[
        "regress",
        "--start-seed",
        &start.to_string(),
        "--iterations",
        &n.to_string(),
        "--jobs",
        "2",
        "--no-triage",
        "--out",
        s(dir),
    ]);
    expect(&o, 0, &["pass"]);
}

fn read(p: impl AsRef<Path>) -> String {
    std::fs::read_to_string(p.as_ref()).unwrap_or_else(|e| panic!("{}: {e}", p.as_ref().display()))
}

/// A copy of regression folder `from` at `to` (its regular files).
fn copy(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for e in std::fs::read_dir(from).unwrap() {
        let e = e.unwrap();
        if e.file_type().unwrap().is_file() {
            std::fs::copy(e.path(), to.join(e.file_name())).unwrap();
        }
    }
}

/// `dir/regress.json` with `field` set to `value`.
fn edit_spec(dir: &Path, field: &str, value: serde_json::Value) {
    let p = dir.join("regress.json");
    let mut v: serde_json::Value = serde_json::from_str(&read(&p)).unwrap();
    v[field] = value;
    // a hand-made folder has no evidence: what the run sealed (its provenance, record, files'
    // digests and the digest over them) no longer describes it (tests/signoff.rs and
    // tests/evidence.rs check that an edited one is refused)
    for k in ["provenance", "record", "files", "coverage_inputs", "digest"] {
        v.as_object_mut().unwrap().remove(k);
    }
    std::fs::write(&p, v.to_string()).unwrap();
}

/// Each result line without what depends on where and how fast it ran.
fn verdicts(dir: &Path) -> Vec<String> {
    read(dir.join("results.jsonl"))
        .lines()
        .map(|l| {
            let mut v: serde_json::Value = serde_json::from_str(l).expect("json line");
            let o = v.as_object_mut().expect("object");
            o.remove("wall_ms");
            o.remove("where");
            v.to_string()
        })
        .collect()
}

/// `pmu50 ARGS` with a deadline: a command that would hang (reading a FIFO) fails the test
/// instead of hanging it.
fn pmu50_within(args: &[&str], env: &[(&str, &str)]) -> Output {
    let mut c = Command::new(common::BIN);
    c.args(args)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped());
    for (k, v) in env {
        c.env(k, v);
    }
    let mut child = c.spawn().unwrap();
    let start = Instant::now();
    while child.try_wait().unwrap().is_none() {
        if start.elapsed() > Duration::from_secs(60) {
            let _ = child.kill();
            panic!("pmu50 {args:?} still runs after 60 s");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    child.wait_with_output().unwrap()
}

#[test]
fn an_absurd_seed_range_is_refused_at_once() {
    let t = tmp("absurd");
    let out = t.join("o");
    let o = pmu50_within(
        &[
            "regress",
            "--start-seed",
            "0",
            "--iterations",
            "1000000000000",
            "--jobs",
            "1",
            "--out",
            s(&out),
        ],
        &[],
    );
    expect(
        &o,
        2,
        &["--iterations 1000000000000: at most 10000000 seeds"],
    );
    assert!(!out.exists(), "nothing is written");
    let o = pmu50(&["regress", "--iterations", "10000001", "--out", s(&out)]);
    expect(&o, 2, &["at most 10000000 seeds"]);
}

#[test]
fn regress_json_is_checked_as_strictly_as_the_command_line() {
    let t = tmp("spec");
    let good = t.join("good");
    regress(&good, 1, 6);
    let cases: [(&str, serde_json::Value, &str); 5] = [
        (
            "shard",
            serde_json::json!({"index": 0, "count": 0}),
            "field `shard`: 0/0; valid is index/count with 0 <= index < count",
        ),
        (
            "shard",
            serde_json::json!({"index": 7, "count": 3}),
            "field `shard`: 7/3",
        ),
        (
            "start_seed",
            serde_json::json!(u64::MAX - 2),
            "field `start_seed`: 18446744073709551613 + 6 seeds passes 2^64",
        ),
        (
            "iterations",
            serde_json::json!(0),
            "field `iterations`: 0 seeds; valid is 1 to 10000000",
        ),
        (
            "iterations",
            serde_json::json!(1_000_000_000_000u64),
            "field `iterations`: 1000000000000 seeds",
        ),
    ];
    for (k, (field, value, want)) in cases.into_iter().enumerate() {
        let d = t.join(format!("bad{k}"));
        copy(&good, &d);
        edit_spec(&d, field, value);
        let spec = d.join("regress.json");
        let want = format!("{}: {want}", spec.display());
        let before = read(d.join("results.jsonl"));
        expect(
            &pmu50_within(&["regress", "--resume", s(&d)], &[]),
            2,
            &[&want],
        );
        expect(
            &pmu50(&["merge", "--out", s(&t.join(format!("m{k}"))), s(&d)]),
            2,
            &[&want],
        );
        expect(
            &pmu50(&["closure", "-o", s(&t.join("c.svg")), s(&d)]),
            2,
            &[&want],
        );
        assert_eq!(
            read(d.join("results.jsonl")),
            before,
            "{field}: the folder is left as it was"
        );
    }
}

#[test]
fn a_torn_last_line_is_cut_before_a_resume_appends() {
    let t = tmp("torn");
    let full = t.join("full");
    regress(&full, 1, 40);
    // An interrupted run: 13 seeds and half a line.
    let cut = t.join("cut");
    std::fs::create_dir(&cut).unwrap();
    std::fs::copy(full.join("regress.json"), cut.join("regress.json")).unwrap();
    let all = read(full.join("results.jsonl"));
    let lines: Vec<&str> = all.lines().collect();
    let mut partial = lines[..13].join("\n");
    partial.push('\n');
    partial.push_str(&lines[13][..lines[13].len() / 2]);
    std::fs::write(cut.join("results.jsonl"), &partial).unwrap();
    // The resume is stopped after its seeds are appended (its report cannot be written)...
    std::fs::create_dir(cut.join("report.html")).unwrap();
    let o = pmu50(&["regress", "--resume", s(&cut), "--no-triage"]);
    expect(&o, 2, &["report.html"]);
    // ... and every line of results.jsonl is a whole result: the torn bytes were cut.
    let kept = read(cut.join("results.jsonl"));
    assert_eq!(kept.lines().count(), 40, "{kept}");
    for l in kept.lines() {
        serde_json::from_str::<serde_json::Value>(l)
            .unwrap_or_else(|e| panic!("a torn line stayed: {e}: {l}"));
    }
    std::fs::remove_dir(cut.join("report.html")).unwrap();
    expect(
        &pmu50(&["regress", "--resume", s(&cut)]),
        0,
        &["40 seeds, 40 pass"],
    );
    assert_eq!(verdicts(&cut), verdicts(&full));
    assert_eq!(
        read(cut.join("coverage.json")),
        read(full.join("coverage.json"))
    );
}

#[test]
fn a_seed_present_twice_or_outside_the_range_is_refused() {
    let t = tmp("dup");
    let a = t.join("a");
    regress(&a, 1, 20);
    let lines: Vec<String> = read(a.join("results.jsonl"))
        .lines()
        .map(String::from)
        .collect();
    // Duplicate lines: the seed and both places are named.
    let dup = t.join("dup");
    copy(&a, &dup);
    std::fs::write(
        dup.join("results.jsonl"),
        format!("{}\n{}\n", lines.join("\n"), lines[2]),
    )
    .unwrap();
    let results = dup.join("results.jsonl");
    let want = format!(
        "seed 3 is in {} (line 3) and in {} (line 21)",
        results.display(),
        results.display()
    );
    expect(&pmu50(&["regress", "--resume", s(&dup)]), 2, &[&want]);
    expect(
        &pmu50(&["merge", "--out", s(&t.join("m1")), s(&dup)]),
        2,
        &[&want],
    );
    // A seed of another range.
    let far = t.join("far");
    copy(&a, &far);
    let foreign = lines[0].replacen("\"seed\":1,", "\"seed\":104,", 1);
    std::fs::write(
        far.join("results.jsonl"),
        format!("{}\n{foreign}\n", lines[1..].join("\n")),
    )
    .unwrap();
    let want = format!(
        "{}: line 20: field `seed`: 104 is outside the seeds of this folder (1..=20)",
        far.join("results.jsonl").display()
    );
    expect(&pmu50(&["regress", "--resume", s(&far)]), 2, &[&want]);
    expect(
        &pmu50(&["merge", "--out", s(&t.join("m2")), s(&far)]),
        2,
        &[&want],
    );
    // A verdict that is not one.
    let odd = t.join("odd");
    copy(&a, &odd);
    std::fs::write(
        odd.join("results.jsonl"),
        lines[0].replacen("\"verdict\":\"pass\"", "\"verdict\":\"fine\"", 1) + "\n",
    )
    .unwrap();
    expect(
        &pmu50(&["regress", "--resume", s(&odd)]),
        2,
        &["line 1: not a seed result: field `verdict`: `fine`; valid is pass, fail or error"],
    );
}

#[test]
fn merge_never_replaces_an_input_and_asks_before_replacing_a_regression() {
    let t = tmp("mergeout");
    let (s0, s1, s2) = (t.join("s0"), t.join("s1"), t.join("s2"));
    for (i, d) in [&s0, &s1, &s2].into_iter().enumerate() {
        let o = pmu50(&[
            "regress",
            "--iterations",
            "30",
            "--shard",
            &format!("{i}/3"),
            "--no-triage",
            "--out",
            s(d),
        ]);
        expect(&o, 0, &[]);
    }
    let kept = read(s1.join("results.jsonl"));
    let cov = s1.join("coverage.json");
    let o = pmu50(&["merge", "--out", s(&s1), s(&s0), s(&s2), s(&cov)]);
    expect(&o, 2, &["this input is inside the output folder"]);
    let o = pmu50(&["merge", "--out", s(&s1), s(&s0), s(&s1), s(&s2)]);
    expect(&o, 2, &["the output folder is also an input"]);
    // An existing regression folder that is not an input: replaced only with --force.
    let o = pmu50(&["merge", "--out", s(&s1), s(&s0), s(&s2)]);
    expect(
        &o,
        2,
        &["holds a regression already (regress.json)", "--force"],
    );
    assert_eq!(read(s1.join("results.jsonl")), kept, "s1 is left as it was");
    // Shard folders below the output folder are fine: the merge writes none of their files.
    let parent = t.join("runs");
    for (i, d) in [&s0, &s1, &s2].into_iter().enumerate() {
        copy(d, &parent.join(format!("shard-{i}")));
    }
    let below: Vec<PathBuf> = (0..3).map(|i| parent.join(format!("shard-{i}"))).collect();
    expect(
        &pmu50(&[
            "merge",
            "--out",
            s(&parent),
            s(&below[0]),
            s(&below[1]),
            s(&below[2]),
        ]),
        0,
        &["30 seeds, 30 pass"],
    );
    assert_eq!(read(below[1].join("results.jsonl")), kept);
    let all = t.join("all");
    expect(
        &pmu50(&["merge", "--out", s(&all), s(&s0), s(&s1), s(&s2)]),
        0,
        &["30 seeds, 30 pass"],
    );
    expect(
        &pmu50(&["merge", "--out", s(&all), s(&s0), s(&s1), s(&s2)]),
        2,
        &["--force"],
    );
    expect(
        &pmu50(&["merge", "--force", "--out", s(&all), s(&s0), s(&s1), s(&s2)]),
        0,
        &["30 seeds, 30 pass"],
    );
}

#[test]
fn special_files_in_a_folder_are_refused() {
    let t = tmp("special");
    let a = t.join("a");
    regress(&a, 1, 5);
    let outside = t.join("outside.jsonl");
    std::fs::write(&outside, "").unwrap();
    fn fifo(p: &Path) {
        let c = std::ffi::CString::new(p.to_str().unwrap()).unwrap();
        assert_eq!(unsafe { libc::mkfifo(c.as_ptr(), 0o600) }, 0);
    }
    type Make = Box<dyn Fn(&Path)>;
    let o2 = outside.clone();
    let cases: Vec<(&str, &str, Make, &str)> = vec![
        (
            "fifo",
            "results.jsonl",
            Box::new(fifo),
            "is a FIFO, not a regular file",
        ),
        (
            "fifo-spec",
            "regress.json",
            Box::new(fifo),
            "is a FIFO, not a regular file",
        ),
        (
            "link",
            "results.jsonl",
            Box::new(move |p| std::os::unix::fs::symlink(&o2, p).unwrap()),
            "is a symbolic link, not a regular file",
        ),
        (
            "device",
            "results.jsonl",
            Box::new(|p| std::os::unix::fs::symlink("/dev/zero", p).unwrap()),
            "is a symbolic link",
        ),
        (
            "folder",
            "results.jsonl",
            Box::new(|p| std::fs::create_dir(p).unwrap()),
            "is a folder, not a regular file",
        ),
    ];
    // A character device itself (as root, which may create one: /dev/zero's numbers).
    let mut cases = cases;
    if unsafe { libc::geteuid() } == 0 {
        let zero: Make = Box::new(|p| {
            let c = std::ffi::CString::new(p.to_str().unwrap()).unwrap();
            assert_eq!(
                unsafe { libc::mknod(c.as_ptr(), libc::S_IFCHR | 0o600, libc::makedev(1, 5)) },
                0
            );
        });
        cases.push((
            "chardev",
            "results.jsonl",
            zero,
            "is a character device, not a regular file",
        ));
    }
    for (tag, file, make, want) in cases {
        let d = t.join(tag);
        copy(&a, &d);
        std::fs::remove_file(d.join(file)).unwrap();
        make(&d.join(file));
        let want = format!("{}: {want}", d.join(file).display());
        expect(
            &pmu50_within(&["regress", "--resume", s(&d)], &[]),
            2,
            &[&want],
        );
        expect(
            &pmu50_within(
                &["merge", "--out", s(&t.join(format!("m-{tag}"))), s(&d)],
                &[],
            ),
            2,
            &[&want],
        );
    }
    assert_eq!(
        read(&outside),
        "",
        "nothing was appended outside the folder"
    );
}

/// A regression folder whose seed 3 failed with signature `sig`, and its repro folder.
fn with_failure(dir: &Path, sig: &str) {
    let lines: Vec<String> = read(dir.join("results.jsonl"))
        .lines()
        .map(|l| {
            let mut v: serde_json::Value = serde_json::from_str(l).unwrap();
            if v["seed"] == 3 {
                v["verdict"] = "fail".into();
                v["failure"] = serde_json::json!({"kind": "dut", "tick": 12, "signal": "pmu50.si", "expected": "0", "got": "1", "block": "b", "fig": "s1", "detail": "planted"});
            }
            v.to_string()
        })
        .collect();
    std::fs::write(dir.join("results.jsonl"), lines.join("\n") + "\n").unwrap();
    let f = dir.join("failures").join(sig);
    std::fs::create_dir_all(&f).unwrap();
    std::fs::write(f.join("repro.toml"), "duration = \"1 ms\"\n").unwrap();
    std::fs::write(f.join("repro.gtkw"), "[dumpfile] \"repro.vcd\"\n").unwrap();
    std::fs::write(
        f.join("failure.txt"),
        format!(
            "signature: {sig}\n\nreproduce:\n  pmu50 regress --repro {}\n",
            f.join("repro.toml").display()
        ),
    )
    .unwrap();
    std::fs::write(f.join("command.txt"), "old\n").unwrap();
}

#[test]
fn merge_carries_the_repro_folders_it_links_and_drops_stale_ones() {
    let t = tmp("repros");
    let sig = "dut-si-s1";
    let (a, b) = (t.join("a"), t.join("b"));
    for (i, d) in [&a, &b].into_iter().enumerate() {
        let o = pmu50(&[
            "regress",
            "--iterations",
            "10",
            "--shard",
            &format!("{i}/2"),
            "--no-triage",
            "--out",
            s(d),
        ]);
        expect(&o, 0, &[]);
    }
    with_failure(&a, sig);
    let m = t.join("m");
    expect(
        &pmu50(&["merge", "--out", s(&m), s(&a), s(&b)]),
        1,
        &[&format!("fail {sig}: 1 seed(s), smallest 3")],
    );
    let f = m.join("failures").join(sig);
    assert_eq!(
        read(f.join("repro.toml")),
        read(a.join("failures").join(sig).join("repro.toml"))
    );
    assert_eq!(read(f.join("repro.gtkw")), "[dumpfile] \"repro.vcd\"\n");
    let cmd = read(f.join("command.txt"));
    assert!(
        cmd.contains(&format!("--repro {}", f.join("repro.toml").display())),
        "{cmd}"
    );
    assert!(
        read(f.join("failure.txt")).ends_with(&format!("\nreproduce:\n  {cmd}")),
        "failure.txt names the merged repro"
    );
    let html = read(m.join("report.html"));
    assert!(
        html.contains(&format!("href=\"failures/{sig}/repro.toml\"")),
        "the report links the repro it carries"
    );
    // The same folder merged again from passing folders: no stale repro, no failure reported.
    let (c, d) = (t.join("c"), t.join("d"));
    for (i, dir) in [&c, &d].into_iter().enumerate() {
        let o = pmu50(&[
            "regress",
            "--iterations",
            "10",
            "--shard",
            &format!("{i}/2"),
            "--no-triage",
            "--out",
            s(dir),
        ]);
        expect(&o, 0, &[]);
    }
    expect(
        &pmu50(&["merge", "--force", "--out", s(&m), s(&c), s(&d)]),
        0,
        &["10 seeds, 10 pass"],
    );
    assert!(!f.exists(), "the stale repro folder is removed");
    assert!(read(m.join("report.html")).contains("No failure."));
    // A failure whose folder holds no repro is reported without a dead link.
    std::fs::remove_dir_all(a.join("failures")).unwrap();
    let n = t.join("n");
    expect(&pmu50(&["merge", "--out", s(&n), s(&a), s(&b)]), 1, &[]);
    let html = read(n.join("report.html"));
    assert!(
        !html.contains("href=\"failures/") && html.contains("no repro folder"),
        "no link to a folder that is not there"
    );
    // A regression rerun into a folder with a stale repro folder removes it.
    std::fs::create_dir_all(c.join("failures/invariant-old-sig")).unwrap();
    std::fs::write(c.join("failures/invariant-old-sig/repro.toml"), "").unwrap();
    regress(&c, 1, 3);
    assert!(!c.join("failures/invariant-old-sig").exists());
}

#[test]
fn coverage_files_that_cannot_be_a_sampler_s_are_refused() {
    let t = tmp("covfiles");
    let a = t.join("a");
    regress(&a, 1, 3);
    let mut v: serde_json::Value = serde_json::from_str(&read(a.join("coverage.json"))).unwrap();
    let k = v["bins"]
        .as_array()
        .unwrap()
        .iter()
        .position(|b| b.get("unreachable").is_some())
        .expect("an unreachable bin");
    let name = v["bins"][k]["name"].as_str().unwrap().to_string();
    v["runs"] = serde_json::json!([{"id": "bench/1", "verdict": "pass"}]);
    let mut u = v.clone();
    u["bins"][k]["hits"] = 777.into();
    let unreachable = common::write(&t, "unreachable.json", u.to_string());
    expect(
        &pmu50(&["merge", "--out", s(&t.join("m1")), s(&unreachable)]),
        2,
        &[
            &format!("bin \"{name}\" is declared unreachable"),
            "but has 777 hits",
        ],
    );
    let mut n = v.clone();
    n["runs"] = serde_json::json!([]);
    let no_runs = common::write(&t, "noruns.json", n.to_string());
    expect(
        &pmu50(&["merge", "--out", s(&t.join("m2")), s(&no_runs), s(&no_runs)]),
        2,
        &["hits counted in no run"],
    );
    // the same file twice is still refused by its run ids
    let one = common::write(&t, "one.json", v.to_string());
    expect(
        &pmu50(&["merge", "--out", s(&t.join("m3")), s(&one), s(&one)]),
        2,
        &["run \"bench/1\" is counted twice"],
    );
}

#[test]
fn adjacent_seed_ranges_merge_into_one_regression_over_their_union() {
    let t = tmp("union");
    let (a, b, whole) = (t.join("a"), t.join("b"), t.join("whole"));
    regress(&a, 1, 20);
    regress(&b, 21, 20);
    regress(&whole, 1, 40);
    let m = t.join("m");
    expect(
        &pmu50(&["merge", "--out", s(&m), s(&b), s(&a)]),
        0,
        &["40 seeds, 40 pass"],
    );
    // the same run, what made each folder aside (the merge's own provenance and command line,
    // and the digest of results.jsonl, whose lines carry where and how fast each seed ran)
    let run = |d: &Path| {
        let mut v: serde_json::Value = serde_json::from_str(&read(d.join("regress.json"))).unwrap();
        for k in ["provenance", "record", "digest"] {
            v.as_object_mut().unwrap().remove(k);
        }
        v["files"].as_object_mut().unwrap().remove("results.jsonl");
        v
    };
    assert_eq!(run(&m), run(&whole));
    assert_eq!(
        read(m.join("coverage.json")),
        read(whole.join("coverage.json"))
    );
    assert_eq!(verdicts(&m), verdicts(&whole));
    // The merged folder is one regression: it resumes and extends like one.
    expect(&pmu50(&["regress", "--resume", s(&m)]), 0, &["40 seeds"]);
    // Overlapping ranges, a gap, different options, directed ranges: refused, naming why.
    let (over, gap, spec, d1, d2) = (
        t.join("over"),
        t.join("gap"),
        t.join("spec"),
        t.join("d1"),
        t.join("d2"),
    );
    regress(&over, 15, 10);
    regress(&gap, 50, 5);
    expect(
        &pmu50(&["merge", "--out", s(&t.join("x1")), s(&a), s(&over)]),
        2,
        &["overlap in seeds 15..=20"],
    );
    expect(
        &pmu50(&["merge", "--out", s(&t.join("x2")), s(&a), s(&b), s(&gap)]),
        2,
        &[
            "seeds 41..=49 lie between",
            "--start-seed 41 --iterations 9",
        ],
    );
    let o = pmu50(&[
        "regress",
        "--start-seed",
        "41",
        "--iterations",
        "5",
        "--check-spec",
        "--no-triage",
        "--out",
        s(&spec),
    ]);
    expect(&o, 0, &[]);
    expect(
        &pmu50(&["merge", "--out", s(&t.join("x3")), s(&m), s(&spec)]),
        2,
        &["parts of different regressions (check_spec false against true)"],
    );
    for (d, start) in [(&d1, "1"), (&d2, "4")] {
        let o = pmu50(&[
            "regress",
            "--start-seed",
            start,
            "--iterations",
            "3",
            "--directed",
            "--no-triage",
            "--out",
            s(d),
        ]);
        expect(&o, 0, &[]);
    }
    expect(
        &pmu50(&["merge", "--out", s(&t.join("x4")), s(&d1), s(&d2)]),
        2,
        &["directed regressions of different seed ranges"],
    );
}

#[test]
fn scheduler_variables_and_resume_flags_are_checked() {
    let t = tmp("env");
    let out = t.join("o");
    let max = u64::MAX.to_string();
    let cases: [(&[(&str, &str)], &str); 3] = [
        (
            &[("SLURM_ARRAY_TASK_ID", "0"), ("SLURM_ARRAY_TASK_MAX", &max)],
            "SLURM_ARRAY_TASK_MAX=18446744073709551615 with SLURM_ARRAY_TASK_MIN=0: more than",
        ),
        (
            &[("SLURM_ARRAY_TASK_ID", ""), ("SLURM_ARRAY_TASK_COUNT", "4")],
            "SLURM_ARRAY_TASK_ID is set but empty",
        ),
        (
            &[("JOB_COMPLETION_INDEX", ""), ("JOB_COMPLETIONS", "4")],
            "JOB_COMPLETION_INDEX is set but empty",
        ),
    ];
    for (env, want) in cases {
        let o = pmu50_within(&["regress", "--iterations", "8", "--out", s(&out)], env);
        expect(&o, 2, &[want]);
        assert!(!out.exists(), "{env:?}: nothing ran");
    }
    let a = t.join("a");
    regress(&a, 1, 3);
    for flag in [
        ["--start-seed", "5"],
        ["--out", "elsewhere"],
        ["--dut", "icarus"],
    ] {
        let o = pmu50(&["regress", "--resume", s(&a), flag[0], flag[1]]);
        expect(&o, 2, &["cannot be used with", flag[0]]);
    }
}

#[test]
fn the_default_first_seed_is_the_same_for_regress_and_the_cluster_scripts() {
    let t = tmp("start");
    let d = t.join("d");
    expect(
        &pmu50(&[
            "regress",
            "--iterations",
            "2",
            "--no-triage",
            "--out",
            s(&d),
        ]),
        0,
        &[],
    );
    let spec: serde_json::Value = serde_json::from_str(&read(d.join("regress.json"))).unwrap();
    assert_eq!(spec["start_seed"], 1);
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let sbatch = read(root.join("cluster/slurm/pmu50_regress.sbatch"));
    assert!(
        sbatch.contains("--start-seed \"${PMU50_START_SEED:-1}\""),
        "the sbatch file starts at seed 1"
    );
    assert!(
        read(root.join("cluster/regress_slurm.sh")).contains(" start=1 "),
        "regress_slurm.sh starts at seed 1"
    );
    assert!(
        read(root.join("cluster/k8s/pmu50-regress-job.yaml"))
            .contains("- name: PMU50_START_SEED\n              value: \"1\""),
        "the Kubernetes Job starts at seed 1"
    );
}

#[test]
fn a_merge_of_more_shard_folders_than_open_files_allows() {
    // 100 shards of one seed each, made from a one-process run, merged with at most 80 open
    // files: the merge keeps a bounded number of results files open.
    let t = tmp("manyshards");
    let one = t.join("one");
    regress(&one, 1, 100);
    let lines: Vec<String> = read(one.join("results.jsonl"))
        .lines()
        .map(String::from)
        .collect();
    let mut dirs = Vec::new();
    for (i, line) in lines.iter().enumerate() {
        let d = t.join(format!("shard-{i:03}"));
        std::fs::create_dir(&d).unwrap();
        std::fs::copy(one.join("regress.json"), d.join("regress.json")).unwrap();
        edit_spec(&d, "shard", serde_json::json!({"index": i, "count": 100}));
        std::fs::write(d.join("results.jsonl"), format!("{line}\n")).unwrap();
        dirs.push(d);
    }
    let merged = t.join("merged");
    let args: Vec<String> = dirs.iter().map(|d| format!("'{}'", d.display())).collect();
    let o = Command::new("sh")
        .arg("-c")
        .arg(format!(
            "ulimit -n 80 && exec '{}' merge --out '{}' {}",
            common::BIN,
            merged.display(),
            args.join(" ")
        ))
        .output()
        .unwrap();
    expect(
        &o,
        0,
        &["merged 100 regression folder(s)", "100 seeds, 100 pass"],
    );
    assert_eq!(
        read(merged.join("coverage.json")),
        read(one.join("coverage.json"))
    );
    assert_eq!(verdicts(&merged), verdicts(&one));
}
