//! The three samplers of the coverage model give the same numbers for the same stimulus.
//!
//! The stimulus is a fixed stream of splitmix64 draws turned into port inputs (`stimulus`
//! below; hdl/ffi/tests/coverage.c and python/tests/test_coverage.py draw the same). Its hits,
//! sampled by the Rust library (`Coverage::sample`), are stored in `coverage_stimulus.json`
//! beside this file; this test checks that
//! - the Rust library's hits are the stored ones (`PMU50_REGENERATE=1` rewrites the file after
//!   an intended change of the model: `PMU50_REGENERATE=1 cargo test -p pmu50-ffi --test coverage`);
//! - the C ABI called from Rust (`pmu50_coverage_step`) gives the same hits;
//! - the C program coverage.c, compiled against the static library and run, writes a
//!   `coverage.json` that `CoverageFile::read` accepts, with the same hits.
//!
//! python/tests/test_coverage.py checks `pmu50.Coverage` against the same stored file.

use pmu50_core::signals::regenerate;
use pmu50_core::{Inputs, Params, Pmu50};
use pmu50_coverage::db::CoverageFile;
use pmu50_coverage::{layout, model_id, Coverage, Edge};
use pmu50_ffi::coverage::*;
use pmu50_ffi::*;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Command;

const EDGES: usize = 20_000;
const GOLDEN: &str = "tests/coverage_stimulus.json";

/// The configuration of the stimulus: short windows and intervals, in ticks of 10 us.
fn params() -> Params {
    Params {
        pw: 1,
        pi: 2,
        ps: 1,
        si_max: 30,
        si_min: 10,
        t1: 10,
        t2: 5,
        cth: 2,
        smp_on: 3,
        ..Params::default()
    }
}

/// The shared stimulus: `n` inputs from splitmix64 draws starting at state 1.
fn stimulus(n: usize) -> Vec<Inputs> {
    let mut rng = pmu50_core::rng::SplitMix64(1);
    let (mut ig, mut fault, mut cs, mut cc) = (false, false, false, false);
    (0..n)
        .map(|_| {
            let r = rng.next();
            ig ^= (r & 0xFF) < 3;
            fault ^= (r >> 8) & 0x3F == 0;
            cs ^= (r >> 14) & 0x1F == 0;
            cc ^= (r >> 19) & 0x1F == 0;
            Inputs {
                ig,
                vs2_ok: !fault,
                cmp_s: cs,
                cmp_c: cc,
                bus_we: (r >> 24) & 0x1F == 0,
                bus_addr: ((r >> 29) % 24) as u8,
                bus_wdata: if (r >> 34) & 1 == 1 {
                    (r >> 40) % 64
                } else {
                    (r >> 40) % 1024
                } as u16,
            }
        })
        .collect()
}

fn rust_hits() -> Vec<u64> {
    let p = params();
    let mut core = Pmu50::new(p).unwrap();
    let mut cov = Coverage::new(&p, 10_000);
    for i in stimulus(EDGES) {
        let before = *core.regs();
        let pmu50_core::TracedStep {
            before: out,
            internals: n,
            ..
        } = core.step_traced(&i);
        cov.sample(&Edge {
            before: &before,
            after: core.regs(),
            out: &out,
            inputs: &i,
            internals: &n,
        });
    }
    cov.hits().to_vec()
}

/// `{name: hits}` of the bins hit at least once.
fn named(hits: &[u64]) -> BTreeMap<String, u64> {
    layout()
        .bins
        .iter()
        .zip(hits)
        .filter(|(_, &h)| h > 0)
        .map(|(b, &h)| (b.name.clone(), h))
        .collect()
}

fn golden_text(hits: &[u64]) -> String {
    let mut s = format!(
        "{{\"model\": \"{}\", \"edges\": {EDGES},\n \"hits\": {{\n",
        model_id(layout())
    );
    let m = named(hits);
    let lines: Vec<String> = m.iter().map(|(k, v)| format!("  \"{k}\": {v}")).collect();
    s.push_str(&lines.join(",\n"));
    s.push_str("\n }}\n");
    s
}

fn golden_path() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(GOLDEN)
}

#[test]
fn rust_sampling_of_the_stimulus_is_the_stored_file() {
    let hits = rust_hits();
    let want = golden_text(&hits);
    let path = golden_path();
    if regenerate(&path, &want) {
        return;
    }
    let have = std::fs::read_to_string(&path).unwrap_or_default();
    assert!(
        have == want,
        "{GOLDEN} is not the Rust sampling of the stimulus (the model or the sampler changed); \
         regenerate with PMU50_REGENERATE=1 cargo test -p pmu50-ffi --test coverage and review the diff"
    );
    // The stimulus reaches far into the model, so that agreement means something.
    let hit = named(&hits).len();
    assert!(hit > 150, "the stimulus hits {hit} bins");
}

#[test]
fn the_c_abi_called_from_rust_samples_the_same_hits() {
    let p: pmu50_params = params().into();
    // SAFETY: valid pointers; both handles are freed at the end.
    unsafe {
        let m = pmu50_new(&p);
        let c = pmu50_coverage_new(&p, 10_000);
        assert!(!m.is_null() && !c.is_null());
        let mut o = pmu50_outputs::default();
        for i in stimulus(EDGES) {
            assert_eq!(
                pmu50_coverage_step(c, m, &pmu50_inputs::from(i), &mut o),
                PMU50_OK
            );
        }
        let n = pmu50_coverage_bin_count();
        let mut hits = vec![0u64; n];
        for (k, h) in hits.iter_mut().enumerate() {
            assert_eq!(pmu50_coverage_hits(c, k, h), PMU50_OK);
        }
        assert_eq!(hits, rust_hits());
        assert_eq!(pmu50_coverage_edges(c), EDGES as u64);
        pmu50_coverage_free(c);
        pmu50_free(m);
    }
}

/// The static library built with this test: target/<profile>/deps/libpmu50_ffi.a first, where
/// `cargo test` builds it; target/<profile>/libpmu50_ffi.a is the copy of the last `cargo build`,
/// older than the test when the crate changed since.
fn static_lib() -> PathBuf {
    let exe = std::env::current_exe().unwrap();
    let deps = exe.parent().unwrap();
    for d in [deps, deps.parent().unwrap()] {
        let lib = d.join("libpmu50_ffi.a");
        if lib.exists() {
            return lib;
        }
    }
    panic!(
        "libpmu50_ffi.a not found next to {} (cargo builds it with the crate's staticlib type)",
        deps.display()
    );
}

#[test]
fn the_c_program_writes_a_coverage_file_with_the_same_hits() {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("ffi_coverage");
    std::fs::create_dir_all(&dir).unwrap();
    let exe = dir.join("coverage_c");
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let cc = std::env::var("CC").unwrap_or_else(|_| "cc".into());
    let build = Command::new(&cc)
        .args(["-std=c99", "-Wall", "-Wextra", "-pedantic", "-Werror", "-I"])
        .arg(root.join("include"))
        .arg(root.join("tests/coverage.c"))
        .arg(static_lib())
        .args(["-lpthread", "-ldl", "-lm", "-o"])
        .arg(&exe)
        .output()
        .unwrap_or_else(|e| panic!("cannot run the C compiler `{cc}`: {e}"));
    assert!(
        build.status.success(),
        "C build failed:\n{}",
        String::from_utf8_lossy(&build.stderr)
    );
    let out = dir.join("coverage.json");
    let _ = std::fs::remove_file(&out);
    let run = Command::new(&exe)
        .arg(&out)
        .arg(EDGES.to_string())
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&run.stdout);
    assert!(
        run.status.success() && stdout.contains("C coverage test: OK"),
        "{stdout}{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let f = CoverageFile::read(&out).expect("the C program's coverage.json reads back");
    assert_eq!(f.hits(), rust_hits());
    assert_eq!(f.runs.len(), 1);
    assert_eq!(
        (f.runs[0].id.as_str(), f.runs[0].verdict.as_str()),
        ("c/stimulus/1", "pass")
    );
}

/// `pmu50_last_error()` as text.
fn last_error() -> String {
    // SAFETY: a NUL-terminated string owned by the library (or NULL).
    unsafe {
        let p = pmu50_last_error();
        if p.is_null() {
            String::new()
        } else {
            std::ffi::CStr::from_ptr(p).to_string_lossy().into_owned()
        }
    }
}

#[test]
fn writes_never_replace_a_device_or_a_fifo_nor_a_merge_input() {
    let d = std::env::temp_dir().join(format!("pmu50-ffi-special-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    let fifo = d.join("fifo.json");
    assert!(Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .unwrap()
        .success());
    // A link to /dev/null: the old rename would have replaced the link only; the write is
    // refused either way, and /dev/null stays a device.
    let null = d.join("null.json");
    std::os::unix::fs::symlink("/dev/null", &null).unwrap();
    let cstr = |p: &Path| std::ffi::CString::new(p.to_str().unwrap()).unwrap();
    let p: pmu50_params = params().into();
    // SAFETY: valid pointers; the handle is freed at the end.
    unsafe {
        let c = pmu50_coverage_new(&p, 10_000);
        assert!(!c.is_null());
        let (id, pass) = (
            std::ffi::CString::new("dpi/1").unwrap(),
            std::ffi::CString::new("pass").unwrap(),
        );
        for (target, kind) in [(&fifo, "FIFO"), (&null, "character device"), (&d, "folder")] {
            assert_eq!(
                pmu50_coverage_write(c, cstr(target).as_ptr(), id.as_ptr(), pass.as_ptr()),
                PMU50_ERR_IO
            );
            let e = last_error();
            assert!(
                e.contains(&format!("is a {kind}, not a regular file")),
                "{e}"
            );
        }
        use std::os::unix::fs::FileTypeExt;
        assert!(std::fs::symlink_metadata(&fifo)
            .unwrap()
            .file_type()
            .is_fifo());
        assert!(std::fs::symlink_metadata(&null)
            .unwrap()
            .file_type()
            .is_symlink());
        // A merge whose output is one of its inputs is refused, and the input is kept.
        let one = d.join("one.json");
        assert_eq!(
            pmu50_coverage_write(c, cstr(&one).as_ptr(), id.as_ptr(), pass.as_ptr()),
            PMU50_OK
        );
        let before = std::fs::read(&one).unwrap();
        let other = d.join("two.json");
        let id2 = std::ffi::CString::new("dpi/2").unwrap();
        assert_eq!(
            pmu50_coverage_write(c, cstr(&other).as_ptr(), id2.as_ptr(), pass.as_ptr()),
            PMU50_OK
        );
        let paths = [cstr(&one), cstr(&other)];
        let ptrs: Vec<*const std::ffi::c_char> = paths.iter().map(|p| p.as_ptr()).collect();
        assert_eq!(
            pmu50_coverage_merge(ptrs.as_ptr(), 2, cstr(&one).as_ptr()),
            PMU50_ERR_COVERAGE
        );
        assert!(
            last_error().contains("the output is also input"),
            "{}",
            last_error()
        );
        assert_eq!(std::fs::read(&one).unwrap(), before);
        assert_eq!(
            pmu50_coverage_merge(ptrs.as_ptr(), 2, cstr(&d.join("all.json")).as_ptr()),
            PMU50_OK
        );
        pmu50_coverage_free(c);
    }
    std::fs::remove_dir_all(&d).unwrap();
}
