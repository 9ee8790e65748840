//! Digital core of the power management unit 50 of patent US 2022/0041215 A1 (NSK): the logic an
//! HDL team implements, as a cycle-accurate register-transfer-level model.
//!
//! Integers and bits only: no floating point type appears in this crate (a test greps for it).
//! One block per file, named after the patent block with its reference numeral; each has
//! `Inputs`, `Outputs`, `Regs` and a `RESET` value, with the synchronous and the combinational
//! side apart, as an HDL engineer writes them:
//! - `outputs(&Regs) -> Outputs`: the registered outputs, decoded from the block's registers;
//! - `eval(&Regs, &Inputs) -> (Comb, Regs)`: the pure next-state function with the block's
//!   combinational outputs of the cycle (`Comb`; `-> Regs` for a block that has none).
//!
//! A block with a structural parameter (`sync_depth`, `cnt_width`: Verilog `parameter`s) is a
//! small value built once with it (`ActionSwitching::new(sync_depth)`, ...), whose `outputs` and
//! `eval` take `&self`; the parameters are never per-tick inputs. [`pmu50`] is the top level
//! (the specification; [`reference::Pmu50Spec`] steps it) and [`kernel`] the fast path that
//! [`unit::Pmu50::step`] runs, proven equal to it by tests; [`signals`] is the table of every port,
//! register and internal signal. See docs/spec.md for
//! the specification and docs/glossary.md for the names.
#![forbid(unsafe_code)]

pub mod action_switching_56a;
pub mod comparator_latch_58ab;
pub mod config;
pub mod count_diagnosis;
pub mod drive_interval_changing_56b;
pub mod kernel;
pub mod params;
pub mod pmu50;
pub mod reference;
pub mod register_file;
pub mod rng;
pub mod sensor_power_determination_57;
pub mod signals;
pub mod timing_generator_56;
pub mod unit;
pub mod updown_counter_58cd;

pub use config::{ConfigError, CoreConfig, Dur};
pub use params::{ParamError, Params};
pub use pmu50::{Inputs, Internals, Outputs, Regs, TracedStep};
pub use reference::Pmu50Spec;
pub use unit::{FastForwardError, Pmu50};

/// The message of a caught panic (`catch_unwind`'s payload): the text of `panic!`, or `None`
/// for a payload that is not a string. The C ABI and the Python module both turn a panic at
/// their boundary into an error with this text.
pub fn panic_payload_text(payload: &(dyn std::any::Any + Send)) -> Option<&str> {
    if let Some(s) = payload.downcast_ref::<&str>() {
        Some(s)
    } else {
        payload.downcast_ref::<String>().map(String::as_str)
    }
}
