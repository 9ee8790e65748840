//! Build modes: the pool of parameter sets a regression draws from (`pmu50 regress
//! --param-sets P`). Reset values and structure are Verilog parameters, so every distinct set is
//! one build of the RTL; a regression fixes at most P sets up front, from its seed range, builds
//! each once, and spreads its seeds over them ([`crate::gen::ParamSet::pick`]). What varies at
//! run time (stimulus, bus writes of legal values, faults) varies per seed as before.
//!
//! The pool is a greedy cover: candidates are drawn by the generator itself, aimed at every
//! configuration bin (`config.*`: structure, reset values, clock classes) and at every
//! [`Shape`] a stimulus needs from reset; the cover takes, one at a time, the candidate that
//! reaches most of what is still missing, until every configuration bin and shape that any
//! candidate reaches is reached by a set of the pool. The rest of the P sets are drawn uniformly.
//! Everything is a pure function of the seed range and the options, so shards, `--resume`,
//! `merge` and `--repro` see the same pool as one process.

use crate::cache::fnv;
use crate::gen::{knob_named, knobs_off, Bias, Knob, ParamSet, Pins, Shape, Stimulus};
use crate::rtl::Fixed;
use pmu50_coverage::model::{Hint, Sampled, POINTS};

/// The default number of parameter sets (`--param-sets`). The greedy cover of the configuration
/// bins and shapes takes 7 to 9 sets of the twin's parameters; 10 leaves room for a drawn one
/// or two. A plain build of the twin costs about 1 s of CPU and one with code coverage about
/// 3 s, so 10 builds keep a 400-seed regression on 2 cores within 30 s (60 s with code
/// coverage), where one build per seed took minutes (docs/verification.md, "Build modes").
pub const DEFAULT_SETS: u32 = 10;

/// Candidates drawn per aim.
const PER_AIM: u64 = 6;

/// Why a pool of P sets cannot be made.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("--param-sets {asked}: the configuration bins need {needed} parameter sets (a greedy cover of {bins} bins); give --param-sets {needed} or more, or 0 for a set per seed")]
pub struct TooFew {
    pub asked: u32,
    pub needed: usize,
    pub bins: usize,
}

/// What a set reaches: configuration bins (by index) and shapes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
enum Feature {
    Bin(usize),
    Shape(Shape),
}

fn features(s: &ParamSet, shapes: bool) -> Vec<Feature> {
    let mut f: Vec<Feature> = s.config_bins().into_iter().map(Feature::Bin).collect();
    if shapes {
        f.extend(s.shapes().into_iter().map(Feature::Shape));
    }
    f
}

/// The knob sets the candidates aim at: for each k, the k-th bin of every configuration point
/// at once (a few sets then reach every bin), each configuration bin alone, the shapes' knobs
/// alone and with each combination, and nothing (uniform).
fn aims(off: &[Knob]) -> Vec<Vec<Knob>> {
    let knobs_of = |h: &Hint| -> Vec<Knob> {
        match h {
            Hint::Knobs(k) => k.iter().filter_map(|n| knob_named(n)).collect(),
            _ => Vec::new(),
        }
    };
    let config: Vec<_> = POINTS
        .iter()
        .filter(|p| p.sampled == Sampled::Config)
        .collect();
    let widest = config.iter().map(|p| p.bins.len()).max().unwrap_or(0);
    let mut combos: Vec<Vec<Knob>> = (0..widest)
        .map(|k| {
            config
                .iter()
                .flat_map(|p| knobs_of(&p.bins[k % p.bins.len()].hint))
                .collect()
        })
        .collect();
    let singles: Vec<Vec<Knob>> = config
        .iter()
        .flat_map(|p| p.bins.iter().map(|b| knobs_of(&b.hint)))
        .filter(|k| !k.is_empty())
        .collect();
    let shaped: [&[Knob]; 3] = [
        &[Knob::LongQuiet],
        &[Knob::LongDurations],
        &[Knob::StatusWrites, Knob::FastMoves],
    ];
    let mut out = Vec::new();
    out.append(&mut combos.clone());
    for s in shaped {
        out.push(s.to_vec());
        for c in &combos {
            let mut k = c.clone();
            k.extend_from_slice(s);
            out.push(k);
        }
    }
    out.append(&mut combos);
    out.extend(singles);
    out.push(Vec::new());
    out.into_iter()
        .map(|mut k| {
            k.retain(|x| !off.contains(x));
            k.sort();
            k.dedup();
            k
        })
        .collect()
}

/// The candidate sets of a seed range: [`PER_AIM`] seeds of a stream of the range's own for
/// each aim, in order, distinct.
fn candidates(start_seed: u64, iterations: u64, pins: Pins, fixed: &Fixed) -> Vec<ParamSet> {
    let base = fnv(&[
        b"param-pool",
        &start_seed.to_le_bytes(),
        &iterations.to_le_bytes(),
    ]);
    let off = knobs_off(fixed);
    let mut out: Vec<ParamSet> = Vec::new();
    for (a, aim) in aims(&off).into_iter().enumerate() {
        let mut bias = Bias::uniform().pinned(pins).fixing(fixed);
        if !aim.is_empty() {
            bias.targets = vec![aim.clone()];
        }
        // the shapes need rarer draws (a long quiet run of one variant)
        let per = if aim.contains(&Knob::LongQuiet) || aim.contains(&Knob::LongDurations) {
            4 * PER_AIM
        } else {
            PER_AIM
        };
        for k in 0..per {
            let seed = fnv(&[
                &base.to_le_bytes(),
                &(a as u64).to_le_bytes(),
                &k.to_le_bytes(),
            ]);
            let s = Stimulus::generate(seed, &bias);
            let set = ParamSet {
                params: s.params,
                clock_us: s.clock_us,
            };
            if !out.contains(&set) {
                out.push(set);
            }
        }
    }
    out
}

/// Greedy cover of every feature the candidates reach: the indices of the candidates taken.
fn greedy(cands: &[Vec<Feature>], mut taken: Vec<usize>) -> Vec<usize> {
    let mut missing: std::collections::BTreeSet<Feature> =
        cands.iter().flatten().copied().collect();
    for &t in &taken {
        for f in &cands[t] {
            missing.remove(f);
        }
    }
    while !missing.is_empty() {
        // the first candidate that reaches most of what is missing
        let (best, gain) = cands
            .iter()
            .enumerate()
            .map(|(i, f)| (i, f.iter().filter(|x| missing.contains(x)).count()))
            .fold((0, 0), |a, b| if b.1 > a.1 { b } else { a });
        if gain == 0 {
            break;
        }
        taken.push(best);
        for f in &cands[best] {
            missing.remove(f);
        }
    }
    taken
}

/// The pool of at most `sets` parameter sets of the seed range `start_seed`, `iterations`
/// (0: none, each seed draws its own): every configuration bin and every shape any candidate
/// reaches is reached by a set of the pool (the shapes only as far as `sets` allows), the rest
/// drawn uniformly. Refused when the configuration bins alone need more than `sets`.
pub fn choose(
    start_seed: u64,
    iterations: u64,
    sets: u32,
    pins: Pins,
    fixed: &Fixed,
) -> Result<Vec<ParamSet>, TooFew> {
    if sets == 0 {
        return Ok(Vec::new());
    }
    let cands = candidates(start_seed, iterations, pins, fixed);
    let with_shapes: Vec<Vec<Feature>> = cands.iter().map(|c| features(c, true)).collect();
    let mut taken = greedy(&with_shapes, Vec::new());
    if taken.len() > sets as usize {
        // the configuration bins first; then the shapes, as far as the sets allow
        let bins_only: Vec<Vec<Feature>> = cands.iter().map(|c| features(c, false)).collect();
        taken = greedy(&bins_only, Vec::new());
        let bins = bins_only
            .iter()
            .flatten()
            .collect::<std::collections::BTreeSet<_>>();
        if taken.len() > sets as usize {
            return Err(TooFew {
                asked: sets,
                needed: taken.len(),
                bins: bins.len(),
            });
        }
        taken = greedy(&with_shapes, taken);
        taken.truncate(sets as usize);
    }
    // the rest: the uniform candidates (the last aim), in order
    let uniform_from = cands.len().saturating_sub(PER_AIM as usize);
    let mut rest = (uniform_from..cands.len()).chain(0..uniform_from);
    while taken.len() < sets as usize {
        match rest.next() {
            Some(i) if !taken.contains(&i) => taken.push(i),
            Some(_) => {}
            None => break,
        }
    }
    Ok(taken.into_iter().map(|i| cands[i]).collect())
}

/// The configuration bins and shapes the candidates of a seed range reach (for the tests).
pub fn reachable(
    start_seed: u64,
    iterations: u64,
    pins: Pins,
    fixed: &Fixed,
) -> (Vec<usize>, Vec<Shape>) {
    let mut bins = std::collections::BTreeSet::new();
    let mut shapes = std::collections::BTreeSet::new();
    for c in candidates(start_seed, iterations, pins, fixed) {
        bins.extend(c.config_bins());
        shapes.extend(c.shapes());
    }
    (bins.into_iter().collect(), shapes.into_iter().collect())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gen::config_indices;

    fn covered(pool: &[ParamSet]) -> (Vec<usize>, Vec<Shape>) {
        let mut b: Vec<usize> = pool.iter().flat_map(|s| s.config_bins()).collect();
        b.sort();
        b.dedup();
        let mut s: Vec<Shape> = pool.iter().flat_map(|s| s.shapes()).collect();
        s.sort();
        s.dedup();
        (b, s)
    }

    #[test]
    fn the_default_pool_reaches_every_configuration_bin_and_shape() {
        let l = pmu50_coverage::layout();
        for (start, n) in [(1, 400), (1, 2000), (7_777, 123)] {
            let pool = choose(start, n, DEFAULT_SETS, Pins::default(), &Fixed::default()).unwrap();
            assert!(pool.len() <= DEFAULT_SETS as usize);
            let (bins, shapes) = covered(&pool);
            let missing: Vec<&str> = config_indices()
                .iter()
                .filter(|i| !bins.contains(i))
                .map(|&i| l.bins[i].name.as_str())
                .collect();
            assert!(
                missing.is_empty(),
                "seeds {start}+{n}: the pool misses {missing:?}"
            );
            assert_eq!(shapes, Shape::ALL.to_vec(), "seeds {start}+{n}");
            // the same range gives the same pool
            assert_eq!(
                pool,
                choose(start, n, DEFAULT_SETS, Pins::default(), &Fixed::default()).unwrap()
            );
        }
    }

    /// Any seed, uniform or aimed at any bin, reaches no configuration bin that the pool does
    /// not: checked over 3000 seeds of each kind of draw, with and without held structure.
    #[test]
    fn no_seed_reaches_a_configuration_bin_the_pool_lacks() {
        let l = pmu50_coverage::layout();
        for pins in [
            Pins::default(),
            Pins {
                sync_depth: Some(3),
                cnt_width: Some(8),
            },
        ] {
            let pool = choose(11, 400, DEFAULT_SETS, pins, &Fixed::default()).unwrap();
            let (bins, _) = covered(&pool);
            let mut biases = vec![Bias::uniform().pinned(pins)];
            for &i in config_indices() {
                biases.push(Bias::from_missing([l.bins[i].name.as_str()]).pinned(pins));
            }
            for (k, bias) in biases.iter().enumerate() {
                for seed in 0..(3000 / biases.len() as u64).max(20) {
                    let s = Stimulus::generate(seed * 1000 + k as u64, bias);
                    let set = ParamSet {
                        params: s.params,
                        clock_us: s.clock_us,
                    };
                    for b in set.config_bins() {
                        assert!(
                            bins.contains(&b),
                            "{pins:?}: seed {seed} reaches {} which the pool lacks",
                            l.bins[b].name
                        );
                    }
                }
            }
        }
    }

    #[test]
    fn an_rtl_that_fixes_its_values_has_a_pool_of_one_set() {
        let p = pmu50_core::Params::default();
        let values = p
            .hdl_parameters()
            .iter()
            .map(|(n, v)| (n.to_string(), *v))
            .collect();
        let pool = choose(1, 400, DEFAULT_SETS, Pins::default(), &Fixed { values }).unwrap();
        let distinct: std::collections::BTreeSet<_> =
            pool.iter().map(|s| format!("{:?}", s.params)).collect();
        assert_eq!(distinct.len(), 1, "{pool:?}");
    }

    #[test]
    fn too_few_sets_are_refused_with_the_number_needed() {
        let e = choose(1, 400, 2, Pins::default(), &Fixed::default()).unwrap_err();
        assert!(e.needed > 2, "{e}");
        assert!(e.to_string().contains("--param-sets"), "{e}");
        assert!(choose(1, 400, 0, Pins::default(), &Fixed::default())
            .unwrap()
            .is_empty());
    }

    #[test]
    fn every_seed_of_a_pooled_bias_has_a_set_of_the_pool() {
        let pool = choose(1, 400, DEFAULT_SETS, Pins::default(), &Fixed::default()).unwrap();
        let l = pmu50_coverage::layout();
        let mut used = std::collections::BTreeSet::new();
        for (k, b) in l.bins.iter().enumerate().step_by(7) {
            let bias = Bias::from_missing([b.name.as_str()]).pooled(&pool);
            for seed in 0..4u64 {
                let s = Stimulus::generate(seed * 600 + k as u64, &bias);
                let set = ParamSet {
                    params: s.params,
                    clock_us: s.clock_us,
                };
                let at = pool.iter().position(|p| *p == set);
                assert!(at.is_some(), "seed {seed} aimed at {}: {set:?}", b.name);
                used.extend(at);
            }
        }
        assert_eq!(used.len(), pool.len(), "the seeds use every set");
    }
}
