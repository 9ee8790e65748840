//! Simulation speed (`make bench`): the bare core's clock edge, and whole scenarios with and
//! without fast-forward of idle key-off gaps. Throughput is reported in ticks per second.

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use pmu50_core::{Inputs, Params, Pmu50};
use pmu50_testbench::scenario::Scenario;
use pmu50_testbench::sim::{run, SimOptions};
use std::hint::black_box;
use std::path::Path;

fn core_step(c: &mut Criterion) {
    let mut g = c.benchmark_group("core");
    const N: u64 = 100_000;
    g.throughput(Throughput::Elements(N));
    g.bench_function("step_key_off_100k_ticks", |b| {
        b.iter(|| {
            let mut core = Pmu50::new(Params::default()).unwrap();
            let mut out = core.peek();
            for k in 0..N {
                let i = Inputs {
                    vs2_ok: out.vs2_en,
                    cmp_s: k & 0x4000 != 0,
                    cmp_c: k & 0x2000 != 0,
                    ..Inputs::default()
                };
                out = core.step(black_box(&i));
            }
            black_box(out)
        })
    });
    g.finish();
}

fn scenarios(c: &mut Criterion) {
    let mut g = c.benchmark_group("scenario");
    g.sample_size(10);
    let sc =
        Scenario::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("scenarios/keyoff_turns.toml"))
            .unwrap();
    g.throughput(Throughput::Elements(sc.ticks));
    for (name, ff) in [
        ("keyoff_turns_fast_forward", true),
        ("keyoff_turns_every_tick", false),
    ] {
        g.bench_function(name, |b| {
            b.iter(|| {
                black_box(
                    run(&sc, SimOptions { fast_forward: ff }, &mut [])
                        .unwrap()
                        .pulses
                        .len(),
                )
            })
        });
    }
    g.finish();
}

criterion_group!(benches, core_step, scenarios);
criterion_main!(benches);
