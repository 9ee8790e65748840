//! Waveform tooling for the PMU 50 RTL model.
//!
//! * [`writer`] — a checked, deterministic VCD writer on top of the `vcd` crate
//!   ([`writer::VcdBuilder`] declares the hierarchy, [`writer::VcdWriter`] dumps
//!   value changes).
//! * [`vcd_text`] — the text of a VCD body (change lines, time stamps) without a branch per
//!   character, which the VCD writer emits with.
//! * [`fst`] — the same checked writer with FST output (`fst-writer`), for long runs.
//! * [`fst_check`] — structural check of an FST (block sizes, counts, widths) before wellen
//!   reads it, the FST form of [`validate`].
//! * [`gtkw`] — GTKWave save files (`.gtkw`) that open a VCD with groups,
//!   number formats and analog traces.
//! * [`reader`] — reads any VCD back with `wellen` (independent of the writer),
//!   after [`validate`] has checked it: a malformed file is an error with its
//!   line, never a panic, a warning or silently dropped data.
//! * [`validate`] — streaming VCD validator with bounded memory.
//! * [`fuzzing`] — bodies of the fuzz targets (also replayed by `cargo test`).
//! * [`diff`] — waveform diff of two VCD files with prefix mapping, timescale
//!   and width normalisation, x/z policies and clock/period sampling.
//!
//! Every fallible operation returns a `thiserror` enum whose message says what
//! was wrong, where, and what would have been valid. Nothing in this crate
//! panics on user input.

pub mod diff;
pub mod fst;
pub mod fst_check;
pub mod fuzzing;
pub mod gtkw;
pub mod reader;
pub mod validate;
pub mod vcd_text;
pub mod writer;

mod guard;
mod time;

pub use reader::Value;
pub use time::{TimeUnit, Timescale};
