//! `pmu50 regress` on RTL that honours only the port contract (docs/hdl-guide.md, "Your RTL"):
//! other names inside, a top without parameters, a map for the deeper compare, and bad RTL
//! refused before any seed. Needs verilator and iverilog (`make deps`).

use crate::common;
use common::*;
use std::path::{Path, PathBuf};

fn hdl() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("hdl")
}

/// A copy of the twin in `dir` (hdl/pmu50.v, hdl/rtl/*.v, hdl/pmu50.f); `edit(file, text)`
/// changes a file's text on the way. Returns the file list.
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

/// The twin under a top `pmu50` without parameters: an RTL that fixes every value.
fn fixed_twin(dir: &Path) -> PathBuf {
    let list = twin_copy(dir, |f, t| {
        if f == "pmu50.v" {
            t.replace("module pmu50 #(", "module pmu50_twin #(")
        } else {
            t
        }
    });
    let ports: Vec<&str> = ["clk", "rst_n"]
        .into_iter()
        .chain(pmu50_core::signals::INPUTS.iter().map(|s| s.name))
        .chain(pmu50_core::signals::OUTPUTS.iter().map(|s| s.name))
        .collect();
    let width = |n: &str| -> String {
        let s = pmu50_core::pmu50::Structural {
            sync_depth: 2,
            cnt_width: 16,
        };
        let b = pmu50_core::signals::INPUTS
            .iter()
            .find(|x| x.name == n)
            .map(|x| x.bits(&s))
            .or_else(|| {
                pmu50_core::signals::OUTPUTS
                    .iter()
                    .find(|x| x.name == n)
                    .map(|x| x.bits(&s))
            })
            .unwrap_or(1);
        if b > 1 {
            format!("[{}:0] ", b - 1)
        } else {
            String::new()
        }
    };
    let decl: Vec<String> = ports
        .iter()
        .map(|p| {
            format!(
                "{} wire {}{p}",
                if pmu50_core::signals::OUTPUTS.iter().any(|x| x.name == *p) {
                    "output"
                } else {
                    "input"
                },
                width(p)
            )
        })
        .collect();
    let conn: Vec<String> = ports.iter().map(|p| format!(".{p}({p})")).collect();
    std::fs::write(
        dir.join("top.v"),
        format!(
            "module pmu50 (\n  {}\n);\n  pmu50_twin u_core ({});\nendmodule\n",
            decl.join(",\n  "),
            conn.join(", ")
        ),
    )
    .unwrap();
    let mut l = std::fs::read_to_string(&list).unwrap();
    l.push_str("top.v\n");
    std::fs::write(&list, l).unwrap();
    list
}

fn regress(args: &[&str], out: &Path) -> std::process::Output {
    let mut a = vec!["regress"];
    a.extend(args);
    a.extend(["--no-triage", "--out", s(out)]);
    pmu50(&a)
}

#[test]
fn a_twin_with_other_register_names_passes_on_its_ports() {
    let t = tmp("renamed");
    // (a `$` in the folder name breaks no build: the tools are run without a shell)
    let list = twin_copy(&t.join("my$rtl"), |f, text| {
        if f.ends_with("timing_generator_56.v") {
            text.replace("tmr", "timer_q")
        } else {
            text
        }
    });
    assert!(
        std::fs::read_to_string(t.join("my$rtl/rtl/timing_generator_56.v"))
            .unwrap()
            .contains("timer_q")
    );
    let o = regress(
        &["--iterations", "3", "--dut", "verilator", "--rtl", s(&list)],
        &t.join("o"),
    );
    expect(&o, 0, &["3 seeds, 3 pass"]);
}

/// A change of a twin file's text (file, text) -> text.
type Edit = Box<dyn Fn(&str, String) -> String>;

#[test]
fn bad_rtl_is_one_error_before_any_seed() {
    let t = tmp("bad");
    let cases: Vec<(&str, Edit, Vec<&str>)> = vec![
        (
            "width",
            Box::new(|f: &str, x: String| {
                if f == "pmu50.v" {
                    x.replace("output wire [15:0]      si,", "output wire [14:0]      si,")
                } else {
                    x
                }
            }),
            vec![
                "pmu50.v:",
                "port `si` of `pmu50` is 15 bit(s) wide",
                "needs 16",
            ],
        ),
        (
            "missing",
            Box::new(|f: &str, x: String| {
                if f == "pmu50.v" {
                    x.replace("    output wire             diag,\n", "")
                        .replace(".diag(diag)", ".diag()")
                } else {
                    x
                }
            }),
            vec!["lacks the contract port `diag`", "output, 1 bit(s)"],
        ),
        (
            "syntax",
            Box::new(|f: &str, x: String| {
                if f == "pmu50.v" {
                    x + "\nmodule broken(; endmodule\n"
                } else {
                    x
                }
            }),
            vec!["does not elaborate", "pmu50.v:"],
        ),
        (
            "top",
            Box::new(|f: &str, x: String| {
                if f == "pmu50.v" {
                    x.replace("module pmu50 #(", "module pmu5 #(")
                } else {
                    x
                }
            }),
            vec!["no module `pmu50`", "pmu5"],
        ),
    ];
    for (name, edit, want) in cases {
        let list = twin_copy(&t.join(name), edit);
        for dut in ["verilator", "icarus"] {
            let out = t.join(format!("o_{name}_{dut}"));
            let o = regress(
                &["--iterations", "5", "--dut", dut, "--rtl", s(&list)],
                &out,
            );
            let msg = expect(&o, 2, &want);
            assert_eq!(
                msg.matches("error:").count(),
                1,
                "{name} {dut}: one error: {msg}"
            );
            assert!(
                !out.join("results.jsonl").exists(),
                "{name} {dut}: no seed ran"
            );
        }
    }
}

#[test]
fn a_top_without_parameters_fixes_its_values_and_every_seed_keeps_them() {
    let t = tmp("fixed");
    let list = fixed_twin(&t.join("rtl"));
    let o = pmu50(&["rtl-info", "--rtl", s(&list)]);
    let info: serde_json::Value =
        serde_json::from_str(&String::from_utf8_lossy(&o.stdout)).unwrap();
    assert_eq!(info["parameters"].as_array().unwrap().len(), 0);
    assert_eq!(info["fixed"]["SI_MAX"], 660);
    assert_eq!(info["fixed"]["CNT_W"], 16);
    let out = t.join("o");
    let o = regress(
        &[
            "--iterations",
            "4",
            "--directed",
            "--dut",
            "verilator",
            "--rtl",
            s(&list),
        ],
        &out,
    );
    expect(
        &o,
        0,
        &[
            "4 seeds, 4 pass",
            "the RTL fixes SYNC_DEPTH=2, CNT_W=16",
            "knobs not drawn",
            "XLong",
        ],
    );
    let spec: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("regress.json")).unwrap()).unwrap();
    assert_eq!(spec["fixed"]["values"].as_array().unwrap().len(), 12);
    let report = std::fs::read_to_string(out.join("report.html")).unwrap();
    assert!(
        report.contains("knobs not drawn") && report.contains("SI_MAX=660"),
        "the report says what is fixed and not drawn"
    );
    // every seed's scenario has the fixed values
    for seed in 1..=4 {
        let sc = pmu50_verif::gen::Stimulus::generate(
            seed,
            &pmu50_verif::gen::Bias::uniform()
                .fixing(&serde_json::from_value(spec["fixed"].clone()).unwrap()),
        );
        assert_eq!(sc.params, pmu50_core::Params::default(), "seed {seed}");
    }
    // a pin that contradicts the RTL is refused
    let o = regress(
        &[
            "--iterations",
            "2",
            "--cnt-width",
            "8",
            "--dut",
            "verilator",
            "--rtl",
            s(&list),
        ],
        &t.join("o2"),
    );
    expect(&o, 2, &["--cnt-width 8: the RTL fixes CNT_W = 16"]);
    // Icarus: the bench instantiates the top without parameters
    let o = regress(
        &["--iterations", "2", "--dut", "icarus", "--rtl", s(&list)],
        &t.join("o3"),
    );
    expect(&o, 0, &["2 seeds, 2 pass"]);
}

#[test]
fn a_map_compares_registers_and_refuses_names_that_do_not_exist() {
    let t = tmp("map");
    // rtl-map proposes the twin's own map
    let o = pmu50(&["rtl-map", "--rtl", "hdl/pmu50.f"]);
    let proposed = expect(&o, 0, &["[registers]"]);
    let shipped = std::fs::read_to_string(hdl().join("pmu50.map.toml")).unwrap();
    let entries = |x: &str| -> Vec<String> {
        x.lines()
            .filter(|l| l.contains(" = \"pmu50."))
            .map(|l| l.split("  #").next().unwrap().trim().to_string())
            .collect()
    };
    assert_eq!(entries(&proposed), entries(&shipped));
    assert_eq!(
        entries(&shipped).len(),
        pmu50_core::signals::N_REGISTERS + pmu50_core::signals::N_INTERNALS
    );
    // a mapped name that does not exist: refused at start with the closest names
    let bad = write(
        &t,
        "bad.toml",
        shipped.replace(
            "\"pmu50.timing_generator.tmr\"",
            "\"pmu50.timing_generator.tmrr\"",
        ),
    );
    let o = regress(
        &["--iterations", "2", "--dut", "verilator", "--map", s(&bad)],
        &t.join("o1"),
    );
    expect(
        &o,
        2,
        &[
            "bad.toml:",
            "`timing_generator.tmr` = `pmu50.timing_generator.tmrr`",
            "closest: pmu50.timing_generator.tmr",
        ],
    );
    let bad = write(
        &t,
        "bad2.toml",
        "[registers]\n\"timing_generator.timer\" = \"pmu50.x\"\n",
    );
    expect(
        &regress(
            &["--iterations", "2", "--dut", "verilator", "--map", s(&bad)],
            &t.join("o2"),
        ),
        2,
        &["bad2.toml:2: `timing_generator.timer` is not a model register"],
    );
    // a bug that shows in a register before any port: the map sees it at the register
    let list = twin_copy(&t.join("mut"), |f, x| {
        if f.ends_with("timing_generator_56.v") {
            format!("`define MUT_KON_NO_RESTART\n{x}")
        } else {
            x
        }
    });
    // (triaged: the failures are shrunk into failures/<signature>/)
    let out = t.join("o3");
    let o = pmu50(&[
        "regress",
        "--out",
        s(&out),
        "--iterations",
        "6",
        "--dut",
        "verilator",
        "--rtl",
        s(&list),
        "--map",
        s(&hdl().join("pmu50.map.toml")),
    ]);
    expect(&o, 1, &["fail"]);
    let results = std::fs::read_to_string(out.join("results.jsonl")).unwrap();
    assert!(
        results.contains("pmu50.timing_generator.tmr"),
        "the first divergence is the mapped timer register: {results}"
    );
    // every failing seed's line carries the command that opens GTKWave on its signature's
    // repro, whose files exist (run in the regression folder); passing lines carry none
    let mut failing = 0;
    for line in results.lines() {
        let v: serde_json::Value = serde_json::from_str(line).unwrap();
        if v["verdict"] == "fail" {
            failing += 1;
            let view = v["view"]
                .as_str()
                .expect("a failing seed's line has `view`");
            let words: Vec<&str> = view.split(' ').collect();
            assert_eq!(words.len(), 3, "{view}");
            assert_eq!(words[0], "gtkwave");
            assert!(words[1].ends_with("/repro.vcd") && words[2].ends_with("/repro.gtkw"));
            for f in &words[1..] {
                assert!(out.join(f).is_file(), "{view}: {f} missing");
            }
        } else {
            assert!(v.get("view").is_none(), "{line}");
        }
    }
    assert!(failing > 0);
}

#[test]
fn an_edited_include_is_built_again() {
    let t = tmp("include");
    let list = twin_copy(&t.join("rtl"), |f, x| {
        if f == "pmu50.v" {
            x.replace(
                "`default_nettype none\n",
                "`default_nettype none\n`include \"extra.vh\"\n",
            )
        } else {
            x
        }
    });
    let inc = write(&t.join("rtl"), "extra.vh", "// nothing yet\n");
    for dut in ["verilator", "icarus"] {
        std::fs::write(&inc, "// nothing yet\n").unwrap();
        expect(
            &regress(
                &["--iterations", "1", "--dut", dut, "--rtl", s(&list)],
                &t.join(format!("a_{dut}")),
            ),
            0,
            &["1 seeds, 1 pass"],
        );
        // the included file now stops the simulation at the first key-on: the cached build is stale
        std::fs::write(&inc, "module extra_stop(input wire clk, input wire sig); always @(posedge clk) if (sig) $fatal(1, \"planted in the include\"); endmodule\n").unwrap();
        let mut top = std::fs::read_to_string(t.join("rtl/pmu50.v")).unwrap();
        if !top.contains("extra_stop") {
            top = top.replace(
                "endmodule\n\n`default_nettype wire",
                "    extra_stop u_stop (.clk(clk), .sig(sig));\nendmodule\n\n`default_nettype wire",
            );
            std::fs::write(t.join("rtl/pmu50.v"), top).unwrap();
        }
        let o = regress(
            &["--iterations", "1", "--dut", dut, "--rtl", s(&list)],
            &t.join(format!("b_{dut}")),
        );
        expect(&o, 1, &["1 fail"]);
        std::fs::write(
            t.join("rtl/pmu50.v"),
            std::fs::read_to_string(t.join("rtl/pmu50.v"))
                .unwrap()
                .replace("    extra_stop u_stop (.clk(clk), .sig(sig));\n", ""),
        )
        .unwrap();
    }
}

#[test]
fn what_a_correct_rtl_prints_is_never_a_verdict() {
    let t = tmp("print");
    // a correct RTL that prints lines like the bench's verdicts, every tick of the key on
    let list = twin_copy(&t.join("rtl"), |f, x| {
        if f == "pmu50.v" {
            x.replace("endmodule\n\n`default_nettype wire", "    always @(posedge clk) if (sig) $display(\"MISMATCH tick=1 signal=sig expected=0 got=1\");\nendmodule\n\n`default_nettype wire")
        } else {
            x
        }
    });
    for dut in ["icarus", "verilator"] {
        let o = regress(
            &["--iterations", "2", "--dut", dut, "--rtl", s(&list)],
            &t.join(format!("o_{dut}")),
        );
        expect(&o, 0, &["2 seeds, 2 pass"]);
    }
}

#[test]
fn an_interrupted_regression_leaves_no_process_and_no_scratch() {
    let t = tmp("interrupt");
    let scratch = t.join("tmp");
    std::fs::create_dir_all(&scratch).unwrap();
    // an RTL that hangs at the first key-on edge
    let list = twin_copy(&t.join("rtl"), |f, x| {
        if f == "pmu50.v" {
            x.replace("endmodule\n\n`default_nettype wire", "    always @(posedge clk) if (ig) while (1) begin end  // planted hang\nendmodule\n\n`default_nettype wire")
        } else {
            x
        }
    });
    let mut child = std::process::Command::new(BIN)
        .args([
            "regress",
            "--iterations",
            "4",
            "--jobs",
            "1",
            "--dut",
            "icarus",
            "--timeout",
            "600",
            "--no-triage",
            "--rtl",
            s(&list),
            "--out",
            s(&t.join("o")),
        ])
        .env("TMPDIR", &scratch)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    let vvp_running = || -> bool {
        std::fs::read_dir("/proc")
            .unwrap()
            .filter_map(|e| e.ok())
            .any(|e| {
                let cmd = std::fs::read(e.path().join("cmdline")).unwrap_or_default();
                let cmd = String::from_utf8_lossy(&cmd);
                cmd.starts_with("vvp") && cmd.contains(s(&scratch))
            })
    };
    let start = std::time::Instant::now();
    while !vvp_running() {
        assert!(
            start.elapsed().as_secs() < 120,
            "the simulation never started"
        );
        std::thread::sleep(std::time::Duration::from_millis(100));
    }
    std::thread::sleep(std::time::Duration::from_millis(300));
    // SAFETY: kill(2) on the child's pid.
    unsafe { libc::kill(child.id() as i32, libc::SIGTERM) };
    assert_eq!(child.wait().unwrap().code(), Some(143));
    std::thread::sleep(std::time::Duration::from_millis(300));
    assert!(
        !vvp_running(),
        "the hanging simulation was killed with the regression"
    );
    let left: Vec<String> = std::fs::read_dir(&scratch)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert!(left.is_empty(), "the scratch folders are removed: {left:?}");
}

#[test]
fn a_second_run_takes_every_build_from_the_cache() {
    let t = tmp("cache");
    let cache = t.join("cache");
    let list = fixed_twin(&t.join("rtl"));
    let run = |exe: &Path, out: &str| {
        let o = std::process::Command::new(exe)
            .args([
                "regress",
                "--iterations",
                "2",
                "--dut",
                "verilator",
                "--no-triage",
                "--rtl",
                s(&list),
                "--out",
                s(&t.join(out)),
            ])
            .env("PMU50_CACHE_DIR", &cache)
            .output()
            .unwrap();
        expect(&o, 0, &["2 seeds, 2 pass"]);
    };
    let libs = || -> Vec<(PathBuf, std::time::SystemTime)> {
        let mut v = Vec::new();
        for d in std::fs::read_dir(cache.join("verilator"))
            .unwrap()
            .flatten()
        {
            for b in std::fs::read_dir(d.path()).into_iter().flatten().flatten() {
                let lib = b.path().join("libpmu50_dut.so");
                if let Ok(m) = std::fs::metadata(&lib) {
                    v.push((lib, m.modified().unwrap()));
                }
            }
        }
        v.sort();
        v
    };
    run(Path::new(BIN), "a");
    let first = libs();
    assert!(
        !first.is_empty(),
        "the run built its library into PMU50_CACHE_DIR"
    );
    // the second run by a copy under another name: its DUT workers are that copy
    std::fs::create_dir_all(t.join("bin")).unwrap();
    let copy = t.join("bin/pmu50-copy");
    std::fs::copy(BIN, &copy).unwrap();
    run(&copy, "b");
    assert_eq!(libs(), first, "the second run built nothing");
}
