//! The contract of the top `pmu50`: its ports (name, direction, width) and its parameters (name,
//! default, legal range on its own), from the core's tables: the signal table
//! (`pmu50_core::signals`: the inputs and outputs, and the HDL-only clock and reset) and the
//! parameter table (`pmu50_core::params`: the Verilog names, defaults and [`LEGAL`] ranges).
//!
//! `pmu50 hdl coverage-monitor` writes it as hdl/formal/pmu50_contract.json (the formal kit reads
//! its inputs, outputs and default parameter set from there) beside the monitor, whose top
//! (hdl/formal/pmu50_cov_top.sv) declares the twin's ports and parameters from it. The Verilog
//! that must stay plain and keep literal values (hdl/pmu50.v, hdl/rtl/*.v,
//! hdl/formal/pmu50_formal.sv) is compared with it by rtl_model/coverage/tests/contract.rs.

use pmu50_core::params::{HDL_DEFAULTS, HDL_NAMES, LEGAL};
use pmu50_core::signals::{Width, HDL_ONLY_PORTS, INPUTS, OUTPUTS};
use std::fmt::Write as _;

/// The top module's name.
pub const TOP: &str = "pmu50";
/// Its clock (rising edge).
pub const CLOCK: &str = "clk";
/// Its power-on reset, active low.
pub const RESET: &str = "rst_n";

/// Direction of a port.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Direction {
    In,
    Out,
}

impl Direction {
    /// As Verilog writes it.
    pub const fn verilog(self) -> &'static str {
        match self {
            Direction::In => "input",
            Direction::Out => "output",
        }
    }

    /// As the contract file writes it.
    pub const fn name(self) -> &'static str {
        match self {
            Direction::In => "in",
            Direction::Out => "out",
        }
    }
}

/// One port of the top.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Port {
    pub name: &'static str,
    pub direction: Direction,
    pub width: Width,
}

impl Port {
    /// The width as written in the contract file: a number of bits, or the name of the
    /// structural parameter that sets it.
    pub fn width_json(&self) -> String {
        match self.width {
            Width::Bits(b) => b.to_string(),
            w => format!("\"{}\"", w.doc()),
        }
    }

    /// The range of a Verilog declaration: `""` for one bit, `[7:0]`, `[CNT_W-1:0]`.
    pub fn verilog_range(&self) -> String {
        match self.width {
            Width::Bits(1) => String::new(),
            Width::Bits(b) => format!("[{}:0]", b - 1),
            w => format!("[{}-1:0]", w.doc()),
        }
    }
}

/// One parameter of the top.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Parameter {
    /// The Verilog name (`SI_MAX`).
    pub name: &'static str,
    /// The `[core]` field of a scenario that sets it (`x`).
    pub field: &'static str,
    pub default: u64,
    /// The least and the greatest legal value on its own (docs/spec.md 4; the rules between
    /// parameters are `Params::validate`'s).
    pub min: u64,
    pub max: u64,
}

/// The ports of the top in declaration order: clock and reset, then the inputs and the
/// outputs in the order of the core's signal table (the vector file's columns).
pub fn ports() -> Vec<Port> {
    let hdl_only = HDL_ONLY_PORTS.iter().map(|&(name, bits, dir, _)| Port {
        name,
        direction: if dir == "out" {
            Direction::Out
        } else {
            Direction::In
        },
        width: Width::Bits(bits),
    });
    let inputs = INPUTS.iter().map(|s| Port {
        name: s.name,
        direction: Direction::In,
        width: s.width,
    });
    let outputs = OUTPUTS.iter().map(|s| Port {
        name: s.name,
        direction: Direction::Out,
        width: s.width,
    });
    hdl_only.chain(inputs).chain(outputs).collect()
}

/// The parameters of the top in the order of the parameter table (the `// param` lines of a
/// vector file).
pub fn parameters() -> Vec<Parameter> {
    HDL_NAMES
        .iter()
        .zip(HDL_DEFAULTS)
        .map(|(&name, &default)| {
            // every name has its entry (a test of pmu50-core)
            let legal = LEGAL.iter().find(|l| l.hdl == name);
            let (min, max) = legal.map_or((0, 0), |l| l.range());
            Parameter {
                name,
                field: legal.map_or("", |l| l.field),
                default,
                min,
                max,
            }
        })
        .collect()
}

/// hdl/formal/pmu50_contract.json: one line per parameter and per port.
pub fn json() -> String {
    let mut v = String::from("{\n");
    v.push_str(
        "  \"generated\": \"by `pmu50 hdl coverage-monitor` from the core's signal and parameter \
         tables (rtl_model/core/src/signals.rs, params.rs): do not edit; a test keeps this file \
         equal to the generator's output\",\n",
    );
    let _ = writeln!(
        v,
        "  \"top\": \"{TOP}\",\n  \"clock\": \"{CLOCK}\",\n  \"reset\": \"{RESET}\",\n  \"reset_active\": \"low\","
    );
    v.push_str("  \"parameters\": [\n");
    let params = parameters();
    for (i, p) in params.iter().enumerate() {
        let _ = writeln!(
            v,
            "    {{\"name\": \"{}\", \"field\": \"{}\", \"default\": {}, \"min\": {}, \"max\": {}}}{}",
            p.name,
            p.field,
            p.default,
            p.min,
            p.max,
            if i + 1 < params.len() { "," } else { "" }
        );
    }
    v.push_str("  ],\n  \"ports\": [\n");
    let ports = ports();
    for (i, p) in ports.iter().enumerate() {
        let _ = writeln!(
            v,
            "    {{\"name\": \"{}\", \"direction\": \"{}\", \"width\": {}, \"max_width\": {}}}{}",
            p.name,
            p.direction.name(),
            p.width_json(),
            p.width.max_bits(),
            if i + 1 < ports.len() { "," } else { "" }
        );
    }
    v.push_str("  ]\n}\n");
    v
}

/// The parameter declarations of a module header with the top's parameters and defaults
/// (`    parameter integer SI_MAX     = 660,`), each line ending in a comma.
pub fn verilog_parameters() -> String {
    let mut v = String::new();
    for p in parameters() {
        let _ = writeln!(v, "    parameter integer {:<10} = {},", p.name, p.default);
    }
    v
}

/// The port declarations of a module header with the top's ports
/// (`    output wire [CNT_W-1:0] cnt_s,`), each line ending in a comma.
pub fn verilog_ports() -> String {
    let mut v = String::new();
    for p in ports() {
        let _ = writeln!(
            v,
            "    {:<6} wire {:<11} {},",
            p.direction.verilog(),
            p.verilog_range(),
            p.name
        );
    }
    v
}

/// The parameter list of an instance of the top that passes each parameter of its own name
/// (`.SYNC_DEPTH(SYNC_DEPTH), .CNT_W(CNT_W), ...`), six to a line, each line indented by
/// `indent`.
pub fn verilog_parameter_map(indent: &str) -> String {
    parameters()
        .chunks(6)
        .map(|c| {
            let items: Vec<String> = c.iter().map(|p| format!(".{0}({0})", p.name)).collect();
            format!("{indent}{}", items.join(", "))
        })
        .collect::<Vec<_>>()
        .join(",\n")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_parameter_has_its_legal_range_and_its_default_is_in_it() {
        let params = parameters();
        assert_eq!(params.len(), HDL_NAMES.len());
        for p in &params {
            assert!(!p.field.is_empty(), "{}: no [core] field", p.name);
            assert!(p.min <= p.default && p.default <= p.max, "{p:?}");
        }
    }

    #[test]
    fn ports_start_with_clock_and_reset_and_are_unique() {
        let ports = ports();
        assert_eq!(ports[0].name, CLOCK);
        assert_eq!(ports[1].name, RESET);
        let mut names: Vec<&str> = ports.iter().map(|p| p.name).collect();
        names.sort_unstable();
        names.dedup();
        assert_eq!(names.len(), ports.len());
        assert_eq!(ports.len(), 2 + INPUTS.len() + OUTPUTS.len());
    }

    #[test]
    fn the_json_is_json_with_every_port_and_parameter() {
        let doc: serde_json::Value = serde_json::from_str(&json()).unwrap();
        assert_eq!(doc["ports"].as_array().unwrap().len(), ports().len());
        let cnt_s = doc["ports"]
            .as_array()
            .unwrap()
            .iter()
            .find(|p| p["name"] == "cnt_s")
            .unwrap();
        assert_eq!(cnt_s["width"], "CNT_W");
        assert_eq!(cnt_s["max_width"], 16);
        let si_max = doc["parameters"]
            .as_array()
            .unwrap()
            .iter()
            .find(|p| p["name"] == "SI_MAX")
            .unwrap();
        assert_eq!(
            (
                &si_max["field"],
                &si_max["default"],
                &si_max["min"],
                &si_max["max"]
            ),
            (
                &serde_json::json!("x"),
                &serde_json::json!(660),
                &serde_json::json!(1),
                &serde_json::json!(65535)
            )
        );
    }

    #[test]
    fn verilog_declarations() {
        assert!(verilog_ports().contains("    output wire [CNT_W-1:0] cnt_s,\n"));
        assert!(verilog_ports().contains("    input  wire [7:0]       bus_addr,\n"));
        assert!(verilog_ports().starts_with("    input  wire             clk,\n"));
        assert!(verilog_parameters().contains("    parameter integer SI_MAX     = 660,\n"));
        let map = verilog_parameter_map("  ");
        assert!(map.starts_with("  .SYNC_DEPTH(SYNC_DEPTH), .CNT_W(CNT_W),"));
        assert!(map.ends_with(".SMP_ON(SMP_ON)"));
    }
}
