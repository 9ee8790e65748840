//! `pmu50 regress`: random regressions measured by functional coverage, failures triaged to a
//! repro (docs/verification.md).
//!
//! A regression is a seed range. Each seed is one generated scenario ([`gen`]) run on the full
//! bench (environment, MPU, core) with the checks and coverage of [`check`]; with a DUT other
//! than the model, the same stimulus also drives the RTL in lockstep ([`dut`]). A seed's result
//! is one line of `results.jsonl`, carrying its sparse coverage, so results and coverage of any
//! set of seeds merge exactly ([`merge`]): the files of a regression depend on its seed range
//! and options only, never on `--jobs`, on sharding or on interruptions.
//!
//! Folder layout (`--out DIR`): `regress.json` (the run), `results.jsonl` (one line per seed,
//! sorted by seed when the run completes), `coverage.json` (merge format), `coverage.ucis.xml`
//! (the same coverage as UCIS 1.0 XML, which pyucis reads and merges), `report.html`,
//! `failures/<signature>/` (shrunk repro, command, waveform).

use crate::error::{file_err, RegressError};
use crate::pool::{run_pool, BATCH};
use crate::spec::{RunSpec, SeedResult, Verdict};
use crate::summary::{Source, Summary};
use crate::{code_cov, dut, folder, triage};
use pmu50_coverage::layout;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};

use std::time::Duration;

/// Options of `pmu50 regress`.
#[derive(Clone, Debug)]
pub struct Options {
    pub spec: RunSpec,
    pub jobs: usize,
    pub out: PathBuf,
    pub timeout: Duration,
    /// Shrink failures and write their repro folders.
    pub triage: bool,
    /// Called with a line of progress after each batch (the CLI prints it on a terminal).
    pub progress: Option<fn(&str)>,
    /// The waivers of the code coverage (`spec.code_coverage`) of a new run; a resumed run
    /// keeps those of its folder.
    pub waivers: Option<code_cov::Waivers>,
    /// What makes the folder (`crate::evidence::for_run`), sealed into its regress.json; a
    /// resumed run keeps its folder's, after checking that the RTL has not changed.
    pub evidence: Option<crate::evidence::RunEvidence>,
}

/// Seeds of a random regression handed to the pool at once: what the pool holds in memory (a
/// seed's result with its coverage is about 7 kB) stays bounded whatever the seed range.
const CHUNK: u64 = 4096;

/// Run a regression into `o.out`: the seeds of the spec not yet in the folder (all of them
/// unless resuming), in batches, on `o.jobs` threads. Finished results go to results.jsonl at
/// once; only their index stays in memory.
pub fn run(
    o: &Options,
    resume: bool,
    stop: &AtomicBool,
    d: &dyn dut::Dut,
) -> Result<Summary, RegressError> {
    let dir = &o.out;
    pmu50_testbench::atomic_file::create_dir(dir)?;
    let results_path = dir.join("results.jsonl");
    let range = o.spec.seeds();
    let mut sink = code_cov::sink::sink(o.spec.code_coverage, o.waivers.clone());
    let mut evidence = o.evidence.clone();
    if resume {
        let sf = folder::read_spec_file(dir)?;
        if let Some(ev) = &sf.evidence {
            check_same_rtl(dir, ev, &o.spec)?;
        }
        evidence = sf.evidence;
        sink.resume(dir, &range)?;
    }
    let mut total = vec![0u64; layout().bins.len()];
    let (done, complete_len) = if resume {
        let s = folder::scan(&results_path, 0, &range, &mut total, |_, _| {})?;
        (
            folder::Store::new(vec![results_path.clone()], s.entries)?,
            s.complete_len,
        )
    } else {
        (
            folder::Store::new(vec![results_path.clone()], Vec::new())?,
            0,
        )
    };
    if !resume {
        // A new run: the folder's previous results are replaced when this run writes them.
        let spec = crate::evidence::spec_text(
            &o.spec,
            evidence.as_ref(),
            &std::collections::BTreeMap::new(),
        )?;
        let mut b = pmu50_testbench::atomic_file::Batch::new();
        b.add(pmu50_testbench::atomic_file::write_atomic(
            &dir.join("regress.json"),
            spec.as_bytes(),
        )?);
        b.add(pmu50_testbench::atomic_file::write_atomic(
            &results_path,
            b"",
        )?);
        b.commit()?;
        sink.start(dir)?;
    }
    // A last line torn by an interruption is cut before anything is appended after it.
    let mut appender = folder::open_regular(&results_path, true)?
        .ok_or_else(|| file_err(&results_path, "cannot be created"))?;
    appender
        .set_len(complete_len)
        .map_err(|e| file_err(&results_path, e))?;
    // Build modes: every parameter set of the pool built once, before any seed, as many at
    // once as the jobs allow (a set that does not build fails the seeds that draw it).
    // (done already when the caller prebuilt the pool: the builds are kept by the DUT)
    d.prebuild(&o.spec.pool, o.jobs)
        .map_err(|e| RegressError::Dut(e.to_string()))?;
    let total_seeds = range.end - range.start;
    let mut n_done = done.len() as u64;
    let mut fails = done
        .entries
        .iter()
        .filter(|e| e.verdict != folder::Verdict::Pass)
        .count() as u64;
    let mut write =
        |mut out: Vec<(SeedResult, Vec<u64>)>, total: &mut Vec<u64>| -> Result<(), RegressError> {
            // the sinks first: a batch whose results an interruption tore is found by --resume
            let results: Vec<&SeedResult> = out.iter().map(|(r, _)| r).collect();
            sink.batch(dir, &results)?;
            let batch_seeds = out.len();
            let mut text = String::new();
            for (r, hits) in &mut out {
                // A failure triage will shrink: the command that opens its repro's waves.
                if o.triage {
                    r.view = r
                        .failure
                        .as_ref()
                        .filter(|f| r.verdict == Verdict::Fail && f.kind != "error")
                        .map(|f| triage::view_command(&Path::new("failures").join(f.signature())));
                }
                for (t, h) in total.iter_mut().zip(hits) {
                    *t = t.saturating_add(*h);
                }
                text.push_str(
                    &serde_json::to_string(r).map_err(|e| RegressError::Usage(e.to_string()))?,
                );
                text.push('\n');
            }
            appender
                .write_all(text.as_bytes())
                .and_then(|_| appender.flush())
                .map_err(|e| file_err(&results_path, e))?;
            if batch_seeds > 0 {
                sink.after_batch(dir)?;
            }
            n_done += out.len() as u64;
            fails += out
                .iter()
                .filter(|(r, _)| r.verdict != Verdict::Pass)
                .count() as u64;
            if let Some(progress) = o.progress {
                let l = layout();
                let hit = l
                    .bins
                    .iter()
                    .zip(total.iter())
                    .filter(|(b, h)| **h > 0 && b.unreachable.is_none())
                    .count();
                let all = l.bins.iter().filter(|b| b.unreachable.is_none()).count();
                progress(&format!(
                    "regress: {n_done}/{total_seeds} seeds, {fails} failing, coverage {hit}/{all}"
                ));
            }
            Ok(())
        };
    if o.spec.directed {
        // Batch by batch: each batch's bias is the coverage of every seed before it (the
        // folder's, read back in seed order, and this run's).
        let mut before = vec![0u64; total.len()];
        let mut reader = done.reader()?;
        let mut cursor = 0;
        let mut lo = range.start;
        while lo < range.end && !stop.load(Ordering::Relaxed) {
            let hi = (lo + BATCH).min(range.end);
            while let Some(e) = done.entries.get(cursor).filter(|e| e.seed < lo) {
                reader
                    .result(e)?
                    .hits(&mut before)
                    .map_err(RegressError::Usage)?;
                cursor += 1;
            }
            let bias = o.spec.bias(&before);
            let todo: Vec<u64> = (lo..hi).filter(|s| !done.contains(*s)).collect();
            let out = run_pool(
                &o.spec,
                &todo,
                &bias,
                d,
                o.jobs,
                o.timeout,
                stop,
                |_| Ok(()),
            )?;
            for (_, hits) in &out {
                for (b, h) in before.iter_mut().zip(hits) {
                    *b = b.saturating_add(*h);
                }
            }
            write(out, &mut total)?;
            lo = hi;
        }
    } else {
        // One queue over each chunk of the range: no core waits for the slowest seed of a
        // batch; the results are written in seed order as soon as every seed before them has
        // finished.
        let bias = o.spec.bias(&[]);
        let mut pending: Vec<(SeedResult, Vec<u64>)> = Vec::new();
        let mut last = std::time::Instant::now();
        let mut lo = range.start;
        while lo < range.end && !stop.load(Ordering::Relaxed) {
            let hi = lo.saturating_add(CHUNK).min(range.end);
            let todo: Vec<u64> = (lo..hi).filter(|s| !done.contains(*s)).collect();
            run_pool(&o.spec, &todo, &bias, d, o.jobs, o.timeout, stop, |ready| {
                pending.extend(ready);
                if pending.len() as u64 >= BATCH || last.elapsed() > Duration::from_secs(2) {
                    last = std::time::Instant::now();
                    write(std::mem::take(&mut pending), &mut total)?;
                }
                Ok(())
            })?;
            lo = hi;
        }
        write(pending, &mut total)?;
    }
    drop(appender);
    drop(done);
    sink.finish(dir)?;
    let mut summary = Summary::build(o.spec.clone(), &[Source::of(dir, &o.spec)])?;
    summary.evidence = evidence;
    if o.triage && !stop.load(Ordering::Relaxed) {
        triage::write_repros(&summary, dir, d, o.timeout)?;
    }
    crate::publish::write(&summary, dir, None)?;
    Ok(summary)
}

/// A resumed run continues on the RTL its folder was started on: refused when any file of it
/// changed (naming the file, or both content hashes).
fn check_same_rtl(
    dir: &Path,
    ev: &crate::evidence::RunEvidence,
    spec: &crate::spec::RunSpec,
) -> Result<(), RegressError> {
    let (Some(was), Some(list)) = (&ev.provenance.rtl, crate::evidence::rtl_list(spec)) else {
        return Ok(());
    };
    let (now, files) = crate::evidence::rtl_of(&list)?;
    if now.hash == was.hash {
        return Ok(());
    }
    Err(RegressError::Usage(format!(
        "--resume {}: the regression was started on RTL {} ({}), the RTL is now {}{}: resume on the RTL it was started on, or start a new regression",
        dir.display(),
        was.hash,
        was.list,
        now.hash,
        crate::evidence::changed_files(&ev.record.rtl_files, &files)
    )))
}
