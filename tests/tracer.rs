//! `pmu50_testbench::observers::tracer::CoreTracer` (after a narrow edge it compares only what such an edge can
//! change) writes the same file as `Writer::dump_frame` with every value of every tick: on random
//! runs with key edges, samples and bus writes, with other changes to the writer in between, and
//! after a step that failed half way.

use pmu50_core::pmu50::{Inputs, Outputs, Structural};
use pmu50_core::{Params, Pmu50};
use pmu50_testbench::observers::tracer::{CoreTracer, FrameSizeError, NARROW_REGISTERS, N_SIGNALS};
use pmu50_waves::writer::{BitType, Logic, SigId, VcdBuilder, WriteError};
use pmu50_waves::{TimeUnit, Timescale};
use proptest::prelude::*;

/// How the test frame declares the widths of the core's signals.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Decl {
    /// each as wide as the core's signal (the tracer's unchecked lines, `CoreTracer::exact`)
    Core,
    /// `bus_wdata` with 4 bits only (a value may not fit: the checked lines)
    NarrowWdata,
    /// some wider than the core's: `bus_addr` 12 bits, the output `smp` 2, `tmr` 24, `fig17` 8
    /// (the checked lines, in the frame's widths)
    Wider,
}

/// The 65 signals in the tracer's frame order (inputs, outputs, registers, internals), plus a bit
/// `extra` outside the frame, with the widths of `decl`.
fn declare(p: &Params, decl: Decl) -> (VcdBuilder, Vec<SigId>, SigId) {
    let s = Structural {
        sync_depth: p.sync_depth,
        cnt_width: p.cnt_width,
    };
    let mut b = VcdBuilder::new(Timescale::new(1, TimeUnit::Us), "tracer test").unwrap();
    let mut names: Vec<(String, u8)> = Vec::new();
    names.extend(
        Inputs::default()
            .values()
            .iter()
            .map(|v| (format!("i_{}", v.0), v.1)),
    );
    names.extend(
        pmu50_core::pmu50::Outputs::default()
            .values(&s)
            .iter()
            .map(|v| (format!("o_{}", v.0), v.1)),
    );
    names.extend(
        pmu50_core::pmu50::reset(p)
            .values(&s)
            .iter()
            .map(|r| (format!("r_{}_{}", r.block, r.name), r.width)),
    );
    names.extend(
        pmu50_core::pmu50::Internals::default()
            .values()
            .iter()
            .map(|v| (format!("x_{}", v.0), v.1)),
    );
    b.push_scope("pmu50").unwrap();
    let ids = names
        .iter()
        .map(|(n, w)| {
            let w = match (decl, n.as_str()) {
                (Decl::NarrowWdata, "i_bus_wdata") => 4,
                (Decl::Wider, "i_bus_addr") => 12,
                (Decl::Wider, "o_smp") => 2,
                (Decl::Wider, "r_timing_generator_tmr") => 24,
                (Decl::Wider, "x_fig17") => 8,
                _ => *w,
            };
            if w == 1 {
                b.add_bit(BitType::Wire, n, Logic::Zero)
            } else {
                b.add_vector(BitType::Wire, n, u32::from(w) - 1, 0, 0)
            }
            .unwrap()
        })
        .collect();
    let extra = b.add_bit(BitType::Wire, "extra", Logic::Zero).unwrap();
    b.pop_scope().unwrap();
    (b, ids, extra)
}

/// Every value of a tick in the frame order.
fn values(
    m: &Pmu50,
    i: &Inputs,
    x: &pmu50_core::pmu50::Internals,
    before: &pmu50_core::pmu50::Outputs,
    r: &pmu50_core::pmu50::Regs,
) -> Vec<u64> {
    let s = m.structural();
    i.values()
        .iter()
        .map(|v| v.2)
        .chain(before.values(&s).iter().map(|v| v.2))
        .chain(r.values(&s).iter().map(|v| v.value))
        .chain(x.values().iter().map(|v| v.2))
        .collect()
}

/// What happens between two ticks of a run.
#[derive(Clone, Copy, Debug)]
enum Between {
    Nothing,
    /// a single change of a variable outside the frame, and of the frame's `ig` (inverted)
    SingleChanges,
}

/// Both writers over one run: (the tracer's file, dump_frame's file with every value). With
/// `mode` 1 the tracer steps in a [`pmu50_testbench::observers::tracer::TracerRun`] from one `SingleChanges` to the
/// next (direct steps, written when the next begins), with 2 in a
/// [`pmu50_testbench::observers::tracer::TracerTextRun`] (written at once), with 0 each step is a run of its own.
fn both(p: Params, run: &[(Inputs, Between)], mode: usize, decl: Decl) -> (String, String) {
    let (b1, ids1, extra1) = declare(&p, decl);
    let (b2, ids2, extra2) = declare(&p, decl);
    let mut w1 = b1.start(Vec::new()).unwrap();
    let mut w2 = b2.start(Vec::new()).unwrap();
    let mut m2 = Pmu50::new(p).unwrap();
    let mut tr = CoreTracer::new(w1.frame(&ids1).unwrap(), Pmu50::new(p).unwrap()).unwrap();
    assert_eq!(
        tr.exact(),
        decl == Decl::Core,
        "the unchecked lines exactly when the frame's widths are the core's"
    );
    let mut f2 = w2.frame(&ids2).unwrap();
    let mut flip = false;
    let mut t = 0;
    let mut k = 0;
    while k < run.len() {
        let between = {
            // the ticks up to the next `SingleChanges`, through `step`
            let mut ticks = |step: &mut dyn FnMut(u64, &Inputs) -> Outputs| {
                while k < run.len() {
                    let (i, b) = &run[k];
                    k += 1;
                    let regs = *m2.regs();
                    let pmu50_core::TracedStep {
                        before,
                        internals: x,
                        after: after2,
                        ..
                    } = m2.step_traced(i);
                    w2.dump_frame(&mut f2, t, &values(&m2, i, &x, &before, &regs))
                        .unwrap();
                    assert_eq!(step(t, i), after2);
                    t += 2;
                    if let Between::SingleChanges = b {
                        return *b;
                    }
                }
                Between::Nothing
            };
            if mode == 1 {
                let mut r = tr.run(&mut w1).unwrap();
                ticks(&mut |t, i| *r.step(t, i).unwrap())
            } else if mode == 2 {
                let mut r = tr.text_run(&mut w1).unwrap();
                ticks(&mut |t, i| *r.step(t, i).unwrap())
            } else {
                ticks(&mut |t, i| *tr.step(&mut w1, t, i).unwrap())
            }
        };
        if let Between::SingleChanges = between {
            flip = !flip;
            let i = &run[k - 1].0;
            for (w, e, ig) in [(&mut w1, extra1, ids1[0]), (&mut w2, extra2, ids2[0])] {
                w.set_time(t - 1).unwrap();
                w.change_bool(e, flip).unwrap();
                w.change_bool(ig, !i.ig).unwrap();
            }
        }
    }
    (
        String::from_utf8(w1.finish().unwrap()).unwrap(),
        String::from_utf8(w2.finish().unwrap()).unwrap(),
    )
}

fn arb_run() -> impl Strategy<Value = Vec<(Inputs, Between)>> {
    // Runs of held inputs (most edges narrow, as in a park), with key edges, comparator flips
    // and bus writes to any address (refused ones too), and now and then something between two
    // ticks.
    let between = prop_oneof![30 => Just(Between::Nothing), 1 => Just(Between::SingleChanges)];
    let one = (
        any::<bool>(),
        any::<bool>(),
        any::<bool>(),
        any::<bool>(),
        prop::bool::weighted(0.1),
        0u8..0x20,
        any::<u16>(),
        1usize..150,
        between,
    );
    prop::collection::vec(one, 1..40).prop_map(|runs| {
        let mut v = Vec::new();
        for (ig, vs2_ok, cmp_s, cmp_c, bus_we, bus_addr, bus_wdata, n, between) in runs {
            v.push((
                Inputs {
                    ig,
                    vs2_ok,
                    cmp_s,
                    cmp_c,
                    bus_we,
                    bus_addr,
                    bus_wdata,
                },
                between,
            ));
            v.extend(std::iter::repeat_n(
                (
                    Inputs {
                        ig,
                        vs2_ok,
                        cmp_s,
                        cmp_c,
                        bus_we: false,
                        bus_addr,
                        bus_wdata,
                    },
                    Between::Nothing,
                ),
                n,
            ));
        }
        v
    })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, failure_persistence: None, ..ProptestConfig::default() })]

    #[test]
    fn same_file_as_every_value(run in arb_run(), which in 0usize..4, mode in 0usize..3, wider in prop::bool::weighted(0.25)) {
        // the defaults, a deep synchronizer with 3-bit counters (as random_7), a fast park, a
        // one-flop synchronizer (a 1-bit `sync`)
        let p = [
            Params::default(),
            Params { sync_depth: 4, cnt_width: 3, ..Params::default() },
            Params { pw: 1, pi: 1, ps: 1, si_max: 6, si_min: 4, smp_on: 3, ..Params::default() },
            Params { sync_depth: 1, ..Params::default() },
        ][which];
        prop_assume!(Pmu50::new(p).is_ok());
        // the frame's widths the core's (unchecked lines), or some wider (checked lines)
        let (a, b) = both(p, &run, mode, if wider { Decl::Wider } else { Decl::Core });
        prop_assert_eq!(a, b);
    }
}

/// A step that fails half way (a value wider than its variable) still takes its edge, and the
/// next step gives every value again. Two cases the held values cannot repair alone: the inputs
/// of the tick after equal those of the tick before (so a comparison with the held inputs would
/// leave the failed tick's `bus_addr` in the file), and a wide edge (a bus write) just before
/// the failed tick (whose registers and outputs the failed step never compared).
#[test]
fn a_failed_step_takes_its_edge_and_is_followed_by_a_full_one() {
    let p = Params::default();
    let run = |fail_at: u64, write_at: Option<u64>, mode: usize| {
        let (b, ids, _) = declare(&p, Decl::NarrowWdata);
        let mut w = b.start(Vec::new()).unwrap();
        let mut tr = CoreTracer::new(w.frame(&ids).unwrap(), Pmu50::new(p).unwrap()).unwrap();
        let (b2, ids2, _) = declare(&p, Decl::NarrowWdata);
        let mut w2 = b2.start(Vec::new()).unwrap();
        let mut f2 = w2.frame(&ids2).unwrap();
        let mut m2 = Pmu50::new(p).unwrap();
        // the failing tick: bus_addr 7 is assigned, then bus_wdata 0x30 does not fit its 4 bits;
        // the write: PW := 9 (a wide edge)
        let input = |t: u64| {
            if t == fail_at {
                Inputs {
                    bus_addr: 7,
                    bus_wdata: 0x30,
                    ..Inputs::default()
                }
            } else if Some(t) == write_at {
                Inputs {
                    bus_we: true,
                    bus_addr: 0x03,
                    bus_wdata: 9,
                    ..Inputs::default()
                }
            } else {
                Inputs {
                    bus_addr: 1,
                    bus_wdata: 3,
                    ..Inputs::default()
                }
            }
        };
        let mut check = |t: u64, i: &Inputs, res: Result<Outputs, WriteError>, tick: u64| {
            let r = *m2.regs();
            let pmu50_core::TracedStep {
                before,
                internals: x,
                after,
                ..
            } = m2.step_traced(i);
            if t == fail_at {
                assert!(
                    matches!(res, Err(WriteError::ValueTooWide { value: 0x30, .. })),
                    "{res:?}"
                );
            } else {
                assert_eq!(res.unwrap(), after);
                w2.dump_frame(&mut f2, t, &values(&m2, i, &x, &before, &r))
                    .unwrap();
            }
            assert_eq!(tick, t + 1, "the edge is taken");
        };
        // the 40 ticks in one run of the tracer, in one text run, or each in a run of its own
        if mode == 2 {
            let mut r = tr.text_run(&mut w).unwrap();
            for t in 0..40u64 {
                let i = input(t);
                let res = r.step(t, &i).copied();
                check(t, &i, res, r.core().tick());
            }
        } else if mode == 1 {
            let mut r = tr.run(&mut w).unwrap();
            for t in 0..40u64 {
                let i = input(t);
                let res = r.step(t, &i).copied();
                check(t, &i, res, r.core().tick());
            }
        } else {
            for t in 0..40u64 {
                let i = input(t);
                let res = tr.step(&mut w, t, &i).copied();
                check(t, &i, res, tr.core().tick());
            }
        }
        // an error before the step starts (time backwards) takes no edge
        assert!(matches!(
            tr.step(&mut w, 5, &Inputs::default()),
            Err(WriteError::TimeBackwards { .. })
        ));
        assert_eq!(tr.core().tick(), 40);
        (
            String::from_utf8(w.finish().unwrap()).unwrap(),
            String::from_utf8(w2.finish().unwrap()).unwrap(),
        )
    };
    for (fail_at, write_at, mode) in [
        (10, None, 0),
        (6, Some(5), 0),
        (10, None, 1),
        (6, Some(5), 1),
        (10, None, 2),
        (6, Some(5), 2),
    ] {
        let (vcd, every) = run(fail_at, write_at, mode);
        // From the tick after the failed one on, the tracer's file holds what every value gives
        // (before it, they differ by what the failed tick assigned, which `every` skipped).
        let step = |v: &str, t: u64| {
            let from = v.find(&format!("#{t}\n")).expect("tick written");
            let rest = &v[from + 1..];
            rest[..rest.find('#').unwrap_or(rest.len())].to_string()
        };
        let code = vcd
            .lines()
            .find_map(|l| l.strip_suffix(" i_bus_addr [7:0] $end")?.rsplit(' ').next())
            .expect("bus_addr declared")
            .to_string();
        assert!(
            step(&vcd, fail_at).contains(&format!("b00000111 {code}\n")),
            "{}",
            step(&vcd, fail_at)
        );
        assert!(
            step(&vcd, fail_at + 1).contains(&format!("b00000001 {code}\n")),
            "tick after the failure must put bus_addr back: {}",
            step(&vcd, fail_at + 1)
        );
        let tail =
            |v: &str| v[v.find(&format!("#{}\n", fail_at + 2)).expect("written")..].to_string();
        assert_eq!(
            tail(&vcd),
            tail(&every),
            "failure at {fail_at}, write at {write_at:?}"
        );
    }
}

#[test]
fn the_frame_must_hold_the_65_signals() {
    let p = Params::default();
    let (b, ids, _) = declare(&p, Decl::Core);
    let mut w = b.start(Vec::new()).unwrap();
    assert_eq!(ids.len(), N_SIGNALS);
    let e = CoreTracer::new(w.frame(&ids[..64]).unwrap(), Pmu50::new(p).unwrap())
        .err()
        .expect("refused");
    assert_eq!(e, FrameSizeError { got: 64 });
    assert!(
        e.to_string().contains("65 variables") && e.to_string().contains("has 64"),
        "{e}"
    );
}

/// The tracer's positions of the registers a narrow edge writes are those of the kernel's list.
#[test]
fn narrow_registers_are_the_kernels_narrow_writes() {
    let p = Params::default();
    let s = Structural {
        sync_depth: p.sync_depth,
        cnt_width: p.cnt_width,
    };
    let regs = pmu50_core::pmu50::reset(&p).values(&s);
    let names: Vec<String> = NARROW_REGISTERS
        .iter()
        .map(|&k| format!("{}.{}", regs[k].block, regs[k].name))
        .collect();
    let mut want: Vec<String> = pmu50_core::kernel::NARROW_WRITES
        .iter()
        .map(|n| n.to_string())
        .collect();
    let mut got = names.clone();
    want.sort();
    got.sort();
    assert_eq!(got, want);
}
