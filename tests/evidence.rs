//! A failure is a full record, and a DUT's pass counts only with the seed's tick count:
//! `--repro` says when the RTL changed since the failure, `--resume` refuses a changed RTL, and
//! an RTL that writes a pass into the bench's verdict file and ends early is a failure.

use std::path::{Path, PathBuf};

use crate::common;
use common::{expect, pmu50, s, tmp};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// A copy of the twin in `dir` (its list `pmu50.f`), with `edit` applied to pmu50.v.
fn twin_copy(dir: &Path, edit: impl Fn(&str) -> String) -> PathBuf {
    let hdl = root().join("hdl");
    std::fs::create_dir_all(dir.join("rtl")).unwrap();
    for e in std::fs::read_dir(hdl.join("rtl")).unwrap() {
        let p = e.unwrap().path();
        std::fs::copy(&p, dir.join("rtl").join(p.file_name().unwrap())).unwrap();
    }
    let top = std::fs::read_to_string(hdl.join("pmu50.v")).unwrap();
    std::fs::write(dir.join("pmu50.v"), edit(&top)).unwrap();
    std::fs::copy(hdl.join("pmu50.f"), dir.join("pmu50.f")).unwrap();
    dir.join("pmu50.f")
}

#[test]
fn an_rtl_that_writes_a_pass_and_ends_early_fails() {
    let t = tmp("early");
    // the RTL reads the bench's verdict file name, writes a pass into it at its third edge,
    // and ends the simulation
    let list = twin_copy(&t.join("rtl"), |top| {
        let cheat = "\n    integer cheat_n = 0; integer cheat_fd; reg [8*1024-1:0] cheat_f;\n    always @(posedge clk) begin\n        cheat_n = cheat_n + 1;\n        if (cheat_n == 3 && $value$plusargs(\"verdict=%s\", cheat_f)) begin\n            cheat_fd = $fopen(cheat_f, \"w\"); $fdisplay(cheat_fd, \"PASS ticks=3\"); $fclose(cheat_fd); $finish;\n        end\n    end\nendmodule";
        let k = top.rfind("endmodule").unwrap();
        format!("{}{}{}", &top[..k], cheat, &top[k + "endmodule".len()..])
    });
    let o = pmu50(&[
        "regress",
        "--iterations",
        "2",
        "--dut",
        "icarus",
        "--rtl",
        s(&list),
        "--no-triage",
        "--history",
        "off",
        "--out",
        s(&t.join("r")),
    ]);
    expect(&o, 1, &["2 fail"]);
    let results = std::fs::read_to_string(t.join("r/results.jsonl")).unwrap();
    assert!(
        results.contains("reported a pass after 3 ticks"),
        "{results}"
    );
}

#[test]
fn repro_and_resume_see_an_rtl_that_changed() {
    let t = tmp("record");
    let list = twin_copy(&t.join("rtl"), |top| top.to_string());
    let dir = t.join("r");
    let o = pmu50(&[
        "regress",
        "--iterations",
        "1",
        "--dut",
        "verilator",
        "--rtl",
        s(&list),
        "--no-triage",
        "--history",
        "off",
        "--out",
        s(&dir),
    ]);
    expect(&o, 0, &["1 pass"]);
    // a repro in the folder's failures/: the same RTL is said to be the same
    let repro = dir.join("failures/x/repro.toml");
    std::fs::create_dir_all(repro.parent().unwrap()).unwrap();
    std::fs::copy(root().join("scenarios/fig15a.toml"), &repro).unwrap();
    let args = [
        "regress",
        "--repro",
        s(&repro),
        "--dut",
        "verilator",
        "--rtl",
        s(&list),
    ];
    expect(
        &pmu50(&args),
        0,
        &["the RTL is the one the failure was found on"],
    );
    // one file edited: said before the run, naming the file
    let f = t.join("rtl/rtl/count_diagnosis.v");
    let mut text = std::fs::read_to_string(&f).unwrap();
    text.push_str("// edited\n");
    std::fs::write(&f, text).unwrap();
    expect(
        &pmu50(&args),
        0,
        &[
            "the RTL changed since the failure was found",
            "changed: rtl/count_diagnosis.v",
        ],
    );
    // a resume on the changed RTL is refused, naming both hashes
    let o = pmu50(&["regress", "--resume", s(&dir)]);
    expect(
        &o,
        2,
        &[
            "the regression was started on RTL sha256:",
            "changed: rtl/count_diagnosis.v",
        ],
    );
}
