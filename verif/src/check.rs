//! What every regression seed is checked against, and the coverage it samples, as one observer
//! of the bench.
//!
//! Checks (the first failure of a seed is its verdict):
//! - the model's invariants at every edge: a skipped quadrant raises `diag` ([0119], docs/spec.md
//!   2.7); `bus_err` rises only at a bus write the register file refuses, for the reason it
//!   gives (docs/spec.md 2.8);
//! - at the end: every key-on read-out equals the true angle within [`READOUT_TOL_DEG`] whenever
//!   the shaft stayed under the tracking bound of docs/analysis.md since the first sample (no Vs2
//!   fault, no parameter write, speed below 0.8 x 90 deg per sampling period), modulo the
//!   counters' range of 2^CNT_W quadrants, where every sample sees a settled sensor (Wt and the
//!   on-key period at least the 99 % settling time);
//! - with `--check-spec`: the readable per-block model (`Pmu50Spec`) stepped beside the kernel,
//!   every register and every output compared after every edge.

use pmu50_core::drive_interval_changing_56b::{Fig17, Fig18};
use pmu50_core::register_file as rf;
use pmu50_core::{Pmu50Spec, Regs};
use pmu50_coverage::Coverage;
use pmu50_testbench::scenario::{Action, Scenario};
use pmu50_testbench::sim::{Observer, RunResult, SimError, TickView};
use serde::{Deserialize, Serialize};

/// A read-out under the tracking bound must be this close to the true angle (docs/analysis.md
/// uses the same 0.5 deg for `pmu50 speed-limit`).
pub const READOUT_TOL_DEG: f64 = 0.5;

/// The first failure of a seed.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Failure {
    /// `invariant`, `spec`, `dut`, `expect` or `error`.
    pub kind: String,
    /// Edge number (clock ticks from reset).
    pub tick: u64,
    /// Full signal path (`pmu50.diag`, `pmu50.drive_interval.si`), or the check's name.
    pub signal: String,
    pub expected: String,
    pub got: String,
    /// The block the signal belongs to.
    pub block: String,
    /// FIG. 17 / FIG. 18 path of the edge (`s6_shorten/s23_detected_cs`, or `-`).
    pub fig: String,
    /// A divergence: every signal that differs at its tick (full paths, sorted), of which
    /// `signal` is the first the DUT reported. Empty for the other kinds.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub diverging: Vec<String>,
    pub detail: String,
}

/// Diverging signals named in a signature before the rest is counted and hashed.
const SIGNATURE_SIGNALS: usize = 4;

impl Failure {
    /// What groups failures: the kind, the set of signals that differ at the failing tick (the
    /// first divergent signal where only one does) and, when one of them is the interval
    /// adaptation's, the FIG. path. A root cause that shows on two signals at once, whichever
    /// the DUT lists first, is one signature.
    pub fn signature(&self) -> String {
        let all: Vec<&str> = if self.diverging.is_empty() {
            vec![self.signal.trim_start_matches("pmu50.")]
        } else {
            self.diverging
                .iter()
                .map(|s| s.trim_start_matches("pmu50."))
                .collect()
        };
        let names = causes(&all);
        let what = if names.len() > SIGNATURE_SIGNALS {
            format!(
                "{}+{}more_{:08x}",
                names[..SIGNATURE_SIGNALS].join("+"),
                names.len() - SIGNATURE_SIGNALS,
                crate::cache::fnv(&[names.join(",").as_bytes()]) as u32
            )
        } else {
            names.join("+")
        };
        // The FIG. 17/18 path tells failures of the interval adaptation apart; a bug elsewhere
        // (a counter, the register file) shows in whatever path the cycle took, and one root
        // cause would fall into as many signatures as paths.
        let fig = if names.iter().any(|s| decided_by_fig(s)) {
            self.fig.replace('/', "_")
        } else {
            "-".to_string()
        };
        let raw = format!("{}-{}-{}", self.kind, what, fig);
        raw.chars()
            .map(|c| {
                if c.is_ascii_alphanumeric() || "_-.+".contains(c) {
                    c
                } else {
                    '_'
                }
            })
            .collect()
    }
}

/// The signals of a divergence that are not the same edge's consequence of another one of them:
/// the count diagnosis compares the two counters ([0119], docs/spec.md 2.7), so `diag` beside a
/// counter is that counter's error; a read shows a register, so `bus_rdata` beside another
/// signal shows that signal's error. A root cause that sometimes trips its consequence on the
/// same edge is one signature (the failure's text still lists every signal that differs).
fn causes<'a>(diverging: &[&'a str]) -> Vec<&'a str> {
    let counter = |s: &str| {
        matches!(
            s,
            "cnt_s" | "cnt_c" | "updown_counter.cnt_s" | "updown_counter.cnt_c"
        )
    };
    let has_counter = diverging.iter().any(|s| counter(s));
    let kept: Vec<&str> = diverging
        .iter()
        .copied()
        .filter(|s| !(has_counter && matches!(*s, "diag" | "count_diagnosis.diag")))
        .collect();
    if kept.len() > 1 {
        kept.into_iter().filter(|s| *s != "bus_rdata").collect()
    } else {
        kept
    }
}

/// Whether the FIG. 17/18 path decides `signal`'s value: the drive interval changing block's
/// state (si, CNTr and the two history flags, at the ports or inside the block, [0240]-[0275])
/// and the path itself.
fn decided_by_fig(signal: &str) -> bool {
    let s = signal.trim_start_matches("pmu50.");
    matches!(
        s,
        "si" | "cnt_r" | "hist_s" | "hist_c" | "internals.fig17" | "internals.fig18"
    ) || s.starts_with("drive_interval.")
}

/// FIG. 17/18 path of an edge, by the coverage bins' names (`s6_shorten/s23_detected_cs`, or
/// `-` where FIG. 17 did not run).
pub fn fig_path(f17: Fig17, f18: Fig18) -> String {
    use pmu50_coverage::model::{FIG17, FIG18, POINTS};
    if f17 == Fig17::Idle {
        return "-".into();
    }
    let a = POINTS[FIG17].bins[f17 as usize - 1].name;
    if f18 == Fig18::Idle {
        a.to_string()
    } else {
        format!("{a}/{}", POINTS[FIG18].bins[f18 as usize - 1].name)
    }
}

/// The observer of one seed: coverage, invariants, and optionally the per-block model.
pub struct SeedChecks {
    pub coverage: Coverage,
    spec: Option<Pmu50Spec>,
    pub failure: Option<Failure>,
    /// Tick of the first sample (the counters' origin).
    pub first_sample: Option<u64>,
    /// Ticks where a bus write changed the parameters.
    pub param_writes: Vec<u64>,
    /// Key-on read-outs the tracking invariant applied to.
    pub readouts_checked: u64,
    cnt_width: u8,
    sync_depth: u8,
}

impl SeedChecks {
    pub fn new(p: &pmu50_core::Params, clock_ns: u64, check_spec: bool) -> SeedChecks {
        SeedChecks {
            coverage: Coverage::new(p, clock_ns),
            spec: if check_spec {
                Pmu50Spec::new(*p).ok()
            } else {
                None
            },
            failure: None,
            first_sample: None,
            param_writes: Vec::new(),
            readouts_checked: 0,
            cnt_width: p.cnt_width,
            sync_depth: p.sync_depth,
        }
    }

    fn fail(&mut self, f: Failure) {
        if self.failure.is_none() {
            self.failure = Some(f);
        }
    }

    /// The end-of-run checks: read-outs under the tracking bound. The counters accumulate from
    /// the first sample, so a read-out is checked only when the whole history since then stayed
    /// under the bound: no Vs2 fault, no parameter write, the shaft below 0.8 x 90 deg per
    /// sampling period, and within the turns the counters' width can tell apart.
    pub fn finish_checks(&mut self, r: &RunResult, sc: &Scenario) {
        let Some(first) = self.first_sample else {
            return;
        };
        let p = &sc.params;
        // Every sample must see a settled sensor (99 %, tau ln 100): the key-off window Wt and
        // the on-key period both at least that long ([0321]: Pw lets the sensor stabilise).
        let settle_ns = sc.env.sensor2.tau_us * 1e3 * 100f64.ln();
        let clk_f = sc.clock_ns() as f64;
        if (f64::from(p.wt()) * clk_f) < settle_ns || (f64::from(p.smp_on) * clk_f) < settle_ns {
            return;
        }
        let period = u64::from(p.si_max.max(p.smp_on));
        let bound = 0.8 * 90.0 / period as f64;
        let clk = sc.clock_ns();
        let faults: Vec<(u64, bool)> = sc
            .events
            .iter()
            .filter_map(|e| {
                if let Action::Vs2Fault(v) = e.action {
                    Some((e.tick, v))
                } else {
                    None
                }
            })
            .collect();
        let faulted_before = faults
            .iter()
            .filter(|(t, _)| *t <= first)
            .map(|(_, v)| *v)
            .next_back()
            .unwrap_or(false);
        // Each counter holds 2^W values, read sign-extended: the read-out is the angle modulo
        // 2^W quadrants (docs/spec.md 2.5), 360 deg at W = 2.
        let modulus = f64::from(1u32 << p.cnt_width) * 90.0;
        for k in r.keyons.iter().filter(|k| k.tick > first) {
            let window = first..=k.tick;
            let faulted = faulted_before || faults.iter().any(|(t, v)| window.contains(t) && *v);
            let wrote = self.param_writes.iter().any(|t| window.contains(t));
            let speed = sc
                .motor
                .max_speed_deg_per_ns(first * clk, (k.tick + 1) * clk)
                * clk as f64;
            if faulted || wrote || speed >= bound {
                return;
            }
            let error = k.error_deg - (k.error_deg / modulus).round() * modulus;
            self.readouts_checked += 1;
            if error.abs() > READOUT_TOL_DEG {
                self.fail(Failure {
                    kind: "invariant".into(),
                    tick: k.tick,
                    signal: "readout".into(),
                    expected: format!("{:.3} deg", k.true_deg),
                    got: format!("{:.3} deg", k.true_deg + k.error_deg),
                    block: "updown_counter".into(),
                    fig: "-".into(),
                    diverging: Vec::new(),
                    detail: format!(
                        "key-on read-out {:.3} deg off the true angle (modulo the counters' range of {modulus} deg) although since the first sample (tick {first}) the shaft stayed under the tracking bound (at most {speed:.4} deg/tick, bound {bound:.4}: 0.8 x 90 deg / {period} ticks) without a Vs2 fault or a parameter write",
                        error
                    ),
                });
                return;
            }
        }
    }
}

impl Observer for SeedChecks {
    fn tick(&mut self, v: &TickView<'_>) -> Result<(), SimError> {
        self.coverage.tick(v)?;
        let (b, a, i, n) = (v.regs, v.after, v.inputs, v.internals);
        if n.first && self.first_sample.is_none() {
            self.first_sample = Some(v.tick);
        }
        if self.failure.is_some() {
            return Ok(());
        }
        let fig = || fig_path(n.fig17, n.fig18);
        if a.updown_counter.quadrant_skip && !a.count_diagnosis.diag {
            self.fail(Failure {
                kind: "invariant".into(),
                tick: v.tick,
                signal: "pmu50.diag".into(),
                expected: "1".into(),
                got: "0".into(),
                block: "count_diagnosis".into(),
                fig: fig(),
                diverging: Vec::new(),
                detail: "quadrant_skip is set but diag is not: a skipped quadrant must raise the count diagnosis ([0119], docs/spec.md 2.7)".into(),
            });
        }
        if i.bus_we {
            let block = rf::RegisterFile::new(self.sync_depth, self.cnt_width);
            let rfi = rf::Inputs {
                bus_we: true,
                bus_addr: i.bus_addr,
                bus_wdata: i.bus_wdata,
                sig: v.ports.sig,
                ..Default::default()
            };
            let refused = block.bus_write(&b.register_file, &rfi).is_err();
            if !refused
                && a.register_file.params(self.sync_depth, self.cnt_width)
                    != b.register_file.params(self.sync_depth, self.cnt_width)
            {
                self.param_writes.push(v.tick);
            }
            if refused != a.register_file.bus_err && !b.register_file.bus_err {
                self.fail(refusal_failure(v.tick, refused, fig()));
            }
        } else if a.register_file.bus_err && !b.register_file.bus_err {
            self.fail(refusal_failure(v.tick, false, fig()));
        }
        if let Some(spec) = self.spec.as_mut() {
            spec.step(i);
            if let Some((signal, block, want, got)) = first_difference(spec.regs(), a) {
                let f = Failure {
                    kind: "spec".into(),
                    tick: v.tick,
                    signal,
                    expected: want,
                    got,
                    block,
                    fig: fig(),
                    diverging: Vec::new(),
                    detail: "the fast kernel and the readable per-block model (Pmu50Spec) differ after this edge".into(),
                };
                self.fail(f);
            }
        }
        Ok(())
    }

    fn needs_every_tick(&self) -> bool {
        true
    }

    /// Skipped repeated key-off periods add their coverage; the per-block model must see every
    /// tick, so with it nothing is skipped.
    fn replays_periods(&self) -> bool {
        self.spec.is_none()
    }

    fn period_boundary(&mut self, k: u64) -> Result<(), SimError> {
        Observer::period_boundary(&mut self.coverage, k)
    }

    fn can_replay(&self, k: u64, len: u64) -> bool {
        Observer::can_replay(&self.coverage, k, len)
    }

    fn replay(&mut self, k: u64, periods: u64, len: u64) -> Result<(), SimError> {
        Observer::replay(&mut self.coverage, k, periods, len)
    }
}

fn refusal_failure(tick: u64, refused: bool, fig: String) -> Failure {
    Failure {
        kind: "invariant".into(),
        tick,
        signal: "pmu50.bus_err".into(),
        expected: if refused { "1" } else { "0" }.into(),
        got: if refused { "0" } else { "1" }.into(),
        block: "register_file".into(),
        fig,
        diverging: Vec::new(),
        detail: if refused {
            "the register file's rules refuse this write, but bus_err did not rise (docs/spec.md 2.8)".into()
        } else {
            "bus_err rose without a write the register file's rules refuse: an unexplained refusal (docs/spec.md 2.8)".into()
        },
    }
}

/// The first register that differs, as (path, block, expected, got).
fn first_difference(want: &Regs, got: &Regs) -> Option<(String, String, String, String)> {
    macro_rules! cmp {
        ($($block:ident . $reg:ident),* $(,)?) => {$(
            if want.$block.$reg != got.$block.$reg {
                return Some((
                    concat!("pmu50.", stringify!($block), ".", stringify!($reg)).to_string(),
                    stringify!($block).to_string(),
                    format!("{:?}", want.$block.$reg),
                    format!("{:?}", got.$block.$reg),
                ));
            }
        )*};
    }
    cmp!(
        action_switching.sync,
        register_file.adaptive,
        register_file.pw,
        register_file.pi,
        register_file.ps,
        register_file.si_max,
        register_file.si_min,
        register_file.t1,
        register_file.t2,
        register_file.cth,
        register_file.smp_on,
        register_file.bus_err,
        register_file.rdata,
        timing_generator.tmr,
        sensor_power_determination.sr,
        comparator_latch.cs,
        comparator_latch.cc,
        comparator_latch.vld,
        updown_counter.cnt_s,
        updown_counter.cnt_c,
        updown_counter.quadrant_skip,
        drive_interval.si,
        drive_interval.hist_s,
        drive_interval.hist_c,
        drive_interval.cnt_r,
        count_diagnosis.diag,
    );
    debug_assert!(want == got, "every register is compared");
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    fn diverged(first: &str, all: &[&str]) -> Failure {
        Failure {
            kind: "dut".into(),
            tick: 9,
            signal: first.into(),
            expected: "0x0".into(),
            got: "0x1".into(),
            block: "ports".into(),
            fig: "s10_expand/s25_no_change".into(),
            diverging: all.iter().map(|s| s.to_string()).collect(),
            detail: String::new(),
        }
    }

    #[test]
    fn one_root_cause_on_two_signals_is_one_signature() {
        // the same set, whichever signal the DUT listed first
        let a = diverged("pmu50.cnt_r", &["pmu50.cnt_r", "pmu50.si"]);
        let b = diverged("pmu50.si", &["pmu50.cnt_r", "pmu50.si"]);
        assert_eq!(a.signature(), b.signature());
        assert_eq!(a.signature(), "dut-cnt_r+si-s10_expand_s25_no_change");
        // one signal: the first divergent signal, as before
        assert_eq!(
            diverged("pmu50.si", &["pmu50.si"]).signature(),
            "dut-si-s10_expand_s25_no_change"
        );
        // many: four named, the rest counted and hashed, the name stays short
        let many: Vec<String> = (0..9).map(|i| format!("pmu50.s{i}")).collect();
        let refs: Vec<&str> = many.iter().map(String::as_str).collect();
        let s = diverged("pmu50.s0", &refs).signature();
        assert!(
            s.starts_with("dut-s0+s1+s2+s3+5more_") && s.len() < 80,
            "{s}"
        );
    }

    #[test]
    fn the_fig_path_groups_only_the_interval_adaptations_failures() {
        // a counter that counts the wrong way shows in whatever path the cycle took: one
        // signature for every path
        let mut a = diverged("pmu50.cnt_c", &["pmu50.cnt_c"]);
        let mut b = a.clone();
        a.fig = "s6_shorten/s23_detected_cs".into();
        b.fig = "fixed".into();
        assert_eq!(a.signature(), "dut-cnt_c--");
        assert_eq!(a.signature(), b.signature());
        // with the register inside the counter block too
        a.diverging = vec!["pmu50.cnt_c".into(), "pmu50.updown_counter.cnt_c".into()];
        assert_eq!(a.signature(), "dut-cnt_c+updown_counter.cnt_c--");
        // the interval's state, at the ports or inside the block, keeps its path
        for s in [
            "pmu50.si",
            "pmu50.drive_interval.cnt_r",
            "pmu50.internals.fig17",
        ] {
            let f = diverged(s, &[s]);
            assert!(
                f.signature().ends_with("-s10_expand_s25_no_change"),
                "{}",
                f.signature()
            );
        }
        // and a set with one of them keeps it too
        let f = diverged("pmu50.cnt_c", &["pmu50.cnt_c", "pmu50.si"]);
        assert_eq!(f.signature(), "dut-cnt_c+si-s10_expand_s25_no_change");
    }

    #[test]
    fn a_consequence_on_the_same_edge_does_not_split_a_root_cause() {
        // the count diagnosis trips on a wrong counter on some edges, not on others
        let alone = diverged("pmu50.cnt_c", &["pmu50.cnt_c"]);
        let tripped = diverged("pmu50.cnt_c", &["pmu50.cnt_c", "pmu50.diag"]);
        assert_eq!(alone.signature(), "dut-cnt_c--");
        assert_eq!(tripped.signature(), alone.signature());
        // diag alone, or beside no counter, is its own
        assert_eq!(
            diverged("pmu50.diag", &["pmu50.diag"]).signature(),
            "dut-diag--"
        );
        assert_eq!(
            diverged("pmu50.diag", &["pmu50.diag", "pmu50.sr"]).signature(),
            "dut-diag+sr--"
        );
        // a read of the wrong register is the register's error; a read alone is the read's
        let read = diverged(
            "pmu50.bus_rdata",
            &["pmu50.bus_rdata", "pmu50.register_file.pw"],
        );
        assert_eq!(read.signature(), "dut-register_file.pw--");
        assert_eq!(
            diverged("pmu50.bus_rdata", &["pmu50.bus_rdata"]).signature(),
            "dut-bus_rdata--"
        );
    }
}
