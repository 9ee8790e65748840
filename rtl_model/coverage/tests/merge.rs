//! coverage.json as a merge format: commutative, associative, refuses a run counted twice and
//! a corrupt or foreign file, and never returns half a merge.

use pmu50_coverage::db::{merge, CoverageFile, DbError, RunRecord};
use pmu50_coverage::layout;
use proptest::prelude::*;

fn file(hits: &[(usize, u64)], runs: &[&str]) -> CoverageFile {
    let mut h = vec![0u64; layout().bins.len()];
    // Hits on reachable bins only: a sampler never hits a bin declared unreachable.
    for &(k, v) in hits {
        let n = h.len();
        if layout().bins[k % n].unreachable.is_none() {
            h[k % n] += v;
        }
    }
    CoverageFile::from_coverage(
        &h,
        runs.iter()
            .map(|r| RunRecord {
                id: r.to_string(),
                verdict: "pass".into(),
            })
            .collect(),
    )
}

fn files() -> impl Strategy<Value = Vec<CoverageFile>> {
    // Up to five files, each with its own runs (ids made unique by the file's position): hits are
    // always counted in at least one run.
    proptest::collection::vec(
        (
            proptest::collection::vec((0usize..5000, 0u64..1_000_000), 0..20),
            1usize..4,
        ),
        1..6,
    )
    .prop_map(|v| {
        v.iter()
            .enumerate()
            .map(|(f, (hits, nruns))| {
                let ids: Vec<String> = (0..*nruns).map(|r| format!("random/{f}-{r}")).collect();
                let refs: Vec<&str> = ids.iter().map(String::as_str).collect();
                file(hits, &refs)
            })
            .collect()
    })
}

fn m(fs: &[&CoverageFile]) -> CoverageFile {
    merge(fs.iter().map(|f| ("x", *f))).expect("merge")
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

    /// Any order of the same files gives the same file.
    #[test]
    fn merge_is_commutative(fs in files(), rot in 0usize..6) {
        let a: Vec<&CoverageFile> = fs.iter().collect();
        let mut b = a.clone();
        b.reverse();
        let r = rot % b.len();
        b.rotate_left(r);
        prop_assert_eq!(m(&a), m(&b));
    }

    /// Any grouping: ((a b) c) = (a (b c)), and a merged file merges like its parts.
    #[test]
    fn merge_is_associative(fs in files(), cut in 0usize..6) {
        let all: Vec<&CoverageFile> = fs.iter().collect();
        let cut = cut % (all.len() + 1);
        let left = m(&all[..cut]);
        let right = m(&all[cut..]);
        prop_assert_eq!(m(&[&left, &right]), m(&all));
        let text = m(&all).to_text();
        prop_assert_eq!(CoverageFile::parse(&text, "t").expect("parse"), m(&all));
    }
}

#[test]
fn the_empty_file_is_the_identity() {
    let a = file(&[(3, 4), (10, 1)], &["random/1"]);
    assert_eq!(m(&[&a, &CoverageFile::empty()]), a);
}

#[test]
fn hits_on_an_unreachable_bin_or_in_no_run_are_refused() {
    let k = layout()
        .bins
        .iter()
        .position(|b| b.unreachable.is_some())
        .expect("an unreachable bin");
    let mut a = file(&[], &["bench/1"]);
    a.bins[k].hits = 777;
    let e = merge([("a.json", &a)]).unwrap_err();
    assert!(
        matches!(e, DbError::UnreachableHit { hits: 777, .. }),
        "{e}"
    );
    assert!(e.to_string().starts_with("a.json: bin"), "{e}");
    // "runs": [] with hits: merged twice it would count its hits twice.
    let r = layout()
        .bins
        .iter()
        .position(|b| b.unreachable.is_none())
        .unwrap();
    let b = file(&[(r, 5)], &[]);
    let e = merge([("b.json", &b), ("b.json", &b)]).unwrap_err();
    assert_eq!(
        e,
        DbError::NoRuns {
            file: "b.json".into(),
            hits: 5
        }
    );
    assert!(CoverageFile::parse(&b.to_text(), "b.json").is_err());
    // no hit and no run: the empty file, accepted
    assert!(merge([("e.json", &CoverageFile::empty())]).is_ok());
}

#[test]
fn a_run_counted_twice_is_refused() {
    let a = file(&[(1, 1)], &["random/7"]);
    let b = file(&[(2, 1)], &["random/7", "random/8"]);
    let e = merge([("a.json", &a), ("b.json", &b)]).unwrap_err();
    assert_eq!(
        e,
        DbError::DuplicateRun {
            id: "random/7".into(),
            first: "a.json".into(),
            second: "b.json".into()
        }
    );
    assert!(e.to_string().contains("counted twice"), "{e}");
}

#[test]
fn pass_and_fail_runs_add_up_to_at_most_every_bin() {
    // cocotb-coverage's pass/fail merge counted a bin twice; here a bin is hit or not.
    let a = file(&[(0, 1)], &["random/1"]);
    let mut b = file(&[(0, 1)], &[]);
    b.runs.push(RunRecord {
        id: "random/2".into(),
        verdict: "fail".into(),
    });
    let (hit, reachable) = m(&[&a, &b]).closure();
    assert_eq!(hit, 1);
    assert!(hit <= reachable);
    assert_eq!(m(&[&a, &b]).bins[0].hits, 2);
}

#[test]
fn corrupt_foreign_and_other_model_files_are_refused_with_the_reason() {
    let good = file(&[(0, 1)], &["random/1"]).to_text();
    let e = CoverageFile::parse(&good[..good.len() / 2], "cut.json").unwrap_err();
    assert!(
        matches!(e, DbError::Corrupt { .. })
            && e.to_string()
                .starts_with("cut.json: not a coverage file: line"),
        "{e}"
    );
    let e = CoverageFile::parse("{\"format\": \"ucdb\", \"version\": 3}", "f.json").unwrap_err();
    assert!(matches!(e, DbError::Foreign { .. }), "{e}");
    let other = good.replacen("pmu50-coverage/", "pmu50-coverage/9", 1);
    let e = CoverageFile::parse(&other, "o.json").unwrap_err();
    assert!(matches!(e, DbError::OtherModel { .. }), "{e}");
    let renamed = good.replacen("fig17.path.s1_no_rise", "fig17.path.s1_renamed", 1);
    // the model id still matches, the bin list does not
    let e = CoverageFile::parse(&renamed, "r.json").unwrap_err();
    assert!(matches!(e, DbError::BinMismatch { index: 0, .. }), "{e}");
    let neg = good.replacen("\"hits\":1", "\"hits\":-1", 1);
    assert!(matches!(
        CoverageFile::parse(&neg, "n.json").unwrap_err(),
        DbError::Corrupt { .. }
    ));
}

#[test]
fn overflowing_hits_are_refused_not_wrapped() {
    let a = file(&[(0, u64::MAX - 1)], &["random/1"]);
    let b = file(&[(0, 5)], &["random/2"]);
    assert!(matches!(
        merge([("a", &a), ("b", &b)]).unwrap_err(),
        DbError::Overflow { .. }
    ));
}
