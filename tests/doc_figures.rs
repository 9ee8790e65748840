//! The figures of the docs come from runs. The twin's sign-off table in docs/verification.md
//! ("The twin's sign-off") is the table `pmu50 signoff` printed for the folder
//! `PMU50_SIGNOFF_DIR` (its `signoff.txt`), row for row, without the first line (which names
//! the RTL by the path of this machine's copy). `make docs-figures` runs `make signoff` and then
//! this test (ignored by `make test`: a sign-off takes minutes); `PMU50_UPDATE_DOCS=1` rewrites
//! the table from the run instead of comparing.

use std::path::{Path, PathBuf};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The fenced block under `heading` in `doc`: (start, end) byte offsets of its content.
fn block(doc: &str, heading: &str) -> (usize, usize) {
    let h = doc
        .find(heading)
        .unwrap_or_else(|| panic!("docs/verification.md has no heading {heading:?}"));
    let open = h
        + doc[h..]
            .find("\n```\n")
            .expect("a fenced block under the heading")
        + 5;
    let close = open + doc[open..].find("```\n").expect("the block's end");
    (open, close)
}

/// The table of a sign-off run, as the docs quote it.
fn table(dir: &Path) -> String {
    let p = dir.join("signoff.txt");
    let text = std::fs::read_to_string(&p).unwrap_or_else(|e| {
        panic!(
            "{}: {e} (make docs-figures runs make signoff first)",
            p.display()
        )
    });
    let mut lines = text.lines();
    let first = lines.next().unwrap_or_default();
    assert!(first.starts_with("every row computed on"), "{first}");
    lines.map(|l| format!("{l}\n")).collect()
}

#[test]
#[ignore = "needs a sign-off run: make docs-figures"]
fn the_docs_signoff_table_is_the_table_of_the_run() {
    let dir = std::env::var_os("PMU50_SIGNOFF_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| root().join("regress_out/signoff"));
    let run = table(&dir);
    let path = root().join("docs/verification.md");
    let doc = std::fs::read_to_string(&path).unwrap();
    let (a, b) = block(&doc, "### The twin's sign-off");
    if std::env::var_os("PMU50_UPDATE_DOCS").is_some() {
        let new = format!("{}{run}{}", &doc[..a], &doc[b..]);
        std::fs::write(&path, new).unwrap();
        return;
    }
    let quoted = &doc[a..b];
    for (n, (q, r)) in quoted.lines().zip(run.lines()).enumerate() {
        assert_eq!(
            q,
            r,
            "docs/verification.md, the sign-off table's line {}: the run printed otherwise (PMU50_UPDATE_DOCS=1 make docs-figures rewrites it)",
            n + 1
        );
    }
    assert_eq!(
        quoted.lines().count(),
        run.lines().count(),
        "docs/verification.md's sign-off table has another number of rows than the run's"
    );
}
