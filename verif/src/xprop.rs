//! `pmu50 xprop --rtl LIST --out FILE.json [--iterations N] [--waivers FILE]`: X-propagation on
//! any RTL, two checks, each its own function:
//! - [`simulate`]: a 4-state simulation (Icarus, hdl/tb/tb_xprop.v) of N regression seeds
//!   (`pmu50 random --regress --seed K`, K = 1..N), every input X during reset and X at each tick
//!   the contract lets it float (docs/verification.md "X-propagation": `bus_wdata` while `bus_we`
//!   is 0; `cmp_s`, `cmp_c` while `smp & sr` is 0, the only ticks the latches take them, spec
//!   2.4); after reset, no contract output may be X or Z at any edge. The first X of each seed is
//!   a finding, with the output and the tick.
//! - [`structural`]: every flip-flop of the RTL is reset: yosys (`hierarchy -top pmu50; proc;
//!   flatten; opt`) lists the flip-flops without an asynchronous reset (nor a synchronous one by
//!   `rst_n`), each a finding named by its register (its instance path) and source line, unless a
//!   waiver says why it needs none.
//!
//! Both read the RTL through [`crate::rtl_reader`]: a Verilog RTL as Icarus and yosys read it, an
//! RTL with SystemVerilog files (or one they cannot read) lowered by slang to plain Verilog, one
//! lowering per parameter set, flip-flops kept with their reset or without, names and `src`
//! lines the RTL's: a flop left out of reset still starts X in the simulation and is named as
//! the RTL names it. An RTL no reader gives is not checked: the row is missing with the reason.
//!
//! The report ([`CheckReport`]) is sealed with its provenance; the sign-off row
//! (`signoff_xprop`) reads it.

use crate::check_report::{CheckReport, CheckRun};
use crate::filelist::FileList;
use crate::rtl_reader::{readers, RtlReader};
use crate::waiver::{Finding, SiteWaivers};
use std::io::Write;
use std::path::Path;
use std::process::Command;

pub const FORMAT: &str = "pmu50-xprop-1";
pub const FILE: &str = "xprop.json";
/// The bench (a variant of hdl/tb/tb_vectors.v with floating inputs), carried by the binary.
pub const TB_XPROP: &str = include_str!("../../hdl/tb/tb_xprop.v");

/// The vector file of regression seed `seed` (the uniform generator's scenario) into `path`;
/// its `// param` lines.
fn vectors(seed: u64, path: &Path) -> Result<Vec<(String, String)>, String> {
    let text = crate::gen::Stimulus::generate(seed, &crate::gen::Bias::uniform())
        .to_toml(&format!("regress_{seed}"));
    let toml_path = path.with_extension("toml");
    std::fs::write(&toml_path, text).map_err(|e| format!("{}: {e}", toml_path.display()))?;
    let sc = pmu50_testbench::scenario::Scenario::load(&toml_path).map_err(|e| e.to_string())?;
    let f = std::fs::File::create(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let mut vw =
        pmu50_testbench::observers::vectors::VectorWriter::new(std::io::BufWriter::new(f), &sc)
            .map_err(|e| e.to_string())?;
    pmu50_testbench::sim::run(
        &sc,
        pmu50_testbench::sim::SimOptions {
            fast_forward: false,
        },
        &mut [&mut vw],
    )
    .map_err(|e| e.to_string())?;
    vw.into_inner()
        .flush()
        .map_err(|e| format!("{}: {e}", path.display()))?;
    let head = std::fs::read_to_string(path).map_err(|e| e.to_string())?;
    Ok(head
        .lines()
        .take_while(|l| l.starts_with("//"))
        .filter_map(|l| l.strip_prefix("// param "))
        .filter_map(|l| l.split_once(' '))
        .map(|(n, v)| (n.to_string(), v.trim().to_string()))
        .collect())
}

const SIMULATION: &str = "iverilog 4-state simulation (hdl/tb/tb_xprop.v)";

/// The 4-state simulation of seeds 1..=n (module doc), with the first reader whose sources
/// Icarus compiles.
pub fn simulate(list: &FileList, n: u64, work: &Path) -> Result<CheckRun, String> {
    let tb = work.join("tb_xprop.v");
    std::fs::write(&tb, TB_XPROP).map_err(|e| e.to_string())?;
    let mut why = Vec::new();
    for r in readers(list) {
        match simulate_with(list, r.as_ref(), n, work, &tb)? {
            Ok(findings) => return Ok(CheckRun::ran(SIMULATION, r.name(), findings)),
            Err(e) => why.push(format!("{}: {e}", r.name())),
        }
    }
    Ok(CheckRun::not_run(
        SIMULATION,
        String::new(),
        format!(
            "Icarus Verilog cannot read this RTL ({}): not simulated in 4 states; an RTL it cannot read has no X-propagation evidence",
            why.join("; ")
        ),
    ))
}

/// The simulation of seeds 1..=n on the RTL as `reader` gives it; `Err` (inner): why Icarus
/// could not compile it.
fn simulate_with(
    list: &FileList,
    reader: &dyn RtlReader,
    n: u64,
    work: &Path,
    tb: &Path,
) -> Result<Result<Vec<Finding>, String>, String> {
    let mut findings = Vec::new();
    for seed in 1..=n {
        let vec = work.join(format!("seed{seed}.vec"));
        let params = vectors(seed, &vec)?;
        let src = match reader.sources(list, &params, "") {
            Ok(s) => s,
            Err(e) => return Ok(Err(e)),
        };
        let sim = work.join(format!("seed{seed}.vvp"));
        let mut c = Command::new("iverilog");
        c.args(["-g2012", "-o"]).arg(&sim).args(&src.iverilog_args);
        for (k, v) in &params {
            c.arg(format!("-Ptb_xprop.{k}={v}"));
        }
        c.arg(tb).args(&src.files);
        let out = c
            .output()
            .map_err(|e| format!("cannot run iverilog (Debian package iverilog): {e}"))?;
        if !out.status.success() {
            let log = String::from_utf8_lossy(&out.stderr);
            let first = log.lines().find(|l| !l.trim().is_empty()).unwrap_or("");
            return Ok(Err(first.trim().to_string()));
        }
        let out = Command::new("vvp")
            .arg("-n")
            .arg(&sim)
            .arg(format!("+vec={}", vec.display()))
            .output()
            .map_err(|e| format!("cannot run vvp: {e}"))?;
        let text = String::from_utf8_lossy(&out.stdout);
        if !text.contains("XPROP_DONE") {
            return Err(format!(
                "the X-propagation bench did not finish seed {seed}: {}",
                text.lines().last().unwrap_or("")
            ));
        }
        for l in text.lines().filter_map(|l| l.strip_prefix("XPROP_X ")) {
            // `tick=K out=NAME value=...`
            let field = |k: &str| {
                l.split_whitespace()
                    .find_map(|f| f.strip_prefix(k))
                    .unwrap_or("")
                    .to_string()
            };
            findings.push(Finding {
                rule: "x-output".into(),
                file: String::new(),
                line: 0,
                signal: field("out="),
                message: format!(
                    "seed {seed}: output {} is {} after edge {}",
                    field("out="),
                    field("value="),
                    field("tick=")
                ),
            });
        }
    }
    Ok(Ok(findings))
}

const STRUCTURAL: &str = "yosys: flip-flops without reset";

/// The flip-flops without reset (module doc), of the RTL as the first reader that gives it to
/// yosys gives it.
pub fn structural(list: &FileList, work: &Path) -> Result<CheckRun, String> {
    let mut why = Vec::new();
    for r in readers(list) {
        match flops_with(list, r.as_ref(), work)? {
            Ok(findings) => return Ok(CheckRun::ran(STRUCTURAL, r.name(), findings)),
            Err(e) => why.push(format!("{}: {e}", r.name())),
        }
    }
    Ok(CheckRun::not_run(
        STRUCTURAL,
        String::new(),
        format!(
            "yosys 0.23 cannot read this RTL ({}): its flip-flops are not checked",
            why.join("; ")
        ),
    ))
}

/// The flip-flops without reset of the RTL as `reader` gives it; `Err` (inner): why yosys could
/// not read it.
fn flops_with(
    list: &FileList,
    reader: &dyn RtlReader,
    work: &Path,
) -> Result<Result<Vec<Finding>, String>, String> {
    let read = match reader.sources(list, &[], "") {
        Ok(s) => s.yosys_read,
        Err(e) => return Ok(Err(e)),
    };
    let json = work.join("flops.json");
    let out = Command::new("yosys")
        .arg("-q")
        .arg("-p")
        .arg(format!(
            "{read}; hierarchy -top pmu50; proc; flatten; opt; write_json {}",
            json.display()
        ))
        .output()
        .map_err(|e| format!("cannot run yosys (Debian package yosys): {e}"))?;
    if !out.status.success() {
        let log = String::from_utf8_lossy(&out.stderr) + String::from_utf8_lossy(&out.stdout);
        let err = log
            .lines()
            .find(|l| l.contains("ERROR"))
            .unwrap_or("yosys failed")
            .trim()
            .to_string();
        return Ok(Err(err));
    }
    let v: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(&json).map_err(|e| format!("{}: {e}", json.display()))?,
    )
    .map_err(|e| format!("{}: {e}", json.display()))?;
    Ok(Ok(unreset_flops(&v)))
}

/// The flip-flop cells of yosys without an asynchronous reset. After `opt`, a register that
/// is cleared on a condition is a `$sdff` (a synchronous reset): it counts as reset only when
/// the condition is the reset port `rst_n`.
const NO_ASYNC_RESET: [&str; 5] = ["$dff", "$dffe", "$sdff", "$sdffe", "$sdffce"];

/// The flip-flops of a yosys JSON netlist without a reset (neither asynchronous nor by
/// `rst_n`), each by the register its Q drives (the netname holding its bits, a visible one
/// first) and the cell's `src` (file:line).
pub fn unreset_flops(v: &serde_json::Value) -> Vec<Finding> {
    let mut out = std::collections::BTreeSet::new();
    let Some(mods) = v.get("modules").and_then(|m| m.as_object()) else {
        return Vec::new();
    };
    for m in mods.values() {
        let nets = m.get("netnames").and_then(|n| n.as_object());
        let Some(cells) = m.get("cells").and_then(|c| c.as_object()) else {
            continue;
        };
        // the reset port's bit: a synchronous reset by it is a reset
        let rst_bit = nets
            .and_then(|n| n.get("rst_n"))
            .and_then(|d| d.pointer("/bits/0"))
            .cloned();
        for c in cells.values() {
            let ty = c.get("type").and_then(|t| t.as_str()).unwrap_or("");
            if !NO_ASYNC_RESET.contains(&ty) {
                continue;
            }
            if ty.starts_with("$sdff")
                && rst_bit.is_some()
                && c.pointer("/connections/SRST/0").cloned() == rst_bit
            {
                continue;
            }
            let q = c.pointer("/connections/Q").cloned().unwrap_or_default();
            let first = q.get(0).cloned().unwrap_or_default();
            let name = nets
                .and_then(|n| {
                    let mut names: Vec<(&String, bool)> = n
                        .iter()
                        .filter(|(_, d)| {
                            d.get("bits")
                                .and_then(|b| b.as_array())
                                .is_some_and(|b| b.contains(&first))
                        })
                        .map(|(k, d)| (k, d.get("hide_name").and_then(|h| h.as_u64()) == Some(1)))
                        .collect();
                    // the register itself (its bits are Q's), a visible name, the shortest
                    names.sort_by_key(|(k, hidden)| {
                        let exact = n[k.as_str()].get("bits") != Some(&q);
                        (exact, *hidden, k.len())
                    });
                    names.first().map(|(k, _)| k.to_string())
                })
                .unwrap_or_default();
            let src = c
                .pointer("/attributes/src")
                .and_then(|s| s.as_str())
                .unwrap_or("")
                .split('|')
                .next_back()
                .unwrap_or("")
                .to_string();
            let (file, line) = src
                .rsplit_once(':')
                .and_then(|(f, l)| Some((f.to_string(), l.split('.').next()?.parse().ok()?)))
                .unwrap_or_default();
            let name = name.trim_start_matches('\\').to_string();
            out.insert((
                file.clone(),
                line,
                name.clone(),
                q.as_array().map_or(0, Vec::len),
            ));
        }
    }
    out.into_iter()
        .map(|(file, line, name, bits)| Finding {
            rule: "no-reset".into(),
            message: format!(
                "flip-flop {name} ({bits} bit(s), {file}:{line}) has no reset: it starts X in silicon"
            ),
            file,
            line,
            signal: name,
        })
        .collect()
}

/// Both checks of `list`, with `waivers` applied.
pub fn run(
    list: &FileList,
    seeds: u64,
    waivers: Option<&SiteWaivers>,
) -> Result<CheckReport, String> {
    let work = tempfile::tempdir().map_err(|e| format!("a scratch folder: {e}"))?;
    let checks = vec![
        simulate(list, seeds, work.path())?,
        structural(list, work.path())?,
    ];
    Ok(CheckReport::new(FORMAT, list, Some(seeds), checks, waivers))
}
