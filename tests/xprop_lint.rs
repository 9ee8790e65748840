//! `pmu50 xprop` and `pmu50 lint` on any RTL, and their sign-off rows: a copy of the twin whose
//! timer `tmr` is dropped from the reset branch is caught by the X row with the register's name
//! (a 4-state simulation sees its outputs go X; yosys finds the flip-flop without reset), while
//! the 2-state Verilator regression passes it; the twin is X-clean and lint-clean, read by the
//! tools themselves; an RTL no reader gives (not even slang: tests/xprop_lint_sv.rs has the
//! SystemVerilog it reads) is not checked, and the rows say why (missing, never met); a lint
//! waiver waives its warning until its line is edited. Needs verilator, iverilog
//! and yosys (`make deps`).

use crate::common;
use common::*;
use std::path::{Path, PathBuf};

fn hdl() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("hdl")
}

/// A copy of the twin in `dir` with `edit` applied to rtl/timing_generator_56.v.
fn twin_copy(dir: &Path, edit: impl Fn(String) -> String) -> PathBuf {
    std::fs::create_dir_all(dir.join("rtl")).unwrap();
    let list = std::fs::read_to_string(hdl().join("pmu50.f")).unwrap();
    for f in list.lines().map(str::trim).filter(|l| !l.is_empty()) {
        let mut text = std::fs::read_to_string(hdl().join(f)).unwrap();
        if f.ends_with("timing_generator_56.v") {
            text = edit(text);
        }
        std::fs::write(dir.join(f), text).unwrap();
    }
    std::fs::write(dir.join("pmu50.f"), list).unwrap();
    dir.join("pmu50.f")
}

const RESET: &str = "    always @(posedge clk or negedge rst_n) begin\n        if (!rst_n)                          tmr <= 16'd0;";

#[test]
fn a_flop_without_reset_is_caught_by_the_x_row_and_not_by_the_2_state_regression() {
    let t = tmp("xplant");
    let plant = twin_copy(&t.join("rtl"), |s| {
        assert!(
            s.contains(RESET),
            "the twin's timer reset as the plant expects"
        );
        s.replace(
            RESET,
            "    always @(posedge clk) begin\n        if (1'b0)                            tmr <= 16'd0;",
        )
    });
    let out = expect(
        &pmu50(&[
            "xprop",
            "--rtl",
            s(&plant),
            "--iterations",
            "1",
            "--out",
            s(&t.join("x.json")),
        ]),
        1,
        &[
            "output vs2_en is",
            "flip-flop timing_generator.tmr (16 bit(s)",
        ],
    );
    assert!(
        out.contains("timing_generator_56.v:57) has no reset"),
        "{out}"
    );
    // the 2-state regression (Verilator starts every flop at 0) passes it
    let o = std::process::Command::new(BIN)
        .args([
            "regress",
            "--no-triage",
            "--dut",
            "verilator",
            "--rtl",
            s(&plant),
            "--iterations",
            "2",
            "--sync-depth",
            "2",
            "--cnt-width",
            "16",
            "--out",
            s(&t.join("reg")),
        ])
        .env("PMU50_CACHE_DIR", t.join("cache"))
        .output()
        .unwrap();
    expect(&o, 0, &["2 seeds, 2 pass"]);
    // the sign-off row: missed, naming the register
    std::fs::copy(t.join("x.json"), t.join("reg/xprop.json")).unwrap();
    let so = text(&pmu50(&["signoff", s(&t.join("reg"))]));
    let row = so.lines().find(|l| l.starts_with("X-propagation")).unwrap();
    assert!(row.contains("MISSED") && row.contains("vs2_en"), "{row}");
}

#[test]
fn the_twin_is_x_clean_and_lint_clean_and_an_unreadable_rtl_is_not_passed() {
    let t = tmp("xtwin");
    let twin = hdl().join("pmu50.f");
    let dir = t.join("run");
    // a sign-off is of an RTL: the regression ran the twin (not the model alone)
    expect(
        &pmu50(&[
            "regress",
            "--dut",
            "verilator",
            "--rtl",
            s(&twin),
            "--iterations",
            "1",
            "--out",
            s(&dir),
        ]),
        0,
        &[],
    );
    expect(
        &pmu50(&[
            "xprop",
            "--rtl",
            s(&twin),
            "--iterations",
            "1",
            "--out",
            s(&dir.join("xprop.json")),
        ]),
        0,
        &["0 finding(s) not waived over 1 seed(s)"],
    );
    expect(
        &pmu50(&[
            "lint",
            "--rtl",
            s(&twin),
            "--out",
            s(&dir.join("lint.json")),
        ]),
        0,
        &[
            "verilator -Wall --lint-only: 0 warning(s)",
            "yosys check: 0 warning(s)",
        ],
    );
    let so = text(&pmu50(&["signoff", s(&dir)]));
    for name in ["X-propagation findings", "lint warnings not waived"] {
        let row = so.lines().find(|l| l.starts_with(name)).unwrap();
        assert!(row.contains(" met "), "{row}");
    }
    // an edited byte: not evidence
    let x = std::fs::read_to_string(dir.join("xprop.json")).unwrap();
    std::fs::write(
        dir.join("xprop.json"),
        x.replacen("\"seeds\": 1", "\"seeds\": 9", 1),
    )
    .unwrap();
    // an edited byte: not evidence (the digest no longer matches: refused, exit 2)
    expect(&pmu50(&["signoff", s(&dir)]), 2, &["xprop.json", "digest"]);

    // an RTL no reader gives (a SystemVerilog file slang cannot elaborate): not checked, the
    // report says why (the row reads it as missing, never met); Verilator refuses to lint it
    let bad = t.join("bad");
    let list = twin_copy(&bad, |s| s);
    std::fs::write(
        bad.join("broken.sv"),
        "module broken(input logic a);\n  assign = a;\nendmodule\n",
    )
    .unwrap();
    let mut l = std::fs::read_to_string(&list).unwrap();
    l.push_str("broken.sv\n");
    std::fs::write(&list, l).unwrap();
    expect(
        &pmu50(&[
            "xprop",
            "--rtl",
            s(&list),
            "--iterations",
            "1",
            "--out",
            s(&dir.join("xprop.json")),
        ]),
        1,
        &[
            "Icarus Verilog cannot read this RTL",
            "slang could not elaborate",
        ],
    );
    expect(
        &pmu50(&[
            "lint",
            "--rtl",
            s(&list),
            "--out",
            s(&dir.join("lint.json")),
        ]),
        2,
        &["verilator --lint-only: %Error"],
    );
    let r: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("xprop.json")).unwrap()).unwrap();
    assert!(
        r["checks"]
            .as_array()
            .unwrap()
            .iter()
            .all(|c| c["ran"] == false && c["reason"].as_str().unwrap().contains("slang")),
        "{r}"
    );
    // and reports of another RTL never join the twin's table
    expect(&pmu50(&["signoff", s(&dir)]), 2, &["made on another RTL"]);
}

#[test]
fn a_lint_waiver_waives_its_warning_until_its_line_changes() {
    let t = tmp("lintw");
    let add = "    wire spare_net = sig;\n";
    let rtl = twin_copy(&t.join("rtl"), |s| {
        let at = s.find("    reg [15:0] tmr;").unwrap();
        format!("{}{add}{}", &s[..at], &s[at..])
    });
    let f = t.join("rtl/rtl/timing_generator_56.v");
    let src = std::fs::read_to_string(&f).unwrap();
    let line = src.lines().position(|l| l.contains("spare_net")).unwrap() as u32 + 1;
    let out = expect(
        &pmu50(&["lint", "--rtl", s(&rtl), "--out", s(&t.join("l.json"))]),
        1,
        &["UNUSEDSIGNAL", "1 warning(s) not waived"],
    );
    assert!(
        out.contains(&format!("timing_generator_56.v:{line}: UNUSEDSIGNAL")),
        "{out}"
    );
    let w = t.join("lint-waivers.toml");
    std::fs::write(
        &w,
        format!(
            "[[waiver]]\nrule = \"UNUSEDSIGNAL\"\nfile = \"rtl/timing_generator_56.v\"\nline = {line}\nsignal = \"spare_net\"\nreason = \"a spare net kept for an ECO\"\nkind = \"LOW_RISK\"\nreviewer = \"the test\"\n"
        ),
    )
    .unwrap();
    // never reviewed on this source (no checksum): it does not apply; refresh checks it again
    // against the report of the RTL as it is, and writes the checksum
    expect(
        &pmu50(&[
            "lint",
            "--rtl",
            s(&rtl),
            "--waivers",
            s(&w),
            "--out",
            s(&t.join("l.json")),
        ]),
        1,
        &["no checksum"],
    );
    expect(
        &pmu50(&[
            "waivers",
            "refresh",
            "--waivers",
            s(&w),
            "--rtl",
            s(&rtl),
            "--report",
            s(&t.join("l.json")),
        ]),
        0,
        &["1 checksum(s) written"],
    );
    assert!(std::fs::read_to_string(&w)
        .unwrap()
        .contains("checksum = \"sha256:"));
    expect(
        &pmu50(&[
            "lint",
            "--rtl",
            s(&rtl),
            "--waivers",
            s(&w),
            "--out",
            s(&t.join("l.json")),
        ]),
        0,
        &["0 warning(s) not waived"],
    );
    // the waived line edited: stale, the warning counts again
    std::fs::write(&f, src.replace("spare_net = sig;", "spare_net = !sig;")).unwrap();
    let out = expect(
        &pmu50(&[
            "lint",
            "--rtl",
            s(&rtl),
            "--waivers",
            s(&w),
            "--out",
            s(&t.join("l.json")),
        ]),
        1,
        &["does not apply, stale", "1 warning(s) not waived"],
    );
    assert!(
        out.contains(&format!("line {line} of rtl/timing_generator_56.v")),
        "{out}"
    );
}
