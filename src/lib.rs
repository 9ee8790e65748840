//! PMU 50 reference model: scenarios, the testbench binding the digital core to its environment,
//! waveform and log output, vector export, and the command-line tool `pmu50`.
//!
//! The digital core is the crate `pmu50-core` (rtl_model/core), the environment models are
//! `pmu50-env` (rtl_model/env), waveform tooling is `pmu50-waves` (waves/).

pub mod analysis;
pub mod atomic_file;
pub mod fuzzing;
pub mod hdl_kit;
pub mod limits;
pub mod observers;
pub mod output;
pub mod plot;
pub mod random;
pub mod regress;
pub mod scenario;
pub mod sim;
