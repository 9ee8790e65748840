//! `--map FILE`: the opt-in deeper compare. A map names, for model registers and internals,
//! the hierarchical signal of the RTL under test that holds the same value; the regression then
//! compares each mapped pair after every edge (registers) or before it (internals), as it
//! compares the ports. Any entry may be left out: an RTL is checked on its ports alone by
//! default (docs/hdl-guide.md, "Your RTL").
//!
//! ```toml
//! # model register (block.register, docs/signals.md) = RTL signal (hierarchical, from pmu50)
//! [registers]
//! "timing_generator.tmr" = "pmu50.u_timing.timer_q"
//! [internals]
//! kon = "pmu50.key_on_pulse"
//! ```
//!
//! `pmu50 rtl-map --rtl FILELIST` proposes a map by matching the RTL's signals to the model's
//! registers and internals by name and width ([`propose`]); the user edits it.

use crate::rtl::{Design, HierSignal};
use crate::shape::Selection;
use pmu50_core::pmu50::Structural;
use pmu50_core::signals::{self, Width};
use serde::Deserialize;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// A map that cannot be used: what, where, and what is valid.
#[derive(Debug, thiserror::Error)]
pub enum MapError {
    #[error("--map {path}: {reason}")]
    File { path: PathBuf, reason: String },
    #[error("--map {path}:{line}: `{key}` is not a model {group} (valid: {valid})")]
    UnknownModel {
        path: PathBuf,
        line: usize,
        key: String,
        group: &'static str,
        valid: String,
    },
    #[error("--map {path}:{line}: `{key}` = `{name}`: the RTL has no signal `{name}`{closest}")]
    NoSignal {
        path: PathBuf,
        line: usize,
        key: String,
        name: String,
        closest: String,
    },
    #[error("--map {path}:{line}: `{key}` = `{name}`: the RTL signal is {actual} bit(s) wide, the model's {key} is {expected}{why}")]
    Width {
        path: PathBuf,
        line: usize,
        key: String,
        name: String,
        expected: u32,
        actual: u32,
        why: String,
    },
    /// A field, element or part the signal does not have (`reason` ends with the closest names).
    #[error("--map {path}:{line}: `{key}` = `{name}`: {reason}")]
    NoField {
        path: PathBuf,
        line: usize,
        key: String,
        name: String,
        reason: String,
    },
    /// A value wider than 64 bits (`what`: its width and shape, then the fields to name).
    #[error("--map {path}:{line}: `{key}` = `{name}`: {what}")]
    TooWide {
        path: PathBuf,
        line: usize,
        key: String,
        name: String,
        what: String,
    },
}

/// A mapped RTL value: the signal, and the bits of it the map's name selects (the whole
/// signal, a field of a packed struct, an element of an array, a part).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Mapped {
    pub signal: HierSignal,
    pub sel: Selection,
}

impl Mapped {
    /// The C++ expression of hdl/tb/lockstep/dut_lib.cpp that reads the value from the root
    /// `R` of a Verilator build: `dut_bits(R->member[2], lsb, width)` (`VlWide` too).
    pub fn accessor(&self) -> String {
        let idx: String = self.sel.elements.iter().map(|e| format!("[{e}]")).collect();
        format!(
            "dut_bits(R->{}{idx}, {}, {})",
            verilator_member(&self.signal.path),
            self.sel.lsb,
            self.sel.width
        )
    }
}

#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
struct MapFile {
    #[serde(default)]
    registers: BTreeMap<String, String>,
    #[serde(default)]
    internals: BTreeMap<String, String>,
}

/// One mapped pair.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Entry {
    /// The model's name: `timing_generator.tmr` (register) or `kon` (internal).
    pub model: String,
    /// The RTL's hierarchical name, from `pmu50`.
    pub rtl: String,
}

/// A map, in the order of the model's signal table.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct RtlMap {
    pub path: Option<PathBuf>,
    pub registers: Vec<Entry>,
    pub internals: Vec<Entry>,
}

fn line_of(text: &str, key: &str) -> usize {
    let quoted = format!("\"{key}\"");
    text.lines()
        .position(|l| {
            let t = l.trim_start();
            t.starts_with(&quoted) || t.split(['=', ' ']).next() == Some(key)
        })
        .map_or(0, |i| i + 1)
}

impl RtlMap {
    /// Read and check a map file's syntax and model names (the RTL names are checked by
    /// [`RtlMap::check`] once the RTL is elaborated).
    pub fn read(path: &Path) -> Result<RtlMap, MapError> {
        let file = |reason: String| MapError::File {
            path: path.to_path_buf(),
            reason,
        };
        if let Some(kind) = pmu50_testbench::atomic_file::special_kind(path) {
            return Err(file(format!("is {kind}, not a map file")));
        }
        let meta = std::fs::metadata(path).map_err(|e| file(e.to_string()))?;
        if meta.len() > 1 << 20 {
            return Err(file(format!(
                "{} bytes: a map is at most 1 MiB",
                meta.len()
            )));
        }
        let text = std::fs::read_to_string(path).map_err(|e| file(e.to_string()))?;
        let raw: MapFile = toml::from_str(&text).map_err(|e| {
            let line = e.span().map_or(0, |s| {
                text[..s.start.min(text.len())].lines().count().max(1)
            });
            file(format!("line {line}: {}", e.message()))
        })?;
        let regs: Vec<String> = signals::REGISTERS.iter().map(|s| s.path()).collect();
        let ints: Vec<String> = signals::INTERNALS
            .iter()
            .map(|s| s.name.to_string())
            .collect();
        let mut map = RtlMap {
            path: Some(path.to_path_buf()),
            ..RtlMap::default()
        };
        for (group, given, valid, out) in [
            ("register", &raw.registers, &regs, &mut map.registers),
            ("internal", &raw.internals, &ints, &mut map.internals),
        ] {
            for k in given.keys() {
                if !valid.contains(k) {
                    return Err(MapError::UnknownModel {
                        path: path.to_path_buf(),
                        line: line_of(&text, k),
                        key: k.clone(),
                        group,
                        valid: valid.join(", "),
                    });
                }
            }
            for v in valid {
                if let Some(r) = given.get(v) {
                    let rtl = r.trim().to_string();
                    if rtl.is_empty() {
                        return Err(file(format!(
                            "line {}: `{v}` maps to an empty name",
                            line_of(&text, v)
                        )));
                    }
                    out.push(Entry {
                        model: v.clone(),
                        rtl,
                    });
                }
            }
        }
        Ok(map)
    }

    pub fn is_empty(&self) -> bool {
        self.registers.is_empty() && self.internals.is_empty()
    }

    fn line(&self, key: &str) -> usize {
        self.path
            .as_ref()
            .and_then(|p| std::fs::read_to_string(p).ok())
            .map_or(0, |t| line_of(&t, key))
    }

    /// Check every mapped name against the elaborated RTL (structure `s`): it exists, and has
    /// the model's width. A name that does not exist is refused with the closest names.
    pub fn check(&self, d: &Design, s: &Structural) -> Result<Vec<(Entry, Mapped)>, MapError> {
        let path = self.path.clone().unwrap_or_default();
        let mut out = Vec::new();
        let widths: Vec<(String, Width)> = signals::REGISTERS
            .iter()
            .map(|x| (x.path(), x.width))
            .chain(
                signals::INTERNALS
                    .iter()
                    .map(|x| (x.name.to_string(), x.width)),
            )
            .collect();
        for e in self.registers.iter().chain(&self.internals) {
            let line = self.line(&e.model);
            let Some((sig, sel)) = d.resolve(&e.rtl) else {
                let all = d.signals.iter().flat_map(|x| {
                    std::iter::once(x.path.clone()).chain(
                        x.shape
                            .fields(8)
                            .into_iter()
                            .map(move |(f, _)| format!("{}{f}", x.path)),
                    )
                });
                let all: Vec<String> = all.collect();
                let closest = closest(&e.rtl, all.iter().map(String::as_str), 5);
                let closest = if closest.is_empty() {
                    String::new()
                } else {
                    format!("; closest: {}", closest.join(", "))
                };
                return Err(MapError::NoSignal {
                    path,
                    line,
                    key: e.model.clone(),
                    name: e.rtl.clone(),
                    closest,
                });
            };
            let sel = match sel {
                Ok(sel) => sel,
                Err(reason) => {
                    let names: Vec<String> = sig
                        .shape
                        .fields(8)
                        .into_iter()
                        .map(|(f, _)| format!("{}{f}", sig.path))
                        .collect();
                    let c = closest(&e.rtl, names.iter().map(String::as_str), 3);
                    return Err(MapError::NoField {
                        path,
                        line,
                        key: e.model.clone(),
                        name: e.rtl.clone(),
                        reason: if c.is_empty() {
                            format!("`{}`: {reason}", sig.path)
                        } else {
                            format!("`{}`: {reason}; closest: {}", sig.path, c.join(", "))
                        },
                    });
                }
            };
            if sel.width > 64 || sel.width == 0 {
                let fields: Vec<String> = sel
                    .shape
                    .fields(8)
                    .into_iter()
                    .filter(|(f, _)| f.matches(['.', '[']).count() == 1)
                    .map(|(f, x)| format!("{}{f} ({} bits)", e.rtl, x.width))
                    .collect();
                return Err(MapError::TooWide {
                    path,
                    line,
                    key: e.model.clone(),
                    name: e.rtl.clone(),
                    what: format!(
                        "{} bits ({}); a map compares at most 64 bits: name a field, an element or a part of it{}",
                        sel.width,
                        sel.shape.describe(),
                        if fields.is_empty() {
                            String::new()
                        } else {
                            format!(": {}", fields.join(", "))
                        }
                    ),
                });
            }
            let w = widths
                .iter()
                .find(|(n, _)| *n == e.model)
                .map(|(_, w)| *w)
                .unwrap_or(Width::Bits(0));
            let expected = u32::from(w.bits(s));
            if sel.width != expected {
                let why = match w {
                    Width::CntWidth => format!(" (CNT_W = {})", s.cnt_width),
                    Width::SyncDepth => format!(" (SYNC_DEPTH = {})", s.sync_depth),
                    Width::Bits(_) => String::new(),
                };
                return Err(MapError::Width {
                    path,
                    line,
                    key: e.model.clone(),
                    name: e.rtl.clone(),
                    expected,
                    actual: sel.width,
                    why,
                });
            }
            out.push((
                e.clone(),
                Mapped {
                    signal: sig.clone(),
                    sel,
                },
            ));
        }
        Ok(out)
    }

    /// The map as TOML, in the model's order.
    pub fn to_toml(&self) -> String {
        let mut s = String::from("# pmu50 rtl-map: model registers and internals (docs/signals.md) -> hierarchical signals of the\n# RTL under test. `pmu50 regress --map FILE` compares each pair after every edge (registers) or\n# before it (internals), beside the ports. Any entry may be left out.\n\n[registers]\n");
        for e in &self.registers {
            s.push_str(&format!("\"{}\" = \"{}\"\n", e.model, e.rtl));
        }
        s.push_str("\n[internals]\n");
        for e in &self.internals {
            s.push_str(&format!("{} = \"{}\"\n", e.model, e.rtl));
        }
        s
    }

    /// A text that changes whenever the map does (for the build cache key).
    pub fn key(&self) -> String {
        self.registers
            .iter()
            .chain(&self.internals)
            .map(|e| format!("{}={};", e.model, e.rtl))
            .collect()
    }
}

/// The `n` names closest to `name` (Jaro-Winkler on the whole path and on its last part).
pub fn closest<'a>(name: &str, names: impl Iterator<Item = &'a str>, n: usize) -> Vec<String> {
    let last = |s: &str| s.rsplit('.').next().unwrap_or(s).to_string();
    let mut scored: Vec<(f64, &str)> = names
        .map(|c| {
            (
                strsim::jaro_winkler(name, c)
                    .max(strsim::jaro_winkler(&last(name), &last(c)) * 0.95),
                c,
            )
        })
        .collect();
    scored.sort_by(|a, b| b.0.total_cmp(&a.0).then(a.1.cmp(b.1)));
    scored
        .into_iter()
        .take(n)
        .map(|(_, c)| c.to_string())
        .collect()
}

/// How a proposed entry was found, for the comment beside it.
#[derive(Clone, Debug, PartialEq)]
pub struct Proposal {
    pub entry: Entry,
    /// 0..1: 1 for the same name in an instance named like the model's block.
    pub score: f64,
    /// Other candidates of the same width, best first.
    pub others: Vec<String>,
}

/// How well an RTL name matches a model register `block.var` (`block` empty for an internal):
/// 1 for the same leaf name in an instance named like the block; a port of a sub-block (a
/// copy of a register elsewhere) scores less than the register.
pub(crate) fn name_score(path: &str, module: &str, is_port: bool, block: &str, var: &str) -> f64 {
    let parts: Vec<&str> = path.split('.').collect();
    let leaf = parts[parts.len() - 1];
    let scope = if parts.len() >= 3 {
        parts[parts.len() - 2]
    } else {
        ""
    };
    // the leaf without the suffixes teams give registers and ports, and without a bit index
    let bare = leaf.split('[').next().unwrap_or(leaf);
    let stem = ["_q", "_o", "_i", "_r", "_reg", "_ff"]
        .iter()
        .find_map(|x| bare.strip_suffix(x))
        .unwrap_or(bare);
    // `qskip` for `quadrant_skip`: the stem's letters in order in the name, the first alike
    let abbreviates = |short: &str, long: &str| {
        let mut it = long.chars();
        short.len() >= 2
            && short.chars().next() == long.chars().next()
            && short.chars().all(|c| it.any(|l| l == c))
    };
    let name_score = if leaf == var {
        1.0
    } else if stem == var {
        0.98
    } else if abbreviates(stem, var) {
        0.95
    } else {
        strsim::jaro_winkler(leaf, var) * 0.9
    };
    let scope_score = if block.is_empty() || scope == block {
        1.0
    } else {
        strsim::jaro_winkler(scope, block).max(strsim::jaro_winkler(module, block))
    };
    let port_penalty = if is_port { 0.9 } else { 1.0 };
    name_score * (0.6 + 0.4 * scope_score) * port_penalty
}

/// Propose a map for an elaborated RTL (structure `s`): for each model register, the signal of
/// the model's width whose variable name and instance best match `block.register`; for each
/// internal, the signal of its width whose name best matches. Ports of the top are never
/// proposed (they are compared anyway). Entries below a score of 0.75 are left out.
pub fn propose(d: &Design, s: &Structural) -> (RtlMap, Vec<Proposal>) {
    let inner: Vec<&HierSignal> = d
        .signals
        .iter()
        .filter(|x| {
            x.path.matches('.').count() >= 1 && !(x.is_port && x.path.matches('.').count() == 1)
        })
        .collect();
    let mut props: Vec<Proposal> = Vec::new();
    let mut taken: Vec<String> = Vec::new();
    let mut pick = |model: String, block: &str, var: &str, width: u32| -> Option<Proposal> {
        let mut cands: Vec<(f64, &HierSignal)> = inner
            .iter()
            .filter(|x| x.width == width && !taken.contains(&x.path))
            .map(|x| (name_score(&x.path, &x.module, x.is_port, block, var), *x))
            .collect();
        cands.sort_by(|a, b| b.0.total_cmp(&a.0).then(a.1.path.cmp(&b.1.path)));
        let (score, best) = cands.first()?;
        if *score < 0.75 {
            return None;
        }
        taken.push(best.path.clone());
        let others = cands
            .iter()
            .skip(1)
            .take(3)
            .map(|(_, c)| c.path.clone())
            .collect();
        Some(Proposal {
            entry: Entry {
                model,
                rtl: best.path.clone(),
            },
            score: *score,
            others,
        })
    };
    let mut map = RtlMap::default();
    for r in signals::REGISTERS {
        if let Some(p) = pick(r.path(), r.scope, r.name, u32::from(r.width.bits(s))) {
            map.registers.push(p.entry.clone());
            props.push(p);
        }
    }
    for x in signals::INTERNALS {
        if let Some(p) = pick(x.name.to_string(), "", x.name, u32::from(x.width.bits(s))) {
            map.internals.push(p.entry.clone());
            props.push(p);
        }
    }
    (map, props)
}

/// The proposal as TOML, each entry with its score and the other candidates, and the model
/// names that found no candidate listed as comments.
pub fn proposal_toml(map: &RtlMap, props: &[Proposal]) -> String {
    let mut s = String::from("# pmu50 rtl-map: a proposed map (model registers and internals -> RTL signals), matched by name\n# and width. Review it: `pmu50 regress --map FILE` compares every entry after every edge.\n\n[registers]\n");
    let note = |model: &str| -> String {
        props
            .iter()
            .find(|p| p.entry.model == model)
            .map_or(String::new(), |p| {
                let others = if p.others.is_empty() {
                    String::new()
                } else {
                    format!("; also {}", p.others.join(", "))
                };
                format!("  # score {:.2}{others}", p.score)
            })
    };
    for r in signals::REGISTERS {
        let k = r.path();
        match map.registers.iter().find(|e| e.model == k) {
            Some(e) => s.push_str(&format!("\"{}\" = \"{}\"{}\n", e.model, e.rtl, note(&k))),
            None => s.push_str(&format!(
                "# \"{k}\" = ?  (no signal of {} bit(s) with a matching name)\n",
                r.width.bits(&Structural {
                    sync_depth: 2,
                    cnt_width: 16
                })
            )),
        }
    }
    s.push_str("\n[internals]\n");
    for x in signals::INTERNALS {
        match map.internals.iter().find(|e| e.model == x.name) {
            Some(e) => s.push_str(&format!("{} = \"{}\"{}\n", e.model, e.rtl, note(x.name))),
            None => s.push_str(&format!(
                "# {} = ?  (no signal with a matching name and width)\n",
                x.name
            )),
        }
    }
    s
}

/// Verilator's name of a hierarchical signal as a member of the root class: `pmu50.a.b` ->
/// `pmu50__DOT__a__DOT__b`, other characters encoded as Verilator encodes them.
pub fn verilator_member(path: &str) -> String {
    let mut out = String::new();
    for (i, part) in path.split('.').enumerate() {
        if i > 0 {
            out.push_str("__DOT__");
        }
        let part = part.trim_start_matches('\\').trim_end();
        let mut prev_us = false;
        for c in part.chars() {
            if c.is_ascii_alphanumeric() {
                out.push(c);
                prev_us = false;
            } else if c == '_' && !prev_us {
                out.push('_');
                prev_us = true;
            } else {
                out.push_str(&format!("__0{:X}", c as u32));
                prev_us = false;
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn member_names_follow_verilator() {
        assert_eq!(
            verilator_member("pmu50.timing_generator.tmr"),
            "pmu50__DOT__timing_generator__DOT__tmr"
        );
        assert_eq!(
            verilator_member("pmu50.internals.kon"),
            "pmu50__DOT__internals__DOT__kon"
        );
        assert_eq!(verilator_member("pmu50.a__b"), "pmu50__DOT__a___05Fb");
    }

    #[test]
    fn a_register_named_by_its_stem_or_an_abbreviation_scores_above_another_name() {
        let q = name_score(
            "pmu50.u_count.qskip_q",
            "pmu_quad_counter",
            false,
            "updown_counter",
            "quadrant_skip",
        );
        let d = name_score(
            "pmu50.u_check.diag_q",
            "pmu_count_check",
            false,
            "updown_counter",
            "quadrant_skip",
        );
        assert!(q > d, "{q} {d}");
        let r = name_score(
            "pmu50.u_check.diag_q",
            "pmu_count_check",
            false,
            "count_diagnosis",
            "diag",
        );
        let p = name_score(
            "pmu50.u_regs.diag_i",
            "pmu_regbank",
            true,
            "count_diagnosis",
            "diag",
        );
        assert!(r > p, "{r} {p}");
        // the same name in the block's own instance stays first
        assert_eq!(
            name_score(
                "pmu50.drive_interval.si",
                "drive_interval_changing_56b",
                false,
                "drive_interval",
                "si"
            ),
            1.0
        );
    }

    #[test]
    fn closest_names_rank_the_leaf() {
        let names = [
            "pmu50.timing_generator.tmr",
            "pmu50.timing_generator.timer",
            "pmu50.register_file.pw",
        ];
        let c = closest("pmu50.timing_generator.tmrr", names.iter().copied(), 2);
        assert_eq!(c[0], "pmu50.timing_generator.tmr");
    }

    /// A file written as the CLI writes: to a temporary file, renamed into place.
    fn put(p: &Path, text: &str) {
        let mut b = pmu50_testbench::atomic_file::Batch::new();
        b.add(pmu50_testbench::atomic_file::write_atomic(p, text.as_bytes()).unwrap());
        b.commit().unwrap();
    }

    #[test]
    fn a_map_names_model_signals_only() {
        let d = tempfile::tempdir().unwrap();
        let p = d.path().join("m.toml");
        put(&p, "[registers]\n\"timing_generator.tmr\" = \"pmu50.t.q\"\n\"timing_generator.tmx\" = \"pmu50.t.x\"\n");
        let e = RtlMap::read(&p).unwrap_err().to_string();
        assert!(
            e.contains(":3: `timing_generator.tmx` is not a model register")
                && e.contains("timing_generator.tmr"),
            "{e}"
        );
        put(&p, "[registers]\n\"timing_generator.tmr\" = \"pmu50.t.q\"\n[internals]\nkon = \"pmu50.k\"\n");
        let m = RtlMap::read(&p).unwrap();
        assert_eq!(
            m.registers,
            vec![Entry {
                model: "timing_generator.tmr".into(),
                rtl: "pmu50.t.q".into()
            }]
        );
        assert_eq!(m.internals.len(), 1);
        put(&p, "[regs]\n");
        assert!(RtlMap::read(&p).unwrap_err().to_string().contains("line 1"));
    }
}
