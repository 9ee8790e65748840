//! `--dut model`: no RTL. A seed's verdict is the model's own checks and invariants
//! ([`crate::check`]); this backend adds nothing to them.

use super::api::{Backend, Build, Caps, Dut, DutError, InFlight, Needs, Ready, Recorded};
use crate::rtl::Fixed;
use pmu50_testbench::scenario::Scenario;

/// The model alone.
#[derive(Default)]
pub struct ModelDut {
    fixed: Fixed,
}

impl Dut for ModelDut {
    fn name(&self) -> &'static str {
        "model"
    }

    fn needs(&self) -> Needs {
        Needs::Nothing
    }

    fn fixed(&self) -> &Fixed {
        &self.fixed
    }

    fn send<'a>(
        &'a self,
        _sc: &Scenario,
        _rec: Recorded,
    ) -> Result<Box<dyn InFlight + 'a>, DutError> {
        Ok(Box::new(Ready(None)))
    }
}

/// The registry's row of the model alone.
pub static BACKEND: Backend = Backend {
    name: "model",
    about: "the model alone: its checks and invariants, no RTL",
    caps: Caps {
        rtl: false,
        map: false,
        code_coverage: false,
        four_state: false,
    },
    make: |_: &Build<'_>| Ok(Box::new(ModelDut::default())),
};
