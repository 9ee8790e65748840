//! Failure triage: failures grouped by signature (kind, first divergent signal, FIG. path);
//! for each group the smallest failing seed is shrunk to the shortest scenario that still fails
//! with the same signature (the run cut after the failure, then events and motions removed one
//! at a time while it still fails), and written to `failures/<signature>/`:
//!
//! - `repro.toml`: the shrunk scenario; `pmu50 regress --repro repro.toml` (with the same `--dut`,
//!   `--rtl`, `--map`, `--check-spec`) reproduces the failure, printed in `command.txt`;
//! - `repro.vcd` and `repro.gtkw`: the model's waveform of the shrunk run, GTKWave zoomed on the
//!   first divergence with a named marker there;
//! - `failure.txt`: what failed, where, and how the seed was shrunk.

use super::check::Failure;
use super::gen::{Action, Bias, Motion, Stimulus};
use super::{dut::Dut, evaluate, RegressError, RunSpec, SeedResult, Summary, BATCH};
use pmu50_coverage::layout;
use std::collections::BTreeMap;
use std::path::Path;
use std::time::Duration;

/// Failing seeds by signature, each list ascending.
pub fn groups(results: &[SeedResult]) -> BTreeMap<String, Vec<u64>> {
    let mut g: BTreeMap<String, Vec<u64>> = BTreeMap::new();
    for r in results {
        if let Some(f) = &r.failure {
            g.entry(f.signature()).or_default().push(r.seed);
        }
    }
    for v in g.values_mut() {
        v.sort_unstable();
    }
    g
}

/// The generator's bias for `seed` in this regression (directed runs steer by the coverage of
/// the seeds of earlier batches).
pub fn bias_for(spec: &RunSpec, seed: u64, results: &[SeedResult]) -> Bias {
    if !spec.directed {
        return Bias::uniform().pinned(spec.pins).fixing(&spec.fixed);
    }
    let lo = spec.seeds().start + (seed - spec.seeds().start) / BATCH * BATCH;
    let mut before = vec![0u64; layout().bins.len()];
    for r in results.iter().filter(|r| r.seed < lo) {
        let _ = r.hits(&mut before);
    }
    Bias::directed(&before, spec.pins).fixing(&spec.fixed)
}

/// Shrink a failing stimulus; returns the smallest one found that fails with `sig`, its
/// failure, and the number of candidates tried.
pub fn shrink(spec: &RunSpec, stim: &Stimulus, first: &Failure, dut: &dyn Dut, timeout: Duration) -> (Stimulus, Failure, usize) {
    let sig = first.signature();
    let tries = std::cell::Cell::new(0usize);
    let fails = |s: &Stimulus| -> Option<Failure> {
        tries.set(tries.get() + 1);
        match evaluate(spec, s, dut, timeout) {
            Ok((_, Some(f), ..)) if f.signature() == sig => Some(f),
            _ => None,
        }
    };
    let mut best = stim.clone();
    let mut best_f = first.clone();
    // 1. The run ends just after the failure.
    let cut = truncate(&best, best_f.tick + 2);
    if let Some(f) = fails(&cut) {
        best = cut;
        best_f = f;
    }
    // 2. Events, then motions, removed one at a time (latest first) while it still fails.
    const MAX_TRIES: usize = 400;
    let mut k = best.events.len();
    while k > 1 && tries.get() < MAX_TRIES {
        k -= 1;
        let mut c = best.clone();
        c.events.remove(k);
        if let Some(f) = fails(&c) {
            best = truncate(&c, f.tick + 2);
            best_f = f;
            k = k.min(best.events.len());
        }
    }
    let mut k = best.motion.len();
    while k > 0 && tries.get() < MAX_TRIES {
        k -= 1;
        if matches!(best.motion[k], Motion::Hold { .. }) {
            continue;
        }
        let mut c = best.clone();
        c.motion[k] = Motion::Hold { ticks: c.motion[k].ticks() };
        if let Some(f) = fails(&c) {
            best = c;
            best_f = f;
        }
    }
    (best, best_f, tries.get())
}

/// The stimulus cut to `ticks` (events and motion past the end dropped).
fn truncate(s: &Stimulus, ticks: u64) -> Stimulus {
    let ticks = ticks.clamp(1, s.ticks);
    let mut c = s.clone();
    c.ticks = ticks;
    c.events.retain(|(t, _)| *t < ticks);
    let mut t = 0;
    let mut motion = Vec::new();
    for m in &s.motion {
        if t >= ticks {
            break;
        }
        let len = m.ticks().min(ticks - t);
        motion.push(match *m {
            Motion::Hold { .. } => Motion::Hold { ticks: len },
            Motion::Move { ticks: full, milli_deg } => Motion::Move { ticks: len, milli_deg: milli_deg * len as i64 / full.max(1) as i64 },
        });
        t += len;
    }
    c.motion = motion;
    if !c.events.iter().any(|(t, a)| *t == 0 && matches!(a, Action::Ig(_))) {
        c.events.insert(0, (0, Action::Ig(false)));
    }
    c
}

/// The command that reproduces a failure from its folder.
pub fn command(spec: &RunSpec, repro: &Path) -> String {
    let mut c = format!("pmu50 regress --repro {}", repro.display());
    match spec.dut {
        super::DutKind::Model => {}
        super::DutKind::Verilator => c.push_str(" --dut verilator"),
        super::DutKind::Icarus => c.push_str(" --dut icarus"),
    }
    if let Some(r) = &spec.rtl {
        c.push_str(&format!(" --rtl {r}"));
    }
    if let Some(m) = &spec.map {
        c.push_str(&format!(" --map {m}"));
    }
    if spec.check_spec {
        c.push_str(" --check-spec");
    }
    c
}

/// Shrink the smallest failing seed of each signature and write its folder.
pub fn write_repros(s: &Summary, dir: &Path, dut: &dyn Dut, timeout: Duration) -> Result<(), RegressError> {
    for (sig, seeds) in groups(&s.results) {
        let seed = seeds[0];
        let Some(first) = s.results.iter().find(|r| r.seed == seed).and_then(|r| r.failure.clone()) else { continue };
        if first.kind == "error" {
            continue;
        }
        let stim = Stimulus::generate(seed, &bias_for(&s.spec, seed, &s.results));
        let (small, f, tries) = shrink(&s.spec, &stim, &first, dut, timeout);
        let folder = dir.join("failures").join(&sig);
        crate::atomic_file::create_dir(&folder)?;
        let name = format!("repro_{seed}");
        let toml = small.to_toml(&name);
        let repro = folder.join("repro.toml");
        let cmd = command(&s.spec, &repro);
        let text = format!(
            "signature: {sig}\nseeds failing with it: {} (smallest {seed})\nfirst failure of seed {seed}: tick {} {} expected {} got {} ({})\nshrunk in {tries} runs: {} -> {} ticks, {} -> {} events\nafter shrinking: tick {} {} expected {} got {} (block {}, FIG. path {})\n{}\n\nreproduce:\n  {cmd}\n",
            seeds.len(),
            first.tick,
            first.signal,
            first.expected,
            first.got,
            first.detail,
            stim.ticks,
            small.ticks,
            stim.events.len(),
            small.events.len(),
            f.tick,
            f.signal,
            f.expected,
            f.got,
            f.block,
            f.fig,
            f.detail,
        );
        let mut b = crate::atomic_file::Batch::new();
        b.add(crate::atomic_file::write_atomic(&repro, toml.as_bytes())?);
        b.add(crate::atomic_file::write_atomic(&folder.join("command.txt"), format!("{cmd}\n").as_bytes())?);
        b.add(crate::atomic_file::write_atomic(&folder.join("failure.txt"), text.as_bytes())?);
        b.commit()?;
        super::wave::write(&folder, &toml, &name, &f)?;
    }
    Ok(())
}
