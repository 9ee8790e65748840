//! Pictures: the SVG writer the timing diagram of a run (crate::observers::timing) and the
//! analyses (testbench/src/analysis) draw their charts with. Every picture is also written as CSV.
//!
//! Every file is written to a temporary file in the same folder and renamed into place.

pub mod svg;

use std::path::Path;

/// Write `bytes` to `path` through a temporary file in the same folder, then rename
/// ([`crate::atomic_file`]: the temporary file is removed on SIGINT/SIGTERM as well).
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), crate::atomic_file::OutputError> {
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        crate::atomic_file::create_dir(dir)?;
    }
    let mut b = crate::atomic_file::Batch::new();
    b.add(crate::atomic_file::write_atomic(path, bytes)?);
    b.commit()
}
