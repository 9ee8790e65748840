//! The peers of the table, one file each: the harness that replays the stimulus through it and
//! returns what it measured (CPU time, ticks, the output checksum, a note).

pub mod model;
pub mod pmu50;
pub mod tracer;
pub mod twin;
