//! The failure of a seed as a DUT reports it: a divergence (the first mismatch, its block, the
//! FIG. 17/18 path of the cycle), a crash or a hang.

use crate::check::{fig_path, Failure};
use crate::lockstep::Mismatch;
use pmu50_core::drive_interval_changing_56b::{Fig17, Fig18};
use pmu50_testbench::scenario::Scenario;
use pmu50_testbench::sim::{self, Observer, SimError, SimOptions, TickView};
use std::time::Duration;

/// The block of a model signal path, for the failure's `block` (the producer of an internal).
fn block_of(signal: &str) -> Option<&'static str> {
    let b = match signal.split_once('.') {
        Some(("internals", "fig17" | "fig18")) => "drive_interval",
        Some(("internals", "kon" | "koff")) => "action_switching",
        Some(("internals", "upd" | "first" | "chg_s" | "chg_c")) => "comparator_latch",
        Some(("internals", "skip_clr")) => "register_file",
        Some(("internals", _)) => return None,
        Some((b, _)) => {
            return pmu50_core::signals::REGISTERS
                .iter()
                .find(|s| s.scope == b)
                .map(|s| s.scope)
        }
        None => return None,
    };
    Some(b)
}

/// The failure of a divergence the DUT reported: the first mismatch (the report lists a port
/// before the register that drives it), the block of the first divergent register, and the
/// FIG. 17/18 path of the cycle.
pub fn divergence(sc: &Scenario, tick: u64, combinational: bool, mm: &[Mismatch]) -> Failure {
    let first = mm.first().cloned().unwrap_or(Mismatch {
        signal: "?".into(),
        expected: 0,
        got: 0,
    });
    let block = mm
        .iter()
        .find_map(|m| block_of(&m.signal))
        .unwrap_or("ports")
        .to_string();
    // internals are compared during cycle `tick`, the rest after edge `tick` (the end of cycle
    // `tick - 1`): the FIG. path of that cycle
    let cycle = if combinational {
        Some(tick)
    } else {
        tick.checked_sub(1)
    };
    let shown: Vec<String> = mm
        .iter()
        .take(8)
        .map(|m| format!("{} expected {:#x} got {:#x}", m.signal, m.expected, m.got))
        .collect();
    let mut f = dut_failure(
        sc,
        cycle,
        format!(
            "the RTL diverges from the model at tick {tick}{}: {}{}",
            if combinational {
                " (before its rising edge)"
            } else {
                ""
            },
            shown.join(", "),
            if mm.len() > 8 {
                format!(" (and {} more)", mm.len() - 8)
            } else {
                String::new()
            }
        ),
    );
    f.tick = tick;
    f.signal = format!("pmu50.{}", first.signal);
    f.expected = format!("0x{:x}", first.expected);
    f.got = format!("0x{:x}", first.got);
    f.block = block;
    let mut all: Vec<String> = mm.iter().map(|m| format!("pmu50.{}", m.signal)).collect();
    all.sort();
    all.dedup();
    f.diverging = all;
    f
}

/// A DUT failure that names no signal (a hang, a crash), at bench cycle `cycle` when known.
pub fn dut_failure(sc: &Scenario, cycle: Option<u64>, detail: String) -> Failure {
    let fig = cycle.map_or_else(|| "-".to_string(), |c| fig_at(sc, c));
    Failure {
        kind: "dut".into(),
        tick: cycle.map_or(0, |c| c + 1),
        signal: "dut".into(),
        expected: "-".into(),
        got: "-".into(),
        block: "-".into(),
        fig,
        diverging: Vec::new(),
        detail,
    }
}

/// The failure of a DUT that did not finish within the time limit.
pub fn timed_out(sc: &Scenario, timeout: Duration) -> Failure {
    dut_failure(
        sc,
        None,
        format!(
            "the DUT did not finish within the per-seed time limit of {} s",
            timeout.as_secs_f64()
        ),
    )
}

/// The FIG. 17/18 path of bench cycle `cycle` (the edge at its end), from a run of the model.
pub fn fig_at(sc: &Scenario, cycle: u64) -> String {
    struct At(u64, Fig17, Fig18);
    impl Observer for At {
        fn tick(&mut self, v: &TickView<'_>) -> Result<(), SimError> {
            if v.tick == self.0 {
                self.1 = v.internals.fig17;
                self.2 = v.internals.fig18;
            }
            Ok(())
        }
    }
    let mut at = At(cycle, Fig17::Idle, Fig18::Idle);
    let mut short = sc.clone();
    short.ticks = short.ticks.min(cycle + 1);
    match sim::run(&short, SimOptions::default(), &mut [&mut at]) {
        Ok(_) => fig_path(at.1, at.2),
        Err(_) => "-".into(),
    }
}
