//! Observers of a run ([`crate::sim::Observer`]): what watches the bench tick by tick and writes
//! or collects something from it.
//!
//! | module | observer | writes |
//! |---|---|---|
//! | [`waveform`] | `VcdObserver` | the VCD or FST of a run and its GTKWave save file |
//! | [`thread`] | `Threaded` | (runs another observer, the waveform's, on a thread of its own) |
//! | [`tracer`] | (used by `VcdObserver`) | the core's signals into a waveform frame, one edge a step |
//! | [`changelog`] | `ChangeLog` | `<name>.log`: one line per register change |
//! | [`markers`] | `MarkerObserver` | the key events, GTKWave's named markers |
//! | [`timing`] | `TimingRecorder` | the FIG. 15/16-style timing diagram (`--svg`) and its CSV |
//! | [`vectors`] | `VectorWriter` | vector files for HDL testbenches (docs/spec.md 6.2) |
//! | [`refusals`] | `RefusalWatch` | the register writes the chip refuses, for the summary |
//! | [`coverage`] | `pmu50_coverage::Coverage` | the functional coverage of the run (its hits) |

pub mod changelog;
pub mod coverage;
pub mod markers;
pub mod refusals;
pub mod thread;
pub mod timing;
pub mod tracer;
pub mod vectors;
pub mod waveform;
