//! `pmu50 regress --dut verilator`: the RTL stepped in lockstep with the core, in memory.
//!
//! The RTL is a Verilator build loaded as a shared library (hdl/tb/lockstep/dut_lib.cpp, one per
//! set of the top's Verilog parameters, built by [`crate::dut::verilator`]). It runs in a DUT
//! worker, a child process of the regression (`pmu50 dut-worker`) that serves seed after seed:
//! the regression sends a seed's stimulus (the core's inputs of every tick, recorded from the
//! model's bench run by [`InputRecorder`]) and the scenario's parameters; the worker steps the
//! Rust core ([`pmu50_core::Pmu50`]) and the RTL side by side and compares, as verification
//! method 2 does (docs/verification.md): every output port after every edge, and the registers
//! and internals a `--map` names (after the edge, and before it). No vector file, no process
//! per seed.
//!
//! The worker is a process of its own so that the RTL cannot take the regression down: an RTL
//! that crashes or calls `$fatal` ends the worker, one that hangs is killed at the per-seed time
//! limit with its process group; the seed fails with the reason and the next seed gets a new
//! worker. An interrupted regression kills every worker ([`kill_children`]).
//!
//! Protocol (pipes, little-endian): request = magic `PMU6`, the kind ([`Request`], one byte),
//! path length (u32) and the library's path, the 12 HDL parameters (u64 each, in the order of
//! [`Params::hdl_parameters`]), the tick count (u64) and one packed input word (u32, [`pack`])
//! per tick (a trace request then the first and last edge, u64 each; a lockstep with code
//! coverage then the length (u32) and the path of the file the seed's counts go to, written
//! before the reply; a VCD request the first and last tick and the nanoseconds of a tick, u64
//! each, then the length (u32) and the path of the VCD the RTL's waveform goes to). Reply = one line of JSON,
//! a [`Reply`]. The worker writes its replies on its own
//! copy of stdout and sends the RTL's stdout (`$display`) to stderr, a log file kept to its last
//! [`LOG_KEEP`] bytes: nothing the RTL prints can be taken for a verdict.

mod children;
mod compare;
mod ffi;
mod protocol;
mod supervisor;
mod vectors;
mod worker;

pub use children::{
    cleanup_on_signal, file_tail, kill_children, register_child, register_scratch,
    unregister_child, unregister_scratch, LOG_KEEP,
};
pub use compare::replay_alone;
pub use protocol::{Answer, Mismatch, Reply, Request};
pub use supervisor::Worker;
pub use vectors::{
    model_coverage, pack, read_vector_inputs, unpack, InputRecorder, VectorInputs, MAX_TICKS,
};
pub use worker::worker_main;
