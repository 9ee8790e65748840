//! Failure triage: failures grouped by signature (kind, first divergent signal, FIG. path);
//! for each group the smallest failing seed is shrunk to the shortest scenario that still fails
//! with the same signature (the run cut after the failure, then events and motions removed one
//! at a time while it still fails), and written to `failures/<signature>/`:
//!
//! - `repro.toml`: the shrunk scenario; `pmu50 regress --repro repro.toml` (with the same `--dut`,
//!   `--rtl`, `--map`, `--check-spec`) reproduces the failure, printed in `command.txt`;
//! - `repro.vcd` and `repro.gtkw`: the model's waveform of the shrunk run, GTKWave zoomed on the
//!   first divergence with a named marker there;
//! - `rtl.vcd` (a backend that gives it: Verilator): the RTL's own waveform of the same ticks,
//!   every signal of the RTL by its own names (a `--trace` build replaying the repro);
//! - `compare.vcd` and `compare.gtkw`: each signal that differs at the failing tick, the model's
//!   and the RTL's side by side, with the inputs and the register bus;
//! - `divergence.svg`: the picture of the same (crate::picture);
//! - `failure.txt`: what failed, where, and how the seed was shrunk.

use crate::check::Failure;
use crate::dut::Dut;
use crate::error::RegressError;
use crate::gen::{Action, Bias, Motion, Stimulus};
use crate::pool::BATCH;
use crate::seed::evaluate;
use crate::spec::RunSpec;
use crate::summary::Summary;
use std::path::Path;
use std::time::Duration;

/// The generator's bias for `seed` in the regression of `s` (directed runs steer by the
/// coverage of the seeds of earlier batches).
pub fn bias_for(s: &Summary, seed: u64) -> Result<Bias, RegressError> {
    let spec = &s.spec;
    if !spec.directed {
        return Ok(Bias::uniform()
            .pinned(spec.pins)
            .fixing(&spec.fixed)
            .pooled(&spec.pool));
    }
    let start = spec.seeds().start;
    let lo = start + (seed - start) / BATCH * BATCH;
    Ok(Bias::directed(&s.hits_before(lo)?, spec.pins)
        .fixing(&spec.fixed)
        .pooled(&spec.pool))
}

/// Shrink a failing stimulus; returns the smallest one found that fails with `sig`, its
/// failure, and the number of candidates tried.
pub fn shrink(
    spec: &RunSpec,
    stim: &Stimulus,
    first: &Failure,
    dut: &dyn Dut,
    timeout: Duration,
) -> (Stimulus, Failure, usize) {
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
        c.motion[k] = Motion::Hold {
            ticks: c.motion[k].ticks(),
        };
        if let Some(f) = fails(&c) {
            best = c;
            best_f = f;
        }
    }
    (best, best_f, tries.get())
}

/// The stimulus cut to `ticks` (events and motion past the end dropped).
pub(crate) fn truncate(s: &Stimulus, ticks: u64) -> Stimulus {
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
            Motion::Move {
                ticks: full,
                milli_deg,
            } => Motion::Move {
                ticks: len,
                milli_deg: milli_deg * len as i64 / full.max(1) as i64,
            },
        });
        t += len;
    }
    c.motion = motion;
    if !c
        .events
        .iter()
        .any(|(t, a)| *t == 0 && matches!(a, Action::Ig(_)))
    {
        c.events.insert(0, (0, Action::Ig(false)));
    }
    c
}

/// `arg` as one word of a POSIX shell command line: as it is when it holds only characters no
/// shell treats specially, else in single quotes (a single quote inside as `'\''`).
pub fn shell_quote(arg: &str) -> String {
    let plain = !arg.is_empty()
        && arg
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || "-_./=:,+@%".contains(c));
    if plain {
        arg.to_string()
    } else {
        format!("'{}'", arg.replace('\'', "'\\''"))
    }
}

/// The command that reproduces a failure from its folder, one shell line with every path
/// quoted ([`shell_quote`]): pasted into a shell it runs `pmu50` and nothing else.
pub fn command(spec: &RunSpec, repro: &Path) -> String {
    let mut c = format!(
        "pmu50 regress --repro {}",
        shell_quote(&repro.display().to_string())
    );
    // the model is `--dut`'s default
    if spec.dut != crate::spec::DutKind::model() {
        c.push_str(&format!(" --dut {}", spec.dut.name()));
    }
    if let Some(r) = &spec.rtl {
        c.push_str(&format!(" --rtl {}", shell_quote(r)));
    }
    if let Some(m) = &spec.map {
        c.push_str(&format!(" --map {}", shell_quote(m)));
    }
    if spec.check_spec {
        c.push_str(" --check-spec");
    }
    c
}

/// The command that opens GTKWave on a repro folder's model and RTL side by side.
pub fn compare_command(folder: &Path) -> String {
    format!(
        "gtkwave {} {}",
        shell_quote(&folder.join("compare.vcd").display().to_string()),
        shell_quote(&folder.join("compare.gtkw").display().to_string())
    )
}

/// The command that opens GTKWave on a repro folder's waveform, zoomed on the divergence.
pub fn view_command(folder: &Path) -> String {
    format!(
        "gtkwave {} {}",
        shell_quote(&folder.join("repro.vcd").display().to_string()),
        shell_quote(&folder.join("repro.gtkw").display().to_string())
    )
}

/// The pictures and waveforms of a repro's divergence beside the model's `repro.vcd`: the RTL's
/// own waveform (`rtl.vcd`, where the backend gives one), the model and the RTL side by side
/// (`compare.vcd`, `compare.gtkw`) and the SVG picture (crate::picture), with the DUT's trace
/// where its backend gives one. Returns the SVG and what could not be written (the files a
/// backend cannot give are left out, and said so in failure.txt).
fn both_sides(
    folder: &Path,
    toml: &str,
    name: &str,
    f: &Failure,
    dut: &dyn Dut,
) -> Result<(String, Vec<String>), String> {
    let path = folder.join("repro.toml");
    let sc =
        pmu50_testbench::scenario::Scenario::parse(toml, &path.display().to_string(), name, &path)
            .map_err(|e| e.to_string())?;
    let (from, to) = crate::wave::compare_window(f.tick, sc.ticks);
    let (rtl_from, rtl_to) = crate::wave::rtl_window(f.tick, sc.ticks);
    let mut notes = Vec::new();
    if f.kind != "dut" || f.signal == "dut" {
        // not a divergence from an RTL (a check of the model, a crash, a hang): the model's side
        let svg = crate::picture::divergence_svg(&sc, f, None).map_err(|e| e.to_string())?;
        return Ok((svg, notes));
    }
    let trace = match crate::dut::record(dut, &sc) {
        Ok(rec) => match dut.trace(&sc, rec, from, to) {
            Some(Ok(t)) => Some(t),
            Some(Err(e)) => {
                notes.push(format!("the DUT's trace: {e}"));
                None
            }
            None => None,
        },
        Err(e) => {
            notes.push(format!("the DUT's trace: {e}"));
            None
        }
    };
    if let Ok(rec) = crate::dut::record(dut, &sc) {
        match dut.rtl_wave(&sc, rec, (rtl_from, rtl_to), &folder.join("rtl.vcd")) {
            Some(Ok(())) => {}
            Some(Err(e)) => notes.push(format!("rtl.vcd: {e}")),
            None => notes.push(format!(
                "rtl.vcd: the {} backend gives no waveform of the RTL (--dut verilator does)",
                dut.name()
            )),
        }
    }
    if let Err(e) = crate::wave::write_compare(folder, &sc, f, trace.as_ref()) {
        notes.push(e.to_string());
    }
    let svg = crate::picture::divergence_svg(&sc, f, trace.as_ref()).map_err(|e| e.to_string())?;
    Ok((svg, notes))
}

/// Shrink the smallest failing seed of each signature and write its folder.
pub fn write_repros(
    s: &Summary,
    dir: &Path,
    dut: &dyn Dut,
    timeout: Duration,
) -> Result<(), RegressError> {
    for (sig, g) in &s.groups {
        let seed = g.smallest;
        let first = g.failure.clone();
        if first.kind == "error" {
            continue;
        }
        let stim = Stimulus::generate(seed, &bias_for(s, seed)?);
        let (small, f, tries) = shrink(&s.spec, &stim, &first, dut, timeout);
        let folder = dir.join("failures").join(sig);
        pmu50_testbench::atomic_file::create_dir(&folder)?;
        let name = format!("repro_{seed}");
        let toml = small.to_toml(&name);
        let repro = folder.join("repro.toml");
        let cmd = command(&s.spec, &repro);
        let view = view_command(&folder);
        let both = compare_command(&folder);
        // the RTL's side and the pictures first: what they could not give is said below
        crate::wave::write(&folder, &toml, &name, &f)?;
        let (svg, notes) =
            both_sides(&folder, &toml, &name, &f, dut).map_err(|e| RegressError::File {
                path: folder.join("divergence.svg"),
                reason: e,
            })?;
        let rtl_wave = if folder.join("rtl.vcd").is_file() {
            "\nthe RTL's own waveform of the same ticks (its signals by its names):\n  rtl.vcd"
                .to_string()
        } else {
            String::new()
        };
        let notes = if notes.is_empty() {
            String::new()
        } else {
            format!("\nnot written: {}", notes.join("; "))
        };
        let diverging = if f.diverging.len() > 1 {
            format!(
                "\nsignals that differ at tick {}: {}",
                f.tick,
                f.diverging
                    .iter()
                    .map(|s| s.trim_start_matches("pmu50."))
                    .collect::<Vec<_>>()
                    .join(", ")
            )
        } else {
            String::new()
        };
        let text = format!(
            "signature: {sig}\nseeds failing with it: {} (smallest {seed})\nfirst failure of seed {seed}: tick {} {} expected {} got {} ({})\nshrunk in {tries} runs: {} -> {} ticks, {} -> {} events\nafter shrinking: tick {} {} expected {} got {} (block {}, FIG. path {}){diverging}\n{}\n\nreproduce:\n  {cmd}\nwaves around the divergence (the model):\n  {view}\nthe model and the RTL side by side:\n  {both}{rtl_wave}\npicture: divergence.svg{notes}\n",
            g.count,
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
        let mut b = pmu50_testbench::atomic_file::Batch::new();
        b.add(pmu50_testbench::atomic_file::write_atomic(
            &repro,
            toml.as_bytes(),
        )?);
        b.add(pmu50_testbench::atomic_file::write_atomic(
            &folder.join("command.txt"),
            format!("{cmd}\n").as_bytes(),
        )?);
        b.add(pmu50_testbench::atomic_file::write_atomic(
            &folder.join("failure.txt"),
            text.as_bytes(),
        )?);
        b.commit()?;
        let mut b = pmu50_testbench::atomic_file::Batch::new();
        b.add(pmu50_testbench::atomic_file::write_atomic(
            &folder.join("divergence.svg"),
            svg.as_bytes(),
        )?);
        b.commit()?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The words a POSIX shell makes of `line` (run with `pmu50` replaced by printf).
    fn words(line: &str) -> Vec<String> {
        let line = line.strip_prefix("pmu50 ").expect("starts with pmu50");
        let o = std::process::Command::new("sh")
            .arg("-c")
            .arg(format!("printf '%s\\n' {line}"))
            .output()
            .unwrap();
        String::from_utf8(o.stdout)
            .unwrap()
            .lines()
            .map(String::from)
            .collect()
    }

    #[test]
    fn the_repro_command_is_one_shell_line_that_runs_pmu50_only() {
        let model = pmu50_coverage::model_id(pmu50_coverage::layout());
        let rtl = "/tmp/x;echo INJECTED $(touch pwned) `id` 'q' \"d\"/rtl.f";
        let spec = RunSpec {
            tool: "t".into(),
            model,
            start_seed: 1,
            iterations: 1,
            directed: false,
            check_spec: true,
            dut: crate::spec::DutKind::new("verilator"),
            rtl: Some(rtl.into()),
            map: Some("/m $(x).toml".into()),
            fixed: Default::default(),
            pins: Default::default(),
            shard: None,
            code_coverage: false,
            param_sets: 0,
            pool: Vec::new(),
        };
        let repro = Path::new("out dir/failures/dut-x-y/repro.toml");
        let cmd = command(&spec, repro);
        assert_eq!(
            words(&cmd),
            [
                "regress",
                "--repro",
                "out dir/failures/dut-x-y/repro.toml",
                "--dut",
                "verilator",
                "--rtl",
                rtl,
                "--map",
                "/m $(x).toml",
                "--check-spec"
            ],
            "{cmd}"
        );
        assert!(!cmd.contains('\n'));
        // plain paths stay readable
        assert_eq!(
            shell_quote("regress_out/failures/a-b.c/repro.toml"),
            "regress_out/failures/a-b.c/repro.toml"
        );
        assert_eq!(shell_quote(""), "''");
        assert_eq!(words(&format!("pmu50 {}", shell_quote("it's"))), ["it's"]);
    }
}
