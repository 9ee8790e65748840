//! The coverage model as synthesizable Verilog: the module `pmu50_cov`, generated from the
//! declaration of [`crate::model`] (each bin's `sv` expression, each point's `when`), with one
//! wire `hit_<bin>` per bin, points and crosses, and the vector `hits` in the model's storage
//! order ([`crate::Layout::bins`]). It reads the twin's ports, registers, internals and a few
//! next-state nets ([`SIGNALS`]: the same names as hdl/pmu50.map.toml and the formal kit), so it
//! binds to the twin (hdl/pmu50.v) by hierarchical names: `pmu50_cov_top` (Verilator) connects
//! them as `dut.<path>`, hdl/formal/coverage.py with yosys `connect`.
//!
//! `hit_<bin>` is 1 in the cycle before the clock edge at which the Rust sampler
//! ([`crate::Coverage::sample`]) counts the bin, from the same values: registers and ports
//! before the edge, the inputs applied at it, the internals of the cycle, the next state. A
//! configuration bin is hit in the first cycle out of reset and at a taken write that changes
//! the parameters (the class of the new set), as [`crate::Coverage::new`] and the sampler count
//! it; in a cross it is the class of the parameters in force.
//!
//! `pmu50 hdl coverage-monitor` writes hdl/formal/pmu50_cov.sv, hdl/formal/pmu50_cov_top.sv, the
//! table hdl/formal/pmu50_cov.json and the top's contract hdl/formal/pmu50_contract.json
//! ([`files`]); a test keeps the committed files equal to these.

use crate::contract;
use crate::model::{crosses, Point, Sampled, POINTS};
use crate::sample::layout;
use std::fmt::Write as _;

/// Where a monitor input comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Source {
    /// The twin's port of the same name (inputs and outputs of docs/signals.md).
    Port,
    /// A net inside the twin, by its hierarchical name below the `pmu50` instance.
    Net(&'static str),
}

/// One input of the monitor: name, width (Verilog), source, meaning.
#[derive(Clone, Copy, Debug)]
pub struct Signal {
    pub name: &'static str,
    pub width: &'static str,
    pub source: Source,
    pub meaning: &'static str,
}

const fn port(name: &'static str, width: &'static str, meaning: &'static str) -> Signal {
    Signal {
        name,
        width,
        source: Source::Port,
        meaning,
    }
}

const fn net(
    name: &'static str,
    width: &'static str,
    path: &'static str,
    meaning: &'static str,
) -> Signal {
    Signal {
        name,
        width,
        source: Source::Net(path),
        meaning,
    }
}

/// The monitor's inputs: every name the bins' expressions may use, besides the helpers that
/// [`verilog`] derives from them.
pub const SIGNALS: &[Signal] = &[
    port("rst_n", "1", "asynchronous reset, active low"),
    port("ig", "1", "key input, applied at the edge"),
    port("cmp_s", "1", "sine comparator, applied at the edge"),
    port("cmp_c", "1", "cosine comparator, applied at the edge"),
    port("bus_we", "1", "MPU write strobe"),
    port("bus_addr", "8", "MPU address"),
    port("bus_wdata", "16", "MPU write data"),
    port("sig", "1", "synchronized key (before the edge)"),
    port("smp", "1", "sampling strobe"),
    port("sr", "1", "Vs2 power-good, registered"),
    port("cs", "1", "sine latch"),
    port("cc", "1", "cosine latch"),
    port("cnt_s", "CNT_W", "sine counter"),
    port("cnt_c", "CNT_W", "cosine counter"),
    port("cnt_r", "8", "power supply count CNTr"),
    port("si", "16", "drive interval"),
    port("hist_s", "1", "change history of Cs"),
    port("hist_c", "1", "change history of Cc"),
    port("diag", "1", "count diagnosis flag"),
    port("quadrant_skip", "1", "sticky skip flag"),
    port("bus_err", "1", "sticky refusal flag"),
    port("vs2_ok", "1", "Vs2 power-good, applied at the edge"),
    port("vs2_en", "1", "Vs2 enable"),
    net(
        "sync",
        "SYNC_DEPTH",
        "action_switching.sync",
        "synchronizer flops",
    ),
    net(
        "tmr",
        "16",
        "timing_generator.tmr",
        "timer of the output cycle",
    ),
    net("adaptive", "1", "register_file.adaptive", "CTRL.adaptive"),
    net("pw", "16", "register_file.pw", "Pw"),
    net("pi", "16", "register_file.pi", "Pi"),
    net("ps", "16", "register_file.ps", "Ps"),
    net("si_max", "16", "register_file.si_max", "x"),
    net("si_min", "16", "register_file.si_min", "min"),
    net("t1", "16", "register_file.t1", "T1"),
    net("t2", "16", "register_file.t2", "T2"),
    net("cth", "8", "register_file.cth", "Cth"),
    net(
        "smp_on",
        "16",
        "register_file.smp_on",
        "on-key sampling period",
    ),
    net("kon", "1", "internals.kon", "sig rises at this edge"),
    net("koff", "1", "internals.koff", "sig falls at this edge"),
    net(
        "upd",
        "1",
        "internals.upd",
        "the latches sample at this edge",
    ),
    net("first", "1", "internals.first", "the first sample"),
    net("chg_s", "1", "internals.chg_s", "Cs changes at this sample"),
    net("chg_c", "1", "internals.chg_c", "Cc changes at this sample"),
    net(
        "skip_clr",
        "1",
        "internals.skip_clr",
        "W1C of STATUS.quadrant_skip",
    ),
    net(
        "fig17",
        "3",
        "internals.fig17",
        "FIG. 17 path (docs/spec.md 2.6 encoding)",
    ),
    net("fig18", "3", "internals.fig18", "FIG. 18 path"),
    net(
        "si_n",
        "16",
        "drive_interval.si_n",
        "drive interval after the edge",
    ),
    net(
        "cnt_r_n",
        "8",
        "drive_interval.cnt_r_n",
        "CNTr after the edge",
    ),
    net(
        "vld",
        "1",
        "comparator_latch.vld",
        "a first sample was taken",
    ),
    net(
        "cnt_s_n",
        "CNT_W",
        "updown_counter.cnt_s_nxt",
        "sine counter after the edge",
    ),
    net(
        "cnt_c_n",
        "CNT_W",
        "updown_counter.cnt_c_nxt",
        "cosine counter after the edge",
    ),
    net(
        "in_range_n",
        "1",
        "count_diagnosis.in_range",
        "|cnt_s - cnt_c| < 2 after the edge",
    ),
    net(
        "skip_n",
        "1",
        "updown_counter.skip_nxt",
        "quadrant_skip after the edge",
    ),
    net(
        "param_wr",
        "1",
        "register_file.param_wr",
        "a legal parameter write is taken",
    ),
    net(
        "c_legal",
        "1",
        "register_file.c_legal",
        "the candidate parameter set is legal",
    ),
    net(
        "c_adaptive",
        "1",
        "register_file.c_adaptive",
        "candidate CTRL.adaptive",
    ),
    net("c_pw", "16", "register_file.c_pw", "candidate Pw"),
    net("c_pi", "16", "register_file.c_pi", "candidate Pi"),
    net("c_ps", "16", "register_file.c_ps", "candidate Ps"),
    net("c_si_max", "16", "register_file.c_si_max", "candidate x"),
    net("c_si_min", "16", "register_file.c_si_min", "candidate min"),
    net("c_t1", "16", "register_file.c_t1", "candidate T1"),
    net("c_t2", "16", "register_file.c_t2", "candidate T2"),
    net("c_cth", "8", "register_file.c_cth", "candidate Cth"),
    net(
        "c_smp_on",
        "16",
        "register_file.c_smp_on",
        "candidate smp_on",
    ),
];

/// The parameter registers a configuration bin's expression may name; in the class after a
/// write each `x` reads `c_x`.
const PARAMS: [&str; 10] = [
    "adaptive", "pw", "pi", "ps", "si_max", "si_min", "t1", "t2", "cth", "smp_on",
];

/// The Verilog name of a bin: `hit_` and its full name with `.` as `__` and the `*` of a cross
/// as `__X__` (bin names are lower case and never hold `__`, so the map is one to one).
pub fn wire_name(bin: &str) -> String {
    let mut s = String::from("hit_");
    for ch in bin.chars() {
        match ch {
            '.' => s.push_str("__"),
            '*' => s.push_str("__X__"),
            c if c.is_ascii_alphanumeric() || c == '_' => s.push(c),
            _ => s.push('_'),
        }
    }
    s
}

fn ident(point: &Point) -> String {
    format!("{}__{}", point.group, point.name)
}

/// `expr` with each parameter register `x` renamed `c_x` (whole identifiers only).
fn candidate(expr: &str) -> String {
    let mut out = String::new();
    let mut word = String::new();
    let flush = |w: &mut String, out: &mut String| {
        if PARAMS.contains(&w.as_str()) {
            out.push_str("c_");
        }
        out.push_str(w);
        w.clear();
    };
    let mut prev_tick = false;
    for ch in expr.chars() {
        if ch.is_ascii_alphanumeric() || ch == '_' {
            // a sized literal's digits and base (16'd300, 8'hFF) are no identifier
            if word.is_empty() && (ch.is_ascii_digit() || prev_tick) {
                out.push(ch);
                prev_tick = prev_tick && ch.is_ascii_alphanumeric();
                continue;
            }
            word.push(ch);
        } else {
            flush(&mut word, &mut out);
            out.push(ch);
            prev_tick = ch == '\'';
        }
    }
    flush(&mut word, &mut out);
    out
}

/// First-match wires `<prefix>_<k>` over the bins' expressions (optionally rewritten).
fn first_match(v: &mut String, prefix: &str, point: &Point, rewrite: impl Fn(&str) -> String) {
    for (k, b) in point.bins.iter().enumerate() {
        let _ = writeln!(v, "    wire {prefix}_m{k} = {};", rewrite(b.sv));
    }
    for k in 0..point.bins.len() {
        let mut terms = vec![format!("{prefix}_m{k}")];
        terms.extend((0..k).map(|j| format!("!{prefix}_m{j}")));
        let _ = writeln!(v, "    wire {prefix}_{k} = {};", terms.join(" && "));
    }
}

/// The monitor module `pmu50_cov`.
pub fn verilog() -> String {
    let l = layout();
    let mut v = String::new();
    v.push_str(HEADER);
    v.push_str("module pmu50_cov #(\n");
    // the structural parameters, with the top's defaults
    for p in contract::parameters()
        .iter()
        .filter(|p| ["SYNC_DEPTH", "CNT_W"].contains(&p.name))
    {
        let _ = writeln!(v, "    parameter integer {:<10} = {},", p.name, p.default);
    }
    v.push_str("    parameter integer CLOCK_NS   = 10000   // the run's clock period (config.clock)\n) (\n    input  wire clk,\n");
    for s in SIGNALS {
        let w = if s.width == "1" {
            "      ".to_string()
        } else if s.width.chars().all(|c| c.is_ascii_digit()) {
            format!("[{}:0]", s.width.parse::<u32>().unwrap_or(1) - 1)
        } else {
            format!("[{}-1:0]", s.width)
        };
        let from = match s.source {
            Source::Port => "port".to_string(),
            Source::Net(p) => p.to_string(),
        };
        let _ = writeln!(
            v,
            "    input  wire {w:<15} {:<14} // {}: {}",
            format!("{},", s.name),
            from,
            s.meaning
        );
    }
    let _ = writeln!(
        v,
        "    output wire [{}:0] hits  // bit i: bin i of the model (pmu50_cov.json)\n);",
        l.bins.len() - 1
    );
    v.push_str(HELPERS);

    // points
    for (pi, p) in POINTS.iter().enumerate() {
        let id = ident(p);
        let off = l.point_offset[pi];
        let _ = writeln!(
            v,
            "\n    // ---- {}.{} ({}): {}",
            p.group, p.name, p.cite, p.meaning
        );
        match p.sampled {
            Sampled::Edge => {
                let _ = writeln!(v, "    wire {id}__sel = rst_n && ({});", p.when);
                first_match(&mut v, &format!("{id}__b"), p, |s| s.to_string());
                for (k, _) in p.bins.iter().enumerate() {
                    let _ = writeln!(
                        v,
                        "    wire {} = {id}__sel && {id}__b_{k};",
                        wire_name(&l.bins[off + k].name)
                    );
                }
            }
            Sampled::Config => {
                first_match(&mut v, &format!("{id}__lvl"), p, |s| s.to_string());
                first_match(&mut v, &format!("{id}__nxt"), p, candidate);
                for (k, _) in p.bins.iter().enumerate() {
                    let _ = writeln!(
                        v,
                        "    wire {} = (cfg_start && {id}__lvl_{k}) || (cfg_change && {id}__nxt_{k});",
                        wire_name(&l.bins[off + k].name)
                    );
                }
            }
        }
    }
    // crosses
    for (c, &off) in crosses().zip(&l.cross_offset) {
        let (pa, pb) = (&POINTS[c.rows], &POINTS[c.columns]);
        let _ = writeln!(
            v,
            "\n    // ---- cross {} ({}): {}",
            c.name, c.cite, c.meaning
        );
        let sel = |p: &Point, pi: usize, k: usize| match p.sampled {
            Sampled::Edge => wire_name(&l.bins[l.point_offset[pi] + k].name),
            Sampled::Config => format!("{}__lvl_{k}", ident(p)),
        };
        for ka in 0..pa.bins.len() {
            for kb in 0..pb.bins.len() {
                let i = off + ka * pb.bins.len() + kb;
                let _ = writeln!(
                    v,
                    "    wire {} = {} && {};",
                    wire_name(&l.bins[i].name),
                    sel(pa, c.rows, ka),
                    sel(pb, c.columns, kb)
                );
            }
        }
    }
    v.push_str("\n    assign hits = {\n");
    let names: Vec<String> = l.bins.iter().rev().map(|b| wire_name(&b.name)).collect();
    for (i, chunk) in names.chunks(4).enumerate() {
        let sep = if (i + 1) * 4 >= names.len() { "" } else { "," };
        let _ = writeln!(v, "        {}{sep}", chunk.join(", "));
    }
    v.push_str("    };\nendmodule\n/* verilator lint_on UNUSEDSIGNAL */\n/* verilator lint_on WIDTH */\n\n`default_nettype wire\n");
    v
}

/// `pmu50_cov_top` for simulation: the twin and the monitor over it, connected by hierarchical
/// names; `hits` is a port.
pub fn verilog_top() -> String {
    let l = layout();
    let mut v = String::from(TOP_HEADER);
    // the twin's parameters and ports, from the top's contract
    v.push_str(&contract::verilog_parameters());
    v.push_str("    parameter integer CLOCK_NS   = 10000\n) (\n");
    v.push_str(&contract::verilog_ports());
    let _ = writeln!(
        v,
        "    output wire [{}:0] hits\n);\n    {} #(\n{}\n    ) dut (\n{}\n    );\n",
        l.bins.len() - 1,
        contract::TOP,
        contract::verilog_parameter_map("        "),
        contract::ports()
            .iter()
            .map(|p| format!("        .{0}({0})", p.name))
            .collect::<Vec<_>>()
            .join(",\n")
    );
    v.push_str(
        "    pmu50_cov #(.SYNC_DEPTH(SYNC_DEPTH), .CNT_W(CNT_W), .CLOCK_NS(CLOCK_NS)) cov (\n        .clk(clk),\n",
    );
    for s in SIGNALS {
        let src = match s.source {
            Source::Port => s.name.to_string(),
            Source::Net(p) => format!("dut.{p}"),
        };
        let _ = writeln!(v, "        .{}({src}),", s.name);
    }
    v.push_str("        .hits(hits)\n    );\nendmodule\n\n`default_nettype wire\n");
    v
}

/// Every file `pmu50 hdl coverage-monitor` writes (into hdl/formal): its name and its text.
/// The monitor, its simulation top, its table and the top's contract
/// ([`contract::json`]).
pub fn files() -> [(&'static str, String); 4] {
    [
        ("pmu50_cov.sv", verilog()),
        ("pmu50_cov_top.sv", verilog_top()),
        ("pmu50_cov.json", table_json()),
        ("pmu50_contract.json", contract::json()),
    ]
}

fn json_str(s: &str) -> String {
    serde_json::to_string(s).unwrap_or_else(|_| "\"\"".into())
}

/// The table of the monitor: every bin with its wire, kind, declared reason if unreachable,
/// whether only port-level stimuli reach it; and the monitor's inputs with their sources.
pub fn table_json() -> String {
    let l = layout();
    let mut v = String::from("{\n  \"model_id\": ");
    v.push_str(&json_str(&crate::model_id(l)));
    v.push_str(",\n  \"signals\": [\n");
    for (i, s) in SIGNALS.iter().enumerate() {
        let src = match s.source {
            Source::Port => "port".to_string(),
            Source::Net(p) => p.to_string(),
        };
        let _ = writeln!(
            v,
            "    {{\"name\": {}, \"width\": {}, \"source\": {}}}{}",
            json_str(s.name),
            json_str(s.width),
            json_str(&src),
            if i + 1 < SIGNALS.len() { "," } else { "" }
        );
    }
    v.push_str("  ],\n  \"bins\": [\n");
    let config: Vec<bool> = l
        .bins
        .iter()
        .map(|b| {
            POINTS.iter().any(|p| {
                p.sampled == Sampled::Config
                    && b.name.starts_with(&format!("{}.{}.", p.group, p.name))
            })
        })
        .collect();
    for (i, b) in l.bins.iter().enumerate() {
        let _ = writeln!(
            v,
            "    {{\"index\": {i}, \"name\": {}, \"wire\": {}, \"kind\": {}, \"config\": {}, \"port_only\": {}, \"unreachable\": {}}}{}",
            json_str(&b.name),
            json_str(&wire_name(&b.name)),
            json_str(match b.kind {
                crate::Kind::Point => "point",
                crate::Kind::Cross => "cross",
            }),
            config[i],
            b.port_only,
            b.unreachable.map(json_str).unwrap_or_else(|| "null".into()),
            if i + 1 < l.bins.len() { "," } else { "" }
        );
    }
    v.push_str("  ]\n}\n");
    v
}

const HEADER: &str =
    "// GENERATED by `pmu50 hdl coverage-monitor` from the coverage model (rtl_model/coverage/src/
// model.rs): do not edit; a test keeps this file equal to the generator's output.
//
// pmu50_cov: the functional coverage model of the PMU 50 core as a synthesizable monitor. One
// wire hit_<bin> per bin (`group.point.bin` with `.` as `__`; a cross `cross.<name>.<a>*<b>` with
// `*` as `__X__`; the table is hdl/formal/pmu50_cov.json), 1 in the cycle before the clock edge
// at which the model's sampler counts the bin. Inputs: the twin's ports, registers, internals
// and next-state nets, named as in hdl/pmu50.map.toml (each input's comment says where it
// comes from below the pmu50 instance). hdl/formal/pmu50_cov_top.sv binds it to the twin for
// simulation; hdl/formal/coverage.py proves each unreachable bin's `!hit` and covers the others.
// The bins' expressions rely on Verilog's context widths (a sized operand widens the compare).
`default_nettype none
/* verilator lint_off WIDTH */
/* verilator lint_off UNUSEDSIGNAL */

";

const HELPERS: &str = "
    // ---- helpers
    // configuration bins: first cycle out of reset, and a taken write that changes the set
    reg started;
    always @(posedge clk or negedge rst_n)
        if (!rst_n) started <= 1'b0;
        else        started <= 1'b1;
    wire cfg_start  = rst_n && !started;
    wire cfg_change = rst_n && param_wr &&
        ({c_adaptive, c_pw, c_pi, c_ps, c_si_max, c_si_min, c_t1, c_t2, c_cth, c_smp_on} !=
         {adaptive, pw, pi, ps, si_max, si_min, t1, t2, cth, smp_on});
    // counter extremes at CNT_W bits (two's complement)
    localparam [CNT_W-1:0] CNT_TOP = {1'b0, {(CNT_W-1){1'b1}}};
    localparam [CNT_W-1:0] CNT_MIN = {1'b1, {(CNT_W-1){1'b0}}};
    // a key edge still inside the synchronizer
    wire in_flight = (sync != {SYNC_DEPTH{1'b0}}) && (sync != {SYNC_DEPTH{1'b1}});
    // count diagnosis after the edge (docs/spec.md 2.7)
    wire diag_n = !in_range_n || skip_n;
    // the timer against the output window, in 18 bits
    wire [17:0] t18  = {2'b00, tmr};
    wire [17:0] pw18 = {2'b00, pw};
    wire [17:0] pi18 = {2'b00, pi};
    wire [17:0] wt18 = pw18 + pi18 + {2'b00, ps};
    // register map
    wire is_param = (bus_addr >= 8'h02) && (bus_addr <= 8'h0B);
    wire readable = (bus_addr <= 8'h0C) || ((bus_addr >= 8'h10) && (bus_addr <= 8'h14));
    // legality rules of the candidate set (docs/spec.md 4)
    wire c_zero = (c_ps == 16'd0) || (c_si_max == 16'd0) || (c_si_min == 16'd0) ||
                  (c_t1 == 16'd0) || (c_t2 == 16'd0) || (c_smp_on == 16'd0);
    wire c_no_settle = (c_pw == 16'd0) && (c_pi == 16'd0);
    // the candidate's window Wt and shortest interval, in 18 bits
    wire [17:0] c_wt18  = {2'b00, c_pw} + {2'b00, c_pi} + {2'b00, c_ps};
    wire [17:0] c_short = {2'b00, c_adaptive ? c_si_min : c_si_max};
    // thirds of [min, x]: th_si with the ends (0 = min, 1-3, 4 = x), th_si_n of the interval
    // after the edge without them
    wire [16:0] th_span  = (si_max > si_min) ? {1'b0, si_max - si_min} : 17'd1;
    wire [17:0] th_pos   = ((si > si_min) ? {2'b00, si - si_min} : 18'd0) * 18'd3;
    wire [17:0] th_pos_n = ((si_n > si_min) ? {2'b00, si_n - si_min} : 18'd0) * 18'd3;
    wire [2:0]  th_si    = (si <= si_min) ? 3'd0 : (si >= si_max) ? 3'd4 :
                           (th_pos <= {1'b0, th_span}) ? 3'd1 :
                           (th_pos <= {th_span, 1'b0}) ? 3'd2 : 3'd3;
    wire [2:0]  th_si_n  = (th_pos_n <= {1'b0, th_span}) ? 3'd1 :
                           (th_pos_n <= {th_span, 1'b0}) ? 3'd2 : 3'd3;
";

const TOP_HEADER: &str = "// GENERATED by `pmu50 hdl coverage-monitor`: do not edit.
//
// pmu50_cov_top: the twin (hdl/pmu50.v) with the coverage monitor pmu50_cov over it, its
// internal inputs connected by hierarchical names (simulation: Verilator, Icarus).
`default_nettype none

module pmu50_cov_top #(
";
