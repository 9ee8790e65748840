//! The command's integration tests, one test binary. Each file of `tests/` stays a module of
//! its own (its `//!` header says what it checks); compiled together, the workspace's crates are
//! linked once instead of once per file, and the test runner spreads the slow suites (RTL builds,
//! regressions) over the cores with the quick ones instead of running file after file.
//!
//! Every `tests/*.rs` is a module here or a `[[test]]` of Cargo.toml (`autotests = false`):
//! tests/architecture.rs fails on a file that is neither, which would never run.
//!
//! One file, one module: `cargo test --release --test integration rtl_sv::` runs tests/rtl_sv.rs.
//! Their shared helpers are `tests/common/` (`use crate::common;`).

mod common;

#[path = "architecture.rs"]
mod architecture;

#[path = "cache.rs"]
mod cache;

#[path = "cli.rs"]
mod cli;

#[path = "cli_faults.rs"]
mod cli_faults;

#[path = "code_coverage.rs"]
mod code_coverage;

#[path = "code_coverage_reference.rs"]
mod code_coverage_reference;

#[path = "coverage_monitor.rs"]
mod coverage_monitor;

#[path = "diff_cli.rs"]
mod diff_cli;

#[path = "evidence.rs"]
mod evidence;

#[path = "fst_cli.rs"]
mod fst_cli;

#[path = "fuzz_replay.rs"]
mod fuzz_replay;

#[path = "grade.rs"]
mod grade;

#[path = "hdl_kit.rs"]
mod hdl_kit;

#[path = "history.rs"]
mod history;

#[path = "interrupt.rs"]
mod interrupt;

#[path = "kernel_scenarios.rs"]
mod kernel_scenarios;

#[path = "mutation.rs"]
mod mutation;

#[path = "patent_sequences.rs"]
mod patent_sequences;

#[path = "plots.rs"]
mod plots;

#[path = "properties.rs"]
mod properties;

#[path = "refusals.rs"]
mod refusals;

#[path = "regress.rs"]
mod regress;

#[path = "regress_corners.rs"]
mod regress_corners;

#[path = "regress_folder.rs"]
mod regress_folder;

#[path = "rtl_contract.rs"]
mod rtl_contract;

#[path = "rtl_files.rs"]
mod rtl_files;

#[path = "rtl_sv.rs"]
mod rtl_sv;

#[path = "scenario_errors.rs"]
mod scenario_errors;

#[path = "signoff.rs"]
mod signoff;

#[path = "skip_ahead.rs"]
mod skip_ahead;

#[path = "trace_levels.rs"]
mod trace_levels;

#[path = "tracer.rs"]
mod tracer;

#[path = "writer_thread.rs"]
mod writer_thread;

#[path = "xprop_lint.rs"]
mod xprop_lint;

#[path = "xprop_lint_sv.rs"]
mod xprop_lint_sv;
