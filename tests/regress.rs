//! `pmu50 regress` and `pmu50 merge` as a user runs them (the model as DUT): results that do
//! not depend on --jobs, shards that merge into exactly the one-process run, an interrupted
//! run resumed, a run killed by SIGTERM keeping its finished seeds, and bad input refused with
//! exit 2 and the reason. (An RTL DUT with a planted bug, its triage and the report in a browser:
//! hdl/regress_smoke.sh, run by `make test`.)

use std::path::{Path, PathBuf};
use std::process::Command;

use crate::common;
use common::{expect_code, pmu50, s, text};

fn tmp() -> tempfile::TempDir {
    tempfile::tempdir().expect("temp dir")
}

/// Each result line without what depends on where and how fast it ran.
fn verdicts(dir: &Path) -> Vec<String> {
    std::fs::read_to_string(dir.join("results.jsonl"))
        .expect("results.jsonl")
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

/// The regression folders `a` and `b` hold the same coverage and the same verdicts.
fn assert_same_results(a: &Path, b: &Path) {
    assert_eq!(read(a.join("coverage.json")), read(b.join("coverage.json")));
    assert_eq!(verdicts(a), verdicts(b));
}

/// `pmu50 regress --resume dir` passes and leaves what the uninterrupted run `whole` left.
fn resume_to(dir: &Path, whole: &Path) {
    expect_code(&pmu50(&["regress", "--resume", s(dir)]), 0);
    assert_same_results(dir, whole);
}

fn read(p: PathBuf) -> String {
    std::fs::read_to_string(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

#[test]
fn results_do_not_depend_on_jobs() {
    let t = tmp();
    let (a, b) = (t.path().join("a"), t.path().join("b"));
    let oa = pmu50(&[
        "regress",
        "--start-seed",
        "100",
        "--iterations",
        "40",
        "--jobs",
        "1",
        "--out",
        s(&a),
    ]);
    let ob = pmu50(&[
        "regress",
        "--start-seed",
        "100",
        "--iterations",
        "40",
        "--jobs",
        "3",
        "--out",
        s(&b),
    ]);
    expect_code(&oa, 0);
    expect_code(&ob, 0);
    assert_same_results(&a, &b);
    assert_eq!(verdicts(&a).len(), 40);
    // every seed ran its checks: the read-out invariant applied somewhere, coverage grew
    let checked: u64 = read(a.join("results.jsonl"))
        .lines()
        .map(|l| {
            serde_json::from_str::<serde_json::Value>(l).unwrap()["readouts_checked"]
                .as_u64()
                .unwrap()
        })
        .sum();
    assert!(checked > 10, "read-outs checked: {checked}");
    let out = String::from_utf8_lossy(&oa.stdout);
    assert!(out.contains("40 seeds, 40 pass, 0 fail, 0 error"), "{out}");
    let html = read(a.join("report.html"));
    assert!(
        html.contains("<svg") && html.contains("Never hit") && html.contains("cross.fig17_x_fig18"),
        "report"
    );
    assert!(
        !html.contains("http://")
            || html
                .matches("http://")
                .all(|_| html.contains("xmlns=\"http://www.w3.org/2000/svg\"")),
        "no external resource"
    );
}

#[test]
fn shards_merge_into_the_one_process_run_and_missing_seeds_resume() {
    let t = tmp();
    let one = t.path().join("one");
    let o = pmu50(&[
        "regress",
        "--start-seed",
        "7",
        "--iterations",
        "45",
        "--out",
        s(&one),
        "--no-triage",
    ]);
    expect_code(&o, 0);
    let shard = |i: usize| t.path().join(format!("shard{i}"));
    for i in 0..3 {
        let o = pmu50(&[
            "regress",
            "--start-seed",
            "7",
            "--iterations",
            "45",
            "--shard",
            &format!("{i}/3"),
            "--out",
            s(&shard(i)),
            "--no-triage",
        ]);
        expect_code(&o, 0);
        assert!(
            read(shard(i).join("results.jsonl")).contains(&format!("\"shard\":\"{i}/3\"")),
            "where it ran"
        );
    }
    // any order gives the one-process coverage and verdicts
    let merged = t.path().join("merged");
    let o = pmu50(&[
        "merge",
        "--out",
        s(&merged),
        s(&shard(2)),
        s(&shard(0)),
        s(&shard(1)),
    ]);
    expect_code(&o, 0);
    assert_same_results(&merged, &one);

    // a shard given twice is refused, and nothing is written
    let twice = t.path().join("twice");
    let o = pmu50(&[
        "merge",
        "--out",
        s(&twice),
        s(&shard(0)),
        s(&shard(1)),
        s(&shard(0)),
    ]);
    expect_code(&o, 2);
    assert!(
        text(&o).contains("shard 0/3 is given twice"),
        "{}",
        text(&o)
    );
    assert!(!twice.join("coverage.json").exists());

    // a missing shard: its seeds are named, and --resume runs only those
    let part = t.path().join("part");
    let o = pmu50(&["merge", "--out", s(&part), s(&shard(0)), s(&shard(2))]);
    expect_code(&o, 1);
    assert!(
        text(&o).contains("missing seeds: 15 (first 22)"),
        "{}",
        text(&o)
    );
    let missing: Vec<u64> = read(part.join("missing.txt"))
        .lines()
        .map(|l| l.parse().unwrap())
        .collect();
    assert_eq!(missing, (22..37).collect::<Vec<_>>());
    resume_to(&part, &one);
    assert!(!part.join("missing.txt").exists());
}

#[test]
fn an_interrupted_regression_resumes_to_the_same_files() {
    let t = tmp();
    let full = t.path().join("full");
    let o = pmu50(&[
        "regress",
        "--iterations",
        "40",
        "--directed",
        "--out",
        s(&full),
        "--no-triage",
    ]);
    expect_code(&o, 0);
    // the same run, cut after 13 seeds and half a line
    let cut = t.path().join("cut");
    std::fs::create_dir(&cut).unwrap();
    std::fs::copy(full.join("regress.json"), cut.join("regress.json")).unwrap();
    let all = read(full.join("results.jsonl"));
    let lines: Vec<&str> = all.lines().collect();
    let mut partial = lines[..13].join("\n");
    partial.push('\n');
    partial.push_str(&lines[13][..lines[13].len() / 2]);
    std::fs::write(cut.join("results.jsonl"), partial).unwrap();
    resume_to(&cut, &full);
}

#[test]
fn sigterm_keeps_the_finished_seeds() {
    let t = tmp();
    let dir = t.path().join("r");
    let mut child = Command::new(env!("CARGO_BIN_EXE_pmu50"))
        .args([
            "regress",
            "--iterations",
            "100000",
            "--jobs",
            "1",
            "--out",
            s(&dir),
        ])
        .spawn()
        .unwrap();
    let results = dir.join("results.jsonl");
    let start = std::time::Instant::now();
    while std::fs::read_to_string(&results)
        .map(|r| r.lines().count())
        .unwrap_or(0)
        < 64
    {
        assert!(start.elapsed().as_secs() < 120, "no batch finished");
        std::thread::sleep(std::time::Duration::from_millis(50));
    }
    unsafe { libc::kill(child.id() as i32, libc::SIGTERM) };
    let status = child.wait().unwrap();
    assert_eq!(status.code(), Some(143));
    let kept = read(results.clone());
    let seeds: Vec<u64> = kept
        .lines()
        .filter(|l| l.ends_with('}'))
        .map(|l| {
            serde_json::from_str::<serde_json::Value>(l).unwrap()["seed"]
                .as_u64()
                .unwrap()
        })
        .collect();
    assert!(
        seeds.len() >= 64 && seeds.iter().zip(1..).all(|(s, k)| *s == k),
        "the finished batches stay, in order"
    );
    assert!(
        std::fs::read_dir(&dir).unwrap().all(|e| !e
            .unwrap()
            .file_name()
            .to_string_lossy()
            .ends_with(".tmp")),
        "no temporary file left"
    );
}

#[test]
fn bad_input_is_refused_with_the_reason() {
    let t = tmp();
    let out = t.path().join("o");
    let list = t.path().join("rtl.f");
    std::fs::write(&list, "rtl/missing.v\n").unwrap();
    let junk = t.path().join("junk.json");
    std::fs::write(
        &junk,
        "{\"format\": \"pmu50-coverage\", \"version\": 1, \"model\": ",
    )
    .unwrap();
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (vec!["regress", "--iterations", "0"], "--iterations 0"),
        (vec!["regress"], "needs --iterations"),
        (
            vec!["regress", "--iterations", "5", "--shard", "3/3"],
            "0 <= I < N",
        ),
        (
            vec![
                "regress",
                "--iterations",
                "5",
                "--shard",
                "1/2",
                "--directed",
            ],
            "--directed steers",
        ),
        (
            vec!["regress", "--iterations", "5", "--rtl", "hdl/pmu50.f"],
            "--rtl needs an RTL simulator",
        ),
        (
            vec![
                "regress",
                "--iterations",
                "5",
                "--dut",
                "verilator",
                "--rtl",
                s(&list),
            ],
            "rtl.f:1: `rtl/missing.v` names",
        ),
        (
            vec!["regress", "--iterations", "5", "--timeout", "0"],
            "--timeout 0",
        ),
        (
            vec!["regress", "--iterations", "5", "--dut", "vcs"],
            "invalid value 'vcs'",
        ),
        (
            vec![
                "regress",
                "--start-seed",
                "18446744073709551615",
                "--iterations",
                "2",
            ],
            "passes 2^64",
        ),
        (vec!["regress", "--resume", s(t.path())], "no regress.json"),
        (
            vec!["merge", "--out", s(&out), s(&junk)],
            "junk.json: not a coverage file",
        ),
        (vec!["merge", "--out", s(&out)], "at least one input"),
    ];
    for (args, want) in cases {
        let mut a = args.clone();
        if a[0] == "regress" && !a.contains(&"--resume") {
            a.extend(["--out", s(&out)]);
        }
        let o = pmu50(&a);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", text(&o));
        assert!(
            text(&o).contains(want),
            "{args:?}: wanted `{want}` in: {}",
            text(&o)
        );
        assert!(!text(&o).contains("panicked"), "{args:?}");
    }
    // folders of different regressions do not merge
    let (a, b) = (t.path().join("a"), t.path().join("b"));
    assert_eq!(
        pmu50(&["regress", "--iterations", "3", "--out", s(&a)])
            .status
            .code(),
        Some(0)
    );
    assert_eq!(
        pmu50(&[
            "regress",
            "--iterations",
            "3",
            "--check-spec",
            "--out",
            s(&b)
        ])
        .status
        .code(),
        Some(0)
    );
    let o = pmu50(&["merge", "--out", s(&out), s(&a), s(&b)]);
    assert_eq!(o.status.code(), Some(2));
    assert!(text(&o).contains("different regressions"), "{}", text(&o));
}

#[test]
fn a_repro_runs_the_seed_checks_on_any_scenario() {
    let t = tmp();
    let sc = t.path().join("x.toml");
    std::fs::write(&sc, "duration = \"40 ms\"\n[expect]\ndiag = true\n").unwrap();
    let o = pmu50(&["regress", "--repro", s(&sc), "--check-spec"]);
    expect_code(&o, 1);
    assert!(
        text(&o).contains("FAIL") && text(&o).contains("diag"),
        "{}",
        text(&o)
    );
    let o = pmu50(&[
        "regress",
        "--repro",
        "scenarios/fig15a.toml",
        "--check-spec",
    ]);
    expect_code(&o, 0);
    assert!(text(&o).starts_with("PASS"), "{}", text(&o));
}

/// The scenarios of seeds 1-12 (uniform) and 1-4 (biased towards long parking), each given to
/// `check` with its seed; returns the ticks the bench skipped over all of them (at the default
/// stepping, `check`'s first run).
fn skip_scenarios(mut check: impl FnMut(u64, &pmu50_testbench::scenario::Scenario) -> u64) -> u64 {
    use pmu50_verif::gen::{Bias, Stimulus};
    let parked = Bias::from_missing(["cnt_r.value.saturated"]);
    let mut skipped = 0;
    for (seed, bias) in (1..=12)
        .map(|s| (s, Bias::uniform()))
        .chain((1..=4).map(|s| (s, parked.clone())))
    {
        let text = Stimulus::generate(seed, &bias).to_toml("t");
        let sc = pmu50_testbench::scenario::Scenario::parse(&text, "t", "t", Path::new("t.toml"))
            .unwrap();
        skipped += check(seed, &sc);
    }
    skipped
}

/// A seed's coverage with repeated key-off periods skipped and replayed (what `regress` runs)
/// equals the coverage of stepping every tick, bin by bin; the skip is taken.
#[test]
fn coverage_of_skipped_periods_equals_every_tick() {
    use pmu50_testbench::sim::{self, Stepping};
    use pmu50_verif::check::SeedChecks;
    let skipped = skip_scenarios(|seed, sc| {
        let mut fast = SeedChecks::new(&sc.params, sc.clock_ns(), false);
        let mut slow = SeedChecks::new(&sc.params, sc.clock_ns(), false);
        let rf = sim::run_with(sc, Stepping::Periods, &mut [&mut fast]).unwrap();
        let rs = sim::run_with(sc, Stepping::EveryTick, &mut [&mut slow]).unwrap();
        assert_eq!(rs.skipped_ticks, 0);
        assert_eq!(fast.coverage.hits(), slow.coverage.hits(), "seed {seed}");
        rf.skipped_ticks
    });
    assert!(skipped > 50_000, "periods were skipped ({skipped} ticks)");
}

/// The stimulus `--dut verilator` sends to the RTL, recorded with repeated periods skipped and
/// filled in from the last period (what `regress` runs), equals the inputs of stepping every
/// tick, tick by tick; the skip is taken.
#[test]
fn the_lockstep_stimulus_of_skipped_periods_equals_every_tick() {
    use pmu50_testbench::sim::{self, Stepping};
    use pmu50_verif::lockstep::InputRecorder;
    let skipped = skip_scenarios(|seed, sc| {
        let (mut fast, mut slow) = (InputRecorder::default(), InputRecorder::default());
        let rf = sim::run_with(sc, Stepping::Periods, &mut [&mut fast]).unwrap();
        sim::run_with(sc, Stepping::EveryTick, &mut [&mut slow]).unwrap();
        assert_eq!(slow.inputs.len() as u64, sc.ticks, "seed {seed}");
        assert!(
            fast.inputs == slow.inputs,
            "seed {seed}: the recorded stimulus differs"
        );
        rf.skipped_ticks
    });
    assert!(skipped > 50_000, "periods were skipped ({skipped} ticks)");
}

/// Build modes: a regression that draws its parameters from a pool of sets (`--param-sets`)
/// gives the one-process results through shards and a merge, an interrupted directed run
/// resumes to the same files, and every shard records the one pool of the seed range.
#[test]
fn a_pooled_regression_merges_and_resumes_to_the_one_process_run() {
    let t = tmp();
    let run = |out: &Path, extra: &[&str]| {
        let mut args = vec![
            "regress",
            "--start-seed",
            "3",
            "--iterations",
            "30",
            "--param-sets",
            "8",
            "--no-triage",
            "--out",
            s(out),
        ];
        args.extend_from_slice(extra);
        expect_code(&pmu50(&args), 0);
    };
    let pool = |dir: &Path| -> serde_json::Value {
        let v: serde_json::Value = serde_json::from_str(&read(dir.join("regress.json"))).unwrap();
        v["pool"].clone()
    };
    let one = t.path().join("one");
    run(&one, &[]);
    assert!(
        pool(&one)
            .as_array()
            .is_some_and(|p| !p.is_empty() && p.len() <= 8),
        "{}",
        pool(&one)
    );
    let shard = |i: usize| t.path().join(format!("shard{i}"));
    for i in 0..2 {
        run(&shard(i), &["--shard", &format!("{i}/2")]);
        assert_eq!(pool(&shard(i)), pool(&one), "shard {i} drew another pool");
    }
    let merged = t.path().join("merged");
    expect_code(
        &pmu50(&["merge", "--out", s(&merged), s(&shard(1)), s(&shard(0))]),
        0,
    );
    assert_same_results(&merged, &one);

    let full = t.path().join("full");
    run(&full, &["--directed"]);
    let cut = t.path().join("cut");
    std::fs::create_dir(&cut).unwrap();
    std::fs::copy(full.join("regress.json"), cut.join("regress.json")).unwrap();
    let all = read(full.join("results.jsonl"));
    let lines: Vec<&str> = all.lines().collect();
    std::fs::write(cut.join("results.jsonl"), lines[..11].join("\n") + "\n").unwrap();
    resume_to(&cut, &full);
}
