//! The proof behind a mutant declared equivalent (`equivalent: <reason>` in hdl/mutants.txt): the
//! sealed verdict of the formal kit's equivalence check (`hdl/formal/run.py --mutants`, `make
//! formal-mutants`: the twin and the twin with the mutant's define side by side from reset, every
//! output compared, proven unbounded by ABC's signal correspondence or pdr). The mutation table
//! counts a mutant as equivalent only with that file, made for this very twin.

use crate::provenance;
use std::path::{Path, PathBuf};

/// The format of the kit's equivalence file.
pub const FORMAT: &str = "pmu50-equivalence";

/// Where the kit writes the proof of `mutant`, below the twin's folder `hdl`.
pub fn proof_path(hdl: &Path, mutant: &str) -> PathBuf {
    hdl.join("build")
        .join("formal")
        .join("equivalence")
        .join(format!("{mutant}.json"))
}

/// Why a mutant declared equivalent is not proven equivalent: which file and what is wrong.
#[derive(Debug, thiserror::Error)]
pub enum EquivalenceError {
    #[error("no equivalence proof at {} ({reason}): run {remedy}", path.display())]
    Missing {
        path: PathBuf,
        reason: String,
        remedy: String,
    },
    #[error(transparent)]
    Sealed(#[from] provenance::ProvenanceError),
    #[error("{}: field `format` is {found:?}, not {FORMAT}", path.display())]
    Format { path: PathBuf, found: String },
    #[error("{}: the proof is of {found:?}, not {mutant}", path.display())]
    OtherMutant {
        path: PathBuf,
        found: String,
        mutant: String,
    },
    #[error("{}: the proof is of the RTL {list} ({hash}), not of this twin ({twin}): run {remedy}", path.display())]
    OtherRtl {
        path: PathBuf,
        list: String,
        hash: String,
        twin: String,
        remedy: String,
    },
    #[error("{}: the proof names no RTL (field `provenance.rtl`)", path.display())]
    NoRtl { path: PathBuf },
    #[error("{}: verdict {verdict:?}, not \"equivalent\": {how}", path.display())]
    NotProven {
        path: PathBuf,
        verdict: String,
        how: String,
    },
}

/// The proof of `mutant` in `path`, for the twin whose content hash is `twin_hash`: Ok(how it
/// was proven) when the sealed file says `equivalent` on every parameter set it names; the
/// error says why not (missing, edited, about another mutant or another RTL, or not a proof).
pub fn check_proof(path: &Path, mutant: &str, twin_hash: &str) -> Result<String, EquivalenceError> {
    let remedy = format!("make formal-mutants (hdl/formal/run.py --mutants --only {mutant})");
    let text = std::fs::read_to_string(path).map_err(|e| EquivalenceError::Missing {
        path: path.to_path_buf(),
        reason: e.to_string(),
        remedy: remedy.clone(),
    })?;
    let (m, p) = provenance::open(path, &text, &remedy)?;
    let field = |k: &str| m.get(k).and_then(|v| v.as_str()).unwrap_or("").to_string();
    if field("format") != FORMAT {
        return Err(EquivalenceError::Format {
            path: path.to_path_buf(),
            found: field("format"),
        });
    }
    if field("mutant") != mutant {
        return Err(EquivalenceError::OtherMutant {
            path: path.to_path_buf(),
            found: field("mutant"),
            mutant: mutant.to_string(),
        });
    }
    match &p.rtl {
        Some(r) if r.hash == twin_hash => {}
        Some(r) => {
            return Err(EquivalenceError::OtherRtl {
                path: path.to_path_buf(),
                list: r.list.clone(),
                hash: r.hash.clone(),
                twin: twin_hash.to_string(),
                remedy,
            })
        }
        None => {
            return Err(EquivalenceError::NoRtl {
                path: path.to_path_buf(),
            })
        }
    }
    if field("verdict") != "equivalent" {
        return Err(EquivalenceError::NotProven {
            path: path.to_path_buf(),
            verdict: field("verdict"),
            how: field("how"),
        });
    }
    Ok(field("how"))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::provenance::{Provenance, RtlId};

    fn sealed(dir: &Path, mutant: &str, verdict: &str, hash: &str) -> PathBuf {
        let mut m = serde_json::Map::new();
        m.insert("format".into(), FORMAT.into());
        m.insert("mutant".into(), mutant.into());
        m.insert("verdict".into(), verdict.into());
        m.insert("how".into(), "scorr (unbounded) on small, default".into());
        let p = Provenance::now(
            "hdl/formal/run.py --mutants",
            Some(RtlId {
                list: "hdl/pmu50.f".into(),
                hash: hash.into(),
            }),
            "formal",
            None,
        );
        let f = proof_path(dir, mutant);
        std::fs::create_dir_all(f.parent().unwrap()).unwrap();
        std::fs::write(&f, provenance::seal(m, &p)).unwrap();
        f
    }

    #[test]
    fn only_a_sealed_equivalent_verdict_of_this_twin_counts() {
        let d = std::env::temp_dir().join(format!("pmu50-equiv-{}", std::process::id()));
        let f = sealed(&d, "MUT_A", "equivalent", "sha256:aa");
        assert!(check_proof(&f, "MUT_A", "sha256:aa")
            .unwrap()
            .contains("scorr"));
        // another twin, another mutant
        assert!(check_proof(&f, "MUT_A", "sha256:bb")
            .unwrap_err()
            .to_string()
            .contains("not of this twin"));
        assert!(check_proof(&f, "MUT_B", "sha256:aa")
            .unwrap_err()
            .to_string()
            .contains("not MUT_B"));
        // an edited byte
        let t = std::fs::read_to_string(&f)
            .unwrap()
            .replace("equivalent\"", "equivalenT\"");
        std::fs::write(&f, t).unwrap();
        assert!(matches!(
            check_proof(&f, "MUT_A", "sha256:aa"),
            Err(EquivalenceError::Sealed(
                provenance::ProvenanceError::Tampered { .. }
            ))
        ));
        // not proven
        let f = sealed(&d, "MUT_C", "not_equivalent", "sha256:aa");
        assert!(check_proof(&f, "MUT_C", "sha256:aa")
            .unwrap_err()
            .to_string()
            .contains("not_equivalent"));
        // missing
        assert!(check_proof(&d.join("none.json"), "MUT_D", "sha256:aa")
            .unwrap_err()
            .to_string()
            .contains("make formal-mutants"));
        let _ = std::fs::remove_dir_all(&d);
    }
}
