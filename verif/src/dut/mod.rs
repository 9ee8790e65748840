//! The design under test of `pmu50 regress --dut NAME [--rtl FILELIST] [--map FILE]`: one type
//! per backend behind the [`Dut`] trait, each a file of this folder and a row of [`BACKENDS`]: its name, its
//! capabilities and its constructor ([`registry`] checks options against them).
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
pub mod registry;
mod run;

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
pub use registry::prepare;
pub use run::{check, record};
pub use verilator::{library_for, VerilatorDut};
