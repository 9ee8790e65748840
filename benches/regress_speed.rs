//! `make bench`, regression part: what a regression seed costs, side by side in one run
//! (docs/verification.md, "Speed").
//!
//! On the scenarios of regression seeds 1..=SEEDS (uniform random), in CPU seconds of this
//! process, fastest of ROUNDS interleaved rounds:
//! - the kernel alone (`Pmu50::step`) replaying the inputs the bench applied;
//! - the bench stepping every tick (environment, MPU, core) with an observer that does nothing;
//! - the same bench with a seed's observer: coverage sampled at every edge and the invariants
//!   (what `pmu50 regress` runs), and the cost of that observer against the bench.
//!
//! Then `pmu50 regress` on every core: seeds per second, wall time.
//!
//!   cargo bench --bench regress_speed [-- --seeds N --rounds R --regress-seeds M]

use pmu50::regress::check::SeedChecks;
use pmu50::regress::gen::{Bias, Stimulus};
use pmu50::scenario::Scenario;
use pmu50::sim::{self, Observer, SimError, SimOptions, TickView};
use pmu50_core::{Inputs, Pmu50};
use std::path::Path;
use std::time::Instant;

fn cpu_now() -> f64 {
    let mut ts = libc::timespec { tv_sec: 0, tv_nsec: 0 };
    // SAFETY: clock_gettime writes one timespec through a valid pointer.
    unsafe { libc::clock_gettime(libc::CLOCK_PROCESS_CPUTIME_ID, &mut ts) };
    ts.tv_sec as f64 + ts.tv_nsec as f64 * 1e-9
}

/// Needs every tick like the coverage observer, replays periods like it, does nothing.
struct Idle;
impl Observer for Idle {
    fn tick(&mut self, v: &TickView<'_>) -> Result<(), SimError> {
        std::hint::black_box(v.tick);
        Ok(())
    }
    fn finish(&mut self, _: &TickView<'_>) -> Result<(), SimError> {
        Ok(())
    }
    fn replays_periods(&self) -> bool {
        true
    }
    fn can_replay(&self, _k: u64, _len: u64) -> bool {
        true
    }
}

/// Records the inputs of every evaluated tick (for the kernel row).
struct Record(Vec<Inputs>);
impl Observer for Record {
    fn tick(&mut self, v: &TickView<'_>) -> Result<(), SimError> {
        self.0.push(*v.inputs);
        Ok(())
    }
    fn finish(&mut self, _: &TickView<'_>) -> Result<(), SimError> {
        Ok(())
    }
}

fn arg(name: &str, default: u64) -> u64 {
    let a: Vec<String> = std::env::args().collect();
    a.iter().position(|x| x == name).and_then(|i| a.get(i + 1)).and_then(|v| v.parse().ok()).unwrap_or(default)
}

fn main() {
    let seeds = arg("--seeds", 40);
    let rounds = arg("--rounds", 7);
    let regress_seeds = arg("--regress-seeds", 1000);
    let scenarios: Vec<Scenario> = (1..=seeds)
        .map(|s| {
            let text = Stimulus::generate(s, &Bias::uniform()).to_toml(&format!("regress_{s}"));
            Scenario::parse(&text, "bench", "bench", Path::new("bench.toml")).expect("a generated scenario parses")
        })
        .collect();
    // Every tick the bench evaluates with a coverage observer, as inputs for the kernel row.
    let mut inputs = Vec::new();
    let mut evaluated = 0u64;
    for sc in &scenarios {
        let mut rec = Record(Vec::new());
        let mut idle = Idle;
        let r = sim::run(sc, SimOptions::default(), &mut [&mut idle, &mut rec]).expect("bench runs");
        evaluated += r.evaluated_ticks;
        inputs.push((sc.params, rec.0));
    }

    let (mut kernel, mut bench, mut checked) = (f64::MAX, f64::MAX, f64::MAX);
    for _ in 0..rounds {
        let t = cpu_now();
        for (p, ins) in &inputs {
            let mut core = Pmu50::new(*p).expect("legal");
            let mut acc = 0u32;
            for i in ins {
                acc = acc.wrapping_add(u32::from(core.step(i).si));
            }
            std::hint::black_box(acc);
        }
        kernel = kernel.min(cpu_now() - t);

        let t = cpu_now();
        for sc in &scenarios {
            let mut idle = Idle;
            std::hint::black_box(sim::run(sc, SimOptions::default(), &mut [&mut idle]).expect("bench runs").evaluated_ticks);
        }
        bench = bench.min(cpu_now() - t);

        let t = cpu_now();
        for sc in &scenarios {
            let mut c = SeedChecks::new(&sc.params, sc.clock_ns(), false);
            let r = sim::run(sc, SimOptions::default(), &mut [&mut c]).expect("bench runs");
            c.finish_checks(&r, sc);
            std::hint::black_box(c.coverage.hits().len());
        }
        checked = checked.min(cpu_now() - t);
    }
    let m = |s: f64| evaluated as f64 / s / 1e6;
    println!("regression seeds 1..={seeds}: {evaluated} evaluated ticks (fastest of {rounds} rounds, CPU seconds of this process)");
    println!("| harness | M ticks/CPU-s | against the bench |");
    println!("|---|---:|---:|");
    println!("| kernel alone (Pmu50::step, the same inputs) | {:.1} | {:.1}x |", m(kernel), bench / kernel);
    println!("| bench, every tick (environment, MPU, core) | {:.1} | 1.00x |", m(bench));
    println!("| bench + coverage at every edge + invariants (a regress seed) | {:.1} | {:.3}x |", m(checked), checked / bench);
    println!("coverage sampling and checks cost {:+.1} % of the untraced bench (goal: at most 10 %)", (checked / bench - 1.0) * 100.0);

    // pmu50 regress on every core.
    let bin = Path::new(env!("CARGO_MANIFEST_DIR")).join("target/release/pmu50");
    if bin.is_file() {
        let out = tempfile::tempdir().expect("temp dir");
        let t = Instant::now();
        let o = std::process::Command::new(&bin)
            .args(["regress", "--iterations", &regress_seeds.to_string(), "--no-triage", "--out"])
            .arg(out.path().join("r"))
            .output()
            .expect("pmu50 runs");
        let wall = t.elapsed().as_secs_f64();
        let cores = std::thread::available_parallelism().map(|n| n.get()).unwrap_or(1);
        println!(
            "pmu50 regress --iterations {regress_seeds} on {cores} cores: {wall:.1} s wall, {:.0} seeds/s (exit {})",
            regress_seeds as f64 / wall,
            o.status.code().unwrap_or(-1)
        );
    } else {
        println!("pmu50 regress row skipped: build target/release/pmu50 first (make bench does)");
    }
}
