//! The shipped simulator as whole child processes: `pmu50 run SCENARIO --trace all` as a user
//! runs it, and the park figures (this bench run again as `--park-child`, the simulator with
//! fast-forward, for its CPU time and peak memory).

use crate::checks::var_paths;
use crate::harness::{cpu_now, fmt_bytes, rusage, Meas, Round};
use crate::stim::{scenario_of, Stim};
use pmu50_testbench::scenario::Scenario;
use pmu50_testbench::sim::{run, SimOptions};
use std::path::Path;
use std::process::Command;

/// Rounds of `pmu50 run SCENARIO --trace all` as a user runs it (`target/release/pmu50`, built
/// by benches/compare.sh): the whole child process's CPU time (start, scenario, environment
/// models, the VCD of every signal with the analog reals, its .gtkw), for the stimulus's ticks.
pub fn pmu50_run<'a>(st: &'a Stim, dir: &Path) -> Result<Round<'a>, String> {
    let bin = Path::new(env!("CARGO_MANIFEST_DIR")).join("target/release/pmu50");
    let sc = scenario_of(st, dir);
    let out = dir.join("pmu50_run");
    let vcd = out.join(format!("{}.vcd", st.name));
    let mut note: Option<String> = None;
    Ok(Box::new(move || {
        let (c0, _) = rusage(libc::RUSAGE_CHILDREN);
        let o = Command::new(&bin)
            .arg("run")
            .arg(&sc)
            .arg("--out-dir")
            .arg(&out)
            .args(["--trace", "all"])
            .output()
            .map_err(|e| format!("{}: {e}", bin.display()))?;
        let (c1, _) = rusage(libc::RUSAGE_CHILDREN);
        if !o.status.success() {
            return Err(format!(
                "pmu50 run {} failed: {}",
                sc.display(),
                String::from_utf8_lossy(&o.stderr)
            ));
        }
        let n = note.get_or_insert_with(|| {
            let bytes = std::fs::metadata(&vcd).map(|m| m.len()).unwrap_or(0);
            let vars = std::fs::read(&vcd)
                .map(|b| var_paths(&b).len())
                .unwrap_or(0);
            format!(
                "whole process; {vars} $var lines with the env reals, {}",
                fmt_bytes(bytes)
            )
        });
        Ok(Meas {
            ticks: st.inputs.len() as u64,
            cpu: c1 - c0,
            checksum: None,
            note: n.clone(),
        })
    }))
}

/// Child process: a parked car for `secs` seconds through the simulator with fast-forward, or
/// (`secs` = 0) the scenario file `file`.
pub fn park_child(secs: u64, file: Option<&str>) {
    let sc = match file {
        Some(f) => Scenario::load(Path::new(f)).unwrap_or_else(|e| panic!("{e}")),
        None => {
            let text = format!(
                "name = \"park_{secs}s\"\ndescription = \"parked: key off, motor still\"\nduration = \"{secs} s\"\n\n[motor]\nstart_deg = 37.0\nsegments = [ {{ kind = \"hold\", duration = \"{secs} s\" }} ]\n"
            );
            Scenario::parse(&text, "park.toml", "park", Path::new("park.toml"))
                .unwrap_or_else(|e| panic!("{e}"))
        }
    };
    let t0 = cpu_now();
    let r = run(&sc, SimOptions { fast_forward: true }, &mut []).unwrap_or_else(|e| panic!("{e}"));
    let cpu = cpu_now() - t0;
    let (_, rss) = rusage(libc::RUSAGE_SELF);
    println!(
        "park cpu_s={cpu:.9} maxrss_kib={rss} ticks={} evaluated={} pulses={}",
        r.ticks,
        r.evaluated_ticks,
        r.pulses.len()
    );
}

/// (CPU seconds, peak MiB, ticks, evaluated ticks) of a park child.
pub fn park(args: &[&str]) -> Result<(f64, f64, f64, f64), String> {
    let exe = std::env::current_exe().map_err(|e| e.to_string())?;
    let out = Command::new(exe)
        .arg("--park-child")
        .args(args)
        .output()
        .map_err(|e| e.to_string())?;
    let text = String::from_utf8_lossy(&out.stdout).to_string();
    if !out.status.success() {
        return Err(format!(
            "park {args:?} failed: {text}{}",
            String::from_utf8_lossy(&out.stderr)
        ));
    }
    let field = |k: &str| {
        text.split_whitespace()
            .find_map(|w| w.strip_prefix(k))
            .and_then(|v| v.parse::<f64>().ok())
            .ok_or_else(|| format!("park: no `{k}` in `{text}`"))
    };
    Ok((
        field("cpu_s=")?,
        field("maxrss_kib=")? / 1024.0,
        field("ticks=")?,
        field("evaluated=")?,
    ))
}
