//! The one reader of an RTL's file list (`--rtl LIST`, `RTL=` of the Makefile): what every part
//! of the kit builds or reads the RTL from. The regression and its backends, lockstep, `rtl-map`,
//! the sign-off, and, through `pmu50 rtl-files --json`, the formal kit, the coverage proofs, the
//! gate-level flow and the cocotb and UVM benches.
//!
//! The format is that of the `-f` files Verilator, VCS and Xcelium read. Each line holds
//! whitespace-separated entries:
//!
//! | entry | meaning |
//! |---|---|
//! | `path/to/file.sv` | a source file, in list order |
//! | `+incdir+DIR[+DIR...]` | folders searched for `` `include `` files |
//! | `+define+NAME[=VALUE][+NAME...]` | macro definitions, as `` `define `` |
//! | `-f FILE`, `-F FILE` | another file list, read in place; its own entries are relative to its folder |
//! | `-y DIR` | a library folder, searched for modules the sources instantiate but do not define |
//! | `+libext+.v[+.sv...]` | the file extensions searched in the library folders (default `.v`, `.sv`) |
//! | `-v FILE` | a library file: its modules are used where instantiated |
//!
//! Comments are `//` to the end of the line, `/* ... */` and a line starting with `#`.
//! `$VAR` and `${VAR}` are replaced by the environment's value; an unset variable is an error.
//! Every relative path is taken from the folder of the list that names it, never from the
//! current folder. Any other option is refused, naming the list, the line and what is valid.

use std::path::{Path, PathBuf};

/// A file list that cannot be read: which list, which line, what was wrong and what is valid.
#[derive(Debug, thiserror::Error)]
pub enum FileListError {
    #[error("--rtl {}: {reason}", list.display())]
    List { list: PathBuf, reason: String },
    #[error("--rtl {}:{line}: `{entry}`: {reason}", list.display())]
    Entry {
        list: PathBuf,
        line: usize,
        entry: String,
        reason: String,
    },
    #[error("--rtl {}:{line}: `{entry}` names {}, which is not a file", list.display(), path.display())]
    MissingFile {
        list: PathBuf,
        line: usize,
        entry: String,
        path: PathBuf,
    },
}

/// An RTL as its file list gives it: sources in order, include folders, defines and libraries,
/// every path absolute.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct FileList {
    /// The list itself (canonical).
    pub list: PathBuf,
    /// Source files, in list order (nested lists in place), each once.
    pub files: Vec<PathBuf>,
    /// `+incdir+` folders, in order, each once.
    pub incdirs: Vec<PathBuf>,
    /// `+define+` macros: (name, value), in order.
    pub defines: Vec<(String, Option<String>)>,
    /// `-y` library folders.
    pub libdirs: Vec<PathBuf>,
    /// `+libext+` extensions (with their dot); `.v`, `.sv` when the list names none.
    pub libext: Vec<String>,
    /// `-v` library files.
    pub libfiles: Vec<PathBuf>,
    /// Every list read: this one and the nested ones.
    pub lists: Vec<PathBuf>,
}

/// Nested lists deeper than this are refused (a list that names itself, through others).
const MAX_DEPTH: usize = 16;
/// Largest list file read.
const MAX_LIST_BYTES: u64 = 1 << 20;

impl FileList {
    /// Read `list` and the lists it names.
    pub fn read(list: &Path) -> Result<FileList, FileListError> {
        let mut fl = FileList {
            list: PathBuf::new(),
            files: Vec::new(),
            incdirs: Vec::new(),
            defines: Vec::new(),
            libdirs: Vec::new(),
            libext: Vec::new(),
            libfiles: Vec::new(),
            lists: Vec::new(),
        };
        fl.list = fl.read_one(list, &mut Vec::new())?;
        if fl.libext.is_empty() {
            fl.libext = vec![".v".into(), ".sv".into()];
        }
        if fl.files.is_empty() {
            return Err(FileListError::List {
                list: list.to_path_buf(),
                reason: "the file list names no Verilog file".into(),
            });
        }
        Ok(fl)
    }

    /// One list, its entries appended; `stack` holds the lists being read (for cycles).
    fn read_one(
        &mut self,
        list: &Path,
        stack: &mut Vec<PathBuf>,
    ) -> Result<PathBuf, FileListError> {
        let bad = |reason: String| FileListError::List {
            list: list.to_path_buf(),
            reason,
        };
        if let Some(kind) = pmu50_testbench::atomic_file::special_kind(list) {
            return Err(bad(format!("is {kind}, not a file list")));
        }
        let meta = std::fs::metadata(list).map_err(|e| bad(e.to_string()))?;
        if !meta.is_file() {
            return Err(bad("is not a regular file".into()));
        }
        if meta.len() > MAX_LIST_BYTES {
            return Err(bad(format!(
                "{} bytes: a file list is at most 1 MiB",
                meta.len()
            )));
        }
        let text = std::fs::read_to_string(list).map_err(|e| bad(e.to_string()))?;
        let abs = list.canonicalize().map_err(|e| bad(e.to_string()))?;
        if stack.contains(&abs) {
            return Err(bad(format!(
                "names itself through {}",
                stack
                    .iter()
                    .map(|p| p.display().to_string())
                    .collect::<Vec<_>>()
                    .join(" -> ")
            )));
        }
        if stack.len() >= MAX_DEPTH {
            return Err(bad(format!("lists nested deeper than {MAX_DEPTH}")));
        }
        stack.push(abs.clone());
        if !self.lists.contains(&abs) {
            self.lists.push(abs.clone());
        }
        let dir = abs.parent().unwrap_or(Path::new("/")).to_path_buf();
        let tokens = tokens(&text);
        let mut k = 0;
        while k < tokens.len() {
            let (line, raw) = (tokens[k].0, tokens[k].1.as_str());
            let at = |reason: String| FileListError::Entry {
                list: list.to_path_buf(),
                line,
                entry: raw.to_string(),
                reason,
            };
            let entry = expand_env(raw).map_err(at)?;
            k += 1;
            // an option that takes the next entry as its argument
            let mut argument = |what: &str| -> Result<(String, usize), FileListError> {
                let next = tokens.get(k).ok_or_else(|| FileListError::Entry {
                    list: list.to_path_buf(),
                    line,
                    entry: raw.to_string(),
                    reason: format!("needs {what} after it"),
                })?;
                k += 1;
                let v = expand_env(&next.1).map_err(|reason| FileListError::Entry {
                    list: list.to_path_buf(),
                    line: next.0,
                    entry: next.1.clone(),
                    reason,
                })?;
                Ok((v, next.0))
            };
            if let Some(rest) = entry.strip_prefix("+incdir+") {
                for d in rest.split('+').filter(|d| !d.is_empty()) {
                    let p = dir.join(d);
                    if !p.is_dir() {
                        return Err(at(format!("{} is not a folder", p.display())));
                    }
                    let p = p.canonicalize().unwrap_or(p);
                    if !self.incdirs.contains(&p) {
                        self.incdirs.push(p);
                    }
                }
            } else if let Some(rest) = entry.strip_prefix("+define+") {
                for d in rest.split('+').filter(|d| !d.is_empty()) {
                    let (name, value) = match d.split_once('=') {
                        Some((n, v)) => (n, Some(v.to_string())),
                        None => (d, None),
                    };
                    if name.is_empty()
                        || !name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_')
                        || name.starts_with(|c: char| c.is_ascii_digit())
                    {
                        return Err(at(format!(
                            "`{name}` is not a macro name (letters, digits and _, not first a digit)"
                        )));
                    }
                    self.defines.push((name.to_string(), value));
                }
            } else if let Some(rest) = entry.strip_prefix("+libext+") {
                for e in rest.split('+').filter(|e| !e.is_empty()) {
                    let e = if e.starts_with('.') {
                        e.to_string()
                    } else {
                        format!(".{e}")
                    };
                    if !self.libext.contains(&e) {
                        self.libext.push(e);
                    }
                }
            } else if entry == "-f" || entry == "-F" {
                let (f, l) = argument("a file list")?;
                let p = dir.join(&f);
                if !p.is_file() {
                    return Err(FileListError::MissingFile {
                        list: list.to_path_buf(),
                        line: l,
                        entry: f,
                        path: p,
                    });
                }
                self.read_one(&p, stack)?;
            } else if entry == "-y" {
                let (d, l) = argument("a library folder")?;
                let p = dir.join(&d);
                if !p.is_dir() {
                    return Err(FileListError::Entry {
                        list: list.to_path_buf(),
                        line: l,
                        entry: d,
                        reason: format!("{} is not a folder", p.display()),
                    });
                }
                let p = p.canonicalize().unwrap_or(p);
                if !self.libdirs.contains(&p) {
                    self.libdirs.push(p);
                }
            } else if entry == "-v" {
                let (f, l) = argument("a library file")?;
                let p = dir.join(&f);
                if !p.is_file() {
                    return Err(FileListError::MissingFile {
                        list: list.to_path_buf(),
                        line: l,
                        entry: f,
                        path: p,
                    });
                }
                let p = p.canonicalize().unwrap_or(p);
                if !self.libfiles.contains(&p) {
                    self.libfiles.push(p);
                }
            } else if entry.starts_with('+') || entry.starts_with('-') {
                return Err(at("not an entry of a file list; valid are source files, +incdir+DIR, +define+NAME[=VALUE], -f FILE, -F FILE, -y DIR, +libext+EXT, -v FILE (tool options go on the tool's command line, not in the RTL's list)".into()));
            } else {
                let p = dir.join(&entry);
                if !p.is_file() || pmu50_testbench::atomic_file::special_kind(&p).is_some() {
                    return Err(FileListError::MissingFile {
                        list: list.to_path_buf(),
                        line,
                        entry,
                        path: p,
                    });
                }
                let p = p.canonicalize().unwrap_or(p);
                if !self.files.contains(&p) {
                    self.files.push(p);
                }
            }
        }
        stack.pop();
        Ok(abs)
    }

    /// The folders searched for `` `include `` files: the `+incdir+` folders, then each source
    /// file's own folder (in list order), each once.
    pub fn include_dirs(&self) -> Vec<PathBuf> {
        let mut dirs: Vec<PathBuf> = self.incdirs.clone();
        for f in &self.files {
            if let Some(d) = f.parent() {
                if !dirs.iter().any(|x| x == d) {
                    dirs.push(d.to_path_buf());
                }
            }
        }
        dirs
    }

    /// `+define+NAME=VALUE` as a simulator takes it (`NAME` or `NAME=VALUE`).
    pub fn define_args(&self) -> Vec<String> {
        self.defines
            .iter()
            .map(|(n, v)| match v {
                Some(v) => format!("{n}={v}"),
                None => n.clone(),
            })
            .collect()
    }

    /// The list's include folders, defines and libraries as Verilator's options (the sources
    /// are passed apart, in order).
    pub fn verilator_args(&self) -> Vec<String> {
        let mut a: Vec<String> = self
            .include_dirs()
            .iter()
            .map(|d| format!("-I{}", d.display()))
            .collect();
        a.extend(self.define_args().iter().map(|d| format!("+define+{d}")));
        for d in &self.libdirs {
            a.push("-y".into());
            a.push(d.display().to_string());
        }
        if !self.libdirs.is_empty() {
            a.push(format!("+libext+{}", self.libext.join("+")));
        }
        for f in &self.libfiles {
            a.push("-v".into());
            a.push(f.display().to_string());
        }
        a
    }

    /// The same as Icarus Verilog's options.
    pub fn iverilog_args(&self) -> Vec<String> {
        let mut a: Vec<String> = self
            .include_dirs()
            .iter()
            .map(|d| format!("-I{}", d.display()))
            .collect();
        a.extend(self.define_args().iter().map(|d| format!("-D{d}")));
        for d in &self.libdirs {
            a.push(format!("-y{}", d.display()));
        }
        if !self.libdirs.is_empty() {
            for e in &self.libext {
                a.push(format!("-Y{e}"));
            }
        }
        for f in &self.libfiles {
            a.push(format!("-l{}", f.display()));
        }
        a
    }

    /// yosys's command that reads the RTL (`read_verilog -sv` with `opts`, the include folders,
    /// the defines and the sources): the same list as the simulators'.
    pub fn yosys_read(&self, opts: &str) -> String {
        let mut read = format!("read_verilog -sv{}", if opts.is_empty() { "" } else { " " });
        read.push_str(opts);
        for d in self.include_dirs() {
            read.push_str(&format!(" -I{}", d.display()));
        }
        for d in self.define_args() {
            read.push_str(&format!(" -D{d}"));
        }
        for f in &self.files {
            read.push_str(&format!(" {}", f.display()));
        }
        read
    }

    /// The files of the RTL whose content defines it: the sources, the library files and every
    /// file of the library folders with a library extension (sorted, each once).
    pub fn content_files(&self) -> Vec<PathBuf> {
        let mut v: Vec<PathBuf> = self.files.clone();
        v.extend(self.libfiles.iter().cloned());
        for d in &self.libdirs {
            if let Ok(rd) = std::fs::read_dir(d) {
                for e in rd.flatten() {
                    let p = e.path();
                    let ext = p
                        .file_name()
                        .and_then(|n| n.to_str())
                        .and_then(|n| n.rfind('.').map(|i| &n[i..]));
                    if p.is_file() && ext.is_some_and(|x| self.libext.iter().any(|e| e == x)) {
                        v.push(p);
                    }
                }
            }
        }
        // included files are part of the RTL too: every file of the include folders
        for d in &self.incdirs {
            if let Ok(rd) = std::fs::read_dir(d) {
                for e in rd.flatten() {
                    let p = e.path();
                    if p.is_file() {
                        v.push(p);
                    }
                }
            }
        }
        v.sort();
        v.dedup();
        v
    }

    /// The RTL's content hash (`sha256:` and 64 hex digits): over the defines and, for every file
    /// of [`FileList::content_files`], its path relative to the list's folder and its bytes'
    /// SHA-256. Where the RTL lives does not change it; an edited byte, a renamed or added file,
    /// another define does.
    pub fn content_hash(&self) -> Result<String, FileListError> {
        let base = self.list.parent().unwrap_or(Path::new("/"));
        let mut text = String::new();
        for (n, v) in &self.defines {
            text.push_str(&format!("define {n}={}\n", v.as_deref().unwrap_or("")));
        }
        for f in self.content_files() {
            let bytes = std::fs::read(&f).map_err(|e| FileListError::List {
                list: self.list.clone(),
                reason: format!("{}: {e}", f.display()),
            })?;
            let rel = relative(&f, base);
            text.push_str(&format!(
                "file {} {}\n",
                rel,
                crate::digest::sha256_hex(&bytes)
            ));
        }
        Ok(format!(
            "sha256:{}",
            crate::digest::sha256_hex(text.as_bytes())
        ))
    }
}

/// `path` relative to `base` where it lies below it, else absolute; `/` separated.
fn relative(path: &Path, base: &Path) -> String {
    path.strip_prefix(base)
        .map(|r| r.display().to_string())
        .unwrap_or_else(|_| path.display().to_string())
}

/// The entries of a list with their line numbers, comments removed.
fn tokens(text: &str) -> Vec<(usize, String)> {
    let mut out = Vec::new();
    let mut in_block = false;
    for (n, line) in text.lines().enumerate() {
        if !in_block && line.trim_start().starts_with('#') {
            continue;
        }
        let mut s = String::new();
        let b = line.as_bytes();
        let mut i = 0;
        while i < b.len() {
            if in_block {
                if b[i] == b'*' && b.get(i + 1) == Some(&b'/') {
                    in_block = false;
                    i += 2;
                    s.push(' ');
                } else {
                    i += 1;
                }
            } else if b[i] == b'/' && b.get(i + 1) == Some(&b'/') {
                break;
            } else if b[i] == b'/' && b.get(i + 1) == Some(&b'*') {
                in_block = true;
                i += 2;
            } else {
                s.push(b[i] as char);
                i += 1;
            }
        }
        for t in s.split_whitespace() {
            out.push((n + 1, t.to_string()));
        }
    }
    out
}

/// `$VAR` and `${VAR}` replaced by the environment's value.
fn expand_env(entry: &str) -> Result<String, String> {
    let mut out = String::new();
    let mut rest = entry;
    while let Some(i) = rest.find('$') {
        out.push_str(&rest[..i]);
        let after = &rest[i + 1..];
        let (name, tail) = if let Some(b) = after.strip_prefix('{') {
            let end = b
                .find('}')
                .ok_or_else(|| "`${` without its `}`".to_string())?;
            (&b[..end], &b[end + 1..])
        } else {
            let end = after
                .find(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
                .unwrap_or(after.len());
            (&after[..end], &after[end..])
        };
        if name.is_empty() {
            return Err("`$` without a variable name".into());
        }
        let v = std::env::var(name)
            .map_err(|_| format!("the environment variable `{name}` is not set"))?;
        out.push_str(&v);
        rest = tail;
    }
    out.push_str(rest);
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tree(tag: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("pmu50-filelist-{tag}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(d.join("rtl/inc")).unwrap();
        std::fs::create_dir_all(d.join("lib")).unwrap();
        std::fs::create_dir_all(d.join("sub")).unwrap();
        for f in [
            "rtl/a.sv",
            "rtl/b.v",
            "rtl/inc/defs.svh",
            "lib/cell.v",
            "sub/c.sv",
        ] {
            std::fs::write(d.join(f), format!("// {f}\n")).unwrap();
        }
        d
    }

    #[test]
    fn every_entry_kind_is_read_relative_to_its_own_list() {
        let d = tree("kinds");
        std::fs::write(d.join("sub/inner.f"), "c.sv  // relative to sub/\n").unwrap();
        std::fs::write(
            d.join("top.f"),
            "# a comment line\n+incdir+rtl/inc\n+define+FOO+BAR=3\nrtl/a.sv /* block\n comment */ rtl/b.v\n-F sub/inner.f\n-y lib +libext+.v\n",
        )
        .unwrap();
        let fl = FileList::read(&d.join("top.f")).unwrap();
        let c = |p: &str| d.join(p).canonicalize().unwrap();
        assert_eq!(fl.files, vec![c("rtl/a.sv"), c("rtl/b.v"), c("sub/c.sv")]);
        assert_eq!(fl.incdirs, vec![c("rtl/inc")]);
        assert_eq!(
            fl.defines,
            vec![("FOO".into(), None), ("BAR".into(), Some("3".into()))]
        );
        assert_eq!(fl.define_args(), vec!["FOO", "BAR=3"]);
        assert_eq!(fl.libdirs, vec![c("lib")]);
        assert_eq!(fl.libext, vec![".v"]);
        assert_eq!(fl.lists, vec![c("top.f"), c("sub/inner.f")]);
        assert!(fl.content_files().contains(&c("lib/cell.v")));
        assert!(fl.content_files().contains(&c("rtl/inc/defs.svh")));
    }

    #[test]
    fn the_content_hash_follows_the_bytes_not_the_place() {
        let d = tree("hash");
        std::fs::write(d.join("top.f"), "rtl/a.sv\nrtl/b.v\n").unwrap();
        let h = FileList::read(&d.join("top.f"))
            .unwrap()
            .content_hash()
            .unwrap();
        assert!(h.starts_with("sha256:") && h.len() == 7 + 64, "{h}");
        // the same tree elsewhere: the same hash
        let e = tree("hash-copy");
        std::fs::write(e.join("top.f"), "rtl/a.sv\nrtl/b.v\n").unwrap();
        assert_eq!(
            FileList::read(&e.join("top.f"))
                .unwrap()
                .content_hash()
                .unwrap(),
            h
        );
        // one byte, or a define, changes it
        std::fs::write(e.join("rtl/b.v"), "// rtl/b.v \n").unwrap();
        let h2 = FileList::read(&e.join("top.f"))
            .unwrap()
            .content_hash()
            .unwrap();
        assert_ne!(h2, h);
        std::fs::write(e.join("top.f"), "+define+X\nrtl/a.sv\nrtl/b.v\n").unwrap();
        let h3 = FileList::read(&e.join("top.f"))
            .unwrap()
            .content_hash()
            .unwrap();
        assert_ne!(h3, h2);
    }

    #[test]
    fn bad_entries_are_refused_with_list_line_and_what_is_valid() {
        let d = tree("bad");
        let cases: [(&str, &str); 7] = [
            (
                "rtl/a.sv\n-Wno-fatal\n",
                "top.f:2: `-Wno-fatal`: not an entry of a file list; valid are",
            ),
            (
                "rtl/a.sv\nrtl/missing.v\n",
                "top.f:2: `rtl/missing.v` names",
            ),
            (
                "+define+9X\nrtl/a.sv\n",
                "top.f:1: `+define+9X`: `9X` is not a macro name",
            ),
            (
                "rtl/a.sv\n-f\n",
                "top.f:2: `-f`: needs a file list after it",
            ),
            ("-f top.f\n", "names itself through"),
            (
                "$PMU50_SURELY_UNSET_VAR/a.sv\n",
                "the environment variable `PMU50_SURELY_UNSET_VAR` is not set",
            ),
            ("// nothing\n", "names no Verilog file"),
        ];
        for (text, want) in cases {
            std::fs::write(d.join("top.f"), text).unwrap();
            let e = FileList::read(&d.join("top.f")).unwrap_err().to_string();
            assert!(e.contains(want), "{text:?}: {e}");
        }
    }

    #[test]
    fn environment_variables_are_expanded() {
        let d = tree("env");
        std::env::set_var("PMU50_FILELIST_TEST_DIR", "rtl");
        std::fs::write(
            d.join("top.f"),
            "${PMU50_FILELIST_TEST_DIR}/a.sv\n$PMU50_FILELIST_TEST_DIR/b.v\n",
        )
        .unwrap();
        let fl = FileList::read(&d.join("top.f")).unwrap();
        assert_eq!(fl.files.len(), 2);
    }
}
