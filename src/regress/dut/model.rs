//! `--dut model`: no RTL. A seed's verdict is the model's own checks and invariants
//! ([`super::super::check`]); this backend adds nothing to them.

use super::{Dut, DutError, InFlight, Needs, Ready, Recorded};
use crate::regress::rtl::Fixed;
use crate::scenario::Scenario;

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
