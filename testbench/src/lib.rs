//! The PMU 50 testbench: scenarios, the bench that binds the digital core (`pmu50-core`) to its
//! environment models (`pmu50-env`) and the MPU's read-out, the observers of a run (waveforms,
//! change logs, vectors, markers, timing), the output of `pmu50 run`, timing diagrams in the
//! patent's style, and the analyses (`speed-limit`, `budget`). docs/architecture.md draws where it
//! stands: below the verification kit and the CLI, above the model's crates.

pub mod analysis;
pub mod atomic_file;
pub mod fuzzing;
pub mod limits;
pub mod observers;
pub mod output;
pub mod plot;
pub mod random;
pub mod scenario;
pub mod scenario_text;
pub mod sim;
