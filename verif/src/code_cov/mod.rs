//! Code coverage of the RTL under test: `pmu50 regress --dut verilator --code-coverage`.
//!
//! The RTL is built with Verilator's line and toggle coverage (`--coverage-line
//! --coverage-toggle`, a build cached apart from the plain one). Each seed's RTL run counts in
//! its own DUT handle; the worker writes the counts of the run as a Verilator `coverage.dat`
//! and the regression reads them back ([`read_counts`]), so the code coverage of a seed is known
//! exactly, whatever worker ran it. A seed whose RTL run ended without a verdict (a hang, a
//! crash) and a seed the model failed before the RTL ran count nothing.
//!
//! Folder layout (`<out>/code/`):
//! - `parts/<first>-<last>.dat`: the summed counts of the seeds of one batch of
//!   `results.jsonl`, written before the batch's results, with the seeds it holds on its second
//!   line (`# seeds 1-32,40`). A Verilator coverage.dat (`verilator_coverage` reads it).
//!   `--resume` keeps the parts whose seeds all have a result, removes those none of whose seeds
//!   has one, and cuts the results of a batch an interruption tore ([`reconcile`]); `pmu50
//!   merge` sums the parts of its folders. So the code coverage of a folder is that of exactly
//!   the seeds of its results, however often it was interrupted, sharded or merged.
//! - `coverage.dat`: every point of every build the seeds used, with its summed count, sorted by
//!   key, file paths relative to the file list's folder (one regression run in one process and
//!   the same regression run in shards and merged give the same bytes).
//! - `lcov.info`: the same as LCOV tracefile data ([`Total::lcov`]).
//! - `waivers.toml`: the waivers applied ([`Waivers`]); `summary.json`: the figures after the
//!   waivers ([`CodeSummary`], format `pmu50-code-coverage-1`).
//!
//! What counts: a line point (a block, or an `if`/`else`/`case` branch: Verilator's `v_line`
//! and `v_branch`) is hit when it ran at least once; a toggle point (one bit of a signal) is
//! toggled when it rose and fell within one seed's run. Verilator counts a bit's changes; the
//! count a seed adds to a toggle point is its changes halved (rounded down: the rise-and-fall
//! pairs from reset on), so that two seeds that each only raise a bit do not add up to a
//! toggle. In the folder's files a toggle point's count is that number of pairs.

pub(crate) mod figures;
pub(crate) mod html;
pub(crate) mod parts;
pub(crate) mod points;
pub(crate) mod sink;
pub(crate) mod sums;
pub(crate) mod waivers;

pub use figures::*;
pub use html::*;
pub use parts::*;
pub use points::*;
pub use sums::*;
pub use waivers::*;
