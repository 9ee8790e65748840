//! The code coverage of a regression as a batch sink: one part per batch of seeds, written
//! before the batch's results, compacted after, reconciled on resume; and the sink of a run
//! without code coverage, which removes the code coverage an earlier run left in the folder.

use super::parts::{compact, reconcile, remove, start, write_part};
use super::sums::Total;
use super::waivers::Waivers;
use crate::error::RegressError;
use crate::sink::BatchSink;
use crate::spec::SeedResult;
use std::ops::Range;
use std::path::Path;

/// The sink of a run: code coverage with these waivers, or none.
pub fn sink(code_coverage: bool, waivers: Option<Waivers>) -> Box<dyn BatchSink> {
    if code_coverage {
        Box::new(CodeSink {
            waivers: waivers.unwrap_or_default(),
        })
    } else {
        Box::new(NoCode)
    }
}

/// `--code-coverage`: the counts of each batch's seeds as a part of `code/`.
struct CodeSink {
    waivers: Waivers,
}

impl BatchSink for CodeSink {
    fn start(&mut self, dir: &Path) -> Result<(), RegressError> {
        start(dir, &self.waivers)
    }
    fn resume(&mut self, dir: &Path, range: &Range<u64>) -> Result<(), RegressError> {
        // the code coverage of exactly the seeds with a result
        reconcile(dir, range)
    }
    fn batch(&mut self, dir: &Path, results: &[&SeedResult]) -> Result<(), RegressError> {
        let mut part = Total::default();
        for r in results {
            if let Some(c) = &r.code {
                part.add_seed(c);
            }
        }
        let seeds: Vec<u64> = results.iter().map(|r| r.seed).collect();
        write_part(dir, &seeds, &part).map(drop)
    }
    fn after_batch(&mut self, dir: &Path) -> Result<(), RegressError> {
        compact(dir, false)
    }
    fn finish(&mut self, dir: &Path) -> Result<(), RegressError> {
        compact(dir, true)
    }
}

/// A run without code coverage.
struct NoCode;

impl BatchSink for NoCode {
    fn start(&mut self, dir: &Path) -> Result<(), RegressError> {
        // no code coverage of an earlier run into this folder stays to be taken for this one's
        remove(dir)
    }
    fn resume(&mut self, _: &Path, _: &Range<u64>) -> Result<(), RegressError> {
        Ok(())
    }
    fn batch(&mut self, _: &Path, _: &[&SeedResult]) -> Result<(), RegressError> {
        Ok(())
    }
    fn after_batch(&mut self, _: &Path) -> Result<(), RegressError> {
        Ok(())
    }
    fn finish(&mut self, _: &Path) -> Result<(), RegressError> {
        Ok(())
    }
}
