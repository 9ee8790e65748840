//! `--dut spec`, a backend of the tests: the readable per-block specification
//! ([`pmu50_core::Pmu50Spec`]) as the design under test, stepped on a seed's recorded inputs
//! beside the fast kernel and compared on every output after every edge. It shows what a new
//! backend is: this file, with its row in `super::BACKENDS`; the registry's rules apply to it
//! from its capabilities, and the regression runs it like any other.

use super::api::{Backend, Build, Caps, Dut, DutError, InFlight, Needs, Ready, Recorded};
use super::failure::divergence;
use crate::lockstep::{unpack, Mismatch};
use crate::rtl::Fixed;
use pmu50_core::{Pmu50, Pmu50Spec};
use pmu50_testbench::scenario::Scenario;

/// The specification model as a DUT.
#[derive(Default)]
pub struct SpecDut {
    fixed: Fixed,
}

impl Dut for SpecDut {
    fn name(&self) -> &'static str {
        "spec"
    }

    fn needs(&self) -> Needs {
        Needs::Inputs
    }

    fn fixed(&self) -> &Fixed {
        &self.fixed
    }

    fn send<'a>(
        &'a self,
        sc: &Scenario,
        rec: Recorded,
    ) -> Result<Box<dyn InFlight + 'a>, DutError> {
        let Recorded::Inputs(words) = rec else {
            return Err(DutError::Tool("the spec DUT steps recorded inputs".into()));
        };
        let param = |e: pmu50_core::ParamError| DutError::Tool(e.to_string());
        let mut kernel = Pmu50::new(sc.params).map_err(param)?;
        let mut spec = Pmu50Spec::new(sc.params).map_err(param)?;
        let s = kernel.structural();
        for (k, &w) in words.iter().enumerate() {
            let i = unpack(w);
            let (want, got) = (kernel.step(&i), spec.step(&i));
            if want != got {
                let mm: Vec<Mismatch> = want
                    .values(&s)
                    .iter()
                    .zip(got.values(&s))
                    .filter(|(a, b)| a.2 != b.2)
                    .map(|(a, b)| Mismatch {
                        signal: a.0.to_string(),
                        expected: a.2,
                        got: b.2,
                    })
                    .collect();
                return Ok(Box::new(Ready(Some(divergence(
                    sc,
                    k as u64 + 1,
                    false,
                    &mm,
                )))));
            }
        }
        Ok(Box::new(Ready(None)))
    }
}

/// The registry's row of the specification model.
pub static BACKEND: Backend = Backend {
    name: "spec",
    about: "the readable per-block specification stepped as the DUT (tests)",
    caps: Caps {
        rtl: false,
        map: false,
        code_coverage: false,
        four_state: false,
    },
    make: |_: &Build<'_>| Ok(Box::new(SpecDut::default())),
};

#[cfg(test)]
mod tests {
    use crate::dut::{self as registry, BACKENDS};
    use crate::gen::{Bias, Stimulus};
    use crate::spec::{DutKind, RunSpec};

    fn spec(dut: &str) -> RunSpec {
        RunSpec {
            tool: "test".into(),
            model: pmu50_coverage::model_id(pmu50_coverage::layout()),
            start_seed: 1,
            iterations: 3,
            directed: false,
            check_spec: false,
            dut: DutKind::new(dut),
            rtl: None,
            map: None,
            fixed: Default::default(),
            pins: Default::default(),
            shard: None,
            code_coverage: false,
            param_sets: 0,
            pool: Vec::new(),
        }
    }

    #[test]
    fn a_backend_of_one_file_and_one_row_is_found_checked_and_run() {
        // found by name, listed among the valid names of an unknown one
        assert!(BACKENDS.iter().any(|b| b.name == "spec"));
        let b = registry::find("spec").unwrap();
        assert!(registry::find("vcs").err().unwrap().contains("spec"));
        // its capabilities decide the options, with the backends that can
        let e = b.check(false, true, false).unwrap_err();
        assert_eq!(e.option, "--map");
        assert_eq!(e.able, vec!["verilator"]);
        assert!(e.to_string().contains("use --dut verilator (not spec)"), "{e}");
        assert!(b.check(true, false, false).is_err());
        // and the regression's seeds run on it
        let d = registry::prepare(&spec("spec")).unwrap();
        assert_eq!(d.name(), "spec");
        for seed in 1..=3 {
            let stim = Stimulus::generate(seed, &Bias::uniform());
            let e = crate::seed::evaluate(
                &spec("spec"),
                &stim,
                d.as_ref(),
                std::time::Duration::from_secs(60),
            )
            .unwrap();
            let (verdict, failure) = (e.0, e.1);
            assert_eq!(failure, None, "seed {seed}");
            assert_eq!(verdict, crate::spec::Verdict::Pass, "seed {seed}");
        }
    }
}
