//! The fast kernel (`Pmu50::step`) against the per-block specification (`Pmu50Spec`) on the
//! scenarios of the co-simulation: every shipped scenario, the HDL directed scenarios, and the 200
//! seeded random scenarios of `hdl/cosim.sh` (seeds 1..=200, generated in-process with
//! `pmu50_testbench::random::random_scenario`). The simulator runs the scenario on `Pmu50` (the kernel); an
//! observer steps `Pmu50Spec` with the same inputs and compares, on every tick, every register
//! before the edge, every output, every internal signal of the cycle, and the final registers.

use pmu50_core::Pmu50Spec;
use pmu50_testbench::random::random_scenario;
use pmu50_testbench::scenario::Scenario;
use pmu50_testbench::sim::{run, Observer, SimError, SimOptions, TickView};
use std::path::Path;

/// Longest scenario stepped here (10 s at a 10 us clock).
const MAX_TICKS: u64 = 1_000_000;

struct SpecLockstep {
    spec: Pmu50Spec,
    name: String,
    ticks: u64,
}

impl SpecLockstep {
    fn check(&self, v: &TickView<'_>, what: &str) -> Result<(), SimError> {
        if self.spec.tick() != v.tick {
            return Err(SimError::observer(
                "kernel against the specification model",
                format!(
                    "{}: spec at tick {}, simulator at {} ({what})",
                    self.name,
                    self.spec.tick(),
                    v.tick
                ),
            ));
        }
        if self.spec.regs() != v.regs {
            return Err(SimError::observer(
                "kernel against the specification model",
                format!(
                    "{}: registers differ at tick {} ({what}):\nkernel {:?}\nspec   {:?}",
                    self.name,
                    v.tick,
                    v.regs,
                    self.spec.regs()
                ),
            ));
        }
        if self.spec.peek() != *v.ports {
            return Err(SimError::observer(
                "kernel against the specification model",
                format!(
                    "{}: outputs differ at tick {} ({what}):\nkernel {:?}\nspec   {:?}",
                    self.name,
                    v.tick,
                    v.ports,
                    self.spec.peek()
                ),
            ));
        }
        Ok(())
    }
}

impl Observer for SpecLockstep {
    fn tick(&mut self, v: &TickView<'_>) -> Result<(), SimError> {
        self.check(v, "before the edge")?;
        let pmu50_core::TracedStep { internals, .. } = self.spec.step_traced(v.inputs);
        if internals != *v.internals {
            return Err(SimError::observer(
                "kernel against the specification model",
                format!(
                    "{}: internals differ in cycle {}:\nkernel {:?}\nspec   {:?}",
                    self.name, v.tick, v.internals, internals
                ),
            ));
        }
        self.ticks += 1;
        Ok(())
    }
    fn finish(&mut self, v: &TickView<'_>) -> Result<(), SimError> {
        self.check(v, "final")
    }
}

fn lockstep(sc: &Scenario) -> u64 {
    let mut obs = SpecLockstep {
        spec: Pmu50Spec::new(sc.params).unwrap(),
        name: sc.name.clone(),
        ticks: 0,
    };
    let r = run(
        sc,
        SimOptions {
            fast_forward: false,
        },
        &mut [&mut obs],
    )
    .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(obs.ticks, sc.ticks, "{}: every tick compared", sc.name);
    assert_eq!(r.final_regs, *obs.spec.regs());
    obs.ticks
}

#[test]
fn shipped_and_directed_scenarios() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut n = 0;
    for dir in ["scenarios", "hdl/scenarios"] {
        let mut files: Vec<_> = std::fs::read_dir(root.join(dir))
            .unwrap()
            .map(|e| e.unwrap().path())
            .filter(|p| p.extension().is_some_and(|e| e == "toml"))
            .collect();
        files.sort();
        for f in files {
            let sc = Scenario::load(&f).unwrap_or_else(|e| panic!("{e}"));
            // Day-long parks (scenarios/park_30d.toml: 2.6e11 ticks) cannot be stepped tick by
            // tick in a test; their kernel runs are compared with per-tick stepping on a 1-day
            // copy by tests/skip_ahead.rs, and every edge they take is covered by the scenarios here.
            if sc.ticks > MAX_TICKS {
                continue;
            }
            assert!(lockstep(&sc) > 0);
            n += 1;
        }
    }
    assert!(n >= 8, "found only {n} scenarios");
}

#[test]
fn cosim_random_scenarios_seeds_1_to_200() {
    let mut total = 0;
    for seed in 1..=200u64 {
        let text = random_scenario(seed);
        let name = format!("random_{seed}");
        let sc = Scenario::parse(
            &text,
            &format!("{name}.toml"),
            &name,
            Path::new(&format!("{name}.toml")),
        )
        .unwrap_or_else(|e| panic!("seed {seed}: {e}"));
        total += lockstep(&sc);
    }
    assert!(total > 200 * 20_000);
}
