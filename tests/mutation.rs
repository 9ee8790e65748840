//! `pmu50 mutation`: the mutation table of the directed regression (docs/verification.md,
//! "Mutation score"), on a few mutants of hdl/mutants.txt and a few seeds.

use crate::common;
use common::*;

/// A mutant caught at its first seed, one that needs more seeds than given (escaped: exit 1),
/// and one declared proven equivalent: counted equivalent (not run) only with the formal kit's
/// sealed equivalence proof of this twin beside the mutants' list, refused without it; the JSON
/// says the same as the table.
#[test]
fn table_counts_seeds_to_catch_and_escapes() {
    let d = tmp("table");
    // the mutants' list in a folder of its own: its proofs are looked up below it
    let list = d.join("mutants.txt");
    std::fs::copy("hdl/mutants.txt", &list).unwrap();
    let run = |tag: &str| {
        let out = d.join(tag);
        let o = pmu50(&[
            "mutation",
            "--iterations",
            "1",
            "--jobs",
            "1",
            "--mutants",
            s(&list),
            "--only",
            "MUT_SR_RESET_ONE,MUT_KOFF_OLD_X,MUT_ERR_CLEAR_WINS",
            "--out",
            s(&out),
        ]);
        (exited(&o, 1), out)
    };
    // no proof: "equivalent" is refused
    let (t, _) = run("noproof");
    assert!(
        t.contains("MUT_ERR_CLEAR_WINS")
            && t.contains("declared equivalent, not proven")
            && t.contains("make formal-mutants"),
        "{t}"
    );
    assert!(t.contains("0 proven equivalent"), "{t}");
    // the kit's sealed verdict for this twin
    let proof = d.join("build/formal/equivalence/MUT_ERR_CLEAR_WINS.json");
    std::fs::create_dir_all(proof.parent().unwrap()).unwrap();
    std::fs::write(
        &proof,
        r#"{"format": "pmu50-equivalence", "mutant": "MUT_ERR_CLEAR_WINS", "verdict": "equivalent", "how": "small: every output equal: scorr proves 19 of the 19 checks (unbounded)"}"#,
    )
    .unwrap();
    let o = pmu50(&[
        "seal",
        s(&proof),
        "--made-by",
        "hdl/formal/run.py --mutants",
        "--rtl",
        "hdl/pmu50.f",
    ]);
    exited(&o, 0);
    let (t, out) = run("proof");
    let row = |m: &str| {
        t.lines()
            .find(|l| l.starts_with(&format!("{m} ")))
            .unwrap_or_else(|| panic!("no row of {m}:\n{t}"))
            .to_string()
    };
    // Sr resets to 1: the first seed sees it after reset (tick 0), on the mapped register and
    // the port it drives at once (one signature names the set)
    let r = row("MUT_SR_RESET_ONE");
    assert!(
        r.contains("sensor_power_determination_57")
            && r.contains(" 1  1: dut-sensor_power_determination.sr+sr-"),
        "{r}"
    );
    // a same-cycle SI_MAX write at key-off is not in seed 1
    assert!(row("MUT_KOFF_OLD_X").contains("escaped"), "{t}");
    assert!(row("MUT_ERR_CLEAR_WINS").contains("equiv"), "{t}");
    assert!(
        t.contains("mutation score: 1/2 caught within 1 directed seeds (50.0 %), 1 escaped, 1 proven equivalent"),
        "{t}"
    );
    let j: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("mutation.json")).unwrap()).unwrap();
    let rows = j["rows"].as_array().unwrap();
    assert_eq!(rows.len(), 3);
    assert_eq!(rows[0]["mutant"], "MUT_SR_RESET_ONE");
    assert_eq!(rows[0]["result"], "caught");
    assert_eq!(rows[0]["seeds"], 1);
    assert_eq!(rows[0]["signal"], "pmu50.sr");
    assert_eq!(rows[1]["result"], "escaped");
    assert_eq!(rows[2]["result"], "equivalent");
    assert!(rows[2]["proof"].as_str().unwrap().contains("scorr proves"));
    assert_eq!(j["escaped"], 1);
    assert!(out.join("mutation.txt").is_file());
}

/// Bad input is refused before anything runs: exit 2 with what was wrong and what is valid.
#[test]
fn bad_input_is_refused() {
    let d = tmp("bad");
    let o = pmu50(&["mutation", "--only", "MUT_NOPE", "--out", s(&d)]);
    expect_code(&o, 2);
    let t = text(&o);
    assert!(
        t.contains("--only MUT_NOPE") && t.contains("MUT_CNT_C_SIGN"),
        "{t}"
    );
    let list = write(&d, "m.txt", "MUT_A | rtl/a.v | ok\nMUT_B | rtl/b.v\n");
    let o = pmu50(&["mutation", "--mutants", s(&list), "--out", s(&d)]);
    expect_code(&o, 2);
    let t = text(&o);
    assert!(
        t.contains("m.txt: line 2") && t.contains("NAME | file | description"),
        "{t}"
    );
    let o = pmu50(&["mutation", "--iterations", "0", "--out", s(&d)]);
    expect_code(&o, 2);
    assert!(text(&o).contains("--iterations 0"), "{}", text(&o));
}
