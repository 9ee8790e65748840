//! The top's contract (`pmu50_coverage::contract`) against the Verilog that restates it by hand:
//! the twin's top hdl/pmu50.v (its parameters with their defaults, its ports with their
//! directions and widths), every parameter default written in the twin's blocks and
//! testbenches (hdl/rtl/*.v, hdl/tb/), and the formal top hdl/formal/pmu50_formal.sv (its
//! parameters, its inputs, the nets it gives the DUT's outputs). These files stay plain Verilog
//! with literal values; a hand edit that drifts from the core's tables fails here. The
//! generated hdl/formal/pmu50_contract.json is checked with the monitor (tests/monitor.rs).

use pmu50_coverage::contract::{self, Direction, Port};
use std::path::{Path, PathBuf};

fn hdl() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../hdl")
}

fn read(rel: &str) -> String {
    std::fs::read_to_string(hdl().join(rel)).unwrap_or_else(|e| panic!("hdl/{rel}: {e}"))
}

/// The text without its comments (`//` to the end of the line, `/* */`), lines kept.
fn strip_comments(text: &str) -> String {
    let mut out = String::new();
    let mut rest = text;
    while !rest.is_empty() {
        let line = rest.find("//");
        let block = rest.find("/*");
        let line_first = match (line, block) {
            (Some(l), Some(b)) => l < b,
            (l, _) => l.is_some(),
        };
        match (line, block) {
            (Some(l), _) if line_first => {
                out.push_str(&rest[..l]);
                rest = &rest[l..];
                rest = rest.find('\n').map_or("", |n| &rest[n..]);
            }
            (_, Some(b)) => {
                out.push_str(&rest[..b]);
                let end = rest[b..].find("*/").map_or(rest.len(), |e| b + e + 2);
                // keep the line count
                out.extend(rest[b..end].chars().filter(|c| *c == '\n'));
                rest = &rest[end..];
            }
            _ => {
                out.push_str(rest);
                rest = "";
            }
        }
    }
    out
}

/// The text between the bracket at `open` and its match.
fn bracketed(text: &str, open: usize) -> &str {
    let mut depth = 0;
    for (i, c) in text[open..].char_indices() {
        match c {
            '(' => depth += 1,
            ')' => {
                depth -= 1;
                if depth == 0 {
                    return &text[open + 1..open + i];
                }
            }
            _ => {}
        }
    }
    panic!("unbalanced brackets from byte {open}")
}

/// A module header: its parameters (name, default as written) and its ports (direction,
/// width as the contract writes it, name), in order.
struct Header {
    params: Vec<(String, String)>,
    ports: Vec<(String, String, String)>,
}

/// A Verilog range as the contract writes a width: `""` -> `1`, `[7:0]` -> `8`,
/// `[CNT_W-1:0]` -> `CNT_W`.
fn width_of(range: &str) -> String {
    let r = range.replace(' ', "");
    if r.is_empty() {
        return "1".into();
    }
    let inner = r.trim_start_matches('[').trim_end_matches(']');
    let (hi, lo) = inner.split_once(':').unwrap_or((inner, "0"));
    assert_eq!(lo, "0", "range {range} does not end at 0");
    match hi.parse::<u32>() {
        Ok(h) => (h + 1).to_string(),
        Err(_) => hi.strip_suffix("-1").unwrap_or(hi).to_string(),
    }
}

/// The header of module `name` in `text` (ANSI style: `module m #(parameter ...) (input ...);`).
fn header(text: &str, name: &str, file: &str) -> Header {
    let text = strip_comments(text);
    let at = text
        .find(&format!("module {name}"))
        .unwrap_or_else(|| panic!("{file}: no module {name}"));
    let mut rest = at + "module ".len() + name.len();
    let mut params = vec![];
    let after = text[rest..].trim_start();
    if after.starts_with('#') {
        let open = rest + text[rest..].find('(').unwrap();
        let list = bracketed(&text, open);
        for item in list.split(',') {
            let words: Vec<&str> = item.split_whitespace().collect();
            // parameter [integer|int] NAME = VALUE
            let eq = words
                .iter()
                .position(|w| *w == "=")
                .unwrap_or_else(|| panic!("{file}: parameter `{}` has no default", item.trim()));
            params.push((words[eq - 1].to_string(), words[eq + 1..].join(" ")));
        }
        rest = open + list.len() + 2;
    }
    let open = rest + text[rest..].find('(').unwrap();
    let list = bracketed(&text, open);
    let mut ports = vec![];
    let (mut dir, mut range) = (String::new(), String::new());
    for item in list.split(',') {
        let mut item = item.trim();
        for d in ["input", "output", "inout"] {
            if let Some(r) = item.strip_prefix(d) {
                dir = d.to_string();
                range.clear();
                item = r.trim_start();
                for kind in ["wire", "reg", "logic"] {
                    item = item.strip_prefix(kind).unwrap_or(item).trim_start();
                }
                if item.starts_with('[') {
                    let end = item.find(']').unwrap() + 1;
                    range = item[..end].to_string();
                    item = item[end..].trim_start();
                }
            }
        }
        ports.push((dir.clone(), width_of(&range), item.to_string()));
    }
    Header { params, ports }
}

fn contract_params() -> Vec<(String, String)> {
    contract::parameters()
        .iter()
        .map(|p| (p.name.to_string(), p.default.to_string()))
        .collect()
}

fn port_row(p: &Port) -> (String, String, String) {
    (
        p.direction.verilog().to_string(),
        p.width_json().trim_matches('"').to_string(),
        p.name.to_string(),
    )
}

#[test]
fn the_twins_top_has_the_contracts_parameters_and_ports() {
    let h = header(&read("pmu50.v"), contract::TOP, "hdl/pmu50.v");
    assert_eq!(h.params, contract_params(), "hdl/pmu50.v: parameters");
    let want: Vec<_> = contract::ports().iter().map(port_row).collect();
    assert_eq!(h.ports, want, "hdl/pmu50.v: ports");
}

/// Every Verilog file of hdl/ that is not generated, relative to hdl/.
fn verilog_files() -> Vec<String> {
    fn walk(dir: &Path, rel: &str, out: &mut Vec<String>) {
        let mut entries: Vec<_> = std::fs::read_dir(dir).unwrap().flatten().collect();
        entries.sort_by_key(|e| e.file_name());
        for e in entries {
            let name = e.file_name().to_string_lossy().to_string();
            let r = if rel.is_empty() {
                name.clone()
            } else {
                format!("{rel}/{name}")
            };
            if e.path().is_dir() {
                if name != "build" && name != "ffi" {
                    walk(&e.path(), &r, out);
                }
            } else if name.ends_with(".v") || name.ends_with(".sv") {
                out.push(r);
            }
        }
    }
    let mut out = vec![];
    walk(&hdl(), "", &mut out);
    out
}

#[test]
fn every_default_written_in_the_verilog_is_the_contracts() {
    let want = contract_params();
    let mut seen = 0;
    let files = verilog_files();
    for f in &files {
        let text = strip_comments(&read(f));
        // `parameter [integer|int] NAME = VALUE` in a header (`,` or `)` after it) or a body (`;`)
        for decl in text.split("parameter").skip(1) {
            let words: Vec<&str> = decl
                .split(|c: char| c.is_whitespace() || c == ',' || c == ';' || c == ')')
                .filter(|w| !w.is_empty())
                .take(4)
                .collect();
            let words: Vec<&str> = words
                .into_iter()
                .filter(|w| *w != "integer" && *w != "int")
                .collect();
            let [name, "=", value, ..] = words.as_slice() else {
                continue;
            };
            if let Some((_, default)) = want.iter().find(|(n, _)| n == name) {
                assert_eq!(
                    value, default,
                    "hdl/{f}: parameter {name} = {value}, the contract's default is {default} (rtl_model/core/src/params.rs)"
                );
                seen += 1;
            }
        }
    }
    // the top, the register file, the formal top, the monitor's top and the testbenches
    // each write the whole set; the blocks their own
    assert!(
        seen >= 5 * want.len(),
        "only {seen} defaults found in {files:?}"
    );
    let rf = header(
        &read("rtl/register_file.v"),
        "register_file",
        "hdl/rtl/register_file.v",
    );
    assert_eq!(rf.params, want, "hdl/rtl/register_file.v: parameters");
}

#[test]
fn the_formal_top_has_the_contracts_parameters_inputs_and_outputs() {
    let file = "hdl/formal/pmu50_formal.sv";
    let text = read("formal/pmu50_formal.sv");
    let h = header(&text, "pmu50_formal", file);
    assert_eq!(h.params, contract_params(), "{file}: parameters");
    // its inputs: the clock and the DUT's inputs (it makes the reset itself)
    let want: Vec<_> = contract::ports()
        .iter()
        .filter(|p| p.direction == Direction::In && p.name != contract::RESET)
        .map(port_row)
        .collect();
    assert_eq!(h.ports, want, "{file}: ports");
    // the DUT's outputs: a net of each name and width (`wire [W] a, b;`)
    let body = strip_comments(&text);
    let mut nets: Vec<(String, String)> = vec![];
    for stmt in body.split(';') {
        let s = stmt.trim();
        let Some(decl) = s.strip_prefix("wire") else {
            continue;
        };
        if decl.contains('=') {
            continue;
        }
        let decl = decl.trim_start();
        let (range, names) = if decl.starts_with('[') {
            decl.split_at(decl.find(']').unwrap() + 1)
        } else {
            ("", decl)
        };
        for n in names.split(',') {
            nets.push((n.trim().to_string(), width_of(range)));
        }
    }
    for p in contract::ports()
        .iter()
        .filter(|p| p.direction == Direction::Out)
    {
        let w = p.width_json().trim_matches('"').to_string();
        assert!(
            nets.contains(&(p.name.to_string(), w.clone())),
            "{file}: no net `{}` of width {w} for the DUT's output",
            p.name
        );
    }
    // the DUT gets every parameter
    let inst = body.find("pmu50 #(").expect("no instance of pmu50");
    let map = bracketed(&body, inst + "pmu50 #".len()).replace(char::is_whitespace, "");
    for p in contract::parameters() {
        assert!(
            map.contains(&format!(".{0}({0})", p.name)),
            "{file}: the DUT's parameter {} is not passed",
            p.name
        );
    }
}

#[test]
fn the_parser_reads_what_a_drift_would_change() {
    // the checks above can fail: a changed default, a narrowed port, a lost parameter
    let twin = read("pmu50.v");
    let h = header(
        &twin.replace("SI_MAX     = 660", "SI_MAX     = 661"),
        "pmu50",
        "x",
    );
    assert_ne!(h.params, contract_params());
    let h = header(
        &twin.replace("[7:0]       bus_addr", "[6:0]       bus_addr"),
        "pmu50",
        "x",
    );
    assert!(h
        .ports
        .contains(&("input".into(), "7".into(), "bus_addr".into())));
    let h = header(
        &twin.replace("output wire [CNT_W-1:0] cnt_s", "output wire [15:0] cnt_s"),
        "pmu50",
        "x",
    );
    assert!(h
        .ports
        .contains(&("output".into(), "16".into(), "cnt_s".into())));
    assert_eq!(
        strip_comments("a // b\n/* c\n d */ e"),
        "a \n\n e",
        "comments go, lines stay"
    );
}

#[test]
fn the_docs_register_map_gives_the_contracts_defaults() {
    // docs/spec.md's register map: `| 0x06 | SI_MAX | 16 | RW | 660 | ... |`; CTRL is ADAPTIVE
    let spec = std::fs::read_to_string(hdl().join("../docs/spec.md")).unwrap();
    for p in contract::parameters() {
        if p.name == "SYNC_DEPTH" || p.name == "CNT_W" {
            continue; // structural: the CFG register reads them
        }
        let reg = if p.name == "ADAPTIVE" { "CTRL" } else { p.name };
        let row = spec
            .lines()
            .find(|l| l.split('|').nth(2).map(str::trim) == Some(reg))
            .unwrap_or_else(|| panic!("docs/spec.md: no register map row for {reg}"));
        let reset = row.split('|').nth(5).map(str::trim);
        assert_eq!(
            reset,
            Some(p.default.to_string().as_str()),
            "docs/spec.md: {row}"
        );
    }
}
