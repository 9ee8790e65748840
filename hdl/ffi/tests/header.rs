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

/// The header's `pmu50_params` (written by hand: its fields are packed by size) is the Rust
/// struct field for field, and each field's comment names its Verilog parameter with the
/// legal range of the top's contract (`1..4`, `not 0`, or nothing for any value).
#[test]
fn header_params_struct_is_the_rust_struct_with_the_contracts_ranges() {
    let header = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("include/pmu50.h"),
    )
    .unwrap();
    let start = header.find("typedef struct pmu50_params {").unwrap();
    let end = start + header[start..].find("} pmu50_params;").unwrap();
    // `    uint8_t  sync_depth; /* SYNC_DEPTH 1..4 */`
    let mut fields = vec![];
    let mut bytes = 0;
    for line in header[start..end].lines().skip(1) {
        let (decl, comment) = line.split_once("/*").unwrap_or((line, ""));
        let words: Vec<&str> = decl.split_whitespace().collect();
        let [ty, name] = words.as_slice() else {
            continue;
        };
        let bits: u32 = match *ty {
            "uint8_t" => 8,
            "uint16_t" => 16,
            t => panic!("pmu50_params: type {t} of {name}"),
        };
        bytes += bits / 8;
        let name = name.trim_end_matches(';');
        let comment = comment.trim_end_matches("*/").trim();
        let hdl = comment
            .split_whitespace()
            .next()
            .unwrap_or("")
            .trim_end_matches([',', ':']);
        let p = pmu50_coverage::contract::parameters()
            .into_iter()
            .find(|p| p.name == hdl)
            .unwrap_or_else(|| panic!("pmu50_params.{name}: `{comment}` names no parameter"));
        assert!(
            p.max < 1 << bits,
            "pmu50_params.{name}: {ty} cannot hold {}",
            p.max
        );
        let range = format!("{}..{}", p.min, p.max);
        let said = if comment.contains("not 0") {
            format!("1..{}", (1u64 << bits) - 1)
        } else {
            comment
                .split_whitespace()
                .find(|w| w.contains(".."))
                .map_or(format!("0..{}", (1u64 << bits) - 1), str::to_string)
        };
        // a range that is the whole register is said as nothing; a 1-bit one as its register
        let whole = if p.max == 1 {
            format!("0..{}", (1u64 << bits) - 1)
        } else {
            range.clone()
        };
        assert_eq!(
            said, whole,
            "pmu50_params.{name}: `{comment}`, the contract says {range}"
        );
        fields.push(name.to_string());
    }
    // the Rust struct's fields in order (its Debug form), and its size
    let debug = format!("{:?}", pmu50_ffi::pmu50_params::default());
    let rust: Vec<&str> = debug
        .trim_start_matches("pmu50_params { ")
        .trim_end_matches(" }")
        .split(", ")
        .filter_map(|f| f.split_once(": ").map(|(n, _)| n))
        .collect();
    assert_eq!(fields, rust);
    assert_eq!(
        bytes as usize,
        std::mem::size_of::<pmu50_ffi::pmu50_params>()
    );
    assert_eq!(fields.len(), pmu50_coverage::contract::parameters().len());
}
