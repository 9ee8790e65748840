//! `coverage-proofs.json` (`make coverage-proofs`, hdl/formal/coverage.py): each bin's
//! reachability and each code-coverage waiver's claim as the proofs decided them, read sealed
//! and checked (every bin once, every bin the model's).

use crate::criterion::{content_as, Folder, Input};
use crate::error::RegressError;
use serde::Deserialize;
use std::collections::BTreeSet;

/// A bin's reachability, as the coverage proofs decided it (`hdl/formal/coverage.py`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum BinStatus {
    /// `assert(!hit_<bin>)` proven unbounded on every parameter set it ran.
    ProvenUnreachable,
    /// Declared unreachable, but the proof found a trace that hits it.
    WrongDeclaration,
    /// `cover(hit_<bin>)` reached within the depth.
    Witnessed,
    /// Neither.
    Undecided,
}

#[derive(Clone, Debug, Deserialize)]
pub struct ProofBin {
    pub name: String,
    pub status: BinStatus,
    /// The model's reason, for a bin it declares unreachable.
    #[serde(default)]
    pub declared_unreachable: Option<String>,
    #[serde(default)]
    pub property: String,
    /// Proven on these parameter sets.
    #[serde(default)]
    pub sets: Vec<String>,
    /// Witnessed (or refuted) on this set, at this step.
    #[serde(default)]
    pub set: String,
    #[serde(default)]
    pub step: Option<u64>,
    /// Undecided: what was tried.
    #[serde(default)]
    pub tried: String,
    /// A witness or counterexample as a vector file.
    #[serde(default)]
    pub witness: Option<String>,
}

impl ProofBin {
    pub(crate) fn status_text(&self) -> &'static str {
        match self.status {
            BinStatus::ProvenUnreachable => "proven unreachable",
            BinStatus::WrongDeclaration => "WRONG DECLARATION",
            BinStatus::Witnessed => "witnessed",
            BinStatus::Undecided => "undecided",
        }
    }

    pub(crate) fn how(&self) -> String {
        let mut w = self.property.clone();
        if !self.sets.is_empty() {
            w += &format!(" on {}", self.sets.join(", "));
        } else if !self.set.is_empty() {
            w += &format!(" on {}", self.set);
        }
        if let Some(k) = self.step {
            w += &format!(" at step {k}");
        }
        if !self.tried.is_empty() {
            w += &format!("; tried: {}", self.tried);
        }
        if let Some(f) = &self.witness {
            w += &format!("; trace {f}");
        }
        w
    }
}

/// `coverage-proofs.json` (`make coverage-proofs`' coverage.json): each bin's reachability.
#[derive(Clone, Debug, Deserialize)]
pub struct Proofs {
    /// The coverage model the proofs are of (`pmu50-coverage/<bins>/<hash>`); hdl/formal/
    /// coverage.py always writes it.
    #[serde(default)]
    pub model_id: Option<String>,
    pub bins: Vec<ProofBin>,
    /// The code-coverage waivers' claims (`holds`) and their verdicts.
    #[serde(default)]
    pub waivers: Vec<ProofWaiver>,
}

/// A waiver's claim as the coverage proofs decided it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ClaimStatus {
    /// Proven on every parameter set.
    Proven,
    /// A trace from reset breaks it.
    Refuted,
    /// Neither.
    Undecided,
}

/// A waiver's claim and its verdict (hdl/formal/coverage.py `waivers`).
#[derive(Clone, Debug, Deserialize)]
pub struct ProofWaiver {
    pub file: String,
    /// `signal t[17:16]` or `line 40`, as the waiver's `what`.
    pub what: String,
    pub holds: String,
    pub status: ClaimStatus,
}

impl Proofs {
    pub const FILE: &'static str = "coverage-proofs.json";
    pub const REMEDY: &'static str =
        "make coverage-proofs RTL=LIST MAP=FILE (sealed by the script; make signoff copies it here)";
    /// The folder's proofs (`Err`: why they are missing): sealed, of this RTL and coverage
    /// model. A bin listed twice, or one the model does not have, is bad input.
    pub fn read(f: &Folder) -> Result<Result<Proofs, String>, RegressError> {
        let (content, _) = match f.open(Proofs::FILE, Proofs::REMEDY, false)? {
            Input::Missing(why) => return Ok(Err(why)),
            Input::Sealed {
                content,
                provenance,
            } => (content, provenance),
        };
        let p: Proofs = content_as(f.dir, Proofs::FILE, content)?;
        let path = f.dir.join(Proofs::FILE);
        let ours = pmu50_coverage::model_id(pmu50_coverage::layout());
        if let Some(id) = p.model_id.as_deref().filter(|id| *id != ours) {
            return Err(crate::error::file_err(
                &path,
                format!(
                    "model_id {id:?}: the proofs are of another coverage model than this \
                     pmu50's ({ours:?}); run `make coverage-proofs` again with this \
                     pmu50's monitor (pmu50 hdl coverage-monitor)"
                ),
            ));
        }
        let known: BTreeSet<&str> = pmu50_coverage::layout()
            .bins
            .iter()
            .map(|b| b.name.as_str())
            .collect();
        let mut seen = BTreeSet::new();
        for b in &p.bins {
            if !known.contains(b.name.as_str()) {
                return Err(crate::error::file_err(
                    &path,
                    format!(
                        "bin `{}`: the coverage model has no such bin; the proofs are of another model",
                        b.name
                    ),
                ));
            }
            if !seen.insert(b.name.as_str()) {
                return Err(crate::error::file_err(
                    &path,
                    format!("bin `{}` is listed twice: each bin is decided once", b.name),
                ));
            }
        }
        Ok(Ok(p))
    }
}
