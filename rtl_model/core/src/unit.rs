//! Power management unit 50 as one object ([`Pmu50`]): its structural parameters, parameters,
//! registers and tick, stepped by the fast kernel ([`crate::kernel`]) behind the lockstep API
//! that the testbench, the C ABI and the Python module use. The specification it is proven equal
//! to is [`crate::pmu50::eval`] (tests/kernel_equivalence.rs); [`crate::Pmu50Spec`] steps that
//! specification with the same API.

use crate::params::{ParamError, Params};
use crate::pmu50::{
    eval, ports, read, reset, tg_inputs, Inputs, Outputs, Regs, Structural, TracedStep,
};
use crate::timing_generator_56 as tg;

#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum FastForwardError {
    #[error("cannot fast-forward {asked} ticks: only {quiet} ticks are free of register changes other than the timer")]
    NotQuiet { asked: u64, quiet: u64 },
}

/// The core: registers plus the structural parameters, with the lockstep API. Two cores are
/// equal when their parameters, registers and tick are: the kernel's constants and read cache
/// are derived from those and are not compared.
#[derive(Clone, Debug)]
pub struct Pmu50 {
    structural: Structural,
    params: Params,
    regs: Regs,
    tick: u64,
    /// Structural parameters pre-decoded for the fast kernel.
    consts: crate::kernel::Consts,
    /// The fast kernel's read-side cache of `regs`.
    shadow: crate::kernel::Shadow,
}

impl PartialEq for Pmu50 {
    fn eq(&self, o: &Pmu50) -> bool {
        (self.structural, self.params, self.regs, self.tick)
            == (o.structural, o.params, o.regs, o.tick)
    }
}
impl Eq for Pmu50 {}

impl Pmu50 {
    /// A core at power-on reset with these parameters (which must be legal).
    pub fn new(p: Params) -> Result<Pmu50, ParamError> {
        p.validate()?;
        let s = Structural {
            sync_depth: p.sync_depth,
            cnt_width: p.cnt_width,
        };
        let k = crate::kernel::Consts::new(&s);
        let regs = reset(&p);
        Ok(Pmu50 {
            structural: s,
            params: p,
            regs,
            tick: 0,
            consts: k,
            shadow: crate::kernel::Shadow::of(&k, &regs),
        })
    }

    /// Back to power-on reset (the parameters given to [`Pmu50::new`]); tick count restarts at 0.
    pub fn reset(&mut self) {
        self.regs = reset(&self.params);
        self.shadow = crate::kernel::Shadow::of(&self.consts, &self.regs);
        self.tick = 0;
    }

    pub fn structural(&self) -> Structural {
        self.structural
    }

    /// Outputs of the current cycle (Moore: registers only).
    pub fn peek(&self) -> Outputs {
        ports(&self.structural, &self.regs)
    }

    /// One rising edge with these inputs; returns the outputs after the edge. Runs the fast
    /// kernel ([`crate::kernel`]), proven equal to [`eval`] by tests; [`crate::Pmu50Spec`] steps
    /// [`eval`] itself.
    #[inline]
    pub fn step(&mut self, i: &Inputs) -> Outputs {
        self.tick += 1;
        crate::kernel::step(&self.consts, &mut self.regs, &mut self.shadow, i)
    }

    /// One rising edge, traced: the outputs before and after it, the internals of the cycle and
    /// whether the edge was wide. Runs the fast kernel's traced edge
    /// ([`crate::kernel::step_traced`]); a caller that does not read `before` does not pay for
    /// it (the step is inlined and its decode dropped).
    #[inline]
    pub fn step_traced(&mut self, i: &Inputs) -> TracedStep {
        self.tick += 1;
        crate::kernel::step_traced(&self.consts, &mut self.regs, &mut self.shadow, i)
    }

    /// All registers (read access for lockstep comparison and waveforms).
    pub fn regs(&self) -> &Regs {
        &self.regs
    }

    /// Number of edges taken since reset.
    pub fn tick(&self) -> u64 {
        self.tick
    }

    /// The register file's read mux at `addr`, as the MPU would read it this cycle.
    pub fn read(&self, addr: u8) -> u16 {
        read(&self.structural, &self.regs, self.peek().sig, addr)
    }

    /// With the inputs held constant, the number of upcoming edges at which no register other
    /// than the free-running timer `timing_generator.tmr` changes (`u64::MAX`: never). Exact:
    /// the edge after that many changes some other register. Used to fast-forward idle key-off
    /// gaps without evaluating every tick.
    pub fn quiet_ticks(&self, i: &Inputs) -> u64 {
        let (_, _, next) = eval(&self.structural, &self.regs, i);
        let only_tmr = Regs {
            timing_generator: self.regs.timing_generator,
            ..next
        } == self.regs;
        if !only_tmr {
            return 0;
        }
        // From here on the synchronizer is settled, no bus write happens, and rdata/diag are
        // stable, so until the first event the state differs from today's only in the timer.
        // The registers' next state depends on the timer only through `vs2_en`, `smp` and the
        // end of the cycle, which are constant on [0, wt-1), {wt-1}, [wt, period) (key off) and
        // on [0, smp_on-1), {smp_on-1} (key on). So the first event is at t+1 or at the start of
        // one of those intervals; each candidate is checked with the real next-state function.
        let a = self.peek();
        let p = self
            .regs
            .register_file
            .params(self.structural.sync_depth, self.structural.cnt_width);
        let ti = tg_inputs(a.sig, false, false, &p, self.regs.drive_interval.si);
        let period = u64::from(tg::period(&ti));
        let t = u64::from(self.regs.timing_generator.tmr);
        let dist = |c: u64| {
            if t >= period {
                1 + c // the next edge wraps the timer to 0
            } else if c > t {
                c - t
            } else {
                period - t + c
            }
        };
        let event_at = |c: u64| {
            let mut at = self.regs;
            at.timing_generator.tmr = c as u16;
            let (_, _, n) = eval(&self.structural, &at, i);
            Regs {
                timing_generator: at.timing_generator,
                ..n
            } != at
        };
        let wt = u64::from(p.pw) + u64::from(p.pi) + u64::from(p.ps);
        let mut best = u64::MAX;
        for c in [t + 1, 0, wt.wrapping_sub(1), wt, period.wrapping_sub(1)] {
            if c < period && c != t && dist(c) < best && event_at(c) {
                best = dist(c);
            }
        }
        best
    }

    /// Advance `n` edges with constant inputs `i`, which must leave every register but the timer
    /// unchanged (`n <= quiet_ticks(i)`); the result is identical to `n` calls of [`Pmu50::step`].
    pub fn fast_forward(&mut self, n: u64, i: &Inputs) -> Result<(), FastForwardError> {
        let quiet = self.quiet_ticks(i);
        if n > quiet {
            return Err(FastForwardError::NotQuiet { asked: n, quiet });
        }
        if n == 0 {
            return Ok(());
        }
        let a = self.peek();
        let p = self
            .regs
            .register_file
            .params(self.structural.sync_depth, self.structural.cnt_width);
        let ti = tg_inputs(a.sig, false, false, &p, self.regs.drive_interval.si);
        let period = u64::from(tg::period(&ti)).max(1);
        let t = u64::from(self.regs.timing_generator.tmr);
        let tmr = if t + 1 >= period {
            (n - 1) % period
        } else {
            (t + n) % period
        };
        self.regs.timing_generator.tmr = tmr as u16;
        self.tick += n;
        Ok(())
    }
}
