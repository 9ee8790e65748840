//! The kit on an RTL unlike the twin (hdl/alt_sv/: a SystemVerilog package imported in module
//! headers, typed parameters, a packed-struct parameter register, its own names), and on the
//! twin with the simulation idioms many teams keep in their RTL (docs/hdl-guide.md,
//! "SystemVerilog and simulation idioms", "The map", "A failure folder"). Needs verilator and
//! iverilog (`make deps`).

use crate::common;
use common::*;
use std::path::{Path, PathBuf};

fn hdl() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("hdl")
}

/// A copy of the twin in `dir`; `edit(file, text)` changes a file's text on the way. Returns
/// the file list.
fn twin_copy(dir: &Path, edit: impl Fn(&str, String) -> String) -> PathBuf {
    std::fs::create_dir_all(dir.join("rtl")).unwrap();
    let list = std::fs::read_to_string(hdl().join("pmu50.f")).unwrap();
    for f in list.lines().map(str::trim).filter(|l| !l.is_empty()) {
        let text = std::fs::read_to_string(hdl().join(f)).unwrap();
        std::fs::write(dir.join(f), edit(f, text)).unwrap();
    }
    std::fs::write(dir.join("pmu50.f"), list).unwrap();
    dir.join("pmu50.f")
}

fn regress(args: &[&str], out: &Path) -> std::process::Output {
    let mut a = vec!["regress", "--jobs", "2"];
    a.extend(args);
    a.extend(["--out", s(out)]);
    pmu50(&a)
}

#[test]
fn delays_initial_blocks_and_display_in_the_rtl_pass_on_every_backend() {
    let t = tmp("idioms");
    // the alternative RTL with `initial #5 $display` and `q <= #1 d`: the directed regression
    let o = regress(
        &[
            "--iterations",
            "4",
            "--directed",
            "--no-triage",
            "--dut",
            "verilator",
            "--rtl",
            s(&hdl().join("alt_sv/pmu50_alt_idioms.f")),
        ],
        &t.join("alt"),
    );
    expect(&o, 0, &["4 seeds, 4 pass"]);
    // the coverage build takes the same options: the delayed flop's lines are counted
    let o = regress(
        &[
            "--iterations",
            "1",
            "--directed",
            "--no-triage",
            "--code-coverage",
            "--dut",
            "verilator",
            "--rtl",
            s(&hdl().join("alt_sv/pmu50_alt_idioms.f")),
        ],
        &t.join("alt_cov"),
    );
    expect(&o, 0, &["1 seeds, 1 pass", "code coverage: line"]);
    let summary: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(t.join("alt_cov/code/summary.json")).unwrap(),
    )
    .unwrap();
    let idioms = summary["files"]
        .as_array()
        .unwrap()
        .iter()
        .find(|f| f["file"] == "idioms/pmu_rail_monitor.sv")
        .expect("the file with the delays is covered");
    assert!(idioms["line"]["hit"].as_u64().unwrap() > 0, "{idioms}");
    // the twin with the same idioms on Icarus (which honours the delay; Icarus 11 cannot read
    // the alternative RTL's package)
    let list = twin_copy(&t.join("rtl"), |f, x| {
        if f.ends_with("sensor_power_determination_57.v") {
            x.replace(
                "else        sr <= vs2_en && vs2_ok;",
                "else        sr <= #1 vs2_en && vs2_ok;",
            )
            .replace(
                "endmodule",
                "    initial #5 $display(\"sensor_power_determination_57: %m\");\nendmodule",
            )
        } else {
            x
        }
    });
    assert!(
        std::fs::read_to_string(t.join("rtl/rtl/sensor_power_determination_57.v"))
            .unwrap()
            .contains("sr <= #1")
    );
    // (the port check elaborates it with Verilator first, with the same --no-timing)
    let o = regress(
        &[
            "--iterations",
            "3",
            "--directed",
            "--no-triage",
            "--dut",
            "icarus",
            "--rtl",
            s(&list),
        ],
        &t.join("twin_icarus"),
    );
    expect(&o, 0, &["3 seeds, 3 pass"]);
}

#[test]
fn icarus_reads_systemverilog_and_names_what_it_cannot() {
    let t = tmp("icarus");
    // the twin compiles as SystemVerilog (-g2012) and passes
    let o = regress(
        &["--iterations", "2", "--no-triage", "--dut", "icarus"],
        &t.join("twin"),
    );
    expect(&o, 0, &["2 seeds, 2 pass"]);
    // Icarus 11 cannot read the alternative RTL's package (`localparam int unsigned`):
    // exit 2 before any seed, at the file and line it names, with the advice
    let out = t.join("alt");
    let o = regress(
        &[
            "--iterations",
            "2",
            "--dut",
            "icarus",
            "--rtl",
            s(&hdl().join("alt_sv/pmu50_alt.f")),
        ],
        &out,
    );
    let msg = expect(
        &o,
        2,
        &[
            "alt_sv/pmu50_alt_pkg.sv:13: Icarus Verilog",
            "cannot read this (syntax error)",
            "though Verilator elaborates the RTL",
            "Use `--dut verilator`",
        ],
    );
    assert_eq!(msg.matches("error:").count(), 1, "{msg}");
    assert!(!out.join("results.jsonl").exists(), "no seed ran");
}

/// The entries of a map file: `"model" = "rtl"` lines without their comments.
fn entries(map: &str) -> Vec<String> {
    map.lines()
        .filter(|l| !l.trim_start().starts_with('#') && l.contains(" = \"pmu50."))
        .map(|l| l.split("  #").next().unwrap().trim().to_string())
        .collect()
}

#[test]
fn a_map_names_fields_of_packed_structs_and_elements_of_arrays() {
    let t = tmp("fields");
    let alt = hdl().join("alt_sv");
    let list = alt.join("pmu50_alt.f");
    let map = alt.join("pmu50_alt.map.toml");
    let text = std::fs::read_to_string(&map).unwrap();
    assert_eq!(
        entries(&text).len(),
        pmu50_core::signals::N_REGISTERS + pmu50_core::signals::N_INTERNALS,
        "one map with every entry"
    );
    assert!(text.contains("\"pmu50.u_regs.cfg_q.pw\""));
    // a copy whose registers are also read as elements of an unpacked array and bits of a
    // vector: `view_q[2]` (declared [1:3]) holds the interval, `hist_v[1:0]` the history bits
    let copy = t.join("copy");
    std::fs::create_dir_all(&copy).unwrap();
    for e in std::fs::read_dir(&alt).unwrap().flatten() {
        if e.path().is_file() {
            let mut text = std::fs::read_to_string(e.path()).unwrap();
            if e.file_name() == "pmu_interval_adapt.sv" {
                let end = text.rfind("endmodule").unwrap();
                text.insert_str(
                    end,
                    "  logic [15:0] view_q [1:3];\n  logic [7:0] hist_v;\n  always_comb begin\n    view_q[1] = 16'd0;\n    view_q[2] = interval_q;\n    view_q[3] = 16'hffff;\n    hist_v = {6'd0, hist_c_q, hist_s_q};\n  end\n",
                );
            }
            std::fs::write(copy.join(e.file_name()), text).unwrap();
        }
    }
    let mut copy_map = text.clone();
    for (from, to) in [
        ("pmu50.u_adapt.interval_q\"", "pmu50.u_adapt.view_q[2]\""),
        ("pmu50.u_adapt.hist_s_q\"", "pmu50.u_adapt.hist_v[0]\""),
        ("pmu50.u_adapt.hist_c_q\"", "pmu50.u_adapt.hist_v[1]\""),
        ("pmu50.u_latch.sign_s_o\"", "pmu50.u_latch.sign_q[0]\""),
        ("pmu50.u_latch.sign_c_o\"", "pmu50.u_latch.sign_q[1]\""),
    ] {
        assert!(copy_map.contains(from), "{from}");
        copy_map = copy_map.replacen(from, to, 1);
    }
    let copy_map = write(&t, "copy.map.toml", copy_map);
    // every entry compared (the parameter registers are fields of the 137-bit cfg_q), and at
    // another structure than the default (the fields and widths resolved again)
    for (tag, rtl, map, extra) in [
        (
            "default",
            &list,
            &map,
            vec!["--directed", "--iterations", "4"],
        ),
        (
            "narrow",
            &copy.join("pmu50_alt.f"),
            &copy_map,
            vec!["--iterations", "2", "--sync-depth", "3", "--cnt-width", "5"],
        ),
    ] {
        let mut a = vec![
            "--no-triage",
            "--dut",
            "verilator",
            "--rtl",
            s(rtl),
            "--map",
            s(map),
        ];
        a.extend(extra);
        let o = regress(&a, &t.join(tag));
        expect(
            &o,
            0,
            &["26 register(s) and 9 internal(s) compared", " pass, 0 fail"],
        );
    }
    // names that do not exist: refused at start with the closest names
    let cases = [
        (
            "pmu50.u_regs.cfg_q.pw\"",
            "pmu50.u_regs.cfg_q.pww\"",
            vec![
                "`register_file.pw` = `pmu50.u_regs.cfg_q.pww`",
                "has no field `pww`",
                "closest: pmu50.u_regs.cfg_q.pw",
            ],
        ),
        (
            "pmu50.u_latch.sign_s_o\"",
            "pmu50.u_latch.sign_q[2]\"",
            vec!["`pmu50.u_latch.sign_q`: bit 2 is outside [1:0]"],
        ),
        (
            "pmu50.u_regs.cfg_q.si_max\"",
            "pmu50.u_regs.cfg_q\"",
            vec![
                "137 bits (struct cfg_t)",
                "name a field",
                "pmu50.u_regs.cfg_q.si_max (16 bits)",
            ],
        ),
    ];
    for (k, (from, to, want)) in cases.iter().enumerate() {
        let bad = write(&t, &format!("bad{k}.toml"), text.replacen(from, to, 1));
        let out = t.join(format!("bad{k}"));
        let o = regress(
            &[
                "--iterations",
                "1",
                "--dut",
                "verilator",
                "--rtl",
                s(&list),
                "--map",
                s(&bad),
            ],
            &out,
        );
        expect(&o, 2, want);
        assert!(!out.join("results.jsonl").exists(), "no seed ran");
    }
}

#[test]
fn rtl_map_finds_the_registers_of_an_rtl_with_its_own_names_by_behaviour() {
    let t = tmp("rtlmap");
    let list = hdl().join("alt_sv/pmu50_alt.f");
    let out = t.join("proposed.toml");
    let o = pmu50(&["rtl-map", "--rtl", s(&list), "-o", s(&out)]);
    expect(&o, 0, &["wrote"]);
    let text = std::fs::read_to_string(&out).unwrap();
    let found = entries(&text);
    assert!(found.len() >= 30, "{} of 35 proposed:\n{text}", found.len());
    // each with its evidence
    for l in text.lines().filter(|l| l.contains(" = \"pmu50.")) {
        assert!(
            l.contains("  # equal to the model") || l.contains("  # never changed"),
            "{l}"
        );
    }
    // the parameter registers are found as fields of the packed struct, by the bus writes
    assert!(
        text.lines()
            .any(|l| l.starts_with("\"register_file.pw\" = \"pmu50.u_")
                && l.contains(".pw\"")
                && l.contains("bus write")),
        "{text}"
    );
    // never the next-state signal of a counter (one tick early)
    let cnt_s = text
        .lines()
        .find(|l| l.starts_with("\"updown_counter.cnt_s\""))
        .expect("cnt_s proposed");
    assert!(
        !cnt_s.contains("next") && !cnt_s.contains("_d\""),
        "{cnt_s}"
    );
    // what it proposes, lockstep confirms: a directed regression with the proposal passes
    let o = regress(
        &[
            "--iterations",
            "4",
            "--directed",
            "--no-triage",
            "--dut",
            "verilator",
            "--rtl",
            s(&list),
            "--map",
            s(&out),
        ],
        &t.join("check"),
    );
    expect(&o, 0, &["4 seeds, 4 pass"]);
}

#[test]
fn a_failure_folder_shows_the_model_and_the_rtl_of_every_diverging_signal() {
    let t = tmp("both");
    // the alternative RTL with a planted bug: at S10 (expand) the interval is one tick long
    // and CNTr is cleared instead of counted, so si and cnt_r diverge on the same edge
    let src = hdl().join("alt_sv");
    let dir = t.join("rtl");
    std::fs::create_dir_all(dir.join("idioms")).unwrap();
    for e in std::fs::read_dir(&src).unwrap().flatten() {
        if e.path().is_file() {
            let mut text = std::fs::read_to_string(e.path()).unwrap();
            if e.file_name() == "pmu_interval_adapt.sv" {
                let a = "          interval_d = longer_si;                  // S10";
                let b = "          cnt_r_d    = cnt_r_inc;                  // S9\n          fig17_o    = F17_S10_EXPAND;";
                assert!(text.contains(a) && text.contains(b));
                text = text
                    .replace(a, "          interval_d = longer_si + 16'd1;  // planted")
                    .replace(b, "          cnt_r_d    = 8'd0;  // planted\n          fig17_o    = F17_S10_EXPAND;");
            }
            std::fs::write(dir.join(e.file_name()), text).unwrap();
        }
    }
    let out = t.join("o");
    let o = regress(
        &[
            "--start-seed",
            "4",
            "--iterations",
            "4",
            "--directed",
            // each seed its own parameter set (no pool): two seeds of the planted bug differ
            "--param-sets",
            "0",
            "--dut",
            "verilator",
            "--rtl",
            s(&dir.join("pmu50_alt.f")),
        ],
        &out,
    );
    // seeds 4 and 7 fail (at different ticks, with different values): one signature
    let msg = expect(
        &o,
        1,
        &["fail dut-cnt_r+si-s10_expand_s25_no_change: 2 seed(s), smallest 4"],
    );
    assert_eq!(
        msg.matches("  fail dut-").count(),
        1,
        "one signature: {msg}"
    );
    let f = std::fs::read_dir(out.join("failures"))
        .unwrap()
        .flatten()
        .next()
        .unwrap()
        .path();
    let failure = std::fs::read_to_string(f.join("failure.txt")).unwrap();
    assert!(
        failure.contains("signals that differ at tick") && failure.contains("cnt_r, si"),
        "{failure}"
    );
    assert!(failure.contains("compare.vcd") && failure.contains("rtl.vcd"));
    // the RTL's own waveform: its signals by its names
    let rtl = std::fs::read_to_string(f.join("rtl.vcd")).unwrap();
    assert!(
        rtl.contains("$scope module u_adapt") && rtl.contains(" interval_q "),
        "rtl.vcd holds the RTL's own hierarchy"
    );
    // the model and the RTL of each diverging signal, side by side
    let w = pmu50_waves::reader::Waveform::open(f.join("compare.vcd")).unwrap();
    let names: Vec<String> = w.signals().iter().map(|x| x.path.clone()).collect();
    for n in [
        "model.si",
        "rtl.si",
        "model.cnt_r",
        "rtl.cnt_r",
        "inputs.ig",
    ] {
        assert!(names.contains(&n.to_string()), "{n}: {names:?}");
    }
    let gtkw = std::fs::read_to_string(f.join("compare.gtkw")).unwrap();
    // the divergence: the named marker's time (`*zoom -1 A ...`)
    let marker: u64 = gtkw
        .lines()
        .find(|l| l.starts_with('*'))
        .and_then(|l| l.split_whitespace().nth(2))
        .unwrap()
        .parse()
        .unwrap();
    let at = |name: &str| -> String {
        let c = w.changes(name).unwrap();
        c.iter()
            .rev()
            .find(|(t, _)| *t <= marker)
            .map(|(_, v)| v.to_string())
            .unwrap()
    };
    assert_ne!(
        at("model.si"),
        at("rtl.si"),
        "si differs at the failing tick"
    );
    assert_ne!(at("model.cnt_r"), at("rtl.cnt_r"));
    // the RTL's own trace holds the same divergence, at the same time: its interval register
    // reads what compare.vcd shows as the RTL's si (compare.vcd in us, rtl.vcd in ns)
    use pmu50_waves::{TimeUnit, Timescale};
    assert_eq!(w.timescale(), Some(Timescale::new(1, TimeUnit::Us)));
    let rv = pmu50_waves::reader::Waveform::open(f.join("rtl.vcd")).unwrap();
    assert_eq!(rv.timescale(), Some(Timescale::new(1, TimeUnit::Ns)));
    let q = rv
        .signals()
        .iter()
        .find(|x| x.path.ends_with("u_adapt.interval_q"))
        .unwrap()
        .path
        .clone();
    let own = rv
        .changes(&q)
        .unwrap()
        .iter()
        .rev()
        .find(|(t, _)| *t <= marker * 1000)
        .map(|(_, v)| v.to_string())
        .unwrap();
    assert_eq!(own, at("rtl.si"), "rtl.vcd's interval_q at the divergence");
    for line in [
        "[dumpfile] \"compare.vcd\"",
        "-si: model / RTL",
        "+{model si} model.si[15:0]",
        "+{RTL si} rtl.si[15:0]",
        "-cnt_r: model / RTL",
        "[markername] Adivergence at tick",
    ] {
        assert!(gtkw.contains(line), "{line}: {gtkw}");
    }
    let svg = std::fs::read_to_string(f.join("divergence.svg")).unwrap();
    for row in ["si (model)", "si (DUT)", "cnt_r (model)", "cnt_r (DUT)"] {
        assert!(svg.contains(row), "{row}");
    }
}
