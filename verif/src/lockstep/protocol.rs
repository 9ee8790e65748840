//! The pipe protocol between the regression and a DUT worker: requests, replies and answers
//! (the module's documentation, [`super`], gives the byte layout).

use serde::{Deserialize, Serialize};
use std::io::Read;
use std::path::PathBuf;

pub(crate) const MAGIC: &[u8; 4] = b"PMU6";

/// One value that differs between the model and the RTL.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Mismatch {
    /// The model's path below `pmu50`: `si`, `drive_interval.si`, `internals.fig17`.
    pub signal: String,
    pub expected: u64,
    pub got: u64,
}

/// A worker's answer to one request, one JSON line on the protocol pipe (the RTL's own output
/// goes elsewhere, so nothing it prints can be taken for a verdict).
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Reply {
    /// Every compared value equal at every tick.
    Pass { ticks: u64 },
    /// The first divergent tick: after rising edge `tick` (outputs, registers), or during cycle
    /// `tick` before its edge (`combinational`: internals); every value that differs there.
    Diverged {
        tick: u64,
        combinational: bool,
        mismatches: Vec<Mismatch>,
    },
    /// `bus_rdata` after each tick of a probe.
    Probe { rdata: Vec<u64> },
    /// The RTL's values after each edge `from..=to` of a trace: for each, the output ports in
    /// table order, then the mapped registers (`regs` names them).
    Trace {
        from: u64,
        regs: Vec<String>,
        values: Vec<Vec<u64>>,
    },
    /// The request could not be run (the library, the parameters).
    Error { reason: String },
}

pub(super) fn read_exact<R: Read>(r: &mut R, n: usize) -> std::io::Result<Vec<u8>> {
    let mut b = vec![0u8; n];
    r.read_exact(&mut b)?;
    Ok(b)
}

pub(super) fn u64s(b: &[u8]) -> impl Iterator<Item = u64> + '_ {
    b.chunks_exact(8)
        .map(|c| u64::from_le_bytes(c.try_into().unwrap_or([0; 8])))
}

/// What a request asks.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Request {
    /// Step the model and the RTL side by side and compare.
    Lockstep = 0,
    /// Step the RTL alone and return `bus_rdata` after each tick.
    Probe = 1,
    /// Step the RTL alone and return its outputs and mapped registers after each edge of a
    /// window (the picture of a failure).
    Trace = 2,
    /// A lockstep, then the RTL's code coverage of the run written to a file.
    LockstepCoverage = 3,
    /// Step the RTL alone (a build with tracing) and write its own waveform of the ticks of a
    /// window to a VCD file.
    Vcd = 4,
}

/// A request as the worker read it: its kind, the library, the 12 HDL parameters, the inputs,
/// the window of a trace (and, for a VCD, the nanoseconds of a tick), and the file a coverage or
/// a VCD goes to.
pub(super) type Received = (
    Request,
    PathBuf,
    [u64; 12],
    Vec<u32>,
    (u64, u64, u64),
    Option<PathBuf>,
);

/// What a worker answered for one request.
pub enum Answer {
    Reply(Reply),
    /// No reply within the time limit: the worker was killed.
    TimedOut,
    /// The worker ended without a reply: how, and the end of its stderr.
    Died(String),
}
