//! The design under test of `pmu50 regress --dut NAME [--rtl FILELIST] [--map FILE]`: one type
//! per backend behind the [`Dut`] trait, each a file of this folder and a row of [`BACKENDS`]: its name, its
//! capabilities and its constructor. Every rule about what a backend can do is checked here,
//! from its capabilities, once ([`Backend::check`]): `--rtl` needs a backend that runs an RTL,
//! `--map` one that compares mapped internals, `--code-coverage` one that measures the RTL's
//! code.
//!
//! - [`model::ModelDut`]: the model alone (its checks and invariants, no RTL).
//! - [`verilator::VerilatorDut`]: an RTL with the contract ports of docs/signals.md as a
//!   Verilator library, one build per set of the top's Verilog parameters, stepped by a DUT
//!   worker in lockstep with the core on the seed's inputs held in memory ([`super::lockstep`]).
//!   A gate-level netlist is such an RTL.
//! - [`icarus::IcarusDut`]: the same RTL on Icarus Verilog, replaying the model's vector file
//!   (hdl/tb/tb_vectors.v, method 1), which compares the outputs.
//!
//! Every backend reads the RTL on its ports (and on the signals a `--map` names): other
//! instance names, other registers or no hierarchy at all are the HDL team's own. The RTL is
//! analysed once, before any seed ([`super::rtl`]): a file list that does not elaborate, a
//! missing contract port or a port of the wrong width is bad input, one error, exit 2.
//!
//! A seed's check is two calls, so that a job can run the model of the next seed while the RTL
//! runs this one: [`Dut::send`] hands the stimulus over, [`InFlight::wait`] takes the verdict
//! within the per-seed time limit. A DUT that hangs or crashes fails its seed with the reason.

mod api;
mod failure;
mod run;
pub mod vtool;

/// The backends: a file of this folder each, and a row here. The macro declares each file's
/// module and lists its `BACKEND` row in [`BACKENDS`], in this order (the order `--help` shows).
macro_rules! backends {
    ($($(#[$attr:meta])* $name:ident),* $(,)?) => {
        $($(#[$attr])* mod $name;)*
        /// Every backend: its name, its capabilities and its constructor.
        pub static BACKENDS: &[&Backend] = &[$($(#[$attr])* &$name::BACKEND),*];
    };
}

backends! {
    model,
    verilator,
    icarus,
    // the per-block specification as a DUT: a backend of the tests (dut/spec_model.rs)
    #[cfg(test)]
    spec_model,
}

pub use api::{Backend, Build, Caps, Dut, DutError, DutTrace, InFlight, Needs, Ready, Recorded};
pub use failure::{divergence, dut_failure, fig_at, timed_out};
pub use run::{check, record};
pub use verilator::{library_for, VerilatorDut};

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
    prepare_as(spec, false)
}

/// [`prepare`] for a run that builds its pool of parameter sets next ([`Dut::prebuild`]): the
/// RTL is analysed here, and a bad build refused by the prebuild (no build of the RTL's
/// defaults, which the pool may not use).
pub fn prepare_for_pool(spec: &RunSpec) -> Result<Box<dyn Dut>, DutError> {
    prepare_as(spec, true)
}

fn prepare_as(spec: &RunSpec, pool_next: bool) -> Result<Box<dyn Dut>, DutError> {
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
        pool_next,
    })
}
