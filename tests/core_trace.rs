//! `pmu50::core_trace::CoreTrace` (only the values of the structs that changed) writes the same
//! file as `Writer::dump_frame` with every value of every tick, whatever the layout, with other
//! changes to the writer in between, and after a dump that failed half way.

use pmu50::core_trace::{CoreTrace, Layout, LayoutError, N_INPUTS, N_INTERNALS, N_OUTPUTS, N_REGISTERS};
use pmu50_core::pmu50::{Inputs, Internals, Outputs, Regs, Structural};
use pmu50_core::{Params, Pmu50};
use pmu50_waves::writer::{BitType, Logic, SigId, VcdBuilder, WriteError};
use pmu50_waves::{TimeUnit, Timescale};
use proptest::prelude::*;

/// One group's declared (name, width) list, in declaration order.
fn group(g: usize, s: &Structural, p: &Params) -> Vec<(String, u8)> {
    match g {
        0 => Inputs::default().values().iter().map(|v| (format!("i_{}", v.0), v.1)).collect(),
        1 => Outputs::default().values(s).iter().map(|v| (format!("o_{}", v.0), v.1)).collect(),
        2 => pmu50_core::pmu50::reset(p).values(s).iter().map(|r| (format!("r_{}_{}", r.block, r.name), r.width)).collect(),
        _ => Internals::default().values().iter().map(|v| (format!("x_{}", v.0), v.1)).collect(),
    }
}

/// The values of group `g` of a tick, in declaration order.
fn group_values(g: usize, s: &Structural, i: &Inputs, o: &Outputs, r: &Regs, x: &Internals) -> Vec<u64> {
    match g {
        0 => i.values().iter().map(|v| v.2).collect(),
        1 => o.values(s).iter().map(|v| v.2).collect(),
        2 => r.values(s).iter().map(|v| v.value).collect(),
        _ => x.values().iter().map(|v| v.2).collect(),
    }
}

/// A builder with the groups `order` in one scope each (plus a bit `extra` outside them), the
/// layout of that order, and the handles in frame order.
fn declare(order: &[usize], s: &Structural, p: &Params, narrow_wdata: bool) -> (VcdBuilder, Layout, Vec<SigId>, SigId) {
    let mut b = VcdBuilder::new(Timescale::new(1, TimeUnit::Us), "core trace test").unwrap();
    let mut ids = Vec::new();
    let mut bases = [None; 4];
    b.push_scope("pmu50").unwrap();
    for &g in order {
        bases[g] = Some(ids.len());
        for (n, w) in group(g, s, p) {
            let w = if narrow_wdata && n == "i_bus_wdata" { 4 } else { w };
            let id = if w == 1 { b.add_bit(BitType::Wire, &n, Logic::Zero) } else { b.add_vector(BitType::Wire, &n, u32::from(w) - 1, 0, 0) };
            ids.push(id.unwrap());
        }
    }
    let extra = b.add_bit(BitType::Wire, "extra", Logic::Zero).unwrap();
    b.pop_scope().unwrap();
    let layout = Layout { inputs: bases[0], outputs: bases[1], registers: bases[2], internals: bases[3] };
    (b, layout, ids, extra)
}

/// Both writers over the same input run: (CoreTrace's file, dump_frame's file).
fn both(order: &[usize], inputs: &[Inputs], extra_at: &[bool]) -> (String, String) {
    let p = Params::default();
    let s = Structural { sync_depth: p.sync_depth, cnt_width: p.cnt_width };
    let (b1, layout, ids1, extra1) = declare(order, &s, &p, false);
    let (b2, _, ids2, extra2) = declare(order, &s, &p, false);
    let mut w1 = b1.start(Vec::new()).unwrap();
    let mut w2 = b2.start(Vec::new()).unwrap();
    let mut trace = CoreTrace::new(w1.frame(&ids1).unwrap(), layout).unwrap();
    let mut f2 = w2.frame(&ids2).unwrap();
    let mut m = Pmu50::new(p).unwrap();
    let mut flip = false;
    for (k, i) in inputs.iter().enumerate() {
        let t = 2 * k as u64;
        let r = *m.regs();
        let (o, x, _) = m.step_traced(i);
        trace.dump(&mut w1, t, i, &o, &r, &x).unwrap();
        let vals: Vec<u64> = order.iter().flat_map(|&g| group_values(g, &s, i, &o, &r, &x)).collect();
        w2.dump_frame(&mut f2, t, &vals).unwrap();
        if extra_at.get(k).copied().unwrap_or(false) {
            // between two ticks: a variable outside the frame, and the frame's `ig` (inverted),
            // changed singly; the next tick must put `ig` back
            flip = !flip;
            w1.change_bool(extra1, flip).unwrap();
            w2.change_bool(extra2, flip).unwrap();
            if let Some(b) = layout.inputs {
                w1.set_time(t + 1).unwrap();
                w2.set_time(t + 1).unwrap();
                w1.change_bool(ids1[b], !i.ig).unwrap();
                w2.change_bool(ids2[b], !i.ig).unwrap();
            }
        }
    }
    (String::from_utf8(w1.finish().unwrap()).unwrap(), String::from_utf8(w2.finish().unwrap()).unwrap())
}

fn arb_inputs() -> impl Strategy<Value = Vec<Inputs>> {
    // Runs of held inputs (so that most ticks change nothing but the timer, as in a park), with
    // key edges, comparator flips and bus writes to any address (refused ones too).
    let one = (any::<bool>(), any::<bool>(), any::<bool>(), any::<bool>(), prop::bool::weighted(0.05), 0u8..0x20, any::<u16>(), 1usize..200);
    prop::collection::vec(one, 1..40).prop_map(|runs| {
        let mut v = Vec::new();
        for (ig, vs2_ok, cmp_s, cmp_c, bus_we, bus_addr, bus_wdata, n) in runs {
            v.push(Inputs { ig, vs2_ok, cmp_s, cmp_c, bus_we, bus_addr, bus_wdata });
            v.extend(std::iter::repeat_n(Inputs { ig, vs2_ok, cmp_s, cmp_c, bus_we: false, bus_addr, bus_wdata }, n));
        }
        v
    })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, failure_persistence: None, ..ProptestConfig::default() })]

    #[test]
    fn same_file_as_every_value(inputs in arb_inputs(), extra in prop::collection::vec(prop::bool::weighted(0.02), 0..4000)) {
        let (a, b) = both(&[0, 1, 2, 3], &inputs, &extra);
        prop_assert_eq!(a, b);
    }

    /// Other group orders and subsets (the levels of `pmu50 run`: ports, registers).
    #[test]
    fn same_file_in_any_layout(inputs in arb_inputs(), which in 0usize..3) {
        let order: &[usize] = [&[1, 2, 0, 3][..], &[1, 0], &[1, 2, 0]][which];
        let (a, b) = both(order, &inputs, &[]);
        prop_assert_eq!(a, b);
    }
}

/// A tick whose dump fails half way (a value wider than its variable) leaves the values before
/// it assigned. The next dump must give every value again: here the inputs of the tick after
/// equal those of the tick before, so a dump that compared with the tick before would leave the
/// failed tick's `bus_addr` in the file.
#[test]
fn a_failed_dump_is_followed_by_a_full_one() {
    let p = Params::default();
    let s = Structural { sync_depth: p.sync_depth, cnt_width: p.cnt_width };
    let (b, layout, ids, _) = declare(&[0, 1, 2, 3], &s, &p, true);
    let mut w = b.start(Vec::new()).unwrap();
    let mut trace = CoreTrace::new(w.frame(&ids).unwrap(), layout).unwrap();
    let mut m = Pmu50::new(p).unwrap();
    for t in 0..20u64 {
        // tick 10: bus_addr 7 is assigned, then bus_wdata 0x30 does not fit its 4 bits
        let i = if t == 10 { Inputs { bus_addr: 7, bus_wdata: 0x30, ..Inputs::default() } } else { Inputs { bus_addr: 1, bus_wdata: 3, ..Inputs::default() } };
        let r = *m.regs();
        let (o, x, _) = m.step_traced(&i);
        let res = trace.dump(&mut w, t, &i, &o, &r, &x);
        if t == 10 {
            assert!(matches!(res, Err(WriteError::ValueTooWide { value: 0x30, .. })), "{res:?}");
        } else {
            res.unwrap();
        }
    }
    let vcd = String::from_utf8(w.finish().unwrap()).unwrap();
    let code = vcd.lines().find_map(|l| l.strip_suffix(" i_bus_addr [7:0] $end")?.rsplit(' ').next()).expect("bus_addr declared").to_string();
    let step = |t: u64| {
        let from = vcd.find(&format!("#{t}\n")).expect("tick written");
        let rest = &vcd[from + 1..];
        rest[..rest.find('#').unwrap_or(rest.len())].to_string()
    };
    assert!(step(10).contains(&format!("b00000111 {code}\n")), "{}", step(10));
    assert!(step(11).contains(&format!("b00000001 {code}\n")), "tick 11 must put bus_addr back: {}", step(11));
}

#[test]
fn layouts_must_match_the_frame() {
    let p = Params::default();
    let s = Structural { sync_depth: p.sync_depth, cnt_width: p.cnt_width };
    let (b, _, ids, _) = declare(&[0, 1, 2, 3], &s, &p, false);
    let mut w = b.start(Vec::new()).unwrap();
    let n = N_INPUTS + N_OUTPUTS + N_REGISTERS + N_INTERNALS;
    assert_eq!(Layout::ALL.len(), n);
    // a frame shorter than the layout
    let e = CoreTrace::new(w.frame(&ids[..n - 1]).unwrap(), Layout::ALL).err().expect("refused");
    assert_eq!(e, LayoutError { layout: Layout::ALL, need: n, got: n - 1 });
    assert!(e.to_string().contains(&format!("{n} variables")), "{e}");
    // overlapping groups of the right total length
    let overlap = Layout { inputs: Some(0), outputs: Some(0), registers: Some(N_OUTPUTS), internals: Some(N_OUTPUTS + N_REGISTERS) };
    assert_eq!(overlap.len(), n);
    assert!(CoreTrace::new(w.frame(&ids).unwrap(), overlap).is_err());
    // a group past the end
    let past = Layout { inputs: Some(n), outputs: Some(0), registers: Some(N_OUTPUTS), internals: None };
    assert!(CoreTrace::new(w.frame(&ids[..past.len()]).unwrap(), past).is_err());
    assert!(CoreTrace::new(w.frame(&ids).unwrap(), Layout::ALL).is_ok());
}
