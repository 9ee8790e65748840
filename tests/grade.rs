//! `pmu50 grade DIR`: the seeds ranked by the coverage each adds; rerunning the graded list
//! alone (`pmu50 regress --seeds-from`) hits every bin the whole regression hit, in far fewer
//! seeds.

use crate::common;
use common::{expect, pmu50, s, tmp};

#[test]
fn a_graded_list_reproduces_its_regressions_coverage_in_fewer_seeds() {
    let t = tmp("grade");
    // uniform, directed, and directed over a pool of parameter sets (build modes: the rerun
    // draws each seed's set from the regression's pool, as the regression did)
    for (directed, pool) in [(false, None), (true, None), (true, Some("4"))] {
        let dir = t.join(match (directed, pool) {
            (false, _) => "r",
            (true, None) => "d",
            (true, Some(_)) => "p",
        });
        let mut args = vec![
            "regress",
            "--iterations",
            "120",
            "--no-triage",
            "--history",
            "off",
            "--out",
            s(&dir),
        ];
        if directed {
            args.push("--directed");
        }
        if let Some(p) = pool {
            args.extend(["--param-sets", p]);
        }
        let o = pmu50(&args);
        expect(&o, 0, &["120 pass"]);
        if pool.is_some() {
            expect(&o, 0, &["4 parameter set(s) of at most 4"]);
        }
        let o = pmu50(&["grade", s(&dir)]);
        let out = expect(&o, 0, &["grade: ", "graded.json"]);
        let g: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(dir.join("graded.json")).unwrap())
                .unwrap();
        let ranked = g["ranked"].as_array().unwrap();
        assert!(
            ranked.len() * 3 < 120,
            "the graded list is not much shorter: {out}"
        );
        // each seed adds at most what the one before it added (greedy), and something
        for w in ranked.windows(2) {
            assert!(w[1]["adds"].as_u64() <= w[0]["adds"].as_u64(), "{out}");
        }
        assert!(ranked.iter().all(|r| r["adds"].as_u64().unwrap() > 0));
        assert!(std::fs::read_to_string(dir.join("graded.svg"))
            .unwrap()
            .contains("<polyline"));
        let o = pmu50(&[
            "regress",
            "--seeds-from",
            s(&dir.join("graded.json")),
            "--out",
            s(&t.join("rerun")),
        ]);
        let out = expect(&o, 0, &["rerun: "]);
        assert!(!out.contains("not hit again"), "{out}");
        assert!(
            out.contains(&format!("coverage {} bins", g["bins_hit"])),
            "{out}"
        );
    }
}
