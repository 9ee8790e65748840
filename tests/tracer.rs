//! `pmu50::tracer::CoreTracer` (after a narrow edge it compares only what such an edge can
//! change) writes the same file as `Writer::dump_frame` with every value of every tick: on random
//! runs with key edges, samples and bus writes, with other changes to the writer in between, with
//! edges it did not see, and after a step that failed half way.

use pmu50::tracer::{CoreTracer, FrameSizeError, N_SIGNALS};
use pmu50_core::pmu50::{Inputs, Structural};
use pmu50_core::{Params, Pmu50};
use pmu50_waves::writer::{BitType, Logic, SigId, VcdBuilder, WriteError};
use pmu50_waves::{TimeUnit, Timescale};
use proptest::prelude::*;

/// The 65 signals in the tracer's frame order (inputs, outputs, registers, internals), plus a bit
/// `extra` outside the frame; `narrow_wdata` declares `bus_wdata` with 4 bits only.
fn declare(p: &Params, narrow_wdata: bool) -> (VcdBuilder, Vec<SigId>, SigId) {
    let s = Structural { sync_depth: p.sync_depth, cnt_width: p.cnt_width };
    let mut b = VcdBuilder::new(Timescale::new(1, TimeUnit::Us), "tracer test").unwrap();
    let mut names: Vec<(String, u8)> = Vec::new();
    names.extend(Inputs::default().values().iter().map(|v| (format!("i_{}", v.0), v.1)));
    names.extend(pmu50_core::pmu50::Outputs::default().values(&s).iter().map(|v| (format!("o_{}", v.0), v.1)));
    names.extend(pmu50_core::pmu50::reset(p).values(&s).iter().map(|r| (format!("r_{}_{}", r.block, r.name), r.width)));
    names.extend(pmu50_core::pmu50::Internals::default().values().iter().map(|v| (format!("x_{}", v.0), v.1)));
    b.push_scope("pmu50").unwrap();
    let ids = names
        .iter()
        .map(|(n, w)| {
            let w = if narrow_wdata && n == "i_bus_wdata" { 4 } else { *w };
            if w == 1 { b.add_bit(BitType::Wire, n, Logic::Zero) } else { b.add_vector(BitType::Wire, n, u32::from(w) - 1, 0, 0) }.unwrap()
        })
        .collect();
    let extra = b.add_bit(BitType::Wire, "extra", Logic::Zero).unwrap();
    b.pop_scope().unwrap();
    (b, ids, extra)
}

/// Every value of a tick in the frame order.
fn values(m: &Pmu50, i: &Inputs, x: &pmu50_core::pmu50::Internals, before: &pmu50_core::pmu50::Outputs, r: &pmu50_core::pmu50::Regs) -> Vec<u64> {
    let s = m.structural();
    i.values().iter().map(|v| v.2).chain(before.values(&s).iter().map(|v| v.2)).chain(r.values(&s).iter().map(|v| v.value)).chain(x.values().iter().map(|v| v.2)).collect()
}

/// What happens between two ticks of a run.
#[derive(Clone, Copy, Debug)]
enum Between {
    Nothing,
    /// a single change of a variable outside the frame, and of the frame's `ig` (inverted)
    SingleChanges,
    /// an edge of the core the tracer does not see (and the reference writer does not dump)
    UnseenEdge,
}

/// Both writers over one run: (the tracer's file, dump_frame's file with every value).
fn both(p: Params, run: &[(Inputs, Between)]) -> (String, String) {
    let (b1, ids1, extra1) = declare(&p, false);
    let (b2, ids2, extra2) = declare(&p, false);
    let mut w1 = b1.start(Vec::new()).unwrap();
    let mut w2 = b2.start(Vec::new()).unwrap();
    let mut m1 = Pmu50::new(p).unwrap();
    let mut m2 = Pmu50::new(p).unwrap();
    let mut tr = CoreTracer::new(w1.frame(&ids1).unwrap(), &m1).unwrap();
    let mut f2 = w2.frame(&ids2).unwrap();
    let mut flip = false;
    let mut t = 0;
    for (i, between) in run {
        let r = *m2.regs();
        let (before, x, after2) = m2.step_traced(i);
        w2.dump_frame(&mut f2, t, &values(&m2, i, &x, &before, &r)).unwrap();
        let after1 = tr.step(&mut w1, &mut m1, t, i).unwrap();
        assert_eq!(*after1, after2);
        t += 2;
        match between {
            Between::Nothing => {}
            Between::SingleChanges => {
                flip = !flip;
                for (w, e, ig) in [(&mut w1, extra1, ids1[0]), (&mut w2, extra2, ids2[0])] {
                    w.set_time(t - 1).unwrap();
                    w.change_bool(e, flip).unwrap();
                    w.change_bool(ig, !i.ig).unwrap();
                }
            }
            Between::UnseenEdge => {
                // the same edge in both cores, dumped by neither writer: the tracer's values of
                // the last tick are stale at the next one
                m1.step(i);
                m2.step(i);
            }
        }
    }
    (String::from_utf8(w1.finish().unwrap()).unwrap(), String::from_utf8(w2.finish().unwrap()).unwrap())
}

fn arb_run() -> impl Strategy<Value = Vec<(Inputs, Between)>> {
    // Runs of held inputs (most edges narrow, as in a park), with key edges, comparator flips
    // and bus writes to any address (refused ones too), and now and then something between two
    // ticks.
    let between = prop_oneof![30 => Just(Between::Nothing), 1 => Just(Between::SingleChanges), 1 => Just(Between::UnseenEdge)];
    let one = (any::<bool>(), any::<bool>(), any::<bool>(), any::<bool>(), prop::bool::weighted(0.1), 0u8..0x20, any::<u16>(), 1usize..150, between);
    prop::collection::vec(one, 1..40).prop_map(|runs| {
        let mut v = Vec::new();
        for (ig, vs2_ok, cmp_s, cmp_c, bus_we, bus_addr, bus_wdata, n, between) in runs {
            v.push((Inputs { ig, vs2_ok, cmp_s, cmp_c, bus_we, bus_addr, bus_wdata }, between));
            v.extend(std::iter::repeat_n((Inputs { ig, vs2_ok, cmp_s, cmp_c, bus_we: false, bus_addr, bus_wdata }, Between::Nothing), n));
        }
        v
    })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, failure_persistence: None, ..ProptestConfig::default() })]

    #[test]
    fn same_file_as_every_value(run in arb_run(), which in 0usize..3) {
        // the defaults, a deep synchronizer with 3-bit counters (as random_7), a fast park
        let p = [
            Params::default(),
            Params { sync_depth: 4, cnt_width: 3, ..Params::default() },
            Params { pw: 1, pi: 1, ps: 1, si_max: 6, si_min: 4, smp_on: 3, ..Params::default() },
        ][which];
        prop_assume!(Pmu50::new(p).is_ok());
        let (a, b) = both(p, &run);
        prop_assert_eq!(a, b);
    }
}

/// A step that fails half way (a value wider than its variable) still takes its edge; the next
/// step gives every value again. Here the inputs of the tick after equal those of the tick
/// before, so a step that compared with the tick before would leave the failed tick's
/// `bus_addr` in the file.
#[test]
fn a_failed_step_takes_its_edge_and_is_followed_by_a_full_one() {
    let p = Params::default();
    let (b, ids, _) = declare(&p, true);
    let mut w = b.start(Vec::new()).unwrap();
    let mut m = Pmu50::new(p).unwrap();
    let mut tr = CoreTracer::new(w.frame(&ids).unwrap(), &m).unwrap();
    for t in 0..20u64 {
        // tick 10: bus_addr 7 is assigned, then bus_wdata 0x30 does not fit its 4 bits
        let i = if t == 10 { Inputs { bus_addr: 7, bus_wdata: 0x30, ..Inputs::default() } } else { Inputs { bus_addr: 1, bus_wdata: 3, ..Inputs::default() } };
        let res = tr.step(&mut w, &mut m, t, &i);
        if t == 10 {
            assert!(matches!(res, Err(WriteError::ValueTooWide { value: 0x30, .. })), "{res:?}");
        } else {
            res.unwrap();
        }
        assert_eq!(m.tick(), t + 1, "the edge is taken");
    }
    // an error before the step starts (time backwards) takes no edge
    assert!(matches!(tr.step(&mut w, &mut m, 5, &Inputs::default()), Err(WriteError::TimeBackwards { .. })));
    assert_eq!(m.tick(), 20);
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
fn the_frame_must_hold_the_65_signals() {
    let p = Params::default();
    let (b, ids, _) = declare(&p, false);
    let mut w = b.start(Vec::new()).unwrap();
    let m = Pmu50::new(p).unwrap();
    assert_eq!(ids.len(), N_SIGNALS);
    let e = CoreTracer::new(w.frame(&ids[..64]).unwrap(), &m).err().expect("refused");
    assert_eq!(e, FrameSizeError { got: 64 });
    assert!(e.to_string().contains("65 variables") && e.to_string().contains("has 64"), "{e}");
}
