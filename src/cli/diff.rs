//! `pmu50 diff`: two waveforms compared (exit 0 equal, 1 different, 2 bad input).

use super::error::{CliError, CmdResult, Outcome};
use super::io::out;
use pmu50_waves::diff::{diff_files, DiffOptions, Sample, XPolicy};
use pmu50_waves::reader::{ReadLimits, DEFAULT_MAX_FILE_BYTES};
use std::path::PathBuf;

/// The options of `pmu50 diff`.
#[derive(clap::Args)]
pub struct Args {
    pub left: PathBuf,
    pub right: PathBuf,
    /// Scope mapping LEFT=RIGHT, e.g. `pmu50=tb_vectors.dut` (repeatable).
    #[arg(long = "map")]
    pub map: Vec<String>,
    /// Compare only at rising edges of this one-bit signal (full path).
    #[arg(long, conflicts_with = "every")]
    pub clock: Option<String>,
    /// Compare only every N time units of the left file.
    #[arg(long)]
    pub every: Option<u64>,
    /// x handling: strict, left (x on the left matches anything), either.
    #[arg(long = "x", value_name = "X", default_value = "strict")]
    pub x_policy: String,
    /// Report at most this many mismatches.
    #[arg(long, default_value_t = 20)]
    pub max: usize,
    /// Signals present on one side only do not count as a difference.
    #[arg(long)]
    pub allow_unmatched: bool,
    /// Absolute tolerance for real values.
    #[arg(long, default_value_t = 0.0)]
    pub real_tol: f64,
    /// Refuse (exit 2) a file larger than this many bytes (default 2 GiB).
    #[arg(long, default_value_t = DEFAULT_MAX_FILE_BYTES)]
    pub max_bytes: u64,
}

pub fn run(a: Args) -> CmdResult {
    let mut prefix_map = Vec::new();
    for m in &a.map {
        match m.split_once('=') {
            Some((l, r)) if !l.is_empty() && !r.is_empty() => {
                prefix_map.push((l.to_string(), r.to_string()))
            }
            _ => {
                return Err(CliError::Usage(format!(
                    "--map {m}: expected LEFT=RIGHT, e.g. pmu50=tb_vectors.dut"
                )))
            }
        }
    }
    let x_policy = match a.x_policy.as_str() {
        "strict" => XPolicy::Strict,
        "left" => XPolicy::LeftXIsWildcard,
        "either" => XPolicy::EitherXIsWildcard,
        other => {
            return Err(CliError::Usage(format!(
                "--x {other}: valid are strict, left, either"
            )))
        }
    };
    let sample = match (a.clock, a.every) {
        (Some(c), _) => Sample::RisingEdge(c),
        (None, Some(0)) => return Err(CliError::Usage("--every must be at least 1".into())),
        (None, Some(n)) => Sample::Every(n),
        (None, None) => Sample::Changes,
    };
    let opts = DiffOptions {
        prefix_map,
        sample,
        x_policy,
        max_reported: a.max,
        real_tolerance: a.real_tol,
        allow_unmatched: a.allow_unmatched,
        read_limits: ReadLimits {
            max_file_bytes: a.max_bytes,
            ..ReadLimits::default()
        },
    };
    let rep = diff_files(&a.left, &a.right, &opts)?;
    out!("{}", rep.to_string().trim_end());
    Ok(Outcome::of(rep.exit_code() == 0))
}
