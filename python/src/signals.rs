//! The signal table as the bindings see it: names, widths and values of the top-level ports, the
//! registers and the internals of the core.
//!
//! Everything the Python side knows about signals comes from the core's single signal table
//! (`rtl_model/core/src/signals.rs`: `INPUTS`, `INPUT_SETTERS`, `OUTPUTS`, `REGISTERS`,
//! `INTERNALS`) through the functions below; nothing else in this crate names a signal.

use pmu50_core::pmu50::Structural;
use pmu50_core::signals::{self as table, Dir, Signal};
use pmu50_core::{Inputs, Internals, Outputs, Regs};

/// One row of the table for Python: kind, name (registers: `block.register`, the VCD path below
/// `pmu50`), width in bits in this structural configuration, and the table's documentation.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Row {
    pub kind: &'static str,
    pub name: String,
    pub width: u8,
    pub signed: bool,
    pub reset: Option<u64>,
    pub meaning: &'static str,
    pub patent: &'static str,
}

/// Python's name of a table kind.
pub fn kind(d: Dir) -> &'static str {
    match d {
        Dir::In => "input",
        Dir::Out => "output",
        Dir::Reg => "register",
        Dir::Internal => "internal",
    }
}

fn named<T>(s: &Structural, list: &[Signal<T>], v: &T) -> Vec<(&'static str, u8, u64)> {
    list.iter()
        .map(|x| (x.name, x.bits(s), (x.get)(v)))
        .collect()
}

/// The top-level inputs as (name, width, value), in port order.
pub fn input_values(i: &Inputs) -> Vec<(&'static str, u8, u64)> {
    // inputs have no structural width
    named(
        &Structural {
            sync_depth: 1,
            cnt_width: 16,
        },
        table::INPUTS,
        i,
    )
}

/// The top-level outputs as (name, width, value), in the order of docs/signals.md.
pub fn output_values(s: &Structural, o: &Outputs) -> Vec<(&'static str, u8, u64)> {
    named(s, table::OUTPUTS, o)
}

/// Every register as (block, name, width, value), in block evaluation order.
pub fn register_values(s: &Structural, r: &Regs) -> Vec<(&'static str, &'static str, u8, u64)> {
    table::REGISTERS
        .iter()
        .map(|x| (x.scope, x.name, x.bits(s), (x.get)(r)))
        .collect()
}

/// The combinational internals as (name, width, value).
pub fn internal_values(x: &Internals) -> Vec<(&'static str, u8, u64)> {
    named(
        &Structural {
            sync_depth: 1,
            cnt_width: 16,
        },
        table::INTERNALS,
        x,
    )
}

/// Set input `name` to `v` (already checked against its width). `false`: no such input.
pub fn set_input(i: &mut Inputs, name: &str, v: u64) -> bool {
    match table::INPUTS.iter().position(|x| x.name == name) {
        Some(k) => {
            table::INPUT_SETTERS[k](i, v);
            true
        }
        None => false,
    }
}

/// The whole table for one structural configuration (widths of `cnt_s`, `cnt_c` and
/// `action_switching.sync` depend on it): inputs, outputs, registers, internals.
pub fn table(s: &Structural, hdl: &[(&'static str, u64)]) -> Vec<Row> {
    fn rows<T>(
        s: &Structural,
        hdl: &[(&'static str, u64)],
        list: &[Signal<T>],
        out: &mut Vec<Row>,
    ) {
        for x in list {
            let reset = match x.reset {
                table::Reset::Value(v) => Some(v),
                table::Reset::Param(p) => hdl.iter().find(|(n, _)| *n == p).map(|(_, v)| *v),
                table::Reset::None => None,
            };
            let name = if x.dir == Dir::Reg {
                x.path()
            } else {
                x.name.to_string()
            };
            out.push(Row {
                kind: kind(x.dir),
                name,
                width: x.bits(s),
                signed: x.signed,
                reset,
                meaning: x.meaning,
                patent: x.patent,
            });
        }
    }
    let mut out = Vec::new();
    rows(s, hdl, table::INPUTS, &mut out);
    rows(s, hdl, table::OUTPUTS, &mut out);
    rows(s, hdl, table::REGISTERS, &mut out);
    rows(s, hdl, table::INTERNALS, &mut out);
    out
}
