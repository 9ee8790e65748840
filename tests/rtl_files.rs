//! One reader of an RTL's file list (`verif/src/filelist.rs`): `+incdir+`, `+define+`, nested
//! `-F` lists, comments, paths relative to the list that names them; what `pmu50 rtl-files`
//! prints for the scripts, and the regression building the RTL from such a list. Needs verilator
//! (`make deps`).

use crate::common;
use common::*;
use std::path::{Path, PathBuf};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// hdl/alt_sv behind a list of lists: `top.f` names `+define+`, `+incdir+` and `-F
/// rtl/inner.f`, whose entries are relative to `rtl/`; one source file includes a header found
/// through the `+incdir+` folder and uses the define.
fn nested(dir: &Path) -> PathBuf {
    let alt = root().join("hdl/alt_sv");
    std::fs::create_dir_all(dir.join("rtl")).unwrap();
    std::fs::create_dir_all(dir.join("include")).unwrap();
    let list = std::fs::read_to_string(alt.join("pmu50_alt.f")).unwrap();
    let mut inner = String::from("/* the sources, relative to this list */\n");
    for f in list.lines().map(str::trim).filter(|l| !l.is_empty()) {
        let mut text = std::fs::read_to_string(alt.join(f)).unwrap();
        if f == "pmu_count_check.sv" {
            // a file that needs the include folder and the define
            text = format!("`include \"alt_check.svh\"\n`ifndef ALT_CHECK_SEEN\n`error \"the define did not arrive\"\n`endif\n{text}");
        }
        std::fs::write(dir.join("rtl").join(f), text).unwrap();
        inner.push_str(&format!("{f}   // {f}\n"));
    }
    std::fs::write(dir.join("rtl/inner.f"), inner).unwrap();
    std::fs::write(
        dir.join("include/alt_check.svh"),
        "`ifdef ALT_DEFINE_GIVEN\n`define ALT_CHECK_SEEN\n`endif\n",
    )
    .unwrap();
    std::fs::write(
        dir.join("top.f"),
        "# the RTL of the test\n+incdir+include\n+define+ALT_DEFINE_GIVEN=1\n-F rtl/inner.f\n",
    )
    .unwrap();
    dir.join("top.f")
}

#[test]
fn nested_lists_with_incdir_and_define_reach_every_tool() {
    let dir = tmp("nested");
    let list = nested(&dir);
    // what the scripts read
    let o = pmu50(&["rtl-files", "--rtl", s(&list), "--json"]);
    let text = expect(&o, 0, &["\"content_hash\": \"sha256:"]);
    let j: serde_json::Value = serde_json::from_str(&text).unwrap();
    assert_eq!(j["files"].as_array().unwrap().len(), 10, "{text}");
    assert!(
        j["files"][0]
            .as_str()
            .unwrap()
            .ends_with("rtl/pmu50_alt_pkg.sv"),
        "{text}"
    );
    assert!(
        j["incdirs"][0].as_str().unwrap().ends_with("/include"),
        "{text}"
    );
    assert_eq!(j["defines"][0]["name"], "ALT_DEFINE_GIVEN");
    assert_eq!(j["lists"].as_array().unwrap().len(), 2);
    let flat = pmu50(&["rtl-files", "--rtl", s(&list)]);
    let flat = expect(&flat, 0, &["+define+ALT_DEFINE_GIVEN=1", "+incdir+"]);
    assert_eq!(flat.lines().filter(|l| l.ends_with(".sv")).count(), 10);
    // the regression elaborates and builds from it (the define reaches the `error guard)
    let o = pmu50(&[
        "regress",
        "--iterations",
        "2",
        "--jobs",
        "1",
        "--dut",
        "verilator",
        "--rtl",
        s(&list),
        "--out",
        s(&dir.join("out")),
    ]);
    expect(&o, 0, &["2 seeds"]);
}

#[test]
fn a_bad_entry_is_refused_with_its_list_and_line() {
    let dir = tmp("bad");
    std::fs::write(dir.join("a.sv"), "module a; endmodule\n").unwrap();
    std::fs::write(dir.join("top.f"), "a.sv\n--timing\n").unwrap();
    let o = pmu50(&["rtl-files", "--rtl", s(&dir.join("top.f"))]);
    expect(
        &o,
        2,
        &["top.f:2: `--timing`: not an entry of a file list; valid are"],
    );
    let o = pmu50(&[
        "regress",
        "--iterations",
        "1",
        "--dut",
        "verilator",
        "--rtl",
        s(&dir.join("top.f")),
    ]);
    expect(&o, 2, &["top.f:2: `--timing`"]);
}
