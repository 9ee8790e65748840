//! The registry of DUT backends: one row each, with its name, what it can do ([`Caps`]) and its
//! constructor. Every rule about what a backend can do is checked here, from its capabilities,
//! once ([`Backend::check`]): `--rtl` needs a backend that runs an RTL, `--map` one that compares
//! mapped internals, `--code-coverage` one that measures the RTL's code. A new backend is a file
//! of this folder with its `BACKEND` row, and its name in the table of `super` ([`BACKENDS`]).

use super::api::{Backend, Build, Caps, Dut, DutError};
use super::BACKENDS;
use crate::map::RtlMap;
use crate::spec::{DutKind, RunSpec};
use std::path::{Path, PathBuf};

/// An option that the chosen backend cannot honour, with the backends that can.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{option} {needs}: use --dut {} (not {dut})", able.join(" or --dut "))]
pub struct Refusal {
    /// The option, as the command line spells it (`--map`).
    pub option: &'static str,
    /// The field of `regress.json` that holds it (`map`).
    pub field: &'static str,
    /// What the option needs of a backend.
    pub needs: &'static str,
    /// The backend asked for.
    pub dut: String,
    /// The backends that can.
    pub able: Vec<&'static str>,
}

impl Refusal {
    /// The same refusal for a field of `regress.json`.
    pub fn as_field(&self) -> String {
        format!(
            "field `{}`: {}; valid with `dut` {} (not {})",
            self.field,
            self.needs,
            self.able.join(" or "),
            self.dut
        )
    }
}

/// The backend called `name`; another name is refused with the valid ones.
pub fn find(name: &str) -> Result<&'static Backend, String> {
    BACKENDS
        .iter()
        .copied()
        .find(|b| b.name == name)
        .ok_or_else(|| {
            format!(
                "unknown DUT `{name}`; valid are {}",
                BACKENDS
                    .iter()
                    .map(|b| b.name)
                    .collect::<Vec<_>>()
                    .join(", ")
            )
        })
}

/// The backend of a recorded run.
pub fn of(kind: &DutKind) -> Result<&'static Backend, String> {
    find(kind.name())
}

/// An option and the capability it needs.
#[derive(Clone, Copy)]
struct Rule {
    option: &'static str,
    field: &'static str,
    needs: &'static str,
    cap: fn(&Caps) -> bool,
}

/// The options a backend may not honour, in the order of [`Backend::check`]'s arguments.
const RULES: &[Rule] = &[
    Rule {
        option: "--rtl",
        field: "rtl",
        needs: "needs an RTL simulator",
        cap: |c| c.rtl,
    },
    Rule {
        option: "--map",
        field: "map",
        needs: "needs a backend that compares the mapped registers and internals",
        cap: |c| c.map,
    },
    Rule {
        option: "--code-coverage",
        field: "code_coverage",
        needs: "measures the RTL's code with Verilator's line and toggle coverage",
        cap: |c| c.code_coverage,
    },
];

impl Backend {
    /// Whether this backend can honour the options: an RTL, a map, code coverage.
    pub fn check(&self, rtl: bool, map: bool, code_coverage: bool) -> Result<(), Refusal> {
        let asked = [rtl, map, code_coverage];
        for (&asked, rule) in asked.iter().zip(RULES) {
            let Rule {
                option,
                field,
                needs,
                cap,
            } = *rule;
            if asked && !cap(&self.caps) {
                return Err(Refusal {
                    option,
                    field,
                    needs,
                    dut: self.name.to_string(),
                    able: BACKENDS
                        .iter()
                        .filter(|b| cap(&b.caps))
                        .map(|b| b.name)
                        .collect(),
                });
            }
        }
        Ok(())
    }
}

/// The DUT of a run spec: its backend, with the RTL (`spec.rtl`, default the twin) and the
/// optional map. The RTL is analysed and built here: bad input fails now.
pub fn prepare(spec: &RunSpec) -> Result<Box<dyn Dut>, DutError> {
    let backend = of(&spec.dut).map_err(DutError::Usage)?;
    backend
        .check(spec.rtl.is_some(), spec.map.is_some(), spec.code_coverage)
        .map_err(|e| DutError::Usage(e.to_string()))?;
    let map = match &spec.map {
        Some(m) => Some(RtlMap::read(Path::new(m))?),
        None => None,
    };
    let list = match &spec.rtl {
        Some(f) => PathBuf::from(f),
        None => crate::hdl_kit::hdl_dir().join("pmu50.f"),
    };
    (backend.make)(&Build {
        list: &list,
        map,
        pins: spec.pins,
        code_coverage: spec.code_coverage,
    })
}
