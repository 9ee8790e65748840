//! The figures of the docs come from runs. The twin's sign-off table in docs/verification.md
//! ("The twin's sign-off") is the table `pmu50 signoff` printed for the folder
//! `PMU50_SIGNOFF_DIR` (its `signoff.txt`), row for row, without the first line (which names
//! the RTL by the path of this machine's copy). The code coverage table ("The twin's figures")
//! and the two mutation tables (section 11, with the map and on the ports alone) are the
//! Markdown files those runs write, quoted between `<!-- run: <file> -->` and `<!-- end run -->`
//! (the file relative to `PMU50_RUNS_DIR`, default `regress_out/`). `make docs-figures` runs
//! `make signoff`, `make mutation` and `make mutation-ports`, then these tests (ignored by `make
//! test`: the runs take many minutes); `PMU50_UPDATE_DOCS=1` rewrites the docs from the runs
//! instead of comparing.

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
    same_lines(&doc[a..b], &run, "the sign-off table");
}

/// The docs' quote of a run is the run's text, line for line.
fn same_lines(quoted: &str, run: &str, what: &str) {
    for (n, (q, r)) in quoted.lines().zip(run.lines()).enumerate() {
        assert_eq!(
            q,
            r,
            "docs/verification.md, {what}, its line {}: the run printed otherwise (PMU50_UPDATE_DOCS=1 make docs-figures rewrites it)",
            n + 1
        );
    }
    assert_eq!(
        quoted.lines().count(),
        run.lines().count(),
        "docs/verification.md's {what} has another number of lines than the run's"
    );
}

/// The quoted blocks of `doc`: (file named by the marker, start, end of the content).
fn quoted_runs(doc: &str) -> Vec<(String, usize, usize)> {
    const OPEN: &str = "<!-- run: ";
    const CLOSE: &str = "<!-- end run -->";
    let mut out = Vec::new();
    let mut at = 0;
    while let Some(i) = doc[at..].find(OPEN) {
        let m = at + i + OPEN.len();
        let eol = m + doc[m..]
            .find(" -->\n")
            .expect("a run marker ends with ` -->`");
        let file = doc[m..eol].to_string();
        let start = eol + " -->\n".len();
        let end = start
            + doc[start..]
                .find(CLOSE)
                .unwrap_or_else(|| panic!("the quote of {file} has no `{CLOSE}`"));
        out.push((file, start, end));
        at = end + CLOSE.len();
    }
    out
}

#[test]
#[ignore = "needs the runs: make docs-figures"]
fn the_docs_code_coverage_and_mutation_tables_are_the_runs() {
    let runs = std::env::var_os("PMU50_RUNS_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| root().join("regress_out"));
    let path = root().join("docs/verification.md");
    let mut doc = std::fs::read_to_string(&path).unwrap();
    let quotes = quoted_runs(&doc);
    let files: Vec<&str> = quotes.iter().map(|(f, _, _)| f.as_str()).collect();
    for want in [
        "signoff/code/summary.md",
        "mutation/mutation.md",
        "mutation-ports/mutation.md",
    ] {
        assert!(
            files.contains(&want),
            "docs/verification.md quotes no run of {want} (a `<!-- run: {want} -->` block)"
        );
    }
    let update = std::env::var_os("PMU50_UPDATE_DOCS").is_some();
    // from the last block to the first, so that a rewrite keeps the earlier offsets
    for (file, a, b) in quotes.into_iter().rev() {
        let p = runs.join(&file);
        let run = std::fs::read_to_string(&p).unwrap_or_else(|e| {
            panic!(
                "{}: {e} (make docs-figures makes it: make signoff, make mutation, make mutation-ports)",
                p.display()
            )
        });
        if update {
            doc = format!("{}{run}{}", &doc[..a], &doc[b..]);
            continue;
        }
        same_lines(&doc[a..b], &run, &format!("the quote of {file}"));
    }
    if update {
        std::fs::write(&path, doc).unwrap();
    }
}
