//! The sampler against a simpler reference: a core driven with random port stimuli, every edge
//! sampled, and the hits of the event bins recounted from what the core visibly did (its
//! outputs before and after each edge) rather than from the sampler's decode.

use pmu50_core::drive_interval_changing_56b::Fig17;
use pmu50_core::updown_counter_58cd::sext;
use pmu50_core::{Inputs, Params, Pmu50, TracedStep};
use pmu50_coverage::{layout, Coverage, Edge};
use std::collections::BTreeMap;

use pmu50_core::rng::SplitMix64 as Rng;

fn hits_of(c: &Coverage) -> BTreeMap<String, u64> {
    layout()
        .bins
        .iter()
        .zip(c.hits())
        .map(|(b, &h)| (b.name.clone(), h))
        .collect()
}

fn run(seed: u64, p: Params, ticks: u64) -> (Coverage, BTreeMap<String, u64>) {
    let mut r = Rng(seed);
    let mut core = Pmu50::new(p).unwrap();
    let mut cov = Coverage::new(&p, 10_000);
    let mut reference: BTreeMap<String, u64> = BTreeMap::new();
    let mut bump = |k: String| *reference.entry(k).or_default() += 1;
    let mut ig = false;
    let (mut cs, mut cc) = (false, false);
    for _ in 0..ticks {
        if r.percent(1) {
            ig = !ig;
        }
        if r.percent(3) {
            cs = !cs;
        }
        if r.percent(3) {
            cc = !cc;
        }
        let we = r.percent(2);
        let i = Inputs {
            ig,
            vs2_ok: !r.percent(5),
            cmp_s: cs,
            cmp_c: cc,
            bus_we: we,
            bus_addr: (r.next() % 0x16) as u8,
            bus_wdata: (r.next() % 700) as u16,
        };
        let before = *core.regs();
        let out = core.peek();
        let TracedStep {
            internals: n,
            after: after_out,
            ..
        } = core.step_traced(&i);
        let after = *core.regs();
        cov.sample(&Edge {
            before: &before,
            after: &after,
            out: &out,
            inputs: &i,
            internals: &n,
        });

        // The reference: what the outputs show.
        if !out.sig && after_out.sig {
            bump("key.edge.on".into());
        }
        if out.sig && !after_out.sig {
            bump("key.edge.off".into());
        }
        let name17 = match n.fig17 {
            Fig17::Idle => None,
            Fig17::S1NoRise => Some("s1_no_rise"),
            Fig17::S5AtMin => Some("s5_at_min"),
            Fig17::S6Shorten => Some("s6_shorten"),
            Fig17::S7AtMax => Some("s7_at_max"),
            Fig17::S9Count => Some("s9_count"),
            Fig17::S10Expand => Some("s10_expand"),
            Fig17::Fixed => Some("fixed"),
        };
        if let Some(b) = name17 {
            bump(format!("fig17.path.{b}"));
        }
        // A counting rule, recounted from the latches and the counters' visible move.
        let w = p.cnt_width;
        let ds = sext(after_out.cnt_s.wrapping_sub(out.cnt_s), w);
        let dc = sext(after_out.cnt_c.wrapping_sub(out.cnt_c), w);
        let s_moved = out.cs != after_out.cs;
        let c_moved = out.cc != after_out.cc;
        if n.upd && !n.first && s_moved != c_moved {
            let rule = if s_moved {
                if out.cc {
                    "0096"
                } else {
                    "0097"
                }
            } else if out.cs {
                "0099"
            } else {
                "0098"
            };
            let (who, d) = if s_moved { ("s", ds) } else { ("c", dc) };
            assert!(
                d == 1 || d == -1,
                "a single sign change moves its counter by one"
            );
            bump(format!(
                "counter.rule.{who}_{rule}_{}",
                if d == 1 { "up" } else { "down" }
            ));
        }
        if n.upd && !n.first && s_moved && c_moved {
            assert_eq!((ds, dc), (0, 0), "a skip holds both counters");
            bump(format!(
                "counter.quadrant_skip.{}",
                if out.sig { "key_on" } else { "key_off" }
            ));
        }
        if we {
            let taken = after.register_file.params(p.sync_depth, p.cnt_width)
                != before.register_file.params(p.sync_depth, p.cnt_width);
            if taken {
                bump("params_changed".into());
            }
        }
    }
    (cov, reference)
}

#[test]
fn event_bins_count_what_the_core_visibly_did() {
    let mut seen_rules = 0;
    for seed in 0..12 {
        let p = Params {
            cnt_width: [16, 2, 3, 8][seed as usize % 4],
            sync_depth: 1 + (seed % 4) as u8,
            ..Params::default()
        };
        let (cov, reference) = run(seed, p, 60_000);
        let got = hits_of(&cov);
        for (k, v) in &reference {
            if k == "params_changed" {
                // every taken write that changed a parameter re-samples the configuration
                let cfg: u64 = got
                    .iter()
                    .filter(|(n, _)| n.starts_with("config.cth."))
                    .map(|(_, h)| h)
                    .sum();
                assert_eq!(
                    cfg,
                    v + 1,
                    "seed {seed}: configuration samples = 1 + parameter changes"
                );
                continue;
            }
            assert_eq!(got.get(k), Some(v), "seed {seed}: bin {k}");
            if k.starts_with("counter.rule.") {
                seen_rules += 1;
            }
        }
        // and nothing was counted that the reference did not see
        for (k, h) in &got {
            if *h > 0
                && (k.starts_with("fig17.path.")
                    || k.starts_with("counter.rule.")
                    || k.starts_with("key.edge.")
                    || k.starts_with("counter.quadrant_skip."))
            {
                assert_eq!(reference.get(k), Some(h), "seed {seed}: bin {k}");
            }
        }
    }
    assert!(
        seen_rules >= 40,
        "the stimulus applied the counting rules ({seen_rules})"
    );
}

#[test]
fn unreachable_bins_are_never_hit_by_random_port_stimuli() {
    let mut total = vec![0u64; layout().bins.len()];
    for seed in 100..112 {
        let p = Params {
            cnt_width: [16, 2, 3, 8][seed as usize % 4],
            sync_depth: 1 + (seed % 4) as u8,
            adaptive: seed % 5 != 0,
            ..Params::default()
        };
        let (cov, _) = run(seed, p, 50_000);
        for (t, h) in total.iter_mut().zip(cov.hits()) {
            *t += h;
        }
    }
    let l = layout();
    for (b, h) in l.bins.iter().zip(&total) {
        if let Some(why) = b.unreachable {
            assert_eq!(
                *h, 0,
                "{} is declared unreachable ({why}) but was hit",
                b.name
            );
        }
    }
    let hit = l
        .bins
        .iter()
        .zip(&total)
        .filter(|(b, h)| b.unreachable.is_none() && **h > 0)
        .count();
    assert!(hit > l.bins.len() / 3, "random port stimuli hit {hit} bins");
}
