//! What a regression hands each batch of seed results to, besides `results.jsonl`: a sink per
//! measurement that keeps files of its own in the folder (the RTL's code coverage is one,
//! `crate::code_cov::sink`). The regression calls every sink at the same points, whatever it
//! measures: a new run or a resumed one, before and after each batch's results are appended,
//! and at the end.

use crate::error::RegressError;
use crate::spec::SeedResult;
use std::ops::Range;
use std::path::Path;

/// A measurement kept per batch of seeds.
pub trait BatchSink {
    /// A new run into `dir`: the sink's files of an earlier run there are replaced or removed.
    fn start(&mut self, dir: &Path) -> Result<(), RegressError>;
    /// A resumed run: keep exactly what belongs to the seeds of `range` that have a result.
    fn resume(&mut self, dir: &Path, range: &Range<u64>) -> Result<(), RegressError>;
    /// A batch, before its results are appended (so an interruption between the two is found
    /// by `resume`).
    fn batch(&mut self, dir: &Path, results: &[&SeedResult]) -> Result<(), RegressError>;
    /// After a batch's results were appended.
    fn after_batch(&mut self, dir: &Path) -> Result<(), RegressError>;
    /// The run is over (complete or interrupted).
    fn finish(&mut self, dir: &Path) -> Result<(), RegressError>;
}
