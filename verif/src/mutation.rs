//! `pmu50 mutation`: the mutation score of the directed regression (docs/verification.md,
//! "Mutation score").
//!
//! For each mutant of `hdl/mutants.txt` (a one-line bug of the twin selected by a `` `define ``),
//! the seeds of a directed regression (`pmu50 regress --directed --dut verilator --map
//! hdl/pmu50.map.toml`) are checked in seed order against the twin built with the mutant's define,
//! and the first failing seed is the number of seeds the regression needs to catch it. The
//! directed bias of each batch depends on the model's coverage of the seeds before it only, so
//! the scenarios are drawn once, on the model, and are those of the regression whatever the RTL.
//! A mutant that passes every seed escaped, unless its line declares it proven equivalent.
//! The twin without a mutant is checked on each catching seed too: a catch the twin shares is
//! no catch.

use crate::dut::{self, Dut};
use crate::gen::{Bias, Pins, Stimulus};
use crate::pool::run_pool;
use crate::pool::BATCH;
use crate::spec::DutKind;
use crate::spec::RunSpec;
use crate::spec::Verdict;
use pmu50_testbench::atomic_file::{self, Batch};
use serde::Serialize;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::Mutex;
use std::time::{Duration, Instant};

#[derive(Debug, thiserror::Error)]
pub enum MutationError {
    #[error("{}: line {line}: {reason}", path.display())]
    Line {
        path: PathBuf,
        line: usize,
        reason: String,
    },
    #[error("{}: {reason}", path.display())]
    File { path: PathBuf, reason: String },
    #[error("{0}")]
    Usage(String),
    #[error(transparent)]
    Output(#[from] atomic_file::OutputError),
}

/// Which checks a mutant is for (the optional fourth field of its line).
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Scope {
    /// No scope: every verification method must catch it (hdl/cosim.sh, cocotb, UVM, formal).
    Every,
    /// `regress`: the directed regression's mutation table only.
    Regress,
    /// `equivalent: <proof>`: proven to behave as the twin; not run.
    Equivalent(String),
}

/// One line of `hdl/mutants.txt`.
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
pub struct Mutant {
    pub name: String,
    /// The RTL file it plants its bug in (relative to hdl/).
    pub file: String,
    pub description: String,
    pub scope: Scope,
}

impl Mutant {
    /// The block: the RTL file's name without folder and extension.
    pub fn block(&self) -> &str {
        let f = self.file.rsplit('/').next().unwrap_or(&self.file);
        f.strip_suffix(".v").unwrap_or(f)
    }
}

/// Parse `hdl/mutants.txt`: `NAME | file | description [| scope]`, `#` comments, blank lines.
pub fn parse_mutants(text: &str, path: &Path) -> Result<Vec<Mutant>, MutationError> {
    let mut out: Vec<Mutant> = Vec::new();
    for (i, raw) in text.lines().enumerate() {
        let line = raw.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let bad = |reason: String| MutationError::Line {
            path: path.to_path_buf(),
            line: i + 1,
            reason,
        };
        let f: Vec<&str> = line.split('|').map(str::trim).collect();
        if !(3..=4).contains(&f.len()) {
            return Err(bad(format!(
                "{} fields: expected NAME | file | description [| scope]",
                f.len()
            )));
        }
        let name = f[0];
        if !name.starts_with("MUT_") || !name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_')
        {
            return Err(bad(format!(
                "`{name}`: a mutant's name is a Verilog macro name starting with MUT_"
            )));
        }
        if out.iter().any(|m| m.name == name) {
            return Err(bad(format!("{name} is listed twice")));
        }
        if f[1].is_empty() || f[2].is_empty() {
            return Err(bad("empty file or description".into()));
        }
        let scope = match f.get(3) {
            None => Scope::Every,
            Some(&"regress") => Scope::Regress,
            Some(s) => match s.strip_prefix("equivalent:").map(str::trim) {
                Some(proof) if !proof.is_empty() => Scope::Equivalent(proof.to_string()),
                _ => {
                    return Err(bad(format!(
                        "scope `{s}`: expected `regress` or `equivalent: <proof>`"
                    )))
                }
            },
        };
        out.push(Mutant {
            name: name.to_string(),
            file: f[1].to_string(),
            description: f[2].to_string(),
            scope,
        });
    }
    Ok(out)
}

/// Options of `pmu50 mutation`.
#[derive(Clone, Debug)]
pub struct Options {
    /// The mutants' list (hdl/mutants.txt).
    pub mutants: PathBuf,
    /// The twin's file list (hdl/pmu50.f) and map (hdl/pmu50.map.toml).
    pub twin: PathBuf,
    pub map: Option<PathBuf>,
    pub start_seed: u64,
    pub iterations: u64,
    /// Mutants checked at once (each with its own DUT worker).
    pub jobs: usize,
    pub timeout: Duration,
    /// Only these mutants (empty: all).
    pub only: Vec<String>,
    pub out: PathBuf,
    /// The pool of parameter sets the seeds draw from (`--param-sets`, 0: a set per seed).
    pub param_sets: u32,
}

/// What the regression did to one mutant.
#[derive(Clone, Debug, Serialize)]
#[serde(tag = "result", rename_all = "snake_case")]
pub enum Outcome {
    /// The first failing seed, how many seeds that is, and its failure.
    Caught {
        seeds: u64,
        seed: u64,
        signature: String,
        tick: u64,
        signal: String,
        expected: String,
        got: String,
    },
    /// Every seed passed.
    Escaped { seeds: u64 },
    /// Declared proven equivalent: not run.
    Equivalent { proof: String },
    /// The mutant could not be checked (the RTL did not build, or the twin fails the seed too).
    Error { reason: String },
}

impl Outcome {
    /// The table's last two cells: seeds to catch (or what happened instead) and the first
    /// failure, as plain text or as a Markdown cell (code spans, `|` escaped).
    fn cells(&self, markdown: bool) -> (String, String) {
        match self {
            Outcome::Caught {
                seeds,
                seed,
                signature,
                tick,
                ..
            } if markdown => (seeds.to_string(), format!("{seed}, `{signature}`, {tick}")),
            Outcome::Caught {
                seeds,
                seed,
                signature,
                tick,
                ..
            } => (seeds.to_string(), format!("{seed}: {signature} @{tick}")),
            Outcome::Escaped { seeds } => ("escaped".into(), format!("all {seeds} seeds pass")),
            Outcome::Equivalent { proof } if markdown => {
                ("equivalent".into(), format!("proof: {proof}"))
            }
            Outcome::Equivalent { proof } => ("equiv".into(), format!("proven: {proof}")),
            Outcome::Error { reason } if markdown => ("error".into(), reason.replace('|', "\\|")),
            Outcome::Error { reason } => ("error".into(), reason.clone()),
        }
    }
}

#[derive(Clone, Debug, Serialize)]
pub struct Row {
    pub mutant: String,
    pub block: String,
    pub scope: Scope,
    pub description: String,
    #[serde(flatten)]
    pub outcome: Outcome,
    pub wall_s: f64,
}

#[derive(Clone, Debug, Serialize)]
pub struct Report {
    pub format: &'static str,
    pub start_seed: u64,
    pub iterations: u64,
    /// What the seeds compare: `ports` (the contract's ports only, as for an RTL without a
    /// map) or `map` (the ports and the twin's mapped registers and internals).
    pub compare: &'static str,
    /// `--param-sets` of the regression whose seeds are checked.
    pub param_sets: u32,
    /// Seeds to catch over the caught mutants: the median and the most.
    pub median_seeds: u64,
    pub max_seeds: u64,
    pub rows: Vec<Row>,
    pub caught: usize,
    pub escaped: usize,
    pub equivalent: usize,
    pub errors: usize,
    /// caught / (mutants - equivalent), percent.
    pub score_percent: f64,
    pub wall_s: f64,
}

impl Report {
    /// Exit code: 0 every mutant caught or proven equivalent, 1 otherwise.
    pub fn ok(&self) -> bool {
        self.escaped == 0 && self.errors == 0
    }

    /// The table as text.
    pub fn text(&self) -> String {
        let mut s = format!(
            "{:<30} {:<30} {:>8}  {}\n",
            "mutant", "block", "seeds", "first failure (seed: signature, tick)"
        );
        for r in &self.rows {
            let (n, what) = r.outcome.cells(false);
            s.push_str(&format!(
                "{:<30} {:<30} {:>8}  {}\n",
                r.mutant, r.block, n, what
            ));
        }
        let run = self.rows.len() - self.equivalent;
        s.push_str(&format!(
            "compared: {}; parameter sets: {}; seeds to catch: median {}, most {}\n",
            if self.compare == "ports" {
                "the ports only"
            } else {
                "the ports and the twin's map"
            },
            if self.param_sets == 0 {
                "one per seed".to_string()
            } else {
                format!("a pool of {}", self.param_sets)
            },
            self.median_seeds,
            self.max_seeds
        ));
        s.push_str(&format!(
            "mutation score: {}/{} caught within {} directed seeds ({:.1} %), {} escaped, {} proven equivalent, {} error(s); {:.0} s wall\n",
            self.caught, run, self.iterations, self.score_percent, self.escaped, self.equivalent, self.errors, self.wall_s
        ));
        s
    }
}

impl Report {
    /// The table as Markdown, as docs/verification.md quotes it (section 11; checked against a
    /// run by tests/doc_figures.rs): a row per mutant, then the score line. No times: they vary
    /// with the machine, the table does not.
    pub fn markdown(&self) -> String {
        let mut s = String::from(
            "| mutant | block | scope | seeds to catch | first failure: seed, signature, tick |\n|---|---|---|---:|---|\n",
        );
        for r in &self.rows {
            let scope = match &r.scope {
                Scope::Every => "every method",
                Scope::Regress => "regress",
                Scope::Equivalent(_) => "equivalent",
            };
            let (n, what) = r.outcome.cells(true);
            s.push_str(&format!(
                "| `{}` | {} | {scope} | {n} | {what} |\n",
                r.mutant, r.block
            ));
        }
        let run = self.rows.len() - self.equivalent;
        let slowest: Vec<String> = self
            .rows
            .iter()
            .filter(
                |r| matches!(r.outcome, Outcome::Caught { seeds, .. } if seeds == self.max_seeds),
            )
            .map(|r| format!("`{}`", r.mutant))
            .collect();
        s.push_str(&format!(
            "\nMutation score{}: {} of {run} caught within {} directed seeds ({:.1} %), {} escaped, {} proven equivalent{}; median {} seeds to catch, most {}{}.\n",
            if self.compare == "ports" { " on the ports alone" } else { "" },
            self.caught,
            self.iterations,
            self.score_percent,
            self.escaped,
            self.equivalent,
            if self.errors > 0 { format!(", {} error(s)", self.errors) } else { String::new() },
            self.median_seeds,
            self.max_seeds,
            if slowest.is_empty() {
                String::new()
            } else {
                format!(" ({})", slowest.join(", "))
            }
        ));
        s
    }
}

/// The directed regression's scenarios: the bias of each batch, from the model's coverage of the
/// seeds before it (as `pmu50 regress --directed` draws them).
fn directed_biases(spec: &RunSpec, model: &dyn Dut) -> Result<Vec<Bias>, MutationError> {
    let mut before = vec![0u64; pmu50_coverage::layout().bins.len()];
    let mut biases = Vec::new();
    let stop = AtomicBool::new(false);
    let jobs = std::thread::available_parallelism().map_or(1, |n| n.get());
    let (start, end) = (spec.start_seed, spec.start_seed + spec.iterations);
    let mut lo = start;
    while lo < end {
        let hi = (lo + BATCH).min(end);
        let bias = spec.bias(&before);
        let seeds: Vec<u64> = (lo..hi).collect();
        let out = run_pool(
            spec,
            &seeds,
            &bias,
            model,
            jobs,
            Duration::from_secs(600),
            &stop,
            |_| Ok(()),
        )
        .map_err(|e| MutationError::Usage(format!("the model's run of the seeds: {e}")))?;
        for (r, hits) in &out {
            if r.verdict != Verdict::Pass {
                return Err(MutationError::Usage(format!(
                    "seed {} fails on the model alone ({}): the regression is not clean",
                    r.seed,
                    r.failure.as_ref().map_or("-".into(), |f| f.signature())
                )));
            }
            for (b, h) in before.iter_mut().zip(hits) {
                *b = b.saturating_add(*h);
            }
        }
        biases.push(bias);
        lo = hi;
    }
    Ok(biases)
}

/// The twin's file list with the mutant's define first, at a stable path (so that its builds
/// stay cached from one run to the next).
fn mutant_list(o: &Options, m: &Mutant) -> Result<PathBuf, MutationError> {
    let twin = crate::rtl::FileList::read(&o.twin).map_err(|e| MutationError::File {
        path: o.twin.clone(),
        reason: e.to_string(),
    })?;
    let dir = o.out.join("rtl").join(&m.name);
    atomic_file::create_dir(&dir)?;
    let dir = dir.canonicalize().map_err(|e| MutationError::File {
        path: dir.clone(),
        reason: e.to_string(),
    })?;
    let defs = dir.join("defines.vh");
    let list = dir.join("rtl.f");
    let body: String = std::iter::once(defs.clone())
        .chain(twin.files.iter().cloned())
        .map(|f| format!("{}\n", f.display()))
        .collect();
    let mut b = Batch::new();
    b.add(atomic_file::write_atomic(
        &defs,
        format!("`define {}\n", m.name).as_bytes(),
    )?);
    b.add(atomic_file::write_atomic(&list, body.as_bytes())?);
    b.commit()?;
    Ok(list)
}

/// Check one mutant on the seeds in order, up to its first failure.
fn one(
    o: &Options,
    spec: &RunSpec,
    biases: &[Bias],
    twin: &dyn Dut,
    m: &Mutant,
    stop: &AtomicBool,
) -> Outcome {
    if let Scope::Equivalent(proof) = &m.scope {
        // equivalent only with the formal kit's sealed proof of this very twin
        let hdl = o.mutants.parent().unwrap_or(Path::new("."));
        let checked = crate::filelist::FileList::read(&o.twin)
            .and_then(|fl| fl.content_hash())
            .map_err(|e| e.to_string())
            .and_then(|h| {
                crate::equivalence::check_proof(
                    &crate::equivalence::proof_path(hdl, &m.name),
                    &m.name,
                    &h,
                )
                .map_err(|e| e.to_string())
            });
        return match checked {
            Ok(how) => Outcome::Equivalent {
                proof: format!("{proof}; proven: {how}"),
            },
            Err(why) => Outcome::Error {
                reason: format!("declared equivalent, not proven: {why}"),
            },
        };
    }
    let list = match mutant_list(o, m) {
        Ok(l) => l,
        Err(e) => {
            return Outcome::Error {
                reason: e.to_string(),
            }
        }
    };
    let mspec = RunSpec {
        rtl: Some(list.display().to_string()),
        ..spec.clone()
    };
    let d = match dut::prepare(&mspec) {
        Ok(d) => d,
        Err(e) => {
            return Outcome::Error {
                reason: format!("the twin with {} does not build: {e}", m.name),
            }
        }
    };
    if !d.fixed().is_empty() {
        return Outcome::Error {
            reason: format!(
                "the twin with {} fixes {}: its top lost parameters",
                m.name,
                d.fixed().text()
            ),
        };
    }
    for seed in spec.start_seed..spec.start_seed + spec.iterations {
        if stop.load(Ordering::Relaxed) {
            return Outcome::Error {
                reason: "interrupted".into(),
            };
        }
        let bias = &biases[((seed - spec.start_seed) / BATCH) as usize];
        let stim = Stimulus::generate(seed, bias);
        let (verdict, failure) = match crate::seed::evaluate(&mspec, &stim, d.as_ref(), o.timeout) {
            Ok(e) => (e.0, e.1),
            Err(f) => (Verdict::Error, Some(*f)),
        };
        if verdict == Verdict::Pass {
            continue;
        }
        let f = failure.unwrap_or_else(|| crate::check::Failure {
            kind: "error".into(),
            tick: 0,
            signal: "-".into(),
            expected: "-".into(),
            got: "-".into(),
            block: "-".into(),
            fig: "-".into(),
            diverging: Vec::new(),
            detail: "no failure given".into(),
        });
        // the control: the twin passes the seed that caught the mutant
        match crate::seed::evaluate(spec, &stim, twin, o.timeout) {
            Ok(e) if e.0 == Verdict::Pass => {}
            Ok(e) => {
                return Outcome::Error {
                    reason: format!(
                        "seed {seed} fails on the twin without a mutant too ({})",
                        e.1.map_or("-".into(), |f| format!("{}: {}", f.signature(), f.detail))
                    ),
                }
            }
            Err(f) => {
                return Outcome::Error {
                    reason: format!("seed {seed} on the twin: {}", f.detail),
                }
            }
        }
        if verdict == Verdict::Error {
            return Outcome::Error {
                reason: format!("seed {seed}: {}", f.detail),
            };
        }
        return Outcome::Caught {
            seeds: seed - spec.start_seed + 1,
            seed,
            signature: f.signature(),
            tick: f.tick,
            signal: f.signal,
            expected: f.expected,
            got: f.got,
        };
    }
    Outcome::Escaped {
        seeds: spec.iterations,
    }
}

/// Run the mutation table into `o.out` (mutation.json, mutation.txt, mutation.md). `progress` is given each
/// finished row's line.
pub fn run(o: &Options, stop: &AtomicBool, progress: fn(&str)) -> Result<Report, MutationError> {
    let t0 = Instant::now();
    if o.iterations == 0 || o.iterations > 100_000 {
        return Err(MutationError::Usage(format!(
            "--iterations {}: give 1 to 100000 seeds",
            o.iterations
        )));
    }
    if o.start_seed.checked_add(o.iterations).is_none() {
        return Err(MutationError::Usage("the seed range passes 2^64".into()));
    }
    let text = std::fs::read_to_string(&o.mutants).map_err(|e| MutationError::File {
        path: o.mutants.clone(),
        reason: e.to_string(),
    })?;
    let all = parse_mutants(&text, &o.mutants)?;
    let mutants: Vec<Mutant> = if o.only.is_empty() {
        all
    } else {
        let mut v = Vec::new();
        for n in &o.only {
            match all.iter().find(|m| &m.name == n) {
                Some(m) => v.push(m.clone()),
                None => {
                    return Err(MutationError::Usage(format!(
                        "--only {n}: not a mutant of {} (valid: {})",
                        o.mutants.display(),
                        all.iter()
                            .map(|m| m.name.as_str())
                            .collect::<Vec<_>>()
                            .join(", ")
                    )))
                }
            }
        }
        v
    };
    atomic_file::create_dir(&o.out)?;
    let spec = RunSpec {
        tool: format!("pmu50 {}", env!("CARGO_PKG_VERSION")),
        model: pmu50_coverage::model_id(pmu50_coverage::layout()),
        start_seed: o.start_seed,
        iterations: o.iterations,
        directed: true,
        check_spec: false,
        dut: DutKind::new("verilator"),
        rtl: Some(o.twin.display().to_string()),
        map: o.map.as_ref().map(|m| m.display().to_string()),
        fixed: Default::default(),
        pins: Pins::default(),
        shard: None,
        code_coverage: false,
        param_sets: o.param_sets,
        pool: Vec::new(),
    };
    let spec = RunSpec {
        pool: crate::param_pool::choose(
            spec.start_seed,
            spec.iterations,
            o.param_sets,
            spec.pins,
            &spec.fixed,
        )
        .map_err(|e| MutationError::Usage(e.to_string()))?,
        ..spec
    };
    let twin = dut::prepare(&spec).map_err(|e| MutationError::Usage(e.to_string()))?;
    if !twin.fixed().is_empty() {
        return Err(MutationError::Usage(format!(
            "{}: the twin fixes {}; the mutation table needs the twin with every parameter",
            o.twin.display(),
            twin.fixed().text()
        )));
    }
    let model = dut::prepare(&RunSpec {
        dut: DutKind::model(),
        rtl: None,
        map: None,
        ..spec.clone()
    })
    .map_err(|e| MutationError::Usage(e.to_string()))?;
    let biases = directed_biases(&spec, model.as_ref())?;

    let next = AtomicUsize::new(0);
    let rows: Mutex<Vec<Option<Row>>> = Mutex::new(vec![None; mutants.len()]);
    std::thread::scope(|s| {
        for _ in 0..o.jobs.max(1).min(mutants.len().max(1)) {
            s.spawn(|| loop {
                let k = next.fetch_add(1, Ordering::Relaxed);
                let Some(m) = mutants.get(k) else { break };
                let t = Instant::now();
                let outcome = one(o, &spec, &biases, twin.as_ref(), m, stop);
                let row = Row {
                    mutant: m.name.clone(),
                    block: m.block().to_string(),
                    scope: m.scope.clone(),
                    description: m.description.clone(),
                    outcome,
                    wall_s: (t.elapsed().as_secs_f64() * 10.0).round() / 10.0,
                };
                let line = match &row.outcome {
                    Outcome::Caught {
                        seeds, signature, ..
                    } => {
                        format!("{}: caught at seed {seeds} ({signature})", row.mutant)
                    }
                    Outcome::Escaped { seeds } => format!("{}: ESCAPED {seeds} seeds", row.mutant),
                    Outcome::Equivalent { .. } => format!("{}: proven equivalent", row.mutant),
                    Outcome::Error { reason } => format!("{}: ERROR {reason}", row.mutant),
                };
                progress(&format!("mutation: {line} ({:.0} s)", row.wall_s));
                if let Ok(mut r) = rows.lock() {
                    r[k] = Some(row);
                }
            });
        }
    });
    let rows: Vec<Row> = rows
        .into_inner()
        .map_err(|_| MutationError::Usage("a mutant's thread panicked".into()))?
        .into_iter()
        .flatten()
        .collect();
    let count = |f: fn(&Outcome) -> bool| rows.iter().filter(|r| f(&r.outcome)).count();
    let caught = count(|o| matches!(o, Outcome::Caught { .. }));
    let escaped = count(|o| matches!(o, Outcome::Escaped { .. }));
    let equivalent = count(|o| matches!(o, Outcome::Equivalent { .. }));
    let errors = count(|o| matches!(o, Outcome::Error { .. }));
    let run_n = rows.len() - equivalent;
    let mut catches: Vec<u64> = rows
        .iter()
        .filter_map(|r| match r.outcome {
            Outcome::Caught { seeds, .. } => Some(seeds),
            _ => None,
        })
        .collect();
    catches.sort_unstable();
    let report = Report {
        format: "pmu50-mutation/1",
        start_seed: o.start_seed,
        iterations: o.iterations,
        compare: if o.map.is_some() { "map" } else { "ports" },
        param_sets: o.param_sets,
        median_seeds: catches.get(catches.len() / 2).copied().unwrap_or(0),
        max_seeds: catches.last().copied().unwrap_or(0),
        caught,
        escaped,
        equivalent,
        errors,
        score_percent: if run_n == 0 {
            100.0
        } else {
            (1000.0 * caught as f64 / run_n as f64).round() / 10.0
        },
        wall_s: (t0.elapsed().as_secs_f64() * 10.0).round() / 10.0,
        rows,
    };
    let json = serde_json::to_string_pretty(&report)
        .map_err(|e| MutationError::Usage(e.to_string()))?
        + "\n";
    let mut b = Batch::new();
    b.add(atomic_file::write_atomic(
        &o.out.join("mutation.json"),
        json.as_bytes(),
    )?);
    b.add(atomic_file::write_atomic(
        &o.out.join("mutation.txt"),
        report.text().as_bytes(),
    )?);
    b.add(atomic_file::write_atomic(
        &o.out.join("mutation.md"),
        report.markdown().as_bytes(),
    )?);
    b.commit()?;
    Ok(report)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_scopes_and_refuses_bad_lines() {
        let p = Path::new("mutants.txt");
        let m = parse_mutants(
            "# c\nMUT_A | rtl/a.v | one\n\nMUT_B | rtl/b.v | two | regress\nMUT_C | rtl/c.v | three | equivalent: never both\n",
            p,
        )
        .unwrap();
        assert_eq!(m.len(), 3);
        assert_eq!(m[0].scope, Scope::Every);
        assert_eq!(m[0].block(), "a");
        assert_eq!(m[1].scope, Scope::Regress);
        assert_eq!(m[2].scope, Scope::Equivalent("never both".into()));
        let e = parse_mutants("MUT_A | rtl/a.v\n", p)
            .unwrap_err()
            .to_string();
        assert!(e.contains("line 1") && e.contains("2 fields"), "{e}");
        let e = parse_mutants("MUT_A | a | b | maybe\n", p)
            .unwrap_err()
            .to_string();
        assert!(e.contains("scope `maybe`"), "{e}");
        let e = parse_mutants("MUT_A | a | b\nMUT_A | a | c\n", p)
            .unwrap_err()
            .to_string();
        assert!(e.contains("line 2") && e.contains("twice"), "{e}");
        let e = parse_mutants("BAD-1 | a | b\n", p).unwrap_err().to_string();
        assert!(e.contains("MUT_"), "{e}");
    }

    #[test]
    fn shipped_list_parses_with_two_mutants_in_each_block() {
        // the kit the binary carries (verif/src/hdl_kit.rs): what an installed pmu50 runs
        let kit = |f: &str| {
            crate::hdl_kit::FILES
                .iter()
                .find(|(n, _)| *n == f)
                .map(|(_, t)| *t)
                .unwrap_or_else(|| panic!("{f}: not in the HDL kit"))
        };
        let p = Path::new("hdl/mutants.txt");
        let m = parse_mutants(kit("mutants.txt"), p).unwrap();
        let blocks: Vec<&str> = crate::hdl_kit::FILES
            .iter()
            .map(|(n, _)| *n)
            .filter(|n| n.starts_with("rtl/") && n.ends_with(".v"))
            .collect();
        assert_eq!(blocks.len(), 8, "the twin's eight block files");
        for f in blocks {
            let stem = f.trim_start_matches("rtl/").trim_end_matches(".v");
            let n = m.iter().filter(|x| x.block() == stem).count();
            assert!(n >= 2, "{f}: {n} mutant(s), at least 2 wanted");
        }
        // every mutant's define is in the file it names
        for x in &m {
            assert!(
                kit(&x.file).contains(&x.name),
                "{}: not in {}",
                x.name,
                x.file
            );
        }
    }
}
