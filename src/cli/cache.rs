//! `pmu50 cache`: the build cache of RTL under test (docs/verification.md, "The build cache"):
//! its size against its cap, its builds per RTL and when each RTL was last used; `pmu50 cache
//! clean` empties it, `--to-cap` trims it to the cap. Builds a running regression uses are kept.

use super::error::{CliError, CmdResult, Outcome};
use super::io::out;
use pmu50_verif::cache;
use std::collections::BTreeMap;
use std::path::PathBuf;
use std::time::SystemTime;

/// The options of `pmu50 cache`.
#[derive(clap::Args)]
pub struct Args {
    #[command(subcommand)]
    pub what: Option<What>,
}

#[derive(clap::Subcommand)]
pub enum What {
    /// Remove every build no running regression uses (with --to-cap: the least recently used
    /// until the cache is under its cap, PMU50_CACHE_MAX).
    Clean {
        #[arg(long)]
        to_cap: bool,
    },
}

fn mib(b: u64) -> String {
    format!("{:.1} MiB", b as f64 / (1u64 << 20) as f64)
}

fn ago(t: SystemTime) -> String {
    match SystemTime::now().duration_since(t) {
        Ok(d) if d.as_secs() < 120 => format!("{} s ago", d.as_secs()),
        Ok(d) if d.as_secs() < 7_200 => format!("{} min ago", d.as_secs() / 60),
        Ok(d) if d.as_secs() < 172_800 => format!("{} h ago", d.as_secs() / 3_600),
        Ok(d) => format!("{} days ago", d.as_secs() / 86_400),
        Err(_) => "now".into(),
    }
}

pub fn run(a: Args) -> CmdResult {
    let root = cache::cache_dir();
    let cap = cache::cache_max().map_err(CliError::Usage)?;
    match a.what {
        Some(What::Clean { to_cap }) => {
            let t = cache::trim(&root, to_cap.then_some(cap));
            out!(
                "{}: removed {} build(s), {} freed; {} in use by a running regression kept; {} now (cap {})",
                root.display(),
                t.removed,
                mib(t.freed),
                t.in_use,
                mib(t.size_after),
                mib(cap)
            );
        }
        None => {
            let units = cache::units(&root);
            let size = cache::size_of(&root);
            out!(
                "{}: {} in {} build(s), cap {} (PMU50_CACHE_MAX){}",
                root.display(),
                mib(size),
                units
                    .iter()
                    .filter(|u| !u.orphan && matches!(u.kind, "verilator" | "icarus" | "runtime"))
                    .count(),
                mib(cap),
                if size > cap {
                    " - over the cap: the next build trims it"
                } else {
                    ""
                }
            );
            // by RTL: builds, size, last use, the file list it was made from
            let mut by: BTreeMap<PathBuf, (usize, u64, SystemTime, &'static str)> = BTreeMap::new();
            for u in &units {
                let e = by
                    .entry(u.rtl.clone())
                    .or_insert((0, 0, SystemTime::UNIX_EPOCH, u.kind));
                e.0 += usize::from(!u.orphan);
                e.1 += u.size;
                e.2 = e.2.max(u.last_use);
            }
            let mut rows: Vec<_> = by.into_iter().collect();
            rows.sort_by_key(|(_, v)| std::cmp::Reverse(v.2));
            out!(
                "{:<10} {:>6} {:>11}  {:<14} rtl",
                "kind",
                "builds",
                "size",
                "last use"
            );
            for (rtl, (n, s, t, kind)) in rows {
                let list = std::fs::read_to_string(rtl.join("rtl.txt"))
                    .map(|l| l.trim().to_string())
                    .unwrap_or_else(|_| {
                        if kind == "runtime" {
                            "(the Verilator runtime)".into()
                        } else if kind == "kit" {
                            format!("(the HDL kit of a pmu50 binary, {})", rtl.display())
                        } else if kind == "ccache" {
                            format!("(the compiler cache of the builds' C++, {})", rtl.display())
                        } else {
                            rtl.display().to_string()
                        }
                    });
                out!(
                    "{:<10} {:>6} {:>11}  {:<14} {list}",
                    kind,
                    n,
                    mib(s),
                    ago(t)
                );
            }
        }
    }
    Ok(Outcome::Pass)
}
