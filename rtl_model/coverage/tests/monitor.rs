//! The Verilog coverage monitor generated from the model: the committed files are the
//! generator's output, every bin has a wire of its own, and the model's identity did not move.

use pmu50_coverage::model::{Sampled, POINTS};
use pmu50_coverage::monitor::{files, verilog, wire_name, Source, SIGNALS};
use pmu50_coverage::{layout, model_id};
use std::collections::BTreeSet;

const FORMAL: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../../hdl/formal/");

#[test]
fn committed_monitor_is_the_generated_one() {
    // the monitor, its top, its table and the top's contract
    for (name, text) in files() {
        let on_disk = std::fs::read_to_string(format!("{FORMAL}{name}")).unwrap();
        assert!(
            on_disk == text,
            "hdl/formal/{name} differs from the model's; run `pmu50 hdl coverage-monitor`"
        );
    }
}

#[test]
fn every_bin_has_its_own_wire_in_the_monitor() {
    let v = verilog();
    let l = layout();
    let wires: BTreeSet<String> = l.bins.iter().map(|b| wire_name(&b.name)).collect();
    assert_eq!(wires.len(), l.bins.len(), "two bins mangle to one wire");
    for w in &wires {
        assert!(
            w.chars().all(|c| c.is_ascii_alphanumeric() || c == '_'),
            "{w} is no Verilog identifier"
        );
        assert!(
            v.contains(&format!("    wire {w} = ")),
            "{w} is not declared"
        );
    }
    // hits lists the wires in storage order, bin 0 last
    let start = v.find("assign hits = {").unwrap();
    let order: Vec<&str> = v[start..]
        .split(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
        .filter(|w| w.starts_with("hit_"))
        .collect();
    let want: Vec<String> = l.bins.iter().rev().map(|b| wire_name(&b.name)).collect();
    assert_eq!(order, want);
}

#[test]
fn every_bin_is_declared_with_its_classification() {
    for p in POINTS.iter() {
        assert_eq!(
            p.when.is_empty(),
            p.sampled == Sampled::Config,
            "{}.{}: an edge point says when it is sampled, a configuration point does not",
            p.group,
            p.name
        );
        for b in p.bins {
            assert!(!b.sv.trim().is_empty(), "{}.{}.{}", p.group, p.name, b.name);
        }
        // the last bin of a point takes whatever the others leave, or the bins are exhaustive
        // by construction; either way no bin's expression names an undeclared signal
        for b in p.bins {
            for word in
                b.sv.split(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
            {
                let ident = word.chars().next().is_some_and(|c| c.is_ascii_alphabetic());
                let literal_base = word.len() > 1
                    && matches!(word.as_bytes()[0], b'b' | b'd' | b'h')
                    && b.sv.contains(&format!("'{word}"));
                if ident && !literal_base {
                    let known = SIGNALS.iter().any(|s| s.name == word)
                        || verilog().contains(&format!("wire {word} ="))
                        || verilog().contains(&format!("wire [2:0]  {word} "))
                        || verilog().contains(&format!("wire [17:0] {word} "))
                        || ["CNT_TOP", "CNT_MIN", "CNT_W", "SYNC_DEPTH", "CLOCK_NS"]
                            .contains(&word);
                    assert!(
                        known,
                        "{}.{}.{}: unknown signal {word}",
                        p.group, p.name, b.name
                    );
                }
            }
        }
    }
    // the monitor reads the twin's nets by the names the map and the kit use
    let map = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../hdl/pmu50.map.toml"
    ))
    .unwrap();
    for s in SIGNALS {
        if let Source::Net(path) = s.source {
            if path.starts_with("internals.") || !path.contains(".c_") && !path.ends_with("_n") {
                let mapped = map.contains(&format!("\"pmu50.{path}\""));
                let next_state = [
                    "si_n",
                    "cnt_r_n",
                    "in_range",
                    "skip_nxt",
                    "param_wr",
                    "c_legal",
                    "cnt_s_nxt",
                    "cnt_c_nxt",
                ]
                .iter()
                .any(|x| path.ends_with(x));
                assert!(
                    mapped || next_state,
                    "{path} is neither in hdl/pmu50.map.toml nor a next-state net"
                );
            }
        }
    }
}

#[test]
fn the_model_identity_is_unchanged() {
    // the names and order of the bins are the coverage files' identity: a change must be
    // deliberate (bump it here and in the goldens)
    assert_eq!(model_id(layout()), "pmu50-coverage/532/44e7828b57d38c80");
}

#[test]
fn configuration_bins_are_rewritten_to_the_candidate_set() {
    let v = verilog();
    assert!(v.contains("wire config__t1__nxt_m1 = 17'd2 * c_t1 >= c_si_max - c_si_min;"));
    assert!(v.contains("wire config__x__nxt_m1 = c_si_max <= 16'd300;"));
}

#[test]
fn every_reachable_bin_declares_how_the_generator_aims_at_it() {
    use pmu50_coverage::model::Hint;
    use pmu50_coverage::Aim;
    for p in POINTS.iter() {
        for b in p.bins {
            let declared = p.unreachable.iter().any(|(n, _)| *n == b.name);
            assert_eq!(
                b.hint == Hint::Never,
                declared,
                "{}.{}.{}: Hint::Never exactly on the bins declared unreachable",
                p.group,
                p.name,
                b.name
            );
        }
    }
    for b in &layout().bins {
        assert_eq!(
            b.aim == Aim::Never,
            b.unreachable.is_some(),
            "{}: a reachable bin without a hint, or an unreachable one with one",
            b.name
        );
        assert_eq!(
            b.aim == Aim::PortLevel,
            b.port_only && b.unreachable.is_none(),
            "{}",
            b.name
        );
    }
}
