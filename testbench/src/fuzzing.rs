//! Bodies of the scenario and duration fuzz targets (`fuzz/fuzz_targets/`).
//!
//! They live in the library so that the cargo-fuzz targets (nightly, libFuzzer, `make fuzz`) and
//! the stable replay test (`tests/fuzz_replay.rs`, part of `make test`) run exactly the same code.
//! A body returns normally for every input, valid or not; it panics only on a bug: a panic inside
//! the parser, an error message that does not name the file, or a duration whose printed form
//! does not parse back to the same value. The regression-folder body is
//! `pmu50_verif::fuzzing::regress_folder`, the VCD reader/diff body [`pmu50_waves::fuzzing::vcd`].

use crate::scenario::Scenario;
use pmu50_core::Dur;
use std::path::Path;

/// File name the scenario body passes to the parser; every error message must start with it.
pub const FUZZ_FILE: &str = "fuzz.toml";

/// Parses `data` (when UTF-8) as a scenario file.
///
/// # Panics
/// When the parser panics, or an error message does not start with [`FUZZ_FILE`].
pub fn scenario(data: &[u8]) {
    let Ok(src) = std::str::from_utf8(data) else {
        return;
    };
    if let Err(e) = Scenario::parse(src, FUZZ_FILE, "fuzz", Path::new(FUZZ_FILE)) {
        let msg = e.to_string();
        assert!(
            msg.starts_with(FUZZ_FILE),
            "error message does not name the file: {msg}"
        );
    }
}

/// Parses `data` (when UTF-8) as a duration (`"2.2 ms"`).
///
/// # Panics
/// When the parser panics, or an accepted duration, printed with `Display`, does not parse back
/// to the same number of nanoseconds.
pub fn duration(data: &[u8]) {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    if let Ok(d) = Dur::parse(text) {
        let shown = d.to_string();
        assert_eq!(
            Dur::parse(&shown),
            Ok(d),
            "`{text}` is {} ns, shown as `{shown}`, which does not parse back",
            d.0
        );
    }
}
