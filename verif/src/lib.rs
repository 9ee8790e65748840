//! The PMU 50 verification kit: `pmu50 regress` against an RTL (seeds, the DUT backends,
//! lockstep, checks, functional coverage per seed, code coverage of the RTL), merge, shards,
//! triage to a repro, the HTML report, sign-off, mutation, RTL maps, and the HDL kit the binary
//! carries. docs/architecture.md draws where it stands: above the testbench, below the CLI.

pub mod cache;
pub mod check;
pub mod code_cov;
pub mod curve;
pub mod dut;
pub mod error;
pub mod folder;
pub mod fuzzing;
pub mod gen;
pub mod hdl_kit;
pub mod lockstep;
pub mod map;
pub mod merge;
pub mod mutation;
pub mod picture;
pub mod pool;
pub mod publish;
pub mod regress;
pub mod report;
pub mod rtl;
pub mod seed;
pub mod shard;
pub mod signoff;
pub mod spec;
pub mod summary;
pub mod triage;
pub mod wave;

pub use curve::pct;
pub use pool::run_pool;
pub use seed::{check_scenario, evaluate, run_model};
pub use spec::{DutKind, Place, RunSpec, SeedResult, Verdict};
pub use summary::{read_spec, scenario_closure, Source, Summary};
