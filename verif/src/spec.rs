//! The record of a regression and of each of its seeds: `regress.json` ([`RunSpec`]: the seed
//! range, the DUT and the options, everything the results depend on) and a line of
//! `results.jsonl` ([`SeedResult`]: the seed's verdict, its failure and its sparse coverage).

use crate::check::Failure;
use crate::gen;
use crate::rtl;
use crate::shard::Shard;
use pmu50_coverage::layout;
use serde::{Deserialize, Serialize};

/// Where the regression's verdicts come from: a DUT backend, by its name in the registry
/// (`crate::dut::BACKENDS`: `model`, `verilator`, `icarus`).
#[derive(Clone, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(transparent)]
pub struct DutKind(String);

impl DutKind {
    /// The backend called `name` (checked against the registry where the run is prepared or
    /// its folder read).
    pub fn new(name: &str) -> DutKind {
        DutKind(name.to_string())
    }
    /// The model alone.
    pub fn model() -> DutKind {
        DutKind::new("model")
    }
    pub fn name(&self) -> &str {
        &self.0
    }
}

/// The run as recorded in `regress.json`: everything its results depend on.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RunSpec {
    pub tool: String,
    pub model: String,
    pub start_seed: u64,
    pub iterations: u64,
    pub directed: bool,
    pub check_spec: bool,
    pub dut: DutKind,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rtl: Option<String>,
    /// `--map`: model registers and internals compared beside the ports.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub map: Option<String>,
    /// What the RTL fixes itself (its top lacks these parameters): every seed keeps them.
    #[serde(default, skip_serializing_if = "rtl::Fixed::is_empty")]
    pub fixed: rtl::Fixed,
    /// Structural parameters held fixed (absent: drawn per seed).
    #[serde(default, skip_serializing_if = "is_default")]
    pub pins: gen::Pins,
    /// This folder's part of the range (absent: the whole range).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shard: Option<Shard>,
    /// `--code-coverage`: the RTL's line and toggle coverage is measured (`code/`).
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub code_coverage: bool,
    /// `--param-sets P`: the seeds draw their parameters from a pool of at most P sets (one
    /// build each); absent or 0, each seed draws its own.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub param_sets: u32,
    /// The pool itself, fixed from the seed range when the run started
    /// ([`crate::param_pool::choose`]).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub pool: Vec<gen::ParamSet>,
}

impl RunSpec {
    /// The same regression (seed range and options), whatever the shard.
    pub fn same_regression(&self, o: &RunSpec) -> bool {
        RunSpec {
            shard: None,
            ..self.clone()
        } == RunSpec {
            shard: None,
            ..o.clone()
        }
    }

    /// The seeds of this folder.
    pub fn seeds(&self) -> std::ops::Range<u64> {
        match &self.shard {
            Some(s) => s.seeds(self.start_seed, self.iterations),
            None => self.start_seed..self.start_seed.saturating_add(self.iterations),
        }
    }

    /// How this regression draws a batch's seeds: directed by `hits_before` (the coverage of
    /// every seed before the batch; ignored by a uniform regression), within the structural
    /// pins, keeping what the RTL fixes, and drawing parameters from the pool. The regression,
    /// its graded rerun and the mutation table all draw through this one constructor, so a
    /// seed is the same scenario in each.
    pub fn bias(&self, hits_before: &[u64]) -> gen::Bias {
        let bias = if self.directed {
            gen::Bias::directed(hits_before, self.pins)
        } else {
            gen::Bias::uniform().pinned(self.pins)
        };
        bias.fixing(&self.fixed).pooled(&self.pool)
    }

    /// The id of a seed's run in coverage.json: the same seed of the same regression is the
    /// same run, and is refused when merged twice.
    pub fn run_id(&self, seed: u64) -> String {
        if self.directed {
            format!("directed:{}+{}/{seed}", self.start_seed, self.iterations)
        } else {
            format!("random/{seed}")
        }
    }
}

fn is_zero(n: &u32) -> bool {
    *n == 0
}

pub(crate) fn is_default(p: &gen::Pins) -> bool {
    *p == gen::Pins::default()
}

/// Where a seed ran.
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Place {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shard: Option<String>,
    pub host: String,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub slurm_job_id: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub slurm_array_task_id: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub k8s_job: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub k8s_index: Option<String>,
}

impl Place {
    pub fn here(shard: Option<&Shard>) -> Place {
        let env = |k: &str| std::env::var(k).ok().filter(|v| !v.is_empty());
        Place {
            shard: shard.map(|s| format!("{}/{}", s.index, s.count)),
            host: hostname(),
            slurm_job_id: env("SLURM_ARRAY_JOB_ID").or_else(|| env("SLURM_JOB_ID")),
            slurm_array_task_id: env("SLURM_ARRAY_TASK_ID"),
            k8s_job: env("JOB_NAME")
                .or_else(|| env("HOSTNAME").filter(|_| env("JOB_COMPLETION_INDEX").is_some())),
            k8s_index: env("JOB_COMPLETION_INDEX"),
        }
    }
}

pub(crate) fn hostname() -> String {
    std::fs::read_to_string("/proc/sys/kernel/hostname")
        .map(|s| s.trim().to_string())
        .ok()
        .filter(|s| !s.is_empty())
        .or_else(|| std::env::var("HOSTNAME").ok())
        .unwrap_or_else(|| "unknown".into())
}

/// One line of results.jsonl.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SeedResult {
    pub seed: u64,
    pub verdict: Verdict,
    /// Simulated ticks, and those evaluated one by one.
    pub ticks: u64,
    pub evaluated: u64,
    /// Key-on read-outs the tracking invariant checked.
    pub readouts_checked: u64,
    pub wall_ms: f64,
    #[serde(default)]
    pub failure: Option<Failure>,
    /// A failing seed (not an `error`): the command, run in the regression folder, that opens
    /// GTKWave on the shrunk repro of its signature (`failures/<signature>/`), zoomed on the
    /// divergence.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub view: Option<String>,
    #[serde(rename = "where")]
    pub place: Place,
    /// The seed's coverage, sparse: `bin:hits,bin:hits,...` (bin = index in the model).
    pub cov: String,
    /// The code coverage of the seed's RTL run (`--code-coverage`), on its way to the folder's
    /// `code/parts/` (never in results.jsonl).
    #[serde(skip)]
    pub code: Option<crate::code_cov::points::SeedCode>,
}

impl SeedResult {
    pub fn hits(&self, out: &mut [u64]) -> Result<(), String> {
        if self.cov.is_empty() {
            return Ok(());
        }
        for pair in self.cov.split(',') {
            let (k, v) = pair
                .split_once(':')
                .ok_or_else(|| format!("coverage entry `{pair}` is not bin:hits"))?;
            let k: usize = k
                .parse()
                .map_err(|_| format!("coverage bin `{k}` is not a number"))?;
            let v: u64 = v
                .parse()
                .map_err(|_| format!("coverage hits `{v}` are not a number"))?;
            let slot = out.get_mut(k).ok_or_else(|| {
                format!(
                    "coverage bin {k} is outside the model's {} bins",
                    layout().bins.len()
                )
            })?;
            if let Some(why) = layout().bins[k].unreachable {
                if v > 0 {
                    return Err(format!(
                        "coverage bin {k} ({}) is declared unreachable ({why}) but has {v} hits",
                        layout().bins[k].name
                    ));
                }
            }
            *slot = slot
                .checked_add(v)
                .ok_or("coverage hits overflow 64 bits")?;
        }
        Ok(())
    }
}

pub fn sparse(hits: &[u64]) -> String {
    let mut s = String::new();
    for (k, &h) in hits.iter().enumerate().filter(|(_, h)| **h > 0) {
        if !s.is_empty() {
            s.push(',');
        }
        s.push_str(&format!("{k}:{h}"));
    }
    s
}

/// A seed's verdict: `pass`, `fail` or `error` in results.jsonl.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Verdict {
    Pass,
    Fail,
    Error,
}

impl Verdict {
    pub fn parse(s: &str) -> Option<Verdict> {
        match s {
            "pass" => Some(Verdict::Pass),
            "fail" => Some(Verdict::Fail),
            "error" => Some(Verdict::Error),
            _ => None,
        }
    }
    pub fn name(self) -> &'static str {
        match self {
            Verdict::Pass => "pass",
            Verdict::Fail => "fail",
            Verdict::Error => "error",
        }
    }
}

impl<'de> Deserialize<'de> for Verdict {
    /// One of the three words; another is refused naming the field and what is valid.
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let s = String::deserialize(d)?;
        Verdict::parse(&s).ok_or_else(|| {
            serde::de::Error::custom(format!(
                "field `verdict`: `{s}`; valid is pass, fail or error"
            ))
        })
    }
}
