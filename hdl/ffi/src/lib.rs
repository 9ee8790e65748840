//! C ABI of the PMU 50 digital core (`pmu50_core::Pmu50`), for lockstep co-simulation of the
//! Verilog twin against the Rust reference model (Verilator C++ testbench, SystemVerilog DPI-C,
//! or any simulator that can call C). The header is `hdl/ffi/include/pmu50.h`; the function and
//! struct documentation there is the contract, this file implements it.
//!
//! Rules of the boundary:
//! - No panic crosses it: every entry point runs under `catch_unwind` and returns
//!   `PMU50_ERR_PANIC` (or NULL / 0) instead.
//! - Every pointer is checked for NULL (`PMU50_ERR_NULL`).
//! - Errors leave a message in a thread-local buffer, read with `pmu50_last_error()`; the pointer
//!   stays valid until the next failing call on the same thread.
//! - C booleans are `uint8_t`, any non-zero value is true; outputs are 0 or 1.
//!
//! Build: `cargo build -p pmu50-ffi --release` gives `target/release/libpmu50_ffi.{a,so}`.
//! Link the static library with `-lpthread -ldl -lm`.

#![allow(non_camel_case_types)]

pub mod core_abi;
pub mod coverage;
pub mod mirror;

pub use core_abi::*;
pub use coverage::{pmu50_coverage_t, PMU50_ERR_COVERAGE, PMU50_ERR_IO, PMU50_ERR_TEXT};
pub use mirror::{pmu50_inputs, pmu50_internals, pmu50_outputs};
