//! The C header `include/pmu50.h` carries the C mirror of the signal table (counts, the
//! `pmu50_inputs`/`pmu50_outputs`/`pmu50_internals` structs and the register index list) between
//! its BEGIN/END GENERATED markers. This test regenerates that text from the table and compares,
//! so the header cannot drift from the model. With `PMU50_REGENERATE=1` it rewrites the header
//! instead (atomically: temporary file in the same folder, then rename):
//! `PMU50_REGENERATE=1 cargo test -p pmu50-ffi --test header`.

use pmu50_core::signals::check_generated;
use pmu50_ffi::mirror::c_structs;

#[test]
fn header_structs_are_generated_from_the_signal_table() {
    let markers = ("/* BEGIN GENERATED", "/* END GENERATED */");
    check_generated(
        &std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../.."),
        "hdl/ffi/include/pmu50.h",
        markers,
        &c_structs(),
        "cargo test -p pmu50-ffi --test header",
    )
    .unwrap_or_else(|e| panic!("{e}"));
}
