//! The C header `include/pmu50.h` carries the C mirror of the signal table (counts, the
//! `pmu50_inputs`/`pmu50_outputs`/`pmu50_internals` structs and the register index list) between
//! its BEGIN/END GENERATED markers. This test regenerates that text from the table and compares,
//! so the header cannot drift from the model. With `PMU50_REGENERATE=1` it rewrites the header
//! instead (atomically: temporary file in the same folder, then rename):
//! `PMU50_REGENERATE=1 cargo test -p pmu50-ffi --test header`.

use pmu50_core::signals::{regenerate, splice};
use pmu50_ffi::mirror::c_structs;
use std::path::Path;

const BEGIN: &str = "/* BEGIN GENERATED";
const END: &str = "/* END GENERATED */";

#[test]
fn header_structs_are_generated_from_the_signal_table() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("include/pmu50.h");
    let text = std::fs::read_to_string(&path).unwrap();
    let want = splice(&text, BEGIN, END, &c_structs()).expect("include/pmu50.h lost its BEGIN/END GENERATED markers");
    if regenerate(&path, &want) {
        return;
    }
    assert!(
        text == want,
        "hdl/ffi/include/pmu50.h differs from the signal table (rtl_model/core/src/signals.rs); \
         regenerate with PMU50_REGENERATE=1 cargo test -p pmu50-ffi --test header and review the diff"
    );
}
