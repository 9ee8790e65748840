//! `--dut icarus`: an RTL with the contract ports on Icarus Verilog, replaying the model's vector
//! file of each seed (hdl/tb/tb_vectors.v, verification method 1), which compares every output
//! after every edge.
//!
//! The RTL is analysed as for Verilator ([`super::verilator::VerilatorDut::prepare`]: ports,
//! parameters, what it fixes) and compiled once with its default parameters before any seed: an
//! RTL that does not compile is bad input. It is compiled as SystemVerilog (`-g2012`); what
//! Verilator elaborates and Icarus cannot read is refused with the file and line Icarus names and
//! the advice to use `--dut verilator`. Each seed's parameter set is compiled once (`-P`, the
//! reset values too) and cached on disk with the list of every file iverilog read (`-M`), so an
//! edited `` `include ``d file is compiled again. A top that lacks some parameters gets an
//! instance with the ones it has. The verdict comes from a file the bench writes (`+verdict`),
//! never from the simulator's output, which the RTL can print on; that output is kept to its
//! last [`LOG_KEEP`] bytes.

use super::api::{Backend, Build, Caps, Dut, DutError, InFlight, Needs, Recorded};
use super::failure::{divergence, dut_failure, timed_out};
use super::verilator::VerilatorDut;
use crate::cache::fnv;
use crate::check::Failure;
use crate::gen::Pins;
use crate::lockstep::{self, Mismatch, LOG_KEEP};
use crate::rtl::{self, FileList, Fixed, RtlError};
use pmu50_core::params::Params;
use pmu50_testbench::scenario::Scenario;
use std::collections::HashMap;
use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::sync::{Arc, Mutex, OnceLock};
use std::time::{Duration, Instant};

/// The bench, carried by the binary.
const TB_VECTORS: &str = include_str!("../../../hdl/tb/tb_vectors.v");

type Slot = Arc<OnceLock<Result<PathBuf, String>>>;

pub struct IcarusDut {
    list: FileList,
    /// The parameters the top has (the others are fixed).
    top_params: Vec<String>,
    fixed: Fixed,
    root: PathBuf,
    tb: PathBuf,
    compiles: Mutex<HashMap<String, Slot>>,
    scratch: tempfile::TempDir,
    notes: Vec<String>,
    /// The leases of this RTL's cache folder and of every compile this run uses
    /// ([`crate::cache`]).
    leases: Mutex<Vec<std::fs::File>>,
}

impl IcarusDut {
    pub fn prepare(list: &Path, pins: Pins) -> Result<IcarusDut, DutError> {
        let fl = FileList::read(list).map_err(RtlError::from)?;
        if !rtl::have_tool("iverilog") {
            return Err(RtlError::NoTool {
                list: fl.list.clone(),
                tool: "iverilog",
                package: "iverilog",
            }
            .into());
        }
        // The analysis (ports, parameters, what the RTL fixes) is Verilator's.
        let v = VerilatorDut::prepare(list, None, pins)?;
        let (top_params, fixed, notes) = (v.top_param_names(), v.fixed().clone(), v.notes());
        drop(v);
        let scratch = tempfile::Builder::new()
            .prefix("pmu50-iv.")
            .tempdir()
            .map_err(|e| DutError::Tool(format!("a scratch folder: {e}")))?;
        lockstep::register_scratch(scratch.path());
        let mut key = Vec::new();
        for f in &fl.files {
            key.push(f.as_os_str().as_encoded_bytes().to_vec());
            key.push(
                std::fs::read(f).map_err(|e| DutError::Tool(format!("{}: {e}", f.display())))?,
            );
        }
        // the defines, libraries and included files of the list too
        key.push(fl.content_hash().map_err(RtlError::from)?.into_bytes());
        let refs: Vec<&[u8]> = key.iter().map(|v| v.as_slice()).collect();
        let root = crate::cache::cache_dir()
            .join("icarus")
            .join(format!("{:016x}", fnv(&refs)));
        // a cap that is not a size is refused before any build
        crate::cache::cache_max().map_err(DutError::Tool)?;
        std::fs::create_dir_all(&root)
            .map_err(|e| DutError::Tool(format!("{}: {e}", root.display())))?;
        let rtl_lease = crate::cache::rtl_lease(&root, &fl.list)
            .map_err(|e| DutError::Tool(format!("{}: {e}", root.display())))?;
        let tb = root.join(format!(
            "tb_vectors_{:016x}.v",
            fnv(&[TB_VECTORS.as_bytes()])
        ));
        if !tb.is_file() {
            pmu50_testbench::atomic_file::write_atomic(&tb, TB_VECTORS.as_bytes())
                .and_then(|f| {
                    let mut b = pmu50_testbench::atomic_file::Batch::new();
                    b.add(f);
                    b.commit()
                })
                .map_err(|e| DutError::Tool(e.to_string()))?;
        }
        let dut = IcarusDut {
            list: fl.clone(),
            top_params,
            fixed,
            root,
            tb,
            compiles: Mutex::new(HashMap::new()),
            scratch,
            notes,
            leases: Mutex::new(vec![rtl_lease]),
        };
        // Compiled once with the defaults: an RTL Icarus refuses fails now.
        let p = dut.fixed.apply(&Params {
            sync_depth: pins.sync_depth.unwrap_or(Params::default().sync_depth),
            cnt_width: pins.cnt_width.unwrap_or(Params::default().cnt_width),
            ..Params::default()
        });
        // Verilator elaborated the RTL above: what Icarus refuses is beyond Icarus.
        dut.compiled(&p, 10_000)
            .map_err(|log| unsupported(&log, &fl.list))?;
        Ok(dut)
    }

    /// The bench compiled for these parameters and clock, from the cache or now (once).
    fn compiled(&self, p: &Params, clock_ns: u64) -> Result<PathBuf, String> {
        let mut args: Vec<String> = p
            .hdl_parameters()
            .iter()
            .map(|(n, v)| format!("-Ptb_vectors.{n}={v}"))
            .collect();
        args.push(format!("-Ptb_vectors.CLOCK_NS={clock_ns}"));
        if !clock_ns.is_multiple_of(2000) {
            args.push("-DTB_TIMESCALE_NS".into());
        }
        let key = format!(
            "{:016x}",
            fnv(&[
                args.join(" ").as_bytes(),
                self.top_params.join(",").as_bytes(),
                TB_VECTORS.as_bytes()
            ])
        );
        let slot = self
            .compiles
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .entry(key.clone())
            .or_default()
            .clone();
        slot.get_or_init(|| {
            // leased, and compiled once under its lock (another process compiling it
            // meanwhile is waited for)
            let vvp = self.root.join(format!("{key}.vvp"));
            let deps = self.root.join(format!("{key}.deps"));
            let (lease, vvp) = crate::cache::obtain(
                &vvp,
                || (vvp.is_file() && crate::cache::files_unchanged(&deps)).then(|| vvp.clone()),
                || self.compile_now(&key, args.clone()),
            )?;
            self.leases
                .lock()
                .unwrap_or_else(|e| e.into_inner())
                .push(lease);
            crate::cache::trim_to_cap();
            Ok(vvp)
        })
        .clone()
    }

    /// Compile `key` now into `<key>.vvp`, its record of the files read in `<key>.deps`.
    fn compile_now(&self, key: &str, mut args: Vec<String>) -> Result<(), String> {
        let vvp = self.root.join(format!("{key}.vvp"));
        let deps = self.root.join(format!("{key}.deps"));
        std::fs::create_dir_all(&self.root).map_err(|e| format!("{}: {e}", self.root.display()))?;
        let tmp = tempfile::Builder::new()
            .prefix(&format!(".compile-{key}-"))
            .tempdir_in(&self.root)
            .map_err(|e| format!("{}: {e}", self.root.display()))?;
        if self.top_params.len() < pmu50_core::params::HDL_NAMES.len() {
            // the instance with the parameters the top has
            let inst = rtl::instance(&self.top_params);
            std::fs::write(tmp.path().join("tb_dut_inst.vh"), inst).map_err(|e| e.to_string())?;
            args.push("-DTB_DUT_INST".into());
            args.push(format!("-I{}", tmp.path().display()));
        }
        args.extend(self.list.iverilog_args());
        let out_vvp = tmp.path().join("tb.vvp");
        let depfile = tmp.path().join("deps.txt");
        let o = Command::new("iverilog")
            .args([
                "-g2012",
                "-Wall",
                "-Wno-timescale",
                "-Wno-implicit-dimensions",
                "-Wno-portbind",
                "-s",
                "tb_vectors",
                "-o",
            ])
            .arg(&out_vvp)
            .arg(format!("-M{}", depfile.display()))
            .args(&args)
            .arg(&self.tb)
            .args(&self.list.files)
            .output()
            .map_err(|e| format!("cannot run iverilog: {e}"))?;
        let log =
            String::from_utf8_lossy(&o.stderr).into_owned() + &String::from_utf8_lossy(&o.stdout);
        if !o.status.success() || !out_vvp.is_file() {
            let lines: Vec<&str> = log.lines().filter(|l| !l.trim().is_empty()).collect();
            return Err(lines[lines.len().saturating_sub(12)..].join("\n"));
        }
        // every file iverilog read, with a hash of each
        let mut files: Vec<PathBuf> = std::fs::read_to_string(&depfile)
            .unwrap_or_default()
            .lines()
            .map(|l| PathBuf::from(l.trim()))
            .filter(|p| p.is_file() && !p.starts_with(tmp.path()))
            .collect();
        files.extend(self.list.files.iter().cloned());
        // the compile, then its record: a compile killed between leaves a record that does
        // not match, never an old compile with a new record
        std::fs::rename(&out_vvp, &vvp).map_err(|e| e.to_string())?;
        crate::cache::write_record(&deps, &files);
        Ok(())
    }
}

/// The error of an RTL that Verilator elaborates and Icarus does not compile: the first
/// `file:line` of Icarus's output that names a file of the RTL (not Icarus's own source, as an
/// internal assertion does), what it says there, and the advice to use Verilator.
fn unsupported(log: &str, list: &Path) -> RtlError {
    let version = Command::new("iverilog")
        .arg("-V")
        .output()
        .ok()
        .and_then(|o| {
            String::from_utf8_lossy(&o.stdout)
                .lines()
                .next()
                .map(|l| l.trim().to_string())
        })
        .filter(|l| l.starts_with("Icarus Verilog"))
        .map(|l| {
            // `Icarus Verilog version 11.0 (stable) ()` -> `Icarus Verilog 11.0`
            let v = l.split_whitespace().nth(3).unwrap_or("");
            format!("Icarus Verilog {v}").trim_end().to_string()
        })
        .unwrap_or_else(|| "Icarus Verilog".into());
    let found = log.lines().find_map(|l| {
        let mut it = l.splitn(3, ':');
        let (file, line, rest) = (it.next()?, it.next()?, it.next().unwrap_or(""));
        let line: u32 = line.trim().parse().ok()?;
        let is_rtl = !file.ends_with(".cc") && !file.ends_with(".h") && Path::new(file).is_file();
        is_rtl.then(|| (format!("{file}:{line}"), rest.trim().to_string()))
    });
    let what = if log.contains("Assertion") {
        "Icarus stopped on an internal assertion".to_string()
    } else {
        found
            .as_ref()
            .map(|(_, w)| w.clone())
            .filter(|w| !w.is_empty())
            .unwrap_or_else(|| "it does not compile".into())
    };
    RtlError::Unsupported {
        at: found.map_or_else(|| format!("--rtl {}", list.display()), |(at, _)| at),
        tool: version,
        what,
        log: log.to_string(),
    }
}

/// A seed's vvp run.
struct Running {
    child: Child,
    started: Instant,
    output: Option<std::thread::JoinHandle<String>>,
    verdict: PathBuf,
    _vec: tempfile::NamedTempFile,
    /// The vector lines of the seed's file: a pass must have replayed exactly these.
    expect_ticks: u64,
}

impl Running {
    fn kill(&mut self) {
        let g = self.child.id() as libc::pid_t;
        // SAFETY: kill(2) with the negated id of the group the child leads.
        unsafe { libc::kill(-g, libc::SIGKILL) };
        let _ = self.child.wait();
        lockstep::unregister_child(g);
    }
}

impl Drop for Running {
    fn drop(&mut self) {
        self.kill();
        let _ = std::fs::remove_file(&self.verdict);
    }
}

/// Read a child's output to its end, keeping the last [`LOG_KEEP`] bytes.
fn keep_tail(mut r: impl Read) -> String {
    let mut kept: Vec<u8> = Vec::new();
    let mut chunk = [0u8; 65536];
    loop {
        match r.read(&mut chunk) {
            Ok(0) | Err(_) => break,
            Ok(n) => {
                kept.extend_from_slice(&chunk[..n]);
                let keep = LOG_KEEP as usize;
                if kept.len() > 2 * keep {
                    kept.drain(..kept.len() - keep);
                }
            }
        }
    }
    let keep = LOG_KEEP as usize;
    if kept.len() > keep {
        kept.drain(..kept.len() - keep);
    }
    String::from_utf8_lossy(&kept).into_owned()
}

/// The ticks of a `PASS ticks=<n>` line of the verdict file (the last one), if any.
fn passed_ticks(text: &str) -> Option<u64> {
    text.lines()
        .filter_map(|l| l.strip_prefix("PASS ticks="))
        .filter_map(|t| t.trim().parse().ok())
        .next_back()
}

/// The vector lines of a vector file (the lines that are not `/` headers or blank): one per
/// tick of the stimulus.
fn vector_lines(path: &Path) -> std::io::Result<u64> {
    use std::io::BufRead;
    let f = std::io::BufReader::with_capacity(1 << 16, std::fs::File::open(path)?);
    let mut n = 0u64;
    for l in f.split(b'\n') {
        let l = l?;
        let t = l.trim_ascii();
        if !t.is_empty() && !t.starts_with(b"/") {
            n += 1;
        }
    }
    Ok(n)
}

/// The verdict file's `MISMATCH tick=<k> signal=<name> expected=<hex> got=<hex>` lines.
fn mismatches(text: &str) -> (u64, Vec<Mismatch>) {
    let mut tick = 0;
    let mut v = Vec::new();
    for l in text.lines().filter(|l| l.starts_with("MISMATCH ")) {
        let field = |k: &str| {
            l.split_whitespace()
                .find_map(|w| w.strip_prefix(k))
                .unwrap_or("")
        };
        tick = field("tick=").parse().unwrap_or(0);
        v.push(Mismatch {
            signal: field("signal=").to_string(),
            expected: u64::from_str_radix(field("expected="), 16).unwrap_or(0),
            got: u64::from_str_radix(field("got="), 16).unwrap_or(0),
        });
    }
    (tick, v)
}

impl InFlight for Running {
    fn wait(
        mut self: Box<Self>,
        sc: &Scenario,
        timeout: Duration,
    ) -> Result<Option<Failure>, DutError> {
        let status = loop {
            match self.child.try_wait() {
                Ok(Some(s)) => break s,
                Ok(None) if self.started.elapsed() > timeout => {
                    self.kill();
                    return Ok(Some(timed_out(sc, timeout)));
                }
                Ok(None) => std::thread::sleep(Duration::from_millis(2)),
                Err(e) => return Err(DutError::Tool(format!("waiting for vvp: {e}"))),
            }
        };
        lockstep::unregister_child(self.child.id() as libc::pid_t);
        let out = self
            .output
            .take()
            .and_then(|h| h.join().ok())
            .unwrap_or_default();
        let verdict = std::fs::read_to_string(&self.verdict).unwrap_or_default();
        if let Some(ran) = passed_ticks(&verdict) {
            if status.success() && ran == self.expect_ticks {
                return Ok(None);
            }
            if ran != self.expect_ticks {
                return Ok(Some(dut_failure(
                    sc,
                    None,
                    format!(
                        "the simulation reported a pass after {ran} ticks, the seed's vector file has {}: a run that ends early or late is not a pass",
                        self.expect_ticks
                    ),
                )));
            }
        }
        let (tick, mm) = mismatches(&verdict);
        if !mm.is_empty() {
            return Ok(Some(divergence(sc, tick, false, &mm)));
        }
        use std::os::unix::process::ExitStatusExt;
        let how = match (status.code(), status.signal()) {
            (Some(c), _) => format!("the simulation ended without a verdict (vvp exit {c})"),
            (_, Some(s)) => format!("the simulation crashed (signal {s})"),
            _ => "the simulation ended without a verdict".into(),
        };
        let tail: Vec<&str> = out
            .lines()
            .filter(|l| !l.trim().is_empty() && !l.starts_with("VCD info"))
            .collect();
        let tail = tail[tail.len().saturating_sub(3)..].join(" | ");
        Ok(Some(dut_failure(
            sc,
            None,
            if tail.is_empty() {
                how
            } else {
                format!("{how}: {tail}")
            },
        )))
    }
}

impl Dut for IcarusDut {
    fn name(&self) -> &'static str {
        "icarus"
    }

    fn needs(&self) -> Needs {
        Needs::Vectors
    }

    fn fixed(&self) -> &Fixed {
        &self.fixed
    }

    fn vector_file(&self, sc: &Scenario) -> Result<tempfile::NamedTempFile, DutError> {
        tempfile::Builder::new()
            .prefix(&format!("{}.", sc.name))
            .suffix(".vec")
            .tempfile_in(self.scratch.path())
            .map_err(|e| {
                DutError::Tool(format!(
                    "a scratch vector file in {}: {e}",
                    self.scratch.path().display()
                ))
            })
    }

    fn prebuild(&self, sets: &[crate::gen::ParamSet], jobs: usize) -> Result<(), DutError> {
        let mut todo: Vec<(Params, u64)> = Vec::new();
        for s in sets {
            let k = (self.fixed.apply(&s.params), s.clock_us * 1000);
            if !todo.contains(&k) {
                todo.push(k);
            }
        }
        let next = std::sync::atomic::AtomicUsize::new(0);
        std::thread::scope(|s| {
            for _ in 0..jobs.max(1).min(todo.len()) {
                s.spawn(|| loop {
                    let k = next.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                    let Some((p, clock_ns)) = todo.get(k) else { break };
                    let _ = self.compiled(p, *clock_ns);
                });
            }
        });
        Ok(())
    }

    fn send<'a>(
        &'a self,
        sc: &Scenario,
        rec: Recorded,
    ) -> Result<Box<dyn InFlight + 'a>, DutError> {
        use std::os::unix::process::CommandExt;
        let Recorded::Vectors(vec) = rec else {
            return Err(DutError::Tool(
                "the Icarus DUT needs the seed's vector file".into(),
            ));
        };
        if !self.fixed.holds(&sc.params) {
            return Err(DutError::Usage(format!(
                "the seed's parameters do not keep what the RTL fixes ({})",
                self.fixed.text()
            )));
        }
        let vvp = self.compiled(&sc.params, sc.clock_ns()).map_err(|log| {
            DutError::Tool(format!("iverilog failed for the seed's parameters:\n{log}"))
        })?;
        let verdict = vec.path().with_extension("verdict");
        let expect_ticks = vector_lines(vec.path())
            .map_err(|e| DutError::Tool(format!("{}: {e}", vec.path().display())))?;
        let mut child = Command::new("vvp")
            .arg("-n")
            .arg(&vvp)
            .arg(format!("+vec={}", vec.path().display()))
            .arg(format!("+verdict={}", verdict.display()))
            .stdin(Stdio::null())
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .process_group(0)
            .spawn()
            .map_err(|e| DutError::Tool(format!("cannot start vvp: {e}")))?;
        lockstep::register_child(child.id() as libc::pid_t);
        let output = child
            .stdout
            .take()
            .map(|o| std::thread::spawn(move || keep_tail(o)));
        Ok(Box::new(Running {
            child,
            started: Instant::now(),
            output,
            verdict,
            _vec: vec,
            expect_ticks,
        }))
    }

    fn notes(&self) -> Vec<String> {
        self.notes.clone()
    }

    fn rtl_wave(
        &self,
        sc: &Scenario,
        rec: Recorded,
        _window: (u64, u64),
        out: &Path,
    ) -> Option<Result<(), DutError>> {
        // the bench's own dump of `tb_vectors.dut` (+vcd), the whole repro replayed unchecked
        let Recorded::Vectors(vec) = rec else {
            return None;
        };
        let go = || -> Result<(), DutError> {
            let vvp = self
                .compiled(&sc.params, sc.clock_ns())
                .map_err(DutError::Tool)?;
            let o = Command::new("vvp")
                .arg("-n")
                .arg(&vvp)
                .arg(format!("+vec={}", vec.path().display()))
                .arg(format!("+vcd={}", out.display()))
                .arg("+nocheck")
                .stdin(Stdio::null())
                .output()
                .map_err(|e| DutError::Tool(format!("cannot start vvp: {e}")))?;
            if o.status.success() && out.is_file() {
                Ok(())
            } else {
                Err(DutError::Tool(format!(
                    "vvp wrote no waveform: {}",
                    String::from_utf8_lossy(&o.stdout).lines().last().unwrap_or("")
                )))
            }
        };
        Some(go())
    }
}

impl Drop for IcarusDut {
    fn drop(&mut self) {
        lockstep::unregister_scratch(self.scratch.path());
    }
}

/// The registry's row of Icarus Verilog: the RTL replaying the model's vector file, four-state.
pub static BACKEND: Backend = Backend {
    name: "icarus",
    about: "an RTL on Icarus Verilog, replaying the model's vector file (four-state)",
    caps: Caps {
        rtl: true,
        map: false,
        code_coverage: false,
        four_state: true,
    },
    make: |b: &Build<'_>| Ok(Box::new(IcarusDut::prepare(b.list, b.pins)?)),
};

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_simulation_that_prints_without_end_is_kept_to_its_last_bytes() {
        let big: Vec<u8> = (0..5_000_000u32).map(|i| b'a' + (i % 26) as u8).collect();
        let kept = keep_tail(std::io::Cursor::new(big.clone()));
        assert_eq!(kept.len() as u64, LOG_KEEP);
        assert!(big.ends_with(kept.as_bytes()));
    }

    #[test]
    fn a_pass_counts_only_with_its_tick_count() {
        assert_eq!(passed_ticks("PASS ticks=120\n"), Some(120));
        assert_eq!(passed_ticks("MISMATCH tick=3 signal=x expected=0 got=1\n"), None);
        assert_eq!(passed_ticks("PASS ticks=oops\n"), None);
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("a.vec");
        std::fs::write(&p, "/ pmu50 vectors\n/ clock_ns 10000\n1 0 0\n\n0 1 1\n0 0 0").unwrap();
        assert_eq!(vector_lines(&p).unwrap(), 3);
    }

    #[test]
    fn what_icarus_cannot_read_is_named_by_file_and_line_with_the_advice() {
        let d = tempfile::tempdir().unwrap();
        let pkg = d.path().join("pkg.sv");
        std::fs::write(&pkg, "package p;\n").unwrap();
        let log = format!("{}:13: syntax error\nI give up.\n", pkg.display());
        let e = unsupported(&log, &d.path().join("rtl.f")).to_string();
        assert!(
            e.starts_with(&format!("{}:13: ", pkg.display()))
                && e.contains("(syntax error)")
                && e.contains("Use `--dut verilator`"),
            "{e}"
        );
        // an internal assertion names Icarus's source, not the RTL: the list is named
        let log = "ivl: elab_type.cc:86: virtual ivl_type_s* data_type_t::elaborate_type_raw(Design*, NetScope*) const: Assertion `0' failed.\n";
        let e = unsupported(log, Path::new("/x/rtl.f")).to_string();
        assert!(
            e.starts_with("--rtl /x/rtl.f: ") && e.contains("internal assertion"),
            "{e}"
        );
    }

    #[test]
    fn the_verdict_file_names_tick_signal_and_values() {
        let (tick, mm) = mismatches("MISMATCH tick=42 signal=cnt_c expected=0 got=2\nMISMATCH tick=42 signal=diag expected=0 got=1\n");
        assert_eq!(tick, 42);
        assert_eq!(
            mm,
            vec![
                Mismatch {
                    signal: "cnt_c".into(),
                    expected: 0,
                    got: 2
                },
                Mismatch {
                    signal: "diag".into(),
                    expected: 0,
                    got: 1
                }
            ]
        );
    }
}
