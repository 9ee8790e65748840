//! `pmu50 signoff DIR`: the sign-off table of a regression folder, each figure against its
//! threshold. A folder with every input and every figure at its threshold exits 0; one figure
//! short, a wrong declaration, an undecided bin, a property not proven or an input missing
//! exits 1 naming the row; a bad input exits 2 naming the file.

use std::path::Path;

mod common;
use common::{expect, pmu50, s, tmp};

/// A `code/summary.json` as `pmu50 regress --code-coverage` writes it, with these figures.
fn code_summary(line: (u64, u64), toggle: (u64, u64), waivers: &str) -> String {
    let count = |(hit, total): (u64, u64)| {
        format!(
            r#"{{"hit": {hit}, "total": {total}, "waived": 0, "pct": {}}}"#,
            if total == 0 {
                100.0
            } else {
                100.0 * hit as f64 / total as f64
            }
        )
    };
    format!(
        r#"{{"format": "pmu50-code-coverage-1", "seeds": 3, "seeds_unaccounted": 0, "line": {}, "toggle": {}, "files": [], "waivers": {waivers}, "waivers_file": "code/waivers.toml"}}"#,
        count(line),
        count(toggle)
    )
}

fn write(p: &Path, text: &str) {
    std::fs::create_dir_all(p.parent().unwrap()).unwrap();
    std::fs::write(p, text).unwrap();
}

/// The inputs beside a model regression: proofs, code coverage and formal verdicts, all met.
fn complete(dir: &Path) {
    // every bin the model declares unreachable proven so, one other witnessed
    let cov: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("coverage.json")).unwrap()).unwrap();
    let mut bins = vec![serde_json::json!(
        {"name": "fig17.path.fixed", "status": "witnessed", "property": "cover (hit_x)"})];
    for b in cov["bins"].as_array().unwrap() {
        if let Some(why) = b.get("unreachable") {
            bins.push(
                serde_json::json!({"name": b["name"], "status": "proven_unreachable",
                "declared_unreachable": why, "property": "assert (!hit_y)"}),
            );
        }
    }
    assert_eq!(bins.len(), 95);
    write(
        &dir.join("coverage-proofs.json"),
        &serde_json::json!({ "bins": bins }).to_string(),
    );
    write(
        &dir.join("code/summary.json"),
        &code_summary((84, 84), (10, 10), "[]"),
    );
    write(
        &dir.join("formal.json"),
        r#"{"format": "pmu50-formal", "version": 1, "properties": [
  {"name": "prop_a", "set": "small", "verdict": "proven", "how": "scorr"}]}"#,
    );
}

#[test]
fn every_figure_at_its_threshold_passes_and_one_short_fails_naming_it() {
    let t = tmp("signoff");
    let dir = t.join("r");
    let o = pmu50(&[
        "regress",
        "--iterations",
        "3",
        "--no-triage",
        "--out",
        s(&dir),
    ]);
    expect(&o, 0, &["pass"]);
    // nothing but the regression: the missing inputs are missed rows that say what writes them
    let o = pmu50(&["signoff", s(&dir)]);
    let text = expect(
        &o,
        1,
        &["coverage-proofs.json missing", "code/summary.json missing"],
    );
    assert!(text.contains("formal.json missing"), "{text}");
    complete(&dir);
    // three seeds do not close the functional coverage: missed at V3, met at a threshold of 10 %
    let o = pmu50(&["signoff", s(&dir)]);
    let text = expect(&o, 1, &["signoff: 1 of 7 thresholds missed"]);
    assert!(
        text.lines()
            .any(|l| l.starts_with("functional coverage") && l.contains("MISSED")),
        "{text}"
    );
    let th = t.join("t.toml");
    write(&th, "[thresholds]\nfunctional = 10\n");
    let o = pmu50(&["signoff", s(&dir), "--thresholds", s(&th)]);
    expect(&o, 0, &["signoff: every threshold met"]);
    // the table is at the top of report.html, and in signoff.json
    let html = std::fs::read_to_string(dir.join("report.html")).unwrap();
    let (signoff, regress) = (html.find("<h2>Sign-off</h2>"), html.find("<h2>Failures"));
    assert!(
        signoff.is_some() && signoff < regress,
        "sign-off table first"
    );
    // with every bin's reachability as the proofs decided it
    assert!(
        html.contains(
            "Reachability of every bin, by the coverage proofs: 94 proven unreachable, 1 witnessed"
        ),
        "{html}"
    );
    assert!(html.contains(
        "<code>fig18.history.both</code></td><td class=\"ok\">proven unreachable</td><td>assert (!hit_y)</td>"
    ));
    // and each bin's decision in coverage.json and the UCIS export
    let cov = std::fs::read_to_string(dir.join("coverage.json")).unwrap();
    assert!(
        cov.contains(r#""name":"fig17.path.fixed","#)
            && cov.contains(r#""proof":"witnessed: cover (hit_x)"}"#),
        "{cov}"
    );
    let ucis = std::fs::read_to_string(dir.join("coverage.ucis.xml")).unwrap();
    assert!(ucis.contains(
        r#"<userAttr key="proof" type="str">proven unreachable: assert (!hit_y)</userAttr>"#
    ));
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("signoff.json")).unwrap()).unwrap();
    assert_eq!(json["met"], true);
    assert_eq!(json["rows"].as_array().unwrap().len(), 7);

    // each input can miss its own row
    let cases: [(&str, &str, &str, &str); 4] = [
        (
            "code/summary.json",
            &code_summary((83, 84), (10, 10), "[]"),
            "code line coverage",
            "83/84",
        ),
        (
            "formal.json",
            r#"{"properties": [{"name": "prop_a", "set": "small", "verdict": "unknown"}]}"#,
            "properties proven",
            "prop_a (small, unknown)",
        ),
        (
            "coverage-proofs.json",
            r#"{"bins": [{"name": "bus.read.unmapped", "status": "undecided"}]}"#,
            "bins undecided",
            "bus.read.unmapped",
        ),
        (
            "coverage-proofs.json",
            r#"{"bins": [{"name": "fig18.history.both", "status": "wrong_declaration",
                "declared_unreachable": "a reason"}]}"#,
            "bins proven unreachable",
            "wrong declarations: fig18.history.both",
        ),
    ];
    for (file, text, row, why) in cases {
        complete(&dir);
        write(&dir.join(file), text);
        let o = pmu50(&["signoff", s(&dir), "--thresholds", s(&th)]);
        let out = expect(&o, 1, &[row]);
        let line = out.lines().find(|l| l.starts_with(row)).unwrap();
        assert!(
            line.contains("MISSED") && line.contains(why),
            "{file}: {line}"
        );
    }

    // a bad input: exit 2, the file and line
    complete(&dir);
    write(
        &dir.join("formal.json"),
        "{\"properties\": [\n{\"name\": 3}]}",
    );
    let o = pmu50(&["signoff", s(&dir)]);
    expect(&o, 2, &["formal.json: line 2"]);

    // proofs left from another coverage model (before bins were split): refused, not counted
    complete(&dir);
    let cur = std::fs::read_to_string(dir.join("coverage-proofs.json")).unwrap();
    write(
        &dir.join("coverage-proofs.json"),
        &cur.replacen(
            "{",
            r#"{"model_id": "pmu50-coverage/471/0123456789abcdef","#,
            1,
        ),
    );
    let o = pmu50(&["signoff", s(&dir)]);
    expect(
        &o,
        2,
        &[
            "coverage-proofs.json",
            "another coverage model",
            "make coverage-proofs",
        ],
    );
    // and this model's id is accepted
    let id = pmu50_coverage::model_id(pmu50_coverage::layout());
    write(
        &dir.join("coverage-proofs.json"),
        &cur.replacen("{", &format!(r#"{{"model_id": "{id}","#), 1),
    );
    let o = pmu50(&["signoff", s(&dir), "--thresholds", s(&th)]);
    expect(&o, 0, &["signoff: every threshold met"]);

    // a waiver whose claim the proofs refute misses the toggle row; proven, it is met and counted
    write(
        &dir.join("code/summary.json"),
        &code_summary(
            (84, 84),
            (10, 10),
            r#"[{"file": "rtl/a.v", "what": "signal x[3]", "reason": "constant", "at": 2, "points": 2, "covered": 0}]"#,
        ),
    );
    for (status, code, want) in [
        (
            "refuted",
            1,
            "claims not proven: rtl/a.v signal x[3]: `x[3] == 1'b0` refuted",
        ),
        (
            "proven",
            0,
            "after 1 waivers (code/waivers.toml), 1 of their 1 claims proven",
        ),
    ] {
        write(
            &dir.join("coverage-proofs.json"),
            &cur.replacen(
                "{",
                &format!(
                    r#"{{"model_id": "{id}", "waivers": [{{"file": "rtl/a.v", "what": "signal x[3]", "holds": "x[3] == 1'b0", "status": "{status}"}}],"#
                ),
                1,
            ),
        );
        let o = pmu50(&["signoff", s(&dir), "--thresholds", s(&th)]);
        let out = expect(&o, code, &[want]);
        let line = out
            .lines()
            .find(|l| l.starts_with("code toggle coverage"))
            .unwrap();
        assert_eq!(line.contains("MISSED"), code == 1, "{line}");
    }
}

#[test]
fn a_port_level_witness_replayed_through_the_rtl_closes_its_bin() {
    let t = tmp("witness");
    let w = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("rtl_model/coverage/tests/witness/bus.write_reg.unmapped.vec");
    let cov = t.join("w.json");
    let o = pmu50(&[
        "lockstep",
        s(&w),
        "--map",
        s(&Path::new(env!("CARGO_MANIFEST_DIR")).join("hdl/pmu50.map.toml")),
        "--coverage",
        s(&cov),
    ]);
    expect(&o, 0, &["PASS", "run lockstep/bus.write_reg.unmapped"]);
    let c: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&cov).unwrap()).unwrap();
    let bin = c["bins"]
        .as_array()
        .unwrap()
        .iter()
        .find(|b| b["name"] == "bus.write_reg.unmapped")
        .unwrap();
    assert!(bin["hits"].as_u64().unwrap() > 0, "{bin}");
    // merged beside a regression, the bin counts as hit
    let r = t.join("r");
    let o = pmu50(&[
        "regress",
        "--iterations",
        "2",
        "--no-triage",
        "--out",
        s(&r),
    ]);
    expect(&o, 0, &["pass"]);
    let m = t.join("m");
    let o = pmu50(&["merge", "--out", s(&m), s(&r), s(&cov)]);
    expect(
        &o,
        0,
        &["merged 1 regression folder(s) and 1 coverage file(s)"],
    );
    let c: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(m.join("coverage.json")).unwrap()).unwrap();
    assert!(c["bins"]
        .as_array()
        .unwrap()
        .iter()
        .any(|b| b["name"] == "bus.write_reg.unmapped" && b["hits"].as_u64().unwrap() > 0));
    // pmu50 signoff counts the merged coverage, not the seeds' alone, run after run
    for _ in 0..2 {
        let o = pmu50(&["signoff", s(&m)]);
        expect(&o, 1, &["(3 runs)"]);
        let c = std::fs::read_to_string(m.join("coverage.json")).unwrap();
        assert!(
            c.contains(r#""name":"bus.write_reg.unmapped","kind":"point","hits":1"#),
            "{c}"
        );
    }
}
