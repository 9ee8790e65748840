//! `pmu50 regress --dut verilator --code-coverage`: the RTL's line and toggle coverage written
//! to `code/` (coverage.dat, lcov.info, summary.json, a section of report.html), the same bytes
//! from one run and from two shards merged and from an interrupted run resumed, waivers applied
//! and a bad waivers file refused naming its file, line and field, and the option refused for
//! the DUTs that cannot measure it. The RTL is a copy of the twin with other names inside under
//! a top without parameters (any RTL with the contract ports; one build for every seed). Needs
//! verilator (`make deps`).

use crate::common;
use common::*;
use std::path::{Path, PathBuf};
use std::process::Output;

fn hdl() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("hdl")
}

/// The twin in `dir` with its internal names changed (modules and a register renamed) under a
/// top `pmu50` without parameters, which fixes every value: one Verilator build serves every
/// seed. Returns the file list.
fn other_rtl(dir: &Path) -> PathBuf {
    std::fs::create_dir_all(dir.join("rtl")).unwrap();
    let list = std::fs::read_to_string(hdl().join("pmu50.f")).unwrap();
    for f in list.lines().map(str::trim).filter(|l| !l.is_empty()) {
        let mut text = std::fs::read_to_string(hdl().join(f)).unwrap();
        if f == "pmu50.v" {
            text = text.replace("module pmu50 #(", "module pmu50_inner #(");
        }
        if f.ends_with("timing_generator_56.v") {
            text = text.replace("tmr", "timer_q");
        }
        std::fs::write(dir.join(f), text).unwrap();
    }
    let ports: Vec<&str> = ["clk", "rst_n"]
        .into_iter()
        .chain(pmu50_core::signals::INPUTS.iter().map(|s| s.name))
        .chain(pmu50_core::signals::OUTPUTS.iter().map(|s| s.name))
        .collect();
    let st = pmu50_core::pmu50::Structural {
        sync_depth: 2,
        cnt_width: 16,
    };
    let decl: Vec<String> = ports
        .iter()
        .map(|p| {
            let out = pmu50_core::signals::OUTPUTS.iter().find(|x| x.name == *p);
            let bits = out
                .map(|x| x.bits(&st))
                .or_else(|| {
                    pmu50_core::signals::INPUTS
                        .iter()
                        .find(|x| x.name == *p)
                        .map(|x| x.bits(&st))
                })
                .unwrap_or(1);
            format!(
                "{} wire {}{p}",
                if out.is_some() { "output" } else { "input" },
                if bits > 1 {
                    format!("[{}:0] ", bits - 1)
                } else {
                    String::new()
                }
            )
        })
        .collect();
    let conn: Vec<String> = ports.iter().map(|p| format!(".{p}({p})")).collect();
    std::fs::write(
        dir.join("top.v"),
        format!(
            "module pmu50 (\n  {}\n);\n  pmu50_inner u_core ({});\nendmodule\n",
            decl.join(",\n  "),
            conn.join(", ")
        ),
    )
    .unwrap();
    std::fs::write(dir.join("pmu50.f"), list + "top.v\n").unwrap();
    dir.join("pmu50.f")
}

/// `pmu50 regress ARGS --out OUT` with the builds in `cache`.
fn regress(args: &[&str], out: &Path, cache: &Path) -> Output {
    let mut a = vec!["regress", "--no-triage", "--out", s(out)];
    a.extend(args);
    std::process::Command::new(BIN)
        .args(&a)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .env("PMU50_CACHE_DIR", cache)
        .output()
        .unwrap()
}

fn read(p: &Path) -> String {
    std::fs::read_to_string(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

/// The waivers of the renamed twin in `rtl`: the timer's high bits, reviewed on its source as
/// it is (the checksum of the lines naming `timer_q`).
fn waivers(rtl: &Path) -> String {
    let src = read(&rtl.join("rtl/timing_generator_56.v"));
    let lines = pmu50_verif::waiver::lines_naming(&src, "timer_q");
    format!(
        r#"# the wrapper's register, renamed
[[waiver]]
file = "rtl/timing_generator_56.v"
signal = "timer_q[15:8]"
reason = "high bits of the timer: the seeds' intervals stay below 256 ticks"
kind = "LOW_RISK"
reviewer = "the test"
checksum = "{}"
"#,
        pmu50_verif::waiver::checksum(&src, &lines)
    )
}

#[test]
fn shards_merged_and_a_resumed_run_give_the_bytes_of_one_run() {
    let t = tmp("shards");
    let cache = t.join("cache");
    let list = other_rtl(&t.join("rtl"));
    let w = t.join("waivers.toml");
    std::fs::write(&w, waivers(&t.join("rtl"))).unwrap();
    let base = [
        "--dut",
        "verilator",
        "--code-coverage",
        "--rtl",
        s(&list),
        "--waivers",
        s(&w),
        "--iterations",
        "4",
        "--jobs",
        "2",
    ];
    let whole = t.join("whole");
    let o = regress(&base, &whole, &cache);
    let out = expect(&o, 0, &["4 seeds, 4 pass", "code coverage: line "]);
    assert!(
        out.contains("waived rtl/timing_generator_56.v signal timer_q[15:8]: 8 point(s)"),
        "the waiver and what it excluded are printed: {out}"
    );
    let code = whole.join("code");
    let dat = read(&code.join("coverage.dat"));
    // line, branch and toggle points, their files relative to the file list's folder
    for want in [
        "\u{1}f\u{2}rtl/timing_generator_56.v\u{1}",
        "\u{1}page\u{2}v_line\u{1}",
        "\u{1}page\u{2}v_branch\u{1}",
        "\u{1}page\u{2}v_toggle\u{1}",
    ] {
        assert!(dat.contains(want), "coverage.dat has {want:?}");
    }
    // a point is its source construct: no module copy, no instance
    assert!(!dat.contains("\u{1}h\u{2}") && !dat.contains("v_line/"));
    let sum: serde_json::Value = serde_json::from_str(&read(&code.join("summary.json"))).unwrap();
    assert_eq!(sum["format"], "pmu50-code-coverage-1");
    assert_eq!(sum["seeds"], 4);
    assert!(sum["line"]["hit"].as_u64().unwrap() > 0);
    assert!(sum["line"]["total"].as_u64().unwrap() >= sum["line"]["hit"].as_u64().unwrap());
    assert_eq!(sum["toggle"]["waived"], 8, "the waiver excludes 8 bits");
    assert_eq!(sum["waivers"][0]["points"], 8);
    // a waived bit the seeds toggled all the same is reported (the reason does not hold)
    let covered = sum["waivers"][0]["covered"].as_u64().unwrap();
    assert!(covered <= 8);
    if covered > 0 {
        assert!(
            out.contains("covered all the same (check the reason)"),
            "{out}"
        );
    }
    // the Markdown table: a row per file and the totals of summary.json
    let md = read(&code.join("summary.md"));
    let all = format!(
        "| **all** | **{}/{} (",
        sum["line"]["hit"], sum["line"]["total"]
    );
    assert!(
        md.contains(&all),
        "summary.md's totals are summary.json's: {md}"
    );
    assert!(md.contains("| rtl/timing_generator_56.v | "), "{md}");
    let timer_waived = "| 8 |";
    assert!(
        md.lines()
            .any(|l| l.starts_with("| rtl/timing_generator_56.v") && l.contains(timer_waived)),
        "the waived bits are on their file's row: {md}"
    );
    let lcov = read(&code.join("lcov.info"));
    assert!(lcov.contains("SF:rtl/timing_generator_56.v\n") && lcov.contains("end_of_record"));
    let report = read(&whole.join("report.html"));
    assert!(report.contains("Code coverage of the RTL"));
    assert!(
        report.contains("high bits of the timer"),
        "the report gives the waiver's reason"
    );
    assert!(!report.contains("<script"), "no script in the report");

    // two shards merged
    let mut shard0 = base.to_vec();
    shard0.extend(["--shard", "0/2"]);
    let mut shard1 = base.to_vec();
    shard1.extend(["--shard", "1/2"]);
    expect(&regress(&shard0, &t.join("s0"), &cache), 0, &["2 seeds"]);
    expect(&regress(&shard1, &t.join("s1"), &cache), 0, &["2 seeds"]);
    let merged = t.join("merged");
    let o = pmu50(&[
        "merge",
        "--out",
        s(&merged),
        s(&t.join("s0")),
        s(&t.join("s1")),
    ]);
    expect(&o, 0, &["code coverage: line "]);
    for f in [
        "coverage.dat",
        "lcov.info",
        "summary.json",
        "summary.md",
        "waivers.toml",
    ] {
        assert_eq!(
            read(&merged.join("code").join(f)),
            read(&code.join(f)),
            "code/{f} of the merged shards is that of the one run"
        );
    }

    // an interrupted run whose last batch was torn: the part was written, the results were
    // cut; --resume cuts them and runs them again, and ends with the one run's bytes
    let torn = t.join("torn");
    let o = regress(&base, &torn, &cache);
    expect(&o, 0, &["4 seeds"]);
    let results = read(&torn.join("results.jsonl"));
    let first: String = results.lines().take(2).map(|l| format!("{l}\n")).collect();
    std::fs::write(torn.join("results.jsonl"), first).unwrap();
    let o = std::process::Command::new(BIN)
        .args(["regress", "--resume", s(&torn)])
        .env("PMU50_CACHE_DIR", &cache)
        .output()
        .unwrap();
    expect(&o, 0, &["4 seeds, 4 pass"]);
    for f in ["coverage.dat", "lcov.info", "summary.json", "summary.md"] {
        assert_eq!(
            read(&torn.join("code").join(f)),
            read(&code.join(f)),
            "code/{f} of the resumed run is that of the one run"
        );
    }
}

#[test]
fn a_bad_waivers_file_is_refused_with_its_file_line_and_field() {
    let t = tmp("badwaivers");
    let list = other_rtl(&t.join("rtl"));
    let cases = [
        (
            "[[waiver]]\nfile = \"rtl/timing_generator_56.v\"\nline = 9999\nreason = \"a reason long enough\"\n",
            ":3: field `line`: line 9999 is past the end of",
        ),
        (
            "[[waiver]]\nfile = \"nowhere.v\"\nline = 3\nreason = \"a reason long enough\"\n",
            ":2: field `file`: `nowhere.v` is none of the RTL's files",
        ),
        (
            "[[waiver]]\nfile = \"rtl/timing_generator_56.v\"\nsignal = \"no_such_signal\"\nreason = \"a reason long enough\"\n",
            ":3: field `signal`: `no_such_signal` does not appear in",
        ),
        (
            "\n[[waiver]]\nfile = \"rtl/timing_generator_56.v\"\nline = 3\n",
            ":2: field `reason`: missing",
        ),
        (
            "[[waiver]]\nfile = \"rtl/timing_generator_56.v\"\nline = 3\nreason = \"a reason long enough\"\nterm = \"* => 0\"\n",
            ":5: field `term`: a pattern of expression terms goes with `expr`",
        ),
        (
            "[[waiver]]\nfile = \"rtl/timing_generator_56.v\"\nline = 3\nreason = \"a reason long enough\"\nholds = \" \"\n",
            ":5: field `holds`: empty",
        ),
        (
            "[[waiver]]\nfile = \"rtl/timing_generator_56.v\"\nline = 3\nreason = \"a reason long enough\"\nreviewer = \"me\"\n",
            ":1: field `kind`: missing: the kind of waiver, one of UNR, NON_RTL, UNSUPPORTED, EXTERNAL, LOW_RISK",
        ),
        (
            "[[waiver]]\nfile = \"rtl/timing_generator_56.v\"\nline = 3\nreason = \"a reason long enough\"\nkind = \"unr\"\nreviewer = \"me\"\n",
            ":5: field `kind`: `unr` is not a kind of waiver",
        ),
        (
            "[[waiver]]\nfile = \"rtl/timing_generator_56.v\"\nline = 3\nreason = \"a reason long enough\"\nkind = \"UNR\"\n",
            ":1: field `reviewer`: missing",
        ),
    ];
    for (i, (text, want)) in cases.iter().enumerate() {
        let w = t.join(format!("bad{i}.toml"));
        std::fs::write(&w, text).unwrap();
        let o = pmu50(&[
            "regress",
            "--dut",
            "verilator",
            "--code-coverage",
            "--rtl",
            s(&list),
            "--waivers",
            s(&w),
            "--iterations",
            "1",
            "--out",
            s(&t.join("o")),
        ]);
        let out = expect(&o, 2, &[want]);
        assert!(
            out.contains(&format!("bad{i}.toml:")),
            "names the file: {out}"
        );
        assert!(!t.join("o").exists(), "nothing is run: {out}");
    }
}

#[test]
fn code_coverage_is_refused_for_a_dut_that_cannot_measure_it() {
    let t = tmp("refused");
    for dut in ["model", "icarus"] {
        let o = pmu50(&[
            "regress",
            "--dut",
            dut,
            "--code-coverage",
            "--iterations",
            "1",
            "--out",
            s(&t.join(dut)),
        ]);
        expect(&o, 2, &["--code-coverage", "use --dut verilator"]);
        assert!(!t.join(dut).exists());
    }
    // the model is the default DUT
    let o = pmu50(&[
        "regress",
        "--code-coverage",
        "--iterations",
        "1",
        "--out",
        s(&t.join("d")),
    ]);
    expect(&o, 2, &["use --dut verilator (not model)"]);
    // waivers need code coverage
    let o = pmu50(&["regress", "--waivers", "x.toml", "--iterations", "1"]);
    expect(&o, 2, &["--code-coverage"]);
}

#[test]
fn the_twins_waivers_are_valid_and_give_each_its_reason() {
    let list = pmu50_verif::rtl::FileList::read(&hdl().join("pmu50.f")).unwrap();
    let w = pmu50_verif::code_cov::Waivers::read(
        &hdl().join("coverage-waivers.toml"),
        Some(&list.files),
    )
    .unwrap();
    for x in &w.list {
        assert!(x.reason.len() >= 10, "waiver at line {} says why", x.at);
        // and states the claim behind it, which make coverage-proofs proves
        assert!(
            x.holds.as_deref().is_some_and(|h| !h.is_empty()),
            "waiver at line {} states its claim (holds)",
            x.at
        );
    }
}

#[test]
fn editing_a_waived_line_makes_its_waiver_stale_in_the_next_signoff() {
    let t = tmp("stale");
    let cache = t.join("cache");
    let list = other_rtl(&t.join("rtl"));
    let w = t.join("waivers.toml");
    std::fs::write(&w, waivers(&t.join("rtl"))).unwrap();
    let args = |out: &Path| {
        let o = regress(
            &[
                "--dut",
                "verilator",
                "--code-coverage",
                "--rtl",
                s(&list),
                "--waivers",
                s(&w),
                "--iterations",
                "1",
            ],
            out,
            &cache,
        );
        expect(&o, 0, &["1 seeds, 1 pass"])
    };
    let before = t.join("before");
    let said = args(&before);
    assert!(
        said.contains("waived rtl/timing_generator_56.v signal timer_q[15:8]: 8 point(s)"),
        "{said}"
    );
    let so = expect(
        &pmu50(&["signoff", s(&before)]),
        1,
        &["code toggle coverage"],
    );
    let row = so
        .lines()
        .find(|l| l.starts_with("code toggle coverage"))
        .unwrap();
    assert!(!row.contains("stale"), "{row}");
    // its claim is not proven (no coverage proofs), and the row says so, naming the waiver
    assert!(
        so.contains("waivers.toml:2 (rtl/timing_generator_56.v signal timer_q[15:8], LOW_RISK)"),
        "{so}"
    );
    // an edit of a line naming the waived signal: the waiver no longer applies
    let f = t.join("rtl/rtl/timing_generator_56.v");
    let src = read(&f);
    let at = src.find("timer_q <= 16'd0;").expect("the timer's reset");
    std::fs::write(
        &f,
        format!(
            "{}timer_q <= 16'h0000;{}",
            &src[..at],
            &src[at + "timer_q <= 16'd0;".len()..]
        ),
    )
    .unwrap();
    let after = t.join("after");
    let said = args(&after);
    assert!(
        said.contains("does not apply, stale: its lines changed since its review"),
        "{said}"
    );
    let so = expect(
        &pmu50(&["signoff", s(&after)]),
        1,
        &["code toggle coverage"],
    );
    let row = so
        .lines()
        .find(|l| l.starts_with("code toggle coverage"))
        .unwrap();
    assert!(
        row.contains("MISSED") && row.contains("stale") && row.contains("timing_generator_56.v"),
        "{row}"
    );
    let sum: serde_json::Value =
        serde_json::from_str(&read(&after.join("code/summary.json"))).unwrap();
    assert_eq!(sum["toggle"]["waived"], 0, "a stale waiver waives nothing");
}
