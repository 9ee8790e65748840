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
