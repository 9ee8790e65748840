//! Formal witnesses replayed on the model. hdl/formal/coverage.py turns the trace of a check
//! into a vector file (inputs, the parameter set, `// bin NAME`): a cover's witness, or the
//! counterexample of a bin declared unreachable whose proof failed. Each must hit its bin in the
//! model's sampler too (the monitor and the sampler agree: tests/coverage_monitor.rs), and a
//! witness of a bin declared unreachable is a wrong declaration: the test fails, naming it.
//!
//! The committed witnesses (tests/witness/) are the port-level bins' covers on the small set;
//! `COVERAGE_WITNESS_DIR` adds a folder of them (`make coverage-proofs` passes the run's).

use pmu50_core::{Inputs, Params, Pmu50};
use pmu50_coverage::{layout, Coverage};
use std::path::{Path, PathBuf};

struct Witness {
    bin: String,
    params: Params,
    rows: Vec<[u32; 7]>,
}

fn read(path: &Path) -> Witness {
    let text = std::fs::read_to_string(path).unwrap();
    let mut w = Witness {
        bin: String::new(),
        params: Params::DEFAULT,
        rows: Vec::new(),
    };
    for line in text.lines() {
        if let Some(b) = line.strip_prefix("// bin ") {
            w.bin = b.trim().to_string();
        } else if let Some(rest) = line.strip_prefix("// param ") {
            let mut f = rest.split_whitespace();
            let k = f.next().unwrap();
            let v = f.next().unwrap().parse().unwrap();
            w.params.set_hdl_parameter(k, v).unwrap();
        } else if !line.starts_with("//") && !line.trim().is_empty() {
            let f: Vec<u32> = line
                .split_whitespace()
                .take(7)
                .map(|x| u32::from_str_radix(x, 16).unwrap())
                .collect();
            assert_eq!(f.len(), 7, "{}: a row of 7 inputs", path.display());
            w.rows.push([f[0], f[1], f[2], f[3], f[4], f[5], f[6]]);
        }
    }
    assert!(!w.bin.is_empty(), "{}: no `// bin` line", path.display());
    w
}

/// The hit counts after replaying the witness.
fn replay(w: &Witness) -> Vec<u64> {
    let mut core = Pmu50::new(w.params).unwrap();
    let mut cov = Coverage::new(&w.params, 10_000);
    for r in &w.rows {
        let i = Inputs {
            ig: r[0] & 1 == 1,
            vs2_ok: r[1] & 1 == 1,
            cmp_s: r[2] & 1 == 1,
            cmp_c: r[3] & 1 == 1,
            bus_we: r[4] & 1 == 1,
            bus_addr: r[5] as u8,
            bus_wdata: r[6] as u16,
        };
        cov.step(&mut core, &i);
    }
    cov.hits().to_vec()
}

fn files() -> Vec<PathBuf> {
    let mut dirs = vec![Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/witness")];
    if let Some(d) = std::env::var_os("COVERAGE_WITNESS_DIR") {
        dirs.push(PathBuf::from(d));
    }
    let mut out = Vec::new();
    for d in dirs {
        if let Ok(rd) = std::fs::read_dir(&d) {
            out.extend(
                rd.map(|e| e.unwrap().path())
                    .filter(|p| p.extension().is_some_and(|x| x == "vec")),
            );
        }
    }
    out.sort();
    out
}

#[test]
fn every_witness_hits_its_bin_and_no_bin_declared_unreachable_has_one() {
    let files = files();
    assert!(
        files.len() >= 4,
        "the committed witnesses of the port-level bins are missing"
    );
    let l = layout();
    let mut wrong = Vec::new();
    for f in &files {
        let w = read(f);
        let i = l
            .bins
            .iter()
            .position(|b| b.name == w.bin)
            .unwrap_or_else(|| panic!("{}: no bin {}", f.display(), w.bin));
        let hits = replay(&w);
        assert!(
            hits[i] > 0,
            "{}: the model does not hit {} on the formal witness ({} ticks)",
            f.display(),
            w.bin,
            w.rows.len()
        );
        if let Some(reason) = l.bins[i].unreachable {
            wrong.push(format!(
                "{} is declared unreachable (\"{reason}\") but {} hits it",
                w.bin,
                f.display()
            ));
        }
    }
    assert!(
        wrong.is_empty(),
        "wrong declarations:\n{}",
        wrong.join("\n")
    );
}

#[test]
fn the_committed_witnesses_close_the_port_level_bins() {
    let l = layout();
    let names: Vec<String> = files().iter().map(|f| read(f).bin).collect();
    for b in l
        .bins
        .iter()
        .filter(|b| b.port_only && b.unreachable.is_none())
    {
        assert!(names.contains(&b.name), "no witness of {}", b.name);
    }
}
