//! `pmu50 signoff DIR`: the sign-off table of a regression folder, each figure against its
//! threshold, every input sealed with its provenance. An honest folder with every figure at its
//! threshold exits 0; one figure short, an input missing or without provenance, or nothing to
//! count exits 1 naming the row; an edited input, inputs of another RTL, model or seed range, a
//! regression that ran no RTL, and a bin or property listed twice exit 2 naming the file and
//! both values. Each trick below once gave "every threshold met".

use std::path::{Path, PathBuf};

use crate::common;
use common::{expect, pmu50, s, tmp};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The twin's file list (its content hash is the one a regression of the twin records).
fn twin() -> String {
    root().join("hdl/pmu50.f").display().to_string()
}

fn write(p: &Path, text: &str) {
    std::fs::create_dir_all(p.parent().unwrap()).unwrap();
    std::fs::write(p, text).unwrap();
}

/// `text` written to `p` and sealed by `pmu50 seal`, as the tool `made_by` writes it.
fn sealed(p: &Path, text: &str, made_by: &str, rtl: &str, seeds: Option<&str>) {
    write(p, text);
    let mut args = vec!["seal", s(p), "--made-by", made_by, "--rtl", rtl];
    if let Some(x) = seeds {
        args.extend(["--seeds", x]);
    }
    expect(&pmu50(&args), 0, &[]);
}

/// A `code/summary.json` with these figures.
fn code_summary(line: (u64, u64), toggle: (u64, u64)) -> String {
    let count = |(hit, total): (u64, u64)| {
        format!(r#"{{"hit": {hit}, "total": {total}, "waived": 0, "pct": 100.0}}"#)
    };
    format!(
        r#"{{"format": "pmu50-code-coverage-1", "seeds": 3, "seeds_unaccounted": 0, "line": {}, "toggle": {}, "expr": {}, "expr_measured": true, "files": [], "waivers": [], "waivers_file": ""}}"#,
        count(line),
        count(toggle),
        count((40, 40))
    )
}

/// Proofs: every bin the model declares unreachable proven, every other bin witnessed.
fn proofs_text() -> String {
    let mut bins = Vec::new();
    for b in &pmu50_coverage::layout().bins {
        bins.push(match b.unreachable {
            Some(why) => serde_json::json!({"name": b.name, "status": "proven_unreachable",
                "declared_unreachable": why, "property": "assert (!hit_y)"}),
            None => serde_json::json!({"name": b.name, "status": "witnessed", "property": "cover (hit_x)"}),
        });
    }
    serde_json::json!({ "bins": bins }).to_string()
}

const FORMAL: &str = r#"{"format": "pmu50-formal", "version": 1, "properties": [
  {"name": "prop_a", "set": "small", "verdict": "proven", "how": "scorr"}]}"#;

/// The inputs beside a regression of the twin, sealed as their tools seal them, all met.
fn complete(dir: &Path) {
    sealed(
        &dir.join("coverage-proofs.json"),
        &proofs_text(),
        "hdl/formal/coverage.py",
        &twin(),
        None,
    );
    sealed(
        &dir.join("code/summary.json"),
        &code_summary((84, 84), (10, 10)),
        "pmu50 regress --code-coverage",
        &twin(),
        Some("1:3"),
    );
    sealed(
        &dir.join("formal.json"),
        FORMAL,
        "hdl/formal/run.py",
        &twin(),
        None,
    );
    // lint and X: clean reports of the twin, as `pmu50 lint` and `pmu50 xprop` write them
    // (tests/xprop_lint.rs runs the commands themselves)
    let clean =
        |tool: &str| format!(r#"{{"tool": "{tool}", "ran": true, "reason": "", "findings": []}}"#);
    sealed(
        &dir.join("lint.json"),
        &format!(
            r#"{{"format": "pmu50-lint-1", "files": 9, "checks": [{}, {}], "unwaived": [], "waivers": [], "waivers_file": ""}}"#,
            clean("verilator -Wall --lint-only"),
            clean("yosys check")
        ),
        "pmu50 lint",
        &twin(),
        None,
    );
    sealed(
        &dir.join("xprop.json"),
        &format!(
            r#"{{"format": "pmu50-xprop-1", "seeds": 1, "files": 9, "checks": [{}, {}], "unwaived": [], "waivers": [], "waivers_file": ""}}"#,
            clean("icarus 4-state"),
            clean("yosys flip-flop reset")
        ),
        "pmu50 xprop",
        &twin(),
        None,
    );
}

/// The sign-off fuzz target's seeds (fuzz/seeds/signoff_folder/): this honest folder, whole, with
/// its lint report absent, and with a formal verdict edited after sealing; each replayed through
/// the target's body. `PMU50_UPDATE_SEEDS=1` rewrites them.
fn fuzz_seeds(dir: &Path) {
    use pmu50_verif::fuzzing::{signoff_folder, SIGNOFF_FILES};
    let parts: Vec<Vec<u8>> = SIGNOFF_FILES
        .iter()
        .map(|f| std::fs::read(dir.join(f)).unwrap())
        .collect();
    let join = |parts: &[Vec<u8>]| parts.join(&0u8);
    let mut no_lint = parts.clone();
    no_lint[6].clear();
    let mut edited = parts.clone();
    edited[5] = String::from_utf8(edited[5].clone())
        .unwrap()
        .replacen("proven", "refuted", 1)
        .into_bytes();
    let seeds = [
        ("honest", join(&parts)),
        ("no-lint", join(&no_lint)),
        ("formal-edited", join(&edited)),
    ];
    let out = Path::new(env!("CARGO_MANIFEST_DIR")).join("fuzz/seeds/signoff_folder");
    for (name, data) in &seeds {
        signoff_folder(data);
        if std::env::var_os("PMU50_UPDATE_SEEDS").is_some() {
            std::fs::create_dir_all(&out).unwrap();
            std::fs::write(out.join(name), data).unwrap();
        }
    }
}

/// A regression of the twin on Verilator, three directed seeds, ports only.
fn regress_twin(dir: &Path) {
    let o = pmu50(&[
        "regress",
        "--directed",
        "--iterations",
        "3",
        "--dut",
        "verilator",
        "--no-triage",
        "--jobs",
        "2",
        "--history",
        "off",
        "--out",
        s(dir),
    ]);
    expect(&o, 0, &["3 pass"]);
}

/// `pmu50 signoff DIR --thresholds TH` with a history beside DIR (no regression in it: with
/// `soak_days = 0` the soak row is met).
fn signoff(dir: &Path, th: &Path) -> std::process::Output {
    let h = dir.parent().unwrap().join("h.sqlite");
    pmu50(&["signoff", s(dir), "--thresholds", s(th), "--history", s(&h)])
}

fn row<'a>(out: &'a str, name: &str) -> &'a str {
    out.lines()
        .find(|l| l.starts_with(name))
        .unwrap_or_else(|| panic!("no row {name}: {out}"))
}

#[test]
fn an_honest_folder_signs_off_and_every_trick_is_refused_or_missing() {
    let t = tmp("signoff");
    let dir = t.join("r");
    regress_twin(&dir);
    // the regression's record: provenance, command line, every RTL file's digest
    let spec: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("regress.json")).unwrap()).unwrap();
    assert_eq!(spec["provenance"]["dut"], "verilator");
    assert!(spec["provenance"]["rtl"]["hash"]
        .as_str()
        .unwrap()
        .starts_with("sha256:"));
    assert!(spec["provenance"]["tools"]["verilator"]
        .as_str()
        .unwrap()
        .contains("Verilator"));
    assert!(spec["provenance"]["tool"]
        .as_str()
        .unwrap()
        .contains("git "));
    assert_eq!(spec["record"]["command"][1], "regress");
    assert!(spec["record"]["rtl_files"]
        .as_array()
        .unwrap()
        .iter()
        .any(|f| f["file"] == "rtl/register_file.v"));
    assert!(spec["files"]["results.jsonl"]
        .as_str()
        .unwrap()
        .starts_with("sha256:"));

    // nothing but the regression: the missing inputs are missed rows that say what writes them
    let o = pmu50(&["signoff", s(&dir), "--history", "off"]);
    let text = expect(
        &o,
        1,
        &["coverage-proofs.json missing", "code/summary.json missing"],
    );
    assert!(text.contains("formal.json missing"), "{text}");
    assert!(
        text.contains("every row computed on the RTL") && text.contains("sha256:"),
        "{text}"
    );
    complete(&dir);
    let th = t.join("t.toml");
    write(&th, "[thresholds]\nfunctional = 10\nsoak_days = 0\n");
    let o = pmu50(&[
        "signoff",
        s(&dir),
        "--thresholds",
        s(&th),
        "--history",
        "off",
    ]);
    let out = expect(&o, 1, &["soak"]);
    // no history: the soak row is missing, whatever its threshold
    assert!(row(&out, "soak").contains("MISSED"), "{out}");
    let hist = t.join("h.sqlite");
    let ok = || {
        pmu50(&[
            "signoff",
            s(&dir),
            "--thresholds",
            s(&th),
            "--history",
            s(&hist),
        ])
    };
    let o = ok();
    expect(&o, 0, &["signoff: every threshold met"]);
    fuzz_seeds(&dir);
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("signoff.json")).unwrap()).unwrap();
    assert_eq!(json["met"], true);
    assert!(json["rtl"]["hash"].as_str().unwrap().starts_with("sha256:"));
    // every bin's decision written into coverage.json, whose new digest regress.json holds
    let cov = std::fs::read_to_string(dir.join("coverage.json")).unwrap();
    assert!(
        cov.contains(r#""proof":"witnessed: cover (hit_x)"}"#),
        "{cov}"
    );
    expect(&ok(), 0, &["signoff: every threshold met"]);

    let saved: Vec<(PathBuf, Vec<u8>)> = [
        "regress.json",
        "results.jsonl",
        "coverage.json",
        "coverage-proofs.json",
        "code/summary.json",
        "formal.json",
    ]
    .iter()
    .map(|f| (dir.join(f), std::fs::read(dir.join(f)).unwrap()))
    .collect();
    let restore = || {
        for (p, b) in &saved {
            std::fs::write(p, b).unwrap();
        }
    };

    // (1) hand-written inputs without provenance: missing, never met
    write(&dir.join("coverage-proofs.json"), &proofs_text());
    write(&dir.join("formal.json"), FORMAL);
    let o = signoff(&dir, &th);
    let out = expect(&o, 1, &["has no provenance"]);
    for r in [
        "bins proven unreachable",
        "bins undecided",
        "properties proven",
    ] {
        assert!(row(&out, r).contains("missing"), "{r}: {out}");
    }
    restore();

    // (2) an input edited after it was written: exit 2, the file and both digests
    for (file, from, to) in [
        ("formal.json", "\"proven\"", "\"proven\" "),
        ("formal.json", "scorr", "pdr"),
        ("code/summary.json", "\"hit\": 84", "\"hit\": 85"),
        ("coverage-proofs.json", "\"witnessed\"", "\"undecided\""),
    ] {
        let p = dir.join(file);
        let text = std::fs::read_to_string(&p).unwrap();
        assert!(text.contains(from), "{file}: {from}");
        write(&p, &text.replacen(from, to, 1));
        let o = signoff(&dir, &th);
        if from.trim() == to.trim() {
            // white space is not content: the digest is over the canonical text
            expect(&o, 0, &["every threshold met"]);
        } else {
            expect(&o, 2, &[file, "edited"]);
        }
        restore();
    }
    // results.jsonl and coverage.json: a byte changed after the run
    for file in ["results.jsonl", "coverage.json"] {
        let p = dir.join(file);
        let mut b = std::fs::read(&p).unwrap();
        let k = b.iter().position(|c| c.is_ascii_digit()).unwrap();
        b[k] = if b[k] == b'9' { b'8' } else { b[k] + 1 };
        std::fs::write(&p, b).unwrap();
        expect(
            &signoff(&dir, &th),
            2,
            &[file, "edited after the run wrote it"],
        );
        restore();
    }

    // (3) inputs of another RTL or seed range: exit 2 naming both values
    let alt = root().join("hdl/alt_sv/pmu50_alt.f").display().to_string();
    sealed(
        &dir.join("formal.json"),
        FORMAL,
        "hdl/formal/run.py",
        &alt,
        None,
    );
    let out = expect(&signoff(&dir, &th), 2, &["formal.json", "another RTL"]);
    assert!(
        out.contains("pmu50_alt.f") && out.contains("pmu50.f"),
        "{out}"
    );
    restore();
    sealed(
        &dir.join("code/summary.json"),
        &code_summary((84, 84), (10, 10)),
        "pmu50 regress --code-coverage",
        &twin(),
        Some("1:2"),
    );
    expect(
        &signoff(&dir, &th),
        2,
        &["code/summary.json", "seeds 1:3 against 1:2"],
    );
    restore();

    // (4) nothing to count is missing: a formal kit that proved no property
    sealed(
        &dir.join("formal.json"),
        r#"{"properties": []}"#,
        "hdl/formal/run.py",
        &twin(),
        None,
    );
    let out = expect(&signoff(&dir, &th), 1, &["properties proven"]);
    assert!(
        row(&out, "properties proven").contains("0 of 0") && out.contains("hdl/formal/run.py"),
        "{out}"
    );
    restore();

    // (5) one bin listed many times counts once: bad input
    let mut v: serde_json::Value = serde_json::from_str(&proofs_text()).unwrap();
    let first = v["bins"][0].clone();
    v["bins"].as_array_mut().unwrap().push(first);
    sealed(
        &dir.join("coverage-proofs.json"),
        &v.to_string(),
        "hdl/formal/coverage.py",
        &twin(),
        None,
    );
    expect(&signoff(&dir, &th), 2, &["is listed twice"]);
    // (6) a bin absent from the proofs file is undecided, not decided
    let mut v: serde_json::Value = serde_json::from_str(&proofs_text()).unwrap();
    v["bins"]
        .as_array_mut()
        .unwrap()
        .retain(|b| b["name"] != "bus.write_reg.unmapped");
    sealed(
        &dir.join("coverage-proofs.json"),
        &v.to_string(),
        "hdl/formal/coverage.py",
        &twin(),
        None,
    );
    let out = expect(&signoff(&dir, &th), 1, &["bins undecided"]);
    assert!(
        row(&out, "bins undecided").contains("bus.write_reg.unmapped"),
        "{out}"
    );
    restore();

    // (7) a regress.json without its provenance: the rows that need it are missing
    let plain: serde_json::Value = serde_json::from_slice(&saved[0].1).unwrap();
    let mut m = plain.as_object().unwrap().clone();
    for k in ["provenance", "digest", "record", "files", "coverage_inputs"] {
        m.remove(k);
    }
    write(
        &dir.join("regress.json"),
        &serde_json::to_string_pretty(&m).unwrap(),
    );
    let out = expect(&signoff(&dir, &th), 1, &["has no provenance"]);
    assert!(row(&out, "seeds passing").contains("missing"), "{out}");
    restore();

    // (8) a regression of the model alone, with every other input in place: exit 2
    let model = t.join("model");
    let o = pmu50(&[
        "regress",
        "--iterations",
        "3",
        "--no-triage",
        "--history",
        "off",
        "--out",
        s(&model),
    ]);
    expect(&o, 0, &["pass"]);
    complete(&model);
    expect(&signoff(&model, &th), 2, &["ran no RTL (dut = model)"]);
}

#[test]
fn a_port_level_witness_replayed_through_the_rtl_closes_its_bin() {
    let t = tmp("witness");
    let w = root().join("rtl_model/coverage/tests/witness/bus.write_reg.unmapped.vec");
    let cov = t.join("w.json");
    let o = pmu50(&[
        "lockstep",
        s(&w),
        "--map",
        s(&root().join("hdl/pmu50.map.toml")),
        "--coverage",
        s(&cov),
    ]);
    expect(&o, 0, &["PASS", "run lockstep/bus.write_reg.unmapped"]);
    // sealed with the RTL it ran on
    expect(
        &pmu50(&["seal", "--check", s(&cov)]),
        0,
        &["pmu50 lockstep"],
    );
    let r = t.join("r");
    regress_twin(&r);
    let m = t.join("m");
    let o = pmu50(&["merge", "--history", "off", "--out", s(&m), s(&r), s(&cov)]);
    expect(
        &o,
        0,
        &["merged 1 regression folder(s) and 1 coverage file(s)"],
    );
    let c = std::fs::read_to_string(m.join("coverage.json")).unwrap();
    assert!(
        c.contains(r#""name":"bus.write_reg.unmapped","kind":"point","hits":1"#),
        "{c}"
    );
    // pmu50 signoff counts the merged coverage, run after run
    for _ in 0..2 {
        let o = pmu50(&["signoff", s(&m), "--history", "off"]);
        expect(&o, 1, &["(4 runs)"]);
    }
    // a coverage file without provenance, merged in: the functional row is missing
    let plain = t.join("plain.json");
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&cov).unwrap()).unwrap();
    let mut o = v.as_object().unwrap().clone();
    o.remove("provenance");
    o.remove("digest");
    write(&plain, &serde_json::to_string(&o).unwrap());
    let m2 = t.join("m2");
    let o = pmu50(&[
        "merge",
        "--history",
        "off",
        "--out",
        s(&m2),
        s(&r),
        s(&plain),
    ]);
    expect(&o, 0, &["merged"]);
    let o = pmu50(&["signoff", s(&m2), "--history", "off"]);
    let out = expect(&o, 1, &["which has no provenance"]);
    assert!(
        row(&out, "functional coverage").contains("missing"),
        "{out}"
    );
    // a witness of another RTL is refused by the merge, naming both
    let other = t.join("other.json");
    std::fs::copy(&cov, &other).unwrap();
    expect(
        &pmu50(&[
            "seal",
            s(&other),
            "--made-by",
            "pmu50 lockstep --coverage",
            "--dut",
            "verilator",
            "--rtl",
            s(&root().join("hdl/alt_sv/pmu50_alt.f")),
        ]),
        0,
        &[],
    );
    let o = pmu50(&[
        "merge",
        "--history",
        "off",
        "--out",
        s(&t.join("m3")),
        s(&r),
        s(&other),
    ]);
    expect(&o, 2, &["different RTLs", "pmu50_alt.f"]);
}
