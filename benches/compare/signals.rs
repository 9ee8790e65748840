//! The model's 65 traced signals, shared by the tracer that writes them and the checks that
//! compare them: their declarations, as `pmu50 run` declares them without the analog `env` reals
//! ([`declare`]), and a tick's values in that order ([`frame_values`]).

use crate::stim::Stim;
use pmu50_core::pmu50::Structural;
use pmu50_core::{Inputs, Internals, Outputs, Regs};
use pmu50_waves::writer::{BitType, SigId, VcdBuilder};
use pmu50_waves::{TimeUnit, Timescale};

/// Number of signals the Rust tracer writes per tick.
pub const NSIG: usize = 7 + 23 + 26 + 9;

/// Every traced value of a tick, in declaration order: inputs, ports, registers (the order of
/// `Regs::values`), internals.
#[inline(always)]
pub fn frame_values(v: &mut [u64; NSIG], i: &Inputs, o: &Outputs, r: &Regs, x: &Internals) {
    let u = |b: bool| u64::from(b);
    let f = &r.register_file;
    *v = [
        u(i.ig),
        u(i.vs2_ok),
        u(i.cmp_s),
        u(i.cmp_c),
        u(i.bus_we),
        u64::from(i.bus_addr),
        u64::from(i.bus_wdata),
        u(o.sig),
        u(o.vr_hi),
        u(o.vm_en),
        u(o.vs1_en),
        u(o.vs2_en),
        u(o.vp_en),
        u(o.rail_hi),
        u(o.st),
        u(o.sr),
        u(o.ps_win),
        u(o.smp),
        u(o.cs),
        u(o.cc),
        u64::from(o.cnt_s),
        u64::from(o.cnt_c),
        u64::from(o.cnt_r),
        u64::from(o.si),
        u(o.hist_s),
        u(o.hist_c),
        u(o.diag),
        u(o.quadrant_skip),
        u64::from(o.bus_rdata),
        u(o.bus_err),
        u64::from(r.action_switching.sync),
        u(f.adaptive),
        u64::from(f.pw),
        u64::from(f.pi),
        u64::from(f.ps),
        u64::from(f.si_max),
        u64::from(f.si_min),
        u64::from(f.t1),
        u64::from(f.t2),
        u64::from(f.cth),
        u64::from(f.smp_on),
        u(f.bus_err),
        u64::from(f.rdata),
        u64::from(r.timing_generator.tmr),
        u(r.sensor_power_determination.sr),
        u(r.comparator_latch.cs),
        u(r.comparator_latch.cc),
        u(r.comparator_latch.vld),
        u64::from(r.updown_counter.cnt_s),
        u64::from(r.updown_counter.cnt_c),
        u(r.updown_counter.quadrant_skip),
        u64::from(r.drive_interval.si),
        u(r.drive_interval.hist_s),
        u(r.drive_interval.hist_c),
        u64::from(r.drive_interval.cnt_r),
        u(r.count_diagnosis.diag),
        u(x.kon),
        u(x.koff),
        u(x.upd),
        u(x.first),
        u(x.chg_s),
        u(x.chg_c),
        u(x.skip_clr),
        x.fig17 as u64,
        x.fig18 as u64,
    ];
}

/// Declarations of the model's VCD (testbench/src/observers/waveform.rs) without the `env` reals.
pub fn declare(st: &Stim) -> (VcdBuilder, Vec<SigId>, u64) {
    let s = Structural {
        sync_depth: st.params.sync_depth,
        cnt_width: st.params.cnt_width,
    };
    let (ts, unit_ns) = if st.clock_ns.is_multiple_of(1000) {
        (Timescale::new(1, TimeUnit::Us), 1000)
    } else {
        (Timescale::new(1, TimeUnit::Ns), 1)
    };
    let mut b = VcdBuilder::new(ts, "pmu50 bench").expect("valid header");
    let mut ids = Vec::new();
    let mut add = |b: &mut VcdBuilder, ty: BitType, n: &str, w: u8| {
        let id = if w == 1 {
            b.add_bit(ty, n, false.into())
        } else {
            b.add_vector(ty, n, u32::from(w) - 1, 0, 0)
        };
        ids.push(id.expect("valid declaration"));
    };
    b.push_scope("pmu50").unwrap();
    for (n, w, _) in Inputs::default().values() {
        add(&mut b, BitType::Wire, n, w);
    }
    for (n, w, _) in Outputs::default().values(&s) {
        add(&mut b, BitType::Wire, n, w);
    }
    let regs = pmu50_core::pmu50::reset(&st.params).values(&s);
    let mut block = "";
    for r in &regs {
        if r.block != block {
            if !block.is_empty() {
                b.pop_scope().unwrap();
            }
            b.push_scope(r.block).unwrap();
            block = r.block;
        }
        add(&mut b, BitType::Reg, r.name, r.width);
    }
    b.pop_scope().unwrap();
    b.push_scope("internals").unwrap();
    for (n, w, _) in Internals::default().values() {
        add(&mut b, BitType::Wire, n, w);
    }
    b.pop_scope().unwrap();
    b.pop_scope().unwrap();
    assert_eq!(ids.len(), NSIG);
    (b, ids, unit_ns)
}
