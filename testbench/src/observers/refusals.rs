//! Register writes the chip refuses. `pmu50 run` reports each in its summary with the scenario's
//! file and line and the reason, and exits 1: a refused write changes nothing but the sticky
//! `bus_err`, so the rest of the run is not what the scenario asked for.
//!
//! The reason is the register file's own ([`pmu50_core::register_file::RegisterFile::bus_write`], the function
//! `register_file::eval` uses), evaluated on the registers and inputs of the tick: no rule is
//! written twice.

use crate::scenario::{Action, Scenario};
use crate::sim::{Observer, SimError, TickView};
use pmu50_core::register_file::{self as rf, WriteRefusal};

/// One refused write.
#[derive(Clone, Debug, PartialEq)]
pub struct RefusedWrite {
    pub file: String,
    pub line: usize,
    pub tick: u64,
    pub time_ns: u64,
    pub reg: String,
    pub value: u16,
    pub reason: WriteRefusal,
}

impl std::fmt::Display for RefusedWrite {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let why = match &self.reason {
            WriteRefusal::KeyOff => "the chip's synchronised key signal sig is still 0 at this tick (the MPU is not powered, [0205]); \
                `ig` passes through sync_depth flip-flops first, so write a few ticks after `ig = true`"
                .to_string(),
            WriteRefusal::NotWritable => "the register is not writable".to_string(),
            WriteRefusal::Illegal(e) => format!("the parameter set would become illegal: {e}"),
        };
        write!(
            f,
            "{}:{}: write {} = {} at {:.3} ms refused by the chip (bus_err set): {why}",
            self.file,
            self.line,
            self.reg,
            self.value,
            self.time_ns as f64 / 1e6
        )
    }
}

/// Observer that checks each timeline write against the register file's rules.
pub struct RefusalWatch {
    file: String,
    sync_depth: u8,
    cnt_width: u8,
    /// (tick, line, register name, value) of every write of the timeline.
    writes: Vec<(u64, usize, String, u16)>,
    next: usize,
    pub refused: Vec<RefusedWrite>,
}

impl RefusalWatch {
    pub fn new(sc: &Scenario) -> RefusalWatch {
        let writes = sc
            .events
            .iter()
            .filter_map(|e| match &e.action {
                Action::Write { name, value, .. } => Some((e.tick, e.line, name.clone(), *value)),
                _ => None,
            })
            .collect();
        RefusalWatch {
            file: sc.path.display().to_string(),
            sync_depth: sc.params.sync_depth,
            cnt_width: sc.params.cnt_width,
            writes,
            next: 0,
            refused: Vec::new(),
        }
    }
}

impl Observer for RefusalWatch {
    fn tick(&mut self, v: &TickView<'_>) -> Result<(), SimError> {
        while self.next < self.writes.len() && self.writes[self.next].0 < v.tick {
            self.next += 1;
        }
        if self.next < self.writes.len() && self.writes[self.next].0 == v.tick && v.inputs.bus_we {
            let (tick, line, reg, value) = self.writes[self.next].clone();
            let i = rf::Inputs {
                bus_we: true,
                bus_addr: v.inputs.bus_addr,
                bus_wdata: v.inputs.bus_wdata,
                sig: v.ports.sig,
                ..Default::default()
            };
            if let Err(reason) = rf::RegisterFile::new(self.sync_depth, self.cnt_width)
                .bus_write(&v.regs.register_file, &i)
            {
                self.refused.push(RefusedWrite {
                    file: self.file.clone(),
                    line,
                    tick,
                    time_ns: v.time_ns,
                    reg,
                    value,
                    reason,
                });
            }
            self.next += 1;
        }
        Ok(())
    }
    /// Writes are timeline events, and the bench evaluates the tick of every event (it never
    /// skips over one), so the watch sees every write without seeing every tick.
    fn needs_every_tick(&self) -> bool {
        false
    }
}
