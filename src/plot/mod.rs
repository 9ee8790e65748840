//! Pictures: the patent-style timing diagram of a run (FIG. 15/16), and the SVG writer the
//! analyses (src/analysis) draw their charts with. Every picture is also written as CSV.
//!
//! Every file is written to a temporary file in the same folder and renamed into place.

pub mod svg;
pub mod timing;

use std::path::Path;

/// Write `bytes` to `path` through a temporary file in the same folder, then rename
/// ([`crate::fsout`]: the temporary file is removed on SIGINT/SIGTERM as well).
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), crate::fsout::OutputError> {
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        crate::fsout::create_dir(dir)?;
    }
    let mut b = crate::fsout::Batch::new();
    b.add(crate::fsout::write_atomic(path, bytes)?);
    b.commit()
}
