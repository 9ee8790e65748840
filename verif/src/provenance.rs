//! Where a file of evidence comes from, and proof that nobody edited it: the provenance block and
//! the digest that every JSON file a sign-off reads carries (docs/verification.md, "Sign-off").
//!
//! A sealed file is a JSON object with two keys besides its own content:
//! - `provenance`: what made it ([`Provenance`]): the tool and its version, the coverage model,
//!   the RTL (its file list and content hash), the DUT, the seed range and the versions of the
//!   simulators and solvers that ran;
//! - `digest`: `sha256:` and the SHA-256 of the file's canonical text without the `digest` key.
//!   The canonical text is compact JSON with every object's keys sorted, strings escaped as
//!   JSON requires and nothing else (Python: `json.dumps(obj, sort_keys=True,
//!   separators=(",", ":"), ensure_ascii=False)`).
//!
//! The Rust writers seal with [`seal`]; the scripts (the formal kit, the coverage proofs) seal
//! through `pmu50 seal`, so one implementation writes every digest. [`open`] checks one: a file
//! without its provenance is missing evidence, a file whose digest differs was edited.

use crate::digest::sha256_hex;
use serde::{Deserialize, Serialize};
use serde_json::{Map, Value};
use std::collections::BTreeMap;
use std::path::Path;
use std::sync::OnceLock;

/// The version of the provenance block.
pub const FORMAT: &str = "pmu50-provenance-1";

/// An RTL by its file list and its content hash (`crate::filelist::FileList::content_hash`).
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RtlId {
    /// The file list, as given.
    pub list: String,
    /// `sha256:...` over the RTL's defines and files.
    pub hash: String,
}

/// A seed range: `count` seeds from `start`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Seeds {
    pub start: u64,
    pub count: u64,
}

/// What made a file of evidence.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Provenance {
    /// [`FORMAT`].
    pub format: String,
    /// The command or script that wrote the file (`pmu50 regress`, `hdl/formal/coverage.py`).
    pub made_by: String,
    /// `pmu50 <version>` and the git commit it was built from, where known.
    pub tool: String,
    /// The id of the functional coverage model (`pmu50_coverage::model_id`).
    pub model_id: String,
    /// The RTL the evidence is about; `None` for the model alone.
    pub rtl: Option<RtlId>,
    /// The DUT backend (`verilator`, `icarus`, `model`) or the engine (`formal`).
    pub dut: String,
    /// The seed range, for evidence made of seeds.
    pub seeds: Option<Seeds>,
    /// The versions of the tools that ran (`verilator`, `iverilog`, `yosys`, ...).
    pub tools: BTreeMap<String, String>,
}

/// A file of evidence that cannot be taken: which file and why.
#[derive(Debug, thiserror::Error)]
pub enum ProvenanceError {
    #[error("{}: {reason}", path.display())]
    Read {
        path: std::path::PathBuf,
        reason: String,
    },
    #[error("{}: no provenance: the file was not written by the kit (or by a version before provenance); run {remedy}", path.display())]
    Missing {
        path: std::path::PathBuf,
        remedy: String,
    },
    #[error("{}: the digest does not match the contents: the file was edited after it was written (recorded {recorded}, computed {computed})", path.display())]
    Tampered {
        path: std::path::PathBuf,
        recorded: String,
        computed: String,
    },
    #[error("{}: field `provenance`: {reason}", path.display())]
    Bad {
        path: std::path::PathBuf,
        reason: String,
    },
}

/// `pmu50 <version>`, with the git commit the binary was built from where known.
pub fn tool_version() -> String {
    match option_env!("PMU50_GIT_COMMIT") {
        Some(c) if !c.is_empty() => format!("pmu50 {} (git {c})", env!("CARGO_PKG_VERSION")),
        _ => format!("pmu50 {}", env!("CARGO_PKG_VERSION")),
    }
}

/// The versions of the simulators and solvers on this machine (those installed), read once.
pub fn tool_versions() -> &'static BTreeMap<String, String> {
    static V: OnceLock<BTreeMap<String, String>> = OnceLock::new();
    V.get_or_init(|| {
        let mut m = BTreeMap::new();
        let probe = |cmd: &str, arg: &str| -> Option<String> {
            let o = std::process::Command::new(cmd).arg(arg).output().ok()?;
            let t = String::from_utf8_lossy(&o.stdout).into_owned()
                + &String::from_utf8_lossy(&o.stderr);
            t.lines()
                .find(|l| !l.trim().is_empty())
                .map(|l| l.trim().to_string())
        };
        for (name, cmd, arg) in [
            ("verilator", "verilator", "--version"),
            ("iverilog", "iverilog", "-V"),
            ("yosys", "yosys", "-V"),
        ] {
            if let Some(v) = probe(cmd, arg) {
                m.insert(name.to_string(), v);
            }
        }
        m
    })
}

impl Provenance {
    /// The provenance of a file `made_by` writes now, about `rtl` on `dut`.
    pub fn now(made_by: &str, rtl: Option<RtlId>, dut: &str, seeds: Option<Seeds>) -> Provenance {
        Provenance {
            format: FORMAT.into(),
            made_by: made_by.into(),
            tool: tool_version(),
            model_id: pmu50_coverage::model_id(pmu50_coverage::layout()),
            rtl,
            dut: dut.into(),
            seeds,
            tools: tool_versions().clone(),
        }
    }
}

/// `v` with every object's keys sorted.
fn sorted(v: &Value) -> Value {
    match v {
        Value::Object(m) => {
            let mut keys: Vec<&String> = m.keys().collect();
            keys.sort();
            let mut out = Map::new();
            for k in keys {
                out.insert(k.clone(), sorted(&m[k]));
            }
            Value::Object(out)
        }
        Value::Array(a) => Value::Array(a.iter().map(sorted).collect()),
        x => x.clone(),
    }
}

/// The canonical text of `v` (compact, keys sorted) and its digest.
pub fn digest_of(v: &Value) -> String {
    let text = serde_json::to_string(&sorted(v)).unwrap_or_default();
    format!("sha256:{}", sha256_hex(text.as_bytes()))
}

/// `content` (a JSON object) with its `provenance` and `digest`, as pretty JSON text.
pub fn seal(mut content: Map<String, Value>, p: &Provenance) -> String {
    content.remove("digest");
    content.insert(
        "provenance".into(),
        serde_json::to_value(p).unwrap_or(Value::Null),
    );
    let digest = digest_of(&Value::Object(content.clone()));
    content.insert("digest".into(), Value::String(digest));
    serde_json::to_string_pretty(&sorted(&Value::Object(content))).unwrap_or_default() + "\n"
}

/// A sealed file read back: its content (without `digest`) and its provenance, the digest
/// checked. `remedy` is the command that makes the file, for the message of a file without one.
pub fn open(
    path: &Path,
    text: &str,
    remedy: &str,
) -> Result<(Map<String, Value>, Provenance), ProvenanceError> {
    let v: Value = serde_json::from_str(text).map_err(|e| ProvenanceError::Read {
        path: path.to_path_buf(),
        reason: format!("line {}: {e}", e.line()),
    })?;
    let Value::Object(mut m) = v else {
        return Err(ProvenanceError::Read {
            path: path.to_path_buf(),
            reason: "not a JSON object".into(),
        });
    };
    let (Some(recorded), Some(p)) = (m.remove("digest"), m.get("provenance").cloned()) else {
        return Err(ProvenanceError::Missing {
            path: path.to_path_buf(),
            remedy: remedy.into(),
        });
    };
    let recorded = recorded.as_str().unwrap_or("").to_string();
    let computed = digest_of(&Value::Object(m.clone()));
    if recorded != computed {
        return Err(ProvenanceError::Tampered {
            path: path.to_path_buf(),
            recorded,
            computed,
        });
    }
    let p: Provenance = serde_json::from_value(p).map_err(|e| ProvenanceError::Bad {
        path: path.to_path_buf(),
        reason: e.to_string(),
    })?;
    if p.format != FORMAT {
        return Err(ProvenanceError::Bad {
            path: path.to_path_buf(),
            reason: format!("format `{}`; valid is `{FORMAT}`", p.format),
        });
    }
    Ok((m, p))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn prov() -> Provenance {
        Provenance {
            format: FORMAT.into(),
            made_by: "test".into(),
            tool: "pmu50 0".into(),
            model_id: "m".into(),
            rtl: Some(RtlId {
                list: "a.f".into(),
                hash: "sha256:00".into(),
            }),
            dut: "verilator".into(),
            seeds: Some(Seeds { start: 1, count: 2 }),
            tools: BTreeMap::new(),
        }
    }

    #[test]
    fn a_sealed_file_opens_and_an_edited_one_does_not() {
        let mut m = Map::new();
        m.insert("b".into(), Value::from(2));
        m.insert(
            "a".into(),
            serde_json::json!({"y": [1, 2.5, "é"], "x": null}),
        );
        let text = seal(m.clone(), &prov());
        let (back, p) = open(Path::new("f.json"), &text, "x").unwrap();
        assert_eq!(p, prov());
        assert_eq!(back["b"], 2);
        // one figure changed
        let edited = text.replacen("\"b\": 2", "\"b\": 3", 1);
        assert_ne!(edited, text);
        let e = open(Path::new("f.json"), &edited, "x")
            .unwrap_err()
            .to_string();
        assert!(e.contains("f.json: the digest does not match"), "{e}");
        // the provenance changed
        let edited = text.replacen("\"count\": 2", "\"count\": 200", 1);
        assert!(open(Path::new("f.json"), &edited, "x").is_err());
        // none at all
        let e = open(Path::new("f.json"), "{\"b\": 2}", "pmu50 regress")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("no provenance") && e.contains("pmu50 regress"),
            "{e}"
        );
    }

    #[test]
    fn the_canonical_text_is_compact_with_sorted_keys() {
        // the digest Python computes with json.dumps(sort_keys=True, separators=(",", ":"),
        // ensure_ascii=False) of the same object
        let v = serde_json::json!({"b": [1, {"d": true, "c": "é"}], "a": 0.5});
        assert_eq!(
            serde_json::to_string(&sorted(&v)).unwrap(),
            r#"{"a":0.5,"b":[1,{"c":"é","d":true}]}"#
        );
    }
}
