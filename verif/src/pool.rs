//! The pool of jobs that runs a list of seeds ([`run_pool`]): each job pipelines its seeds (the
//! model of seed n+1 runs while the DUT runs seed n), and the results come back in seed order.

use crate::dut;
use crate::error::RegressError;
use crate::gen::Bias;
use crate::seed::{start_seed, Pending, Stage};
use crate::spec::{Place, RunSpec, SeedResult};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::time::Duration;

/// Seeds generated between two updates of the directed bias (and written to results.jsonl at once).
pub const BATCH: u64 = 32;

/// Run seeds on `jobs` threads. `ready` is given the results in seed order, each as soon as
/// every seed before it has finished; all of them are also returned, in seed order.
#[allow(clippy::too_many_arguments)]
pub fn run_pool(
    spec: &RunSpec,
    seeds: &[u64],
    bias: &Bias,
    dut: &dyn dut::Dut,
    jobs: usize,
    timeout: Duration,
    stop: &AtomicBool,
    mut ready: impl FnMut(Vec<(SeedResult, Vec<u64>)>) -> Result<(), RegressError>,
) -> Result<Vec<(SeedResult, Vec<u64>)>, RegressError> {
    let next = AtomicUsize::new(0);
    let place = Place::here(spec.shard.as_ref());
    let (tx, rx) = std::sync::mpsc::channel::<(usize, SeedResult, Vec<u64>)>();
    let mut all: Vec<Option<(SeedResult, Vec<u64>)>> = vec![None; seeds.len()];
    let mut err = None;
    std::thread::scope(|s| {
        for _ in 0..jobs.max(1).min(seeds.len().max(1)) {
            let tx = tx.clone();
            let (next, place) = (&next, &place);
            // A job pipelines its seeds: while the RTL of seed n runs in this job's DUT worker,
            // the model runs seed n+1 here; then n's verdict is taken and n+1 is sent. So the
            // regression waits for the model only where it is slower than the RTL.
            s.spawn(move || {
                let mut running: Option<(usize, Pending)> = None;
                let emit = |k: usize, (mut r, hits): (SeedResult, Vec<u64>)| {
                    r.place = place.clone();
                    tx.send((k, r, hits)).is_ok()
                };
                loop {
                    let k = if stop.load(Ordering::Relaxed) {
                        None
                    } else {
                        Some(next.fetch_add(1, Ordering::Relaxed))
                    };
                    let stage = k.and_then(|k| {
                        seeds
                            .get(k)
                            .map(|&seed| (k, start_seed(spec, seed, bias, dut)))
                    });
                    if let Some((j, p)) = running.take() {
                        if !emit(j, p.finish(dut, timeout)) {
                            break;
                        }
                    }
                    match stage {
                        None => break,
                        Some((k, Stage::Done(r, hits))) => {
                            if !emit(k, (*r, hits)) {
                                break;
                            }
                        }
                        Some((k, Stage::Pending(mut p))) => match p.send(dut) {
                            Err(e) => {
                                let (r, hits) = p.failed(e);
                                if !emit(k, (r, hits)) {
                                    break;
                                }
                            }
                            Ok(()) => running = Some((k, p)),
                        },
                    }
                }
            });
        }
        drop(tx);
        let mut flushed = 0;
        for (k, r, hits) in rx {
            all[k] = Some((r, hits));
            let start = flushed;
            while flushed < all.len() && all[flushed].is_some() {
                flushed += 1;
            }
            if flushed > start && err.is_none() {
                let out = all[start..flushed].iter().flatten().cloned().collect();
                if let Err(e) = ready(out) {
                    err = Some(e);
                    stop.store(true, Ordering::Relaxed);
                }
            }
        }
    });
    if let Some(e) = err {
        return Err(e);
    }
    Ok(all.into_iter().flatten().collect())
}
