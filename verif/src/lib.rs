//! The PMU 50 verification kit: `pmu50 regress` against an RTL (seeds, the DUT backends,
//! lockstep, checks, functional coverage per seed, code coverage of the RTL), merge, shards,
//! triage to a repro, the HTML report, sign-off, mutation, RTL maps, and the HDL kit the binary
//! carries. docs/architecture.md draws where it stands: above the testbench, below the CLI.
//!
//! The public face: a module per command the CLI runs (`regress`, `merge`, `signoff`,
//! `mutation`, `report`, `map`, `lockstep`), the generator (`gen`), the DUT backends behind
//! their registry (`dut`), the RTL's file list and elaboration (`rtl`), code coverage
//! (`code_cov`), the HDL kit (`hdl_kit`), and the records of a run re-exported below. The
//! implementation (a seed's run, the pool, the build cache, triage, a folder's files) is private.

pub mod behaviour;
pub mod cache;
pub mod check;
pub mod check_report;
pub mod code_cov;
pub mod criterion;
mod curve;
pub mod digest;
pub mod dut;
pub mod equivalence;
pub mod error;
pub mod evidence;
pub mod filelist;
pub mod folder;
pub mod fuzzing;
pub mod gen;
pub mod grade;
pub mod hdl_kit;
pub mod history;
pub mod lint;
pub mod lockstep;
pub mod map;
pub mod merge;
pub mod mutation;
pub mod param_pool;
mod picture;
mod pool;
pub mod proofs;
pub mod provenance;
mod publish;
pub mod regress;
pub mod report;
pub mod rtl;
pub mod rtl_reader;
mod seed;
pub mod shape;
pub mod shard;
pub mod signoff;
mod signoff_checks;
mod signoff_expr;
mod signoff_lint;
mod signoff_soak;
mod signoff_waivers;
mod signoff_xprop;
mod sink;
mod spec;
mod summary;
mod triage;
pub mod waiver;
mod wave;
pub mod xprop;

pub use curve::pct;
pub use pool::run_pool;
pub use seed::{check_scenario, evaluate, run_model};
pub use spec::{DutKind, Place, RunSpec, SeedResult, Verdict};
pub use summary::{read_spec, scenario_closure, Source, Summary};
