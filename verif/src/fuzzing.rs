//! Body of the regression-folder fuzz target (`fuzz/fuzz_targets/regress_folder.rs`), in the
//! library so that the cargo-fuzz target and the stable replay test (`tests/fuzz_replay.rs`) run
//! exactly the same code. It returns normally for every input; it panics only on a bug.

/// File names the regression-folder body gives its parts; every error message names one.
pub const FOLDER_FILES: [&str; 5] = [
    "a/regress.json",
    "a/results.jsonl",
    "b/regress.json",
    "b/results.jsonl",
    "c/coverage.json",
];

/// Reads `data` as the files of two regression folders and a coverage file, separated by NUL
/// bytes ([`FOLDER_FILES`], in that order; missing parts are empty): each `regress.json` as
/// `--resume` reads it, each `results.jsonl` against its folder's seed range (or seeds 1-100),
/// the two folders planned as one merge, and the coverage file as a merge input.
///
/// # Panics
/// When a reader panics; when an error message does not name its file; when a checked
/// `regress.json` does not print and parse back to the same run; when an accepted result lies
/// outside its range, a torn line is counted, or a seed is accepted twice; when a merge plan
/// does not cover both folders' seeds.
pub fn regress_folder(data: &[u8]) {
    use crate::{folder, merge};
    use std::path::Path;
    let mut parts: Vec<&[u8]> = data.splitn(5, |b| *b == 0).collect();
    parts.resize(5, &[]);
    let named = |e: &dyn std::fmt::Display, k: usize| {
        let msg = e.to_string();
        assert!(
            msg.contains(FOLDER_FILES[k]),
            "error message does not name {}: {msg}",
            FOLDER_FILES[k]
        );
    };
    let mut specs = Vec::new();
    for (k, part) in [(0usize, parts[0]), (2, parts[2])] {
        let text = String::from_utf8_lossy(part);
        let spec = match folder::parse_spec(&text, Path::new(FOLDER_FILES[k])) {
            Ok(s) => {
                let again = serde_json::to_string_pretty(&s).expect("a run prints");
                assert_eq!(
                    folder::parse_spec(&again, Path::new(FOLDER_FILES[k]))
                        .ok()
                        .as_ref(),
                    Some(&s),
                    "regress.json does not parse back: {again}"
                );
                assert!(s.seeds().end - s.seeds().start <= folder::MAX_SEEDS);
                Some(s)
            }
            Err(e) => {
                named(&e, k);
                None
            }
        };
        let range = spec.as_ref().map_or(1..101, |s| s.seeds());
        let mut hits = vec![0u64; pmu50_coverage::layout().bins.len()];
        let path = Path::new(FOLDER_FILES[k + 1]);
        match folder::scan_reader(parts[k + 1], path, 0, &range, &mut hits, &mut |r, e| {
            assert!(range.contains(&r.seed) && e.seed == r.seed)
        }) {
            Ok(s) => {
                assert!(s.complete_len <= parts[k + 1].len() as u64);
                let torn = &parts[k + 1][s.complete_len as usize..];
                assert!(!torn.contains(&b'\n'), "a complete line was left out");
                let n = s.entries.len();
                if let Ok(store) = folder::Store::new(vec![path.to_path_buf()], s.entries) {
                    assert_eq!(store.len(), n);
                    assert!(
                        store.entries.windows(2).all(|w| w[0].seed < w[1].seed),
                        "a seed accepted twice"
                    );
                }
            }
            Err(e) => named(&e, k + 1),
        }
        if let Some(s) = spec {
            specs.push((std::path::PathBuf::from(FOLDER_FILES[k]), s));
        }
    }
    if specs.len() == 2 {
        if let Ok(whole) = merge::plan(&specs) {
            let w = whole.seeds();
            for (_, s) in &specs {
                let (a, b) = (s.start_seed, s.start_seed + s.iterations);
                assert!(
                    w.start <= a && b <= w.end,
                    "the merged range {w:?} leaves out seeds {a}..{b}"
                );
            }
        }
    }
    if let Err(e) =
        pmu50_coverage::CoverageFile::parse(&String::from_utf8_lossy(parts[4]), FOLDER_FILES[4])
    {
        named(&e, 4);
    }
}

/// File names of the sign-off folder body, in the order of its NUL-separated parts.
pub const SIGNOFF_FILES: [&str; 8] = [
    "regress.json",
    "results.jsonl",
    "coverage.json",
    "code/summary.json",
    "coverage-proofs.json",
    "formal.json",
    "lint.json",
    "xprop.json",
];

/// The thresholds the sign-off folder body applies: a folder of a few seeds can meet them, and
/// the soak row reads an empty history.
pub const SIGNOFF_THRESHOLDS: &str = "[thresholds]\nfunctional = 10\nsoak_days = 0\n";

/// The inputs of a sign-off row (indices into [`SIGNOFF_FILES`]) besides `regress.json`.
fn row_inputs(row: &str) -> &'static [usize] {
    match row {
        r if r.starts_with("functional") => &[1, 2],
        r if r.starts_with("bins") => &[2, 4],
        r if r.starts_with("code") => &[3, 4],
        r if r.starts_with("properties") => &[5],
        r if r.starts_with("lint") => &[6],
        r if r.starts_with("X-propagation") => &[7],
        r if r.starts_with("seeds") => &[1],
        _ => &[],
    }
}

/// Writes `data` as the files of a sign-off folder ([`SIGNOFF_FILES`], NUL-separated; an empty
/// part is an absent file) into a fresh temporary folder and computes its sign-off table with
/// [`SIGNOFF_THRESHOLDS`] and an empty history.
///
/// # Panics
/// When the sign-off panics, returns an error with an empty message, or meets a row from an
/// input that is not as its maker wrote it: every sealed input the row reads (and
/// `regress.json`) must open with its digest and provenance intact, and `results.jsonl` and
/// `coverage.json` must have the digests `regress.json` seals. The fuzzer cannot forge SHA-256,
/// so a mutated input can only keep a row met by leaving the file's content as it was.
pub fn signoff_folder(data: &[u8]) {
    use std::path::Path;
    use std::sync::atomic::{AtomicU64, Ordering};
    static RUN: AtomicU64 = AtomicU64::new(0);
    let mut parts: Vec<&[u8]> = data.splitn(SIGNOFF_FILES.len(), |b| *b == 0).collect();
    parts.resize(SIGNOFF_FILES.len(), &[]);
    let dir = std::env::temp_dir().join(format!(
        "pmu50-fuzz-signoff-{}-{}",
        std::process::id(),
        RUN.fetch_add(1, Ordering::Relaxed)
    ));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(dir.join("code")).expect("a temporary folder");
    for (name, part) in SIGNOFF_FILES.iter().zip(&parts) {
        if !part.is_empty() {
            std::fs::write(dir.join(name), part).expect("a temporary file");
        }
    }
    let th = dir.join("thresholds.toml");
    std::fs::write(&th, SIGNOFF_THRESHOLDS).expect("a temporary file");
    let history = crate::history::Location::Sqlite(dir.join("history.sqlite"));
    let result = crate::signoff::run(&dir, Some(&th), Some(&history));
    let sealed_ok = |k: usize| -> bool {
        let text = String::from_utf8_lossy(parts[k]);
        crate::evidence::open_sealed(Path::new(SIGNOFF_FILES[k]), &text, "").is_ok()
    };
    let digest_ok = |k: usize| -> bool {
        let text = String::from_utf8_lossy(parts[0]);
        let Ok(sf) = crate::evidence::parse_spec_file(&text, Path::new(SIGNOFF_FILES[0])) else {
            return false;
        };
        sf.files.get(SIGNOFF_FILES[k]).map(String::as_str)
            == Some(&format!("sha256:{}", crate::digest::sha256_hex(parts[k])))
    };
    match &result {
        Err(e) => assert!(!e.to_string().trim().is_empty(), "an empty error message"),
        Ok((so, _)) => {
            for row in so.rows.iter().filter(|r| r.met) {
                let inputs = row_inputs(row.name);
                if inputs.is_empty() {
                    continue;
                }
                assert!(
                    sealed_ok(0),
                    "row {:?} met with regress.json not as the run wrote it",
                    row.name
                );
                for &k in inputs {
                    let ok = if k == 1 || k == 2 {
                        digest_ok(k)
                    } else {
                        sealed_ok(k)
                    };
                    assert!(
                        ok,
                        "row {:?} met from {} not as its maker wrote it",
                        row.name, SIGNOFF_FILES[k]
                    );
                }
            }
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}
