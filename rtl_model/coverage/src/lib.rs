//! Functional coverage of the PMU 50 digital core: one model, declared once ([`model`]), sampled
//! from the core's state at each clock edge ([`Coverage::sample`]) by the Rust testbench
//! (`pmu50 regress`), the Python package (`pmu50.Coverage`) and the C ABI (a SystemVerilog DPI
//! bench), and merged exactly across runs, shards and machines ([`db`]).
//!
//! Every bin cites the patent paragraph or docs/spec.md section it measures; bins that can
//! never be hit are declared with the reason. docs/verification.md is the verification plan
//! built on it.

pub mod contract;
pub mod db;
pub mod model;
pub mod monitor;
pub mod sample;
pub mod ucis;

pub use db::{merge, CoverageFile, DbError, RunRecord};
pub use model::{model_id, Aim, BinInfo, Hint, Kind, Layout};
pub use sample::{layout, Coverage, Edge};
pub use ucis::{to_ucis_xml, write_ucis_xml};
