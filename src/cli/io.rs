//! The command's streams: `out!` and `err!` print without ever panicking; a closed or full
//! stream is remembered and makes the exit code 2 ([`exit_code`]).

use std::sync::atomic::{AtomicBool, Ordering};

/// Set when stdout or stderr could not be written (closed pipe, full disk).
pub static STREAM_FAILED: AtomicBool = AtomicBool::new(false);

/// Remember that a stream could not be written.
pub fn stream_failed() {
    STREAM_FAILED.store(true, Ordering::Relaxed);
}

/// `println!` that never panics: on a closed or full stdout the rest of the output is dropped
/// and the exit code becomes 2.
macro_rules! out {
    ($($t:tt)*) => {{
        use std::io::Write as _;
        if writeln!(std::io::stdout().lock(), $($t)*).is_err() {
            $crate::cli::io::stream_failed();
        }
    }};
}

/// `eprintln!` that never panics (see [`out!`]).
macro_rules! err {
    ($($t:tt)*) => {{
        use std::io::Write as _;
        if writeln!(std::io::stderr().lock(), $($t)*).is_err() {
            $crate::cli::io::stream_failed();
        }
    }};
}

pub(crate) use {err, out};

/// The process's exit code: `code`, or 2 when a stream failed.
pub fn exit_code(code: u8) -> std::process::ExitCode {
    if STREAM_FAILED.load(Ordering::Relaxed) {
        std::process::ExitCode::from(code.max(2))
    } else {
        std::process::ExitCode::from(code)
    }
}
