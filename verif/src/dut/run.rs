//! One scenario on a DUT: the model's run with the recording the DUT needs, handed over, the
//! verdict awaited (a repro, a shrink try).

use super::api::{Dut, DutError, Needs, Recorded};
use crate::check::Failure;
use pmu50_testbench::scenario::Scenario;
use pmu50_testbench::sim::{self, SimOptions};
use std::time::Duration;

/// Run `sc` on the model with the recording `dut` needs, then hand it to the DUT and wait: the
/// check of one scenario (a repro, a shrink try).
pub fn check(dut: &dyn Dut, sc: &Scenario, timeout: Duration) -> Result<Option<Failure>, DutError> {
    let rec = record(dut, sc)?;
    dut.send(sc, rec)?.wait(sc, timeout)
}

/// The model's run of `sc` with the recording `dut` needs (no checks).
pub fn record(dut: &dyn Dut, sc: &Scenario) -> Result<Recorded, DutError> {
    match dut.needs() {
        Needs::Nothing => Ok(Recorded::None),
        Needs::Inputs => {
            let mut rec = crate::lockstep::InputRecorder::default();
            sim::run(sc, SimOptions::default(), &mut [&mut rec])
                .map_err(|e| DutError::Tool(e.to_string()))?;
            Ok(Recorded::Inputs(rec.inputs))
        }
        Needs::Vectors => {
            let vec = dut.vector_file(sc)?;
            let mut w = pmu50_testbench::observers::vectors::VectorWriter::new(
                std::io::BufWriter::new(vec.as_file()),
                sc,
            )
            .map_err(|e| DutError::Tool(e.to_string()))?;
            sim::run(sc, SimOptions::default(), &mut [&mut w])
                .map_err(|e| DutError::Tool(e.to_string()))?;
            use std::io::Write;
            w.into_inner()
                .flush()
                .map_err(|e| DutError::Tool(format!("{}: {e}", vec.path().display())))?;
            Ok(Recorded::Vectors(vec))
        }
    }
}
