//! The specification model as a stepping type: [`Pmu50Spec`] steps the readable per-block model
//! ([`crate::pmu50::eval`], one file per patent block) exactly as [`crate::Pmu50`] steps the fast
//! kernel ([`crate::kernel`]). The two are proven equal by tests comparing every register, every
//! output and every internal signal on every tick (`rtl_model/core/tests/kernel_equivalence.rs`,
//! `tests/kernel_scenarios.rs`); `make bench` measures both.

use crate::params::{ParamError, Params};
use crate::pmu50::{eval, ports, reset, Inputs, Outputs, Regs, Structural, TracedStep};

/// The per-block specification model with the stepping API of [`crate::Pmu50`].
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Pmu50Spec {
    structural: Structural,
    params: Params,
    regs: Regs,
    tick: u64,
}

impl Pmu50Spec {
    /// A core at power-on reset with these parameters (which must be legal).
    pub fn new(p: Params) -> Result<Pmu50Spec, ParamError> {
        p.validate()?;
        Ok(Pmu50Spec {
            structural: Structural {
                sync_depth: p.sync_depth,
                cnt_width: p.cnt_width,
            },
            params: p,
            regs: reset(&p),
            tick: 0,
        })
    }

    /// Back to power-on reset; tick count restarts at 0.
    pub fn reset(&mut self) {
        self.regs = reset(&self.params);
        self.tick = 0;
    }

    pub fn structural(&self) -> Structural {
        self.structural
    }

    /// Outputs of the current cycle (Moore: registers only).
    pub fn peek(&self) -> Outputs {
        ports(&self.structural, &self.regs)
    }

    /// One rising edge with these inputs; returns the outputs after the edge.
    pub fn step(&mut self, i: &Inputs) -> Outputs {
        self.step_traced(i).after
    }

    /// One rising edge, traced (`wide` is always true: the specification does not classify
    /// edges).
    pub fn step_traced(&mut self, i: &Inputs) -> TracedStep {
        let (before, internals, next) = eval(&self.structural, &self.regs, i);
        self.regs = next;
        self.tick += 1;
        TracedStep {
            before,
            internals,
            after: self.peek(),
            wide: true,
        }
    }

    /// All registers.
    pub fn regs(&self) -> &Regs {
        &self.regs
    }

    /// Number of edges taken since reset.
    pub fn tick(&self) -> u64 {
        self.tick
    }
}
