//! The signal table as the bindings see it: names, widths and values of the top-level ports, the
//! registers and the internals of the core.
//!
//! Everything the Python side knows about signals comes from the Rust side through the four
//! functions below (the `values()` lists of `rtl_model/core/src/pmu50.rs` today). Nothing else in
//! this crate names a signal, so replacing these lists by a single signal table in the core is a
//! change of this file only; [`set_input`] is the one place that maps an input name to its field.

use pmu50_core::pmu50::Structural;
use pmu50_core::{Inputs, Internals, Outputs, Regs};

/// Kind of a signal in the table.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    Input,
    Output,
    Register,
    Internal,
}

impl Kind {
    pub fn as_str(self) -> &'static str {
        match self {
            Kind::Input => "input",
            Kind::Output => "output",
            Kind::Register => "register",
            Kind::Internal => "internal",
        }
    }
}

/// One row of the table: kind, name (registers: `block.register`, the VCD path below `pmu50`),
/// width in bits.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Row {
    pub kind: Kind,
    pub name: String,
    pub width: u8,
}

/// The top-level inputs as (name, width, value), in port order.
pub fn input_values(i: &Inputs) -> [(&'static str, u8, u64); 7] {
    i.values()
}

/// The top-level outputs as (name, width, value), in the order of docs/signals.md.
pub fn output_values(s: &Structural, o: &Outputs) -> [(&'static str, u8, u64); 23] {
    o.values(s)
}

/// Every register as (block, name, width, value), in block evaluation order.
pub fn register_values(s: &Structural, r: &Regs) -> Vec<(&'static str, &'static str, u8, u64)> {
    r.values(s).into_iter().map(|v| (v.block, v.name, v.width, v.value)).collect()
}

/// The combinational internals as (name, width, value).
pub fn internal_values(x: &Internals) -> [(&'static str, u8, u64); 9] {
    x.values()
}

/// Set input `name` to `v` (already checked against its width). `false`: no such input.
pub fn set_input(i: &mut Inputs, name: &str, v: u64) -> bool {
    match name {
        "ig" => i.ig = v != 0,
        "vs2_ok" => i.vs2_ok = v != 0,
        "cmp_s" => i.cmp_s = v != 0,
        "cmp_c" => i.cmp_c = v != 0,
        "bus_we" => i.bus_we = v != 0,
        "bus_addr" => i.bus_addr = v as u8,
        "bus_wdata" => i.bus_wdata = v as u16,
        _ => return false,
    }
    true
}

/// The whole table for one structural configuration (widths of `cnt_s`, `cnt_c` and
/// `action_switching.sync` depend on it): inputs, outputs, registers, internals.
pub fn table(s: &Structural) -> Vec<Row> {
    let mut rows = Vec::new();
    let row = |kind, name: String, width| Row { kind, name, width };
    for (n, w, _) in input_values(&Inputs::default()) {
        rows.push(row(Kind::Input, n.to_string(), w));
    }
    for (n, w, _) in output_values(s, &Outputs::default()) {
        rows.push(row(Kind::Output, n.to_string(), w));
    }
    let reset = pmu50_core::pmu50::reset(&pmu50_core::Params { sync_depth: s.sync_depth, cnt_width: s.cnt_width, ..Default::default() });
    for (b, n, w, _) in register_values(s, &reset) {
        rows.push(row(Kind::Register, format!("{b}.{n}"), w));
    }
    for (n, w, _) in internal_values(&Internals::default()) {
        rows.push(row(Kind::Internal, n.to_string(), w));
    }
    rows
}
