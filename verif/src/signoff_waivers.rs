//! The waivers behind a code-coverage row, checked: a waiver excludes points from a row's
//! figure only while its claim is shown to hold. Each of these misses the row and is named:
//! a waiver that is stale (its source lines changed since its review) or was never reviewed on
//! this source (no checksum); a waiver without a claim (`holds`); a claim that the coverage
//! proofs of this folder (`coverage-proofs.json`) did not prove (refuted, undecided, or not in
//! the file: proofs run without it); a waived point that the seeds covered all the same (the
//! claim that it cannot be covered is false).

use crate::code_cov::figures::{CodeSummary, WaiverUse};
use crate::proofs::{ClaimStatus, ProofWaiver};

/// What is wrong with the waivers of one row (those whose `what` starts with `kind`: `line`,
/// `signal `, `expr`), each naming the waiver (`code/waivers.toml:12 (file signal t[17:16])`).
/// `proofs` is `None` when the folder has no coverage proofs.
pub fn problems(c: &CodeSummary, kind: &str, proofs: Option<&[ProofWaiver]>) -> Vec<String> {
    let mut out = Vec::new();
    for w in c.waivers.iter().filter(|w| w.what.starts_with(kind)) {
        let name = || name(c, w);
        if let Some(st) = &w.stale {
            out.push(format!("{} does not apply, {st}", name()));
            continue;
        }
        match &w.holds {
            None => out.push(format!(
                "{} states no claim (holds) for the coverage proofs to prove",
                name()
            )),
            Some(h) => {
                let verdict = proofs.and_then(|p| {
                    p.iter()
                        .find(|p| p.file == w.file && p.what == w.what && p.holds == *h)
                        .map(|p| p.status)
                });
                match verdict {
                    Some(ClaimStatus::Proven) => {}
                    Some(ClaimStatus::Refuted) => {
                        out.push(format!("{}: its claim `{h}` is refuted", name()))
                    }
                    Some(ClaimStatus::Undecided) => {
                        out.push(format!("{}: its claim `{h}` is undecided", name()))
                    }
                    None => out.push(format!(
                        "{}: its claim `{h}` was not proven in this run ({})",
                        name(),
                        if proofs.is_some() {
                            "not in coverage-proofs.json"
                        } else {
                            "no coverage-proofs.json: make coverage-proofs"
                        }
                    )),
                }
            }
        }
        if w.covered > 0 {
            out.push(format!(
                "{}: {} of its {} point(s) were covered all the same, so its claim is false",
                name(),
                w.covered,
                w.points
            ));
        }
    }
    out
}

fn name(c: &CodeSummary, w: &WaiverUse) -> String {
    format!(
        "waiver {}:{} ({} {}, {})",
        if c.waivers_file.is_empty() {
            "code/waivers.toml"
        } else {
            &c.waivers_file
        },
        w.at,
        w.file,
        w.what,
        w.kind
    )
}
