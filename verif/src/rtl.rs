//! What the regression knows of an RTL under test without reading its inside: the port contract
//! of docs/signals.md.
//!
//! An RTL is a Verilog file list whose top module `pmu50` has the contract ports at the contract
//! widths ([`contract_ports`]). Its inside is the HDL team's own: other instance names, other
//! registers, or a flat gate-level netlist with no parameters and no hierarchy. This module
//! elaborates the file list once with Verilator (`--xml-only`, seconds) and reads from the XML:
//! - the top's ports with their widths, checked against the contract before any seed runs;
//! - the top's Verilog parameters and their default values: the parameters the top has are set
//!   per build (`-G`, Icarus `-P`), the ones it lacks are fixed by the RTL itself;
//! - every signal of the hierarchy (hierarchical name, width, module and variable), which a
//!   `--map` names and `pmu50 rtl-map` matches against the model's registers.
//!
//! Nothing here reads a register by name: a parameter that the top lacks is read back through
//! the register bus after reset ([`crate::dut::verilator`]'s probe), which every RTL with the
//! contract ports answers.

pub use crate::filelist::FileList;
use crate::shape::Shape;
use pmu50_core::params::{Params, HDL_NAMES};
use pmu50_core::pmu50::Structural;
use pmu50_core::signals::{self, Width};
use std::path::{Path, PathBuf};
use std::process::Command;

/// Most bytes of a tool's log kept for an error message.
const LOG_TAIL: usize = 4096;

/// How Verilator reads an RTL's delays and timing controls (`q <= #1 d`, `initial #5
/// $display(...)`): ignored (`--no-timing`), as synthesis ignores them. The same options for the
/// port check ([`elaborate`]) and every build of [`crate::dut::verilator`] (the coverage build
/// too), so an RTL that elaborates also builds. `--timing` would schedule each delay on
/// Verilator's timing wheel, which the library, stepped one evaluation per clock level and never
/// advancing time, would have to drive; it needs C++20 coroutines and slows every tick, for a
/// delay that the cycle-level contract (docs/hdl-guide.md) cannot observe: a delay is shorter
/// than the clock period, and what it changes is when, inside a cycle, a flop's new value
/// appears. Lint warnings these idioms raise (`ASSIGNDLY`, `STMTDLY`) do not stop a build
/// (`-Wno-fatal`): they are the lint's business.
pub const VERILATOR_TIMING: &[&str] = &["--no-timing"];

/// A bad RTL: what is wrong, where, and what is valid. Every variant is bad input (exit 2).
#[derive(Debug, thiserror::Error)]
pub enum RtlError {
    #[error(transparent)]
    FileList(#[from] crate::filelist::FileListError),
    #[error("--rtl {list}: `{tool}` is not installed (Debian package {package}; `make deps` installs it)")]
    NoTool {
        list: PathBuf,
        tool: &'static str,
        package: &'static str,
    },
    #[error("--rtl {list}: the RTL does not elaborate with {tool}:\n{log}")]
    Build {
        list: PathBuf,
        tool: &'static str,
        log: String,
    },
    /// Verilator elaborates the RTL, another simulator cannot read it (a SystemVerilog construct
    /// beyond it): where it stopped, and the advice.
    #[error("{at}: {tool} cannot read this ({what}), though Verilator elaborates the RTL: the simulator reads only part of SystemVerilog (docs/hdl-guide.md, \"SystemVerilog\"). Use `--dut verilator` for this RTL.\nits output:\n{log}")]
    Unsupported {
        /// `file:line` the simulator names, or the file list when it names none.
        at: String,
        tool: String,
        what: String,
        log: String,
    },
    #[error("--rtl {list}: the design has no module `pmu50` (the contract's top, docs/signals.md); modules: {modules}")]
    NoTop { list: PathBuf, modules: String },
    #[error("{file}: top `pmu50` lacks the contract port `{port}` ({dir}, {expected} bit(s), docs/signals.md)")]
    MissingPort {
        file: String,
        port: &'static str,
        dir: &'static str,
        expected: u32,
    },
    #[error("{file}:{line}: port `{port}` of `pmu50` is {actual} bit(s) wide, the contract (docs/signals.md) needs {expected}{why}")]
    PortWidth {
        file: String,
        line: u32,
        port: String,
        expected: u32,
        actual: u32,
        why: String,
    },
    #[error("{file}:{line}: port `{port}` of `pmu50` is an {actual}, the contract (docs/signals.md) needs an {expected}")]
    PortDir {
        file: String,
        line: u32,
        port: String,
        expected: &'static str,
        actual: String,
    },
    #[error("--rtl {list}: {what}")]
    Fixed { list: PathBuf, what: String },
    #[error("--rtl {list}: cannot read Verilator's XML of the design: {reason}")]
    Xml { list: PathBuf, reason: String },
    #[error("{0}")]
    Io(String),
}

/// A port's direction.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PortDir {
    Input,
    Output,
}

impl PortDir {
    fn name(self) -> &'static str {
        match self {
            PortDir::Input => "input",
            PortDir::Output => "output",
        }
    }
}

/// A contract port: its name, direction and width (which may depend on a structural
/// parameter).
#[derive(Clone, Copy, Debug)]
pub struct ContractPort {
    pub name: &'static str,
    pub dir: PortDir,
    pub width: Width,
}

/// The ports every RTL under test has: `clk`, `rst_n`, then the model's inputs and outputs
/// (docs/signals.md), in the order of the model's signal table.
pub fn contract_ports() -> Vec<ContractPort> {
    let mut v = vec![
        ContractPort {
            name: "clk",
            dir: PortDir::Input,
            width: Width::Bits(1),
        },
        ContractPort {
            name: "rst_n",
            dir: PortDir::Input,
            width: Width::Bits(1),
        },
    ];
    v.extend(signals::INPUTS.iter().map(|s| ContractPort {
        name: s.name,
        dir: PortDir::Input,
        width: s.width,
    }));
    v.extend(signals::OUTPUTS.iter().map(|s| ContractPort {
        name: s.name,
        dir: PortDir::Output,
        width: s.width,
    }));
    v
}

/// `pmu50 #(.P(P), ...) dut (.clk(clk), ...);`: an instance of the contract top with the
/// parameters `params` (none: no parameter list), every contract port connected to a net of
/// its name (the benches' instance of an RTL that lacks some parameters).
pub fn instance(params: &[String]) -> String {
    let ports: Vec<String> = contract_ports()
        .iter()
        .map(|p| format!(".{0}({0})", p.name))
        .collect();
    let params: Vec<String> = params.iter().map(|n| format!(".{n}({n})")).collect();
    if params.is_empty() {
        format!("    pmu50 dut (\n        {}\n    );\n", ports.join(", "))
    } else {
        format!(
            "    pmu50 #({}) dut (\n        {}\n    );\n",
            params.join(", "),
            ports.join(", ")
        )
    }
}

/// One signal of the elaborated hierarchy.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct HierSignal {
    /// `pmu50.timing_generator.tmr`, `pmu50.internals.kon`.
    pub path: String,
    pub width: u32,
    /// The module (definition) it is declared in, and its name there (what a Verilator
    /// configuration file names).
    pub module: String,
    pub var: String,
    /// A port of its module, or a parameter.
    pub is_port: bool,
    /// Its data type: a map may name a field or an element of it ([`Shape::select`]).
    pub shape: Shape,
}

/// The elaborated RTL, as Verilator's XML shows it.
#[derive(Clone, Debug)]
pub struct Design {
    /// The top's ports: name, direction, width, file and line.
    pub ports: Vec<(String, PortDir, u32, String, u32)>,
    /// The top's Verilog parameters with their values in this elaboration.
    pub params: Vec<(String, i64)>,
    /// Every variable of the hierarchy below `pmu50` (not parameters).
    pub signals: Vec<HierSignal>,
    /// Every file Verilator read.
    pub files_read: Vec<PathBuf>,
}

fn tail(s: &str) -> String {
    let s = s.trim_end();
    if s.len() <= LOG_TAIL {
        return s.to_string();
    }
    let mut start = s.len() - LOG_TAIL;
    while !s.is_char_boundary(start) {
        start += 1;
    }
    format!("...{}", &s[start..])
}

/// Whether a tool can be started (found on the PATH and executable).
pub fn have_tool(tool: &str) -> bool {
    let arg = if tool == "iverilog" {
        "-V"
    } else {
        "--version"
    };
    Command::new(tool)
        .arg(arg)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .status()
        .is_ok()
}

/// Elaborate `fl` with Verilator (`--xml-only`) with these top parameters, in `work` (a
/// scratch folder).
pub fn elaborate(
    fl: &FileList,
    gparams: &[(String, u64)],
    work: &Path,
) -> Result<Design, RtlError> {
    if !have_tool("verilator") {
        return Err(RtlError::NoTool {
            list: fl.list.clone(),
            tool: "verilator",
            package: "verilator",
        });
    }
    std::fs::create_dir_all(work).map_err(|e| RtlError::Io(format!("{}: {e}", work.display())))?;
    let xml = work.join("design.xml");
    let mut cmd = Command::new("verilator");
    cmd.arg("--xml-only")
        .arg("--xml-output")
        .arg(&xml)
        .arg("-Mdir")
        .arg(work)
        .args([
            "--top-module",
            "pmu50",
            "-Wno-fatal",
            "-Wno-lint",
            "-Wno-style",
        ])
        .args(VERILATOR_TIMING);
    cmd.args(fl.verilator_args());
    for (n, v) in gparams {
        cmd.arg(format!("-G{n}={v}"));
    }
    cmd.args(&fl.files);
    let out = cmd
        .output()
        .map_err(|e| RtlError::Io(format!("cannot run verilator: {e}")))?;
    let log =
        String::from_utf8_lossy(&out.stderr).into_owned() + &String::from_utf8_lossy(&out.stdout);
    if !out.status.success() || !xml.is_file() {
        if log.contains("Cannot find top module")
            || log.contains("Specified --top-module 'pmu50' was not found")
        {
            let modules = modules_of(fl);
            return Err(RtlError::NoTop {
                list: fl.list.clone(),
                modules: if modules.is_empty() {
                    "none".into()
                } else {
                    modules.join(", ")
                },
            });
        }
        return Err(RtlError::Build {
            list: fl.list.clone(),
            tool: "verilator",
            log: tail(&log),
        });
    }
    let text = std::fs::read_to_string(&xml)
        .map_err(|e| RtlError::Io(format!("{}: {e}", xml.display())))?;
    parse_xml(&text).map_err(|reason| RtlError::Xml {
        list: fl.list.clone(),
        reason,
    })
}

/// [`elaborate`], its XML kept in `cache` (a folder of this RTL's cache) with the hash of every
/// file Verilator read: an unchanged RTL is not elaborated again.
pub fn elaborate_cached(
    fl: &FileList,
    gparams: &[(String, u64)],
    work: &Path,
    cache: &Path,
) -> Result<Design, RtlError> {
    let key: String = gparams.iter().map(|(n, v)| format!("{n}={v};")).collect();
    let stem = cache.join(format!(
        "design-{:016x}",
        crate::cache::fnv(&[key.as_bytes()])
    ));
    let (xml, record) = (stem.with_extension("xml"), stem.with_extension("deps"));
    if let (true, Ok(text)) = (
        crate::cache::files_unchanged(&record),
        std::fs::read_to_string(&xml),
    ) {
        if let Ok(d) = parse_xml(&text) {
            return Ok(d);
        }
    }
    let d = elaborate(fl, gparams, work)?;
    let _ = std::fs::create_dir_all(cache);
    if std::fs::copy(work.join("design.xml"), xml.with_extension("xml.tmp")).is_ok()
        && std::fs::rename(xml.with_extension("xml.tmp"), &xml).is_ok()
    {
        let mut files = d.files_read.clone();
        files.extend(fl.files.iter().cloned());
        crate::cache::write_record(&record, &files);
    }
    Ok(d)
}

/// Module names declared in the files (for the message of a missing top).
fn modules_of(fl: &FileList) -> Vec<String> {
    let mut v = Vec::new();
    for f in &fl.files {
        if let Ok(t) = std::fs::read_to_string(f) {
            for l in t.lines() {
                let l = l.trim_start();
                if let Some(rest) = l.strip_prefix("module ") {
                    let name: String = rest
                        .trim_start()
                        .chars()
                        .take_while(|c| c.is_alphanumeric() || *c == '_' || *c == '$')
                        .collect();
                    if !name.is_empty() && !v.contains(&name) {
                        v.push(name);
                    }
                }
            }
        }
    }
    v
}

/// Read Verilator's XML (`--xml-only`) of a design whose top is `pmu50`.
pub fn parse_xml(text: &str) -> Result<Design, String> {
    let doc = roxmltree::Document::parse(text).map_err(|e| e.to_string())?;
    let root = doc.root_element();
    // file ids -> names
    let mut file_names = std::collections::HashMap::new();
    let mut files_read = Vec::new();
    if let Some(files) = root.children().find(|n| n.has_tag_name("files")) {
        for f in files.children().filter(|n| n.has_tag_name("file")) {
            let (Some(id), Some(name)) = (f.attribute("id"), f.attribute("filename")) else {
                continue;
            };
            file_names.insert(id.to_string(), name.to_string());
            if !name.starts_with('<') {
                files_read.push(PathBuf::from(name));
            }
        }
    }
    let netlist = root
        .children()
        .find(|n| n.has_tag_name("netlist"))
        .ok_or("no <netlist>")?;
    // the data types, resolved to their shapes (widths, struct members, arrays)
    let mut type_nodes = std::collections::HashMap::new();
    if let Some(tt) = netlist.children().find(|n| n.has_tag_name("typetable")) {
        for t in tt.children().filter(|n| n.is_element()) {
            if let Some(id) = t.attribute("id") {
                type_nodes.insert(id.to_string(), t);
            }
        }
    }
    let mut shapes: std::collections::HashMap<String, Shape> = std::collections::HashMap::new();
    for id in type_nodes.keys() {
        shapes.insert(id.clone(), shape_of(id, &type_nodes, 0));
    }
    let modules: std::collections::HashMap<&str, roxmltree::Node> = netlist
        .children()
        .filter(|n| n.has_tag_name("module"))
        .filter_map(|m| m.attribute("name").map(|n| (n, m)))
        .collect();
    let top = netlist
        .children()
        .find(|n| n.has_tag_name("module") && n.attribute("topModule") == Some("1"))
        .ok_or("no top module")?;
    if top.attribute("origName").or(top.attribute("name")) != Some("pmu50") {
        return Err(format!(
            "the top module is `{}`, not `pmu50`",
            top.attribute("name").unwrap_or("?")
        ));
    }
    let loc = |n: &roxmltree::Node| -> (String, u32) {
        let l = n.attribute("loc").unwrap_or("");
        let mut it = l.split(',');
        let file = it
            .next()
            .and_then(|id| file_names.get(id))
            .cloned()
            .unwrap_or_else(|| "?".into());
        let line = it.next().and_then(|s| s.parse().ok()).unwrap_or(0);
        (file, line)
    };
    let shape_of_var = |n: &roxmltree::Node| -> Shape {
        n.attribute("dtype_id")
            .and_then(|d| shapes.get(d))
            .cloned()
            .unwrap_or_else(|| Shape::Other("?".into()))
    };
    let width_of = |n: &roxmltree::Node| shape_of_var(n).width();
    let mut ports = Vec::new();
    let mut params = Vec::new();
    for v in top.children().filter(|n| n.has_tag_name("var")) {
        let name = v
            .attribute("origName")
            .or(v.attribute("name"))
            .unwrap_or("")
            .to_string();
        if v.attribute("param") == Some("true") {
            let value = v
                .descendants()
                .find(|n| n.has_tag_name("const"))
                .and_then(|c| c.attribute("name"))
                .and_then(verilog_int);
            if let Some(value) = value {
                params.push((name, value));
            }
            continue;
        }
        if let Some(dir) = v.attribute("dir") {
            let d = match dir {
                "input" => PortDir::Input,
                "output" => PortDir::Output,
                other => {
                    let (file, line) = loc(&v);
                    return Err(format!("{file}:{line}: port `{name}` is an {other} port"));
                }
            };
            let (file, line) = loc(&v);
            ports.push((name, d, width_of(&v), file, line));
        }
    }
    // the hierarchy: cells (instances) with their module, from <cells>
    let mut signals = Vec::new();
    let mut stack: Vec<(String, String)> = Vec::new();
    if let Some(cells) = root.children().find(|n| n.has_tag_name("cells")) {
        for c in cells.descendants().filter(|n| n.has_tag_name("cell")) {
            if let (Some(hier), Some(m)) = (c.attribute("hier"), c.attribute("submodname")) {
                stack.push((hier.to_string(), m.to_string()));
            }
        }
    }
    if stack.is_empty() {
        stack.push((
            "pmu50".into(),
            top.attribute("name").unwrap_or("pmu50").into(),
        ));
    }
    for (hier, mname) in &stack {
        let Some(m) = modules.get(mname.as_str()) else {
            continue;
        };
        let orig = m.attribute("origName").unwrap_or(mname).to_string();
        collect_vars(*m, hier, &orig, &shape_of_var, &mut signals);
    }
    Ok(Design {
        ports,
        params,
        signals,
        files_read,
    })
}

/// The variables of a module body and of its named blocks (generate scopes).
fn collect_vars(
    node: roxmltree::Node,
    prefix: &str,
    module: &str,
    shape_of: &dyn Fn(&roxmltree::Node) -> Shape,
    out: &mut Vec<HierSignal>,
) {
    for c in node.children().filter(|n| n.is_element()) {
        if c.has_tag_name("var") {
            if c.attribute("param") == Some("true") || c.attribute("localparam") == Some("true") {
                continue;
            }
            let name = c
                .attribute("origName")
                .or(c.attribute("name"))
                .unwrap_or("")
                .to_string();
            let shape = shape_of(&c);
            out.push(HierSignal {
                path: format!("{prefix}.{name}"),
                width: shape.width(),
                shape,
                module: module.to_string(),
                var: c.attribute("name").unwrap_or("").to_string(),
                is_port: c.attribute("dir").is_some(),
            });
        } else if c.has_tag_name("begin") {
            match c.attribute("name") {
                Some(n) if !n.is_empty() => {
                    collect_vars(c, &format!("{prefix}.{n}"), module, shape_of, out)
                }
                _ => collect_vars(c, prefix, module, shape_of, out),
            }
        } else if c.has_tag_name("func") || c.has_tag_name("task") || c.has_tag_name("instance") {
            continue;
        }
    }
}

/// The shape of data type `id` of Verilator's type table (`basicdtype`, `refdtype`,
/// `enumdtype`, `structdtype`, `uniondtype`, `packarraydtype`, `unpackarraydtype`).
fn shape_of(
    id: &str,
    nodes: &std::collections::HashMap<String, roxmltree::Node>,
    depth: u32,
) -> Shape {
    let Some(t) = nodes.get(id) else {
        return Shape::Other(format!("type {id}"));
    };
    if depth > 64 {
        return Shape::Other("a type nested too deep".into());
    }
    let sub = |t: &roxmltree::Node| {
        t.attribute("sub_dtype_id")
            .map_or(Shape::Other("?".into()), |s| shape_of(s, nodes, depth + 1))
    };
    // an array's range: its <range> child's two constants
    let range = |t: &roxmltree::Node| -> Option<(i64, i64)> {
        let r = t.children().find(|n| n.has_tag_name("range"))?;
        let mut c = r
            .children()
            .filter(|n| n.has_tag_name("const"))
            .filter_map(|n| n.attribute("name").and_then(verilog_int));
        Some((c.next()?, c.next()?))
    };
    let attr = |n: &str| t.attribute(n).and_then(|s| s.parse::<i64>().ok());
    match t.tag_name().name() {
        "basicdtype" => match (attr("left"), attr("right")) {
            (Some(left), Some(right)) => Shape::Bits { left, right },
            _ => match t.attribute("name") {
                Some("logic" | "bit" | "reg" | "wire") | None => Shape::bit(),
                Some("int" | "integer") => Shape::Bits { left: 31, right: 0 },
                Some("byte") => Shape::Bits { left: 7, right: 0 },
                Some("shortint") => Shape::Bits { left: 15, right: 0 },
                Some("longint") => Shape::Bits { left: 63, right: 0 },
                Some(other) => Shape::Other(other.to_string()),
            },
        },
        "refdtype" | "enumdtype" | "typedefdtype" | "constdtype" => sub(t),
        "structdtype" | "uniondtype" => Shape::Struct {
            name: t.attribute("name").unwrap_or("").to_string(),
            union: t.has_tag_name("uniondtype"),
            members: t
                .children()
                .filter(|n| n.has_tag_name("memberdtype"))
                .map(|m| (m.attribute("name").unwrap_or("").to_string(), sub(&m)))
                .collect(),
        },
        "packarraydtype" | "unpackarraydtype" => {
            let (left, right) = range(t)
                .or_else(|| Some((attr("left")?, attr("right")?)))
                .unwrap_or((0, 0));
            let elem = Box::new(sub(t));
            if t.has_tag_name("packarraydtype") {
                Shape::Packed { left, right, elem }
            } else {
                Shape::Unpacked { left, right, elem }
            }
        }
        other => Shape::Other(other.to_string()),
    }
}

/// A Verilator XML constant: `32'sh5`, `32'h294`, `1'h1`, `5`.
fn verilog_int(s: &str) -> Option<i64> {
    let (_, v) = s.split_once('\'').unwrap_or(("", s));
    let v = v.trim_start_matches('s');
    let (radix, digits) = match v.chars().next()? {
        'h' => (16, &v[1..]),
        'd' => (10, &v[1..]),
        'b' => (2, &v[1..]),
        'o' => (8, &v[1..]),
        _ => (10, v),
    };
    let u = u64::from_str_radix(&digits.replace('_', ""), radix).ok()?;
    // a signed 32-bit integer parameter
    if s.contains("'s") && s.starts_with("32") && u & 0x8000_0000 != 0 {
        return Some(u as i64 - (1i64 << 32));
    }
    Some(u as i64)
}

impl Design {
    /// The value of a top parameter in this elaboration.
    pub fn param(&self, name: &str) -> Option<i64> {
        self.params.iter().find(|(n, _)| n == name).map(|(_, v)| *v)
    }

    /// The names of [`HDL_NAMES`] the top lacks (fixed by the RTL).
    pub fn missing_params(&self) -> Vec<&'static str> {
        HDL_NAMES
            .iter()
            .copied()
            .filter(|n| self.param(n).is_none())
            .collect()
    }

    /// Check the top's ports against the contract for a core of structure `s`: every contract
    /// port present, with its direction and width. Extra ports are allowed (inputs tied to 0).
    pub fn check_contract(&self, s: &Structural) -> Result<(), RtlError> {
        let top_file = self
            .ports
            .first()
            .map(|p| p.3.clone())
            .unwrap_or_else(|| "pmu50".into());
        for c in contract_ports() {
            let expected = u32::from(c.width.bits(s));
            let Some((name, dir, actual, file, line)) = self.ports.iter().find(|p| p.0 == c.name)
            else {
                return Err(RtlError::MissingPort {
                    file: top_file,
                    port: c.name,
                    dir: c.dir.name(),
                    expected,
                });
            };
            if *dir != c.dir {
                return Err(RtlError::PortDir {
                    file: file.clone(),
                    line: *line,
                    port: name.clone(),
                    expected: c.dir.name(),
                    actual: dir.name().into(),
                });
            }
            if *actual != expected {
                let why = match c.width {
                    Width::CntWidth => format!(" (CNT_W = {})", s.cnt_width),
                    Width::SyncDepth => format!(" (SYNC_DEPTH = {})", s.sync_depth),
                    Width::Bits(_) => String::new(),
                };
                return Err(RtlError::PortWidth {
                    file: file.clone(),
                    line: *line,
                    port: name.clone(),
                    expected,
                    actual: *actual,
                    why,
                });
            }
        }
        Ok(())
    }

    /// The width of a top port.
    pub fn port_width(&self, name: &str) -> Option<u32> {
        self.ports.iter().find(|p| p.0 == name).map(|p| p.2)
    }

    /// A signal of the hierarchy by its path.
    pub fn signal(&self, path: &str) -> Option<&HierSignal> {
        self.signals.iter().find(|s| s.path == path)
    }

    /// A map's name resolved: the signal it starts with (the longest path of the hierarchy
    /// that begins it) and the bits of it that the rest selects (`.field`, `[i]`, `[hi:lo]`).
    /// `None`: no signal begins the name; `Some(Err)`: the signal has no such field or index.
    pub fn resolve(
        &self,
        name: &str,
    ) -> Option<(&HierSignal, Result<crate::shape::Selection, String>)> {
        let (sig, rest) = crate::shape::split_signal(name, |p| self.signal(p).is_some())?;
        let s = self.signal(sig)?;
        Some((s, s.shape.select(rest)))
    }
}

/// What an RTL fixes itself: the parameters its top lacks, with the values the RTL has (read
/// back through the bus after reset). Every seed keeps these values.
#[derive(Clone, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Fixed {
    /// (Verilog parameter name, value), in [`HDL_NAMES`] order.
    pub values: Vec<(String, u64)>,
}

impl Fixed {
    pub fn is_empty(&self) -> bool {
        self.values.is_empty()
    }

    pub fn get(&self, name: &str) -> Option<u64> {
        self.values.iter().find(|(n, _)| n == name).map(|(_, v)| *v)
    }

    /// `p` with the fixed values put in.
    pub fn apply(&self, p: &Params) -> Params {
        let mut q = *p;
        for (n, v) in &self.values {
            let _ = q.set_hdl_parameter(n, *v);
        }
        q
    }

    /// Whether `p` has every fixed value.
    pub fn holds(&self, p: &Params) -> bool {
        self.apply(p) == *p
    }

    /// `SYNC_DEPTH=2, CNT_W=16, ...` for a message.
    pub fn text(&self) -> String {
        self.values
            .iter()
            .map(|(n, v)| format!("{n}={v}"))
            .collect::<Vec<_>>()
            .join(", ")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn verilog_constants_read_in_every_radix() {
        assert_eq!(verilog_int("32'sh294"), Some(660));
        assert_eq!(verilog_int("32'h5"), Some(5));
        assert_eq!(verilog_int("1'h1"), Some(1));
        assert_eq!(verilog_int("32'sd12"), Some(12));
        assert_eq!(verilog_int("32'shffffffff"), Some(-1));
        assert_eq!(verilog_int("8'b1010_0000"), Some(160));
        assert_eq!(verilog_int("x"), None);
    }

    #[test]
    fn the_contract_has_clock_reset_inputs_and_outputs_in_table_order() {
        let c = contract_ports();
        assert_eq!(c.len(), 2 + signals::N_INPUTS + signals::N_OUTPUTS);
        assert_eq!((c[0].name, c[1].name, c[2].name), ("clk", "rst_n", "ig"));
        assert!(c
            .iter()
            .any(|p| p.name == "cnt_s" && p.width == Width::CntWidth && p.dir == PortDir::Output));
    }
}
