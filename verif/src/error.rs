//! The error of a regression and of the folders it reads and writes.

use std::path::{Path, PathBuf};

#[derive(Debug, thiserror::Error)]
pub enum RegressError {
    #[error("{0}")]
    Usage(String),
    #[error("{}: {reason}", path.display())]
    File { path: PathBuf, reason: String },
    #[error("{}: line {line}: {reason}", path.display())]
    Line {
        path: PathBuf,
        line: u64,
        reason: String,
    },
    #[error(transparent)]
    Output(#[from] pmu50_testbench::atomic_file::OutputError),
    #[error("{0}")]
    Dut(String),
}

pub(crate) fn file_err(path: &Path, reason: impl std::fmt::Display) -> RegressError {
    RegressError::File {
        path: path.to_path_buf(),
        reason: reason.to_string(),
    }
}
