//! `make bench`, regression part: what a regression seed costs, side by side in one run
//! (docs/verification.md, "Speed").
//!
//! On the scenarios of regression seeds 1..=SEEDS (uniform random), in CPU seconds of this
//! process, fastest of ROUNDS interleaved rounds:
//! - the kernel alone (`Pmu50::step`) replaying the inputs the bench applied;
//! - the bench stepping every tick (environment, MPU, core) with an observer that does nothing;
//! - the same bench with the coverage sampled at every edge (and replayed over skipped periods),
//!   and its cost against the bench;
//! - the same bench with a seed's observer: the coverage and the invariants (what `pmu50
//!   regress` runs), and its cost.
//!
//! Then `pmu50 regress` on every core: seeds per second, wall time.
//!
//! Then `--dut verilator` against Verilator alone, side by side (docs/verification.md, "Speed"),
//! on seeds 1..=DUT_SEEDS with SYNC_DEPTH 2 and CNT_W 16 held (one RTL library), one job, wall
//! time, fastest of DUT_ROUNDS:
//! - Verilator alone: the same RTL library stepped in this process on the same stimuli held in
//!   memory, as a plain harness runs it (two evaluations a tick, outputs folded, nothing
//!   compared: `regress::lockstep::replay_alone`), the stimuli recorded beforehand (not timed);
//! - Verilator alone as a testbench of its own replays stimulus files: the same library driven by
//!   hdl/tb/lockstep/replay_main.cpp, one process per seed reading the seed's vector file
//!   (written beforehand, not timed);
//! - `pmu50 regress --dut model` on those seeds (the model with coverage and checks);
//! - `pmu50 regress --dut verilator` on those seeds, as the user runs it (the whole process:
//!   model, DUT worker, lockstep comparison of every register, report files).
//!
//!   cargo bench --bench regress_speed [-- --seeds N --rounds R --regress-seeds M --dut-seeds D --dut-rounds K]

use pmu50_core::{Inputs, Pmu50};
use pmu50_testbench::scenario::Scenario;
use pmu50_testbench::sim::{self, Observer, SimError, SimOptions, TickView};
use pmu50_verif::check::SeedChecks;
use pmu50_verif::gen::{Bias, Stimulus};
use std::path::Path;
use std::time::Instant;

fn cpu_now() -> f64 {
    let mut ts = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
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
}

fn arg(name: &str, default: u64) -> u64 {
    let a: Vec<String> = std::env::args().collect();
    a.iter()
        .position(|x| x == name)
        .and_then(|i| a.get(i + 1))
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}

fn main() {
    let seeds = arg("--seeds", 40);
    let rounds = arg("--rounds", 7);
    let regress_seeds = arg("--regress-seeds", 1000);
    let scenarios: Vec<Scenario> = (1..=seeds)
        .map(|s| {
            let text = Stimulus::generate(s, &Bias::uniform()).to_toml(&format!("regress_{s}"));
            Scenario::parse(&text, "bench", "bench", Path::new("bench.toml"))
                .expect("a generated scenario parses")
        })
        .collect();
    // Every tick the bench evaluates with a coverage observer, as inputs for the kernel row.
    let mut inputs = Vec::new();
    let mut evaluated = 0u64;
    for sc in &scenarios {
        let mut rec = Record(Vec::new());
        let mut idle = Idle;
        let r =
            sim::run(sc, SimOptions::default(), &mut [&mut idle, &mut rec]).expect("bench runs");
        evaluated += r.evaluated_ticks;
        inputs.push((sc.params, rec.0));
    }

    let (mut kernel, mut bench, mut covered, mut checked) =
        (f64::MAX, f64::MAX, f64::MAX, f64::MAX);
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
            std::hint::black_box(
                sim::run(sc, SimOptions::default(), &mut [&mut idle])
                    .expect("bench runs")
                    .evaluated_ticks,
            );
        }
        bench = bench.min(cpu_now() - t);

        let t = cpu_now();
        for sc in &scenarios {
            // the coverage alone, as a seed samples and replays it (`SeedChecks` without the
            // invariants)
            let mut c = pmu50_coverage::Coverage::new(&sc.params, sc.clock_ns());
            sim::run(sc, SimOptions::default(), &mut [&mut c]).expect("bench runs");
            std::hint::black_box(c.hits().len());
        }
        covered = covered.min(cpu_now() - t);

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
    println!(
        "| kernel alone (Pmu50::step, the same inputs) | {:.1} | {:.1}x |",
        m(kernel),
        bench / kernel
    );
    println!(
        "| bench, every tick (environment, MPU, core) | {:.1} | 1.00x |",
        m(bench)
    );
    println!(
        "| bench + coverage sampled at every edge | {:.1} | {:.3}x |",
        m(covered),
        covered / bench
    );
    println!(
        "| bench + coverage + invariants (a regress seed) | {:.1} | {:.3}x |",
        m(checked),
        checked / bench
    );
    println!("coverage sampling costs {:+.1} % of the untraced bench (goal: at most 10 %); with the invariants {:+.1} %", (covered / bench - 1.0) * 100.0, (checked / bench - 1.0) * 100.0);

    // pmu50 regress on every core.
    let bin = Path::new(env!("CARGO_MANIFEST_DIR")).join("target/release/pmu50");
    if bin.is_file() {
        let out = tempfile::tempdir().expect("temp dir");
        let t = Instant::now();
        let o = std::process::Command::new(&bin)
            .args([
                "regress",
                "--iterations",
                &regress_seeds.to_string(),
                "--no-triage",
                "--out",
            ])
            .arg(out.path().join("r"))
            .output()
            .expect("pmu50 runs");
        let wall = t.elapsed().as_secs_f64();
        let cores = std::thread::available_parallelism()
            .map(|n| n.get())
            .unwrap_or(1);
        println!(
            "pmu50 regress --iterations {regress_seeds} on {cores} cores: {wall:.1} s wall, {:.0} seeds/s (exit {})",
            regress_seeds as f64 / wall,
            o.status.code().unwrap_or(-1)
        );
    } else {
        println!("pmu50 regress row skipped: build target/release/pmu50 first (make bench does)");
    }
    dut_rows(&bin, arg("--dut-seeds", 200), arg("--dut-rounds", 3));
}

/// `regress --dut verilator` against Verilator alone on the same stimuli (module documentation).
fn dut_rows(bin: &Path, seeds: u64, rounds: u64) {
    use pmu50_verif::lockstep::{replay_alone, InputRecorder};
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let have = |tool: &str| {
        std::process::Command::new(tool)
            .arg("--version")
            .output()
            .is_ok_and(|o| o.status.success())
    };
    if !bin.is_file() || !have("verilator") {
        println!("regress --dut verilator rows skipped: they need target/release/pmu50 and verilator (make deps)");
        return;
    }
    // The twin with every parameter fixed (a wrapper top without parameters): one library
    // serves every seed, as for a netlist, so both rows step the same library.
    let fixed_dir = tempfile::tempdir().expect("temp dir");
    let list = fixed_twin(root, fixed_dir.path());
    let lib = match pmu50_verif::dut::library_for(&list, &pmu50_core::Params::default()) {
        Ok(l) => l,
        Err(e) => {
            println!("regress --dut verilator rows skipped: the RTL library did not build: {e}");
            return;
        }
    };
    let all: Vec<(String, u64)> = pmu50_core::Params::default()
        .hdl_parameters()
        .iter()
        .map(|(n, v)| (n.to_string(), *v))
        .collect();
    let bias = Bias::uniform().fixing(&pmu50_verif::rtl::Fixed { values: all });
    let stimuli: Vec<(pmu50_core::Params, Vec<u32>)> = (1..=seeds)
        .map(|s| {
            let text = Stimulus::generate(s, &bias).to_toml(&format!("regress_{s}"));
            let sc = Scenario::parse(&text, "bench", "bench", Path::new("bench.toml"))
                .expect("a generated scenario parses");
            let mut rec = InputRecorder::default();
            sim::run(&sc, SimOptions::default(), &mut [&mut rec]).expect("bench runs");
            (sc.params, rec.inputs)
        })
        .collect();
    let ticks: usize = stimuli.iter().map(|(_, i)| i.len()).sum();
    // The vector files and the file-replaying testbench.
    let files = tempfile::tempdir().expect("temp dir");
    let replay = root.join("hdl/build/bench/replay");
    let _ = std::fs::create_dir_all(root.join("hdl/build/bench"));
    let built = std::process::Command::new("g++")
        .args(["-O2", "-o"])
        .arg(&replay)
        .arg(root.join("hdl/tb/lockstep/replay_main.cpp"))
        .arg("-ldl")
        .status()
        .is_ok_and(|s| s.success());
    let vecs: Vec<std::path::PathBuf> = (1..=seeds)
        .map(|s| {
            let text = Stimulus::generate(s, &bias).to_toml(&format!("regress_{s}"));
            let sc = Scenario::parse(&text, "bench", "bench", Path::new("bench.toml"))
                .expect("a generated scenario parses");
            let path = files.path().join(format!("regress_{s}.vec"));
            let f = std::io::BufWriter::new(std::fs::File::create(&path).expect("a vector file"));
            let mut w = pmu50_testbench::observers::vectors::VectorWriter::new(f, &sc)
                .expect("vector header");
            sim::run(&sc, SimOptions::default(), &mut [&mut w]).expect("bench runs");
            path
        })
        .collect();
    // CPU seconds of the waited-for children (the regress process and its DUT workers).
    let children_cpu = || {
        // SAFETY: getrusage writes one rusage through a valid pointer.
        let mut u: libc::rusage = unsafe { std::mem::zeroed() };
        unsafe { libc::getrusage(libc::RUSAGE_CHILDREN, &mut u) };
        let tv = |t: libc::timeval| t.tv_sec as f64 + t.tv_usec as f64 * 1e-6;
        tv(u.ru_utime) + tv(u.ru_stime)
    };
    let regress = |dut: &str| -> (f64, f64, Option<i32>) {
        let out = tempfile::tempdir().expect("temp dir");
        let cpu = children_cpu();
        let t = Instant::now();
        let o = std::process::Command::new(bin)
            .args([
                "regress",
                "--iterations",
                &seeds.to_string(),
                "--jobs",
                "1",
                "--no-triage",
                "--dut",
                dut,
                "--out",
            ])
            .arg(out.path().join("r"))
            .args(if dut == "model" {
                vec![]
            } else {
                vec!["--rtl".to_string(), list.display().to_string()]
            })
            .output()
            .expect("pmu50 runs");
        (
            t.elapsed().as_secs_f64(),
            children_cpu() - cpu,
            o.status.code(),
        )
    };
    // (wall, CPU) of each, fastest wall of the rounds
    let (mut alone, mut files_alone, mut model, mut lockstep) = (
        (f64::MAX, 0.0),
        (f64::MAX, 0.0),
        (f64::MAX, 0.0),
        (f64::MAX, 0.0),
    );
    let mut exits = Vec::new();
    for _ in 0..rounds {
        let (t, cpu) = (Instant::now(), cpu_now());
        for (_, inputs) in &stimuli {
            std::hint::black_box(replay_alone(&lib, inputs).expect("the RTL library loads"));
        }
        let w = t.elapsed().as_secs_f64();
        if w < alone.0 {
            alone = (w, cpu_now() - cpu);
        }
        if built {
            let (t, cpu) = (Instant::now(), children_cpu());
            for v in &vecs {
                let o = std::process::Command::new(&replay)
                    .arg(&lib)
                    .arg(v)
                    .output()
                    .expect("replay runs");
                assert!(
                    o.status.success(),
                    "replay {}: {}",
                    v.display(),
                    String::from_utf8_lossy(&o.stderr)
                );
            }
            let w = t.elapsed().as_secs_f64();
            if w < files_alone.0 {
                files_alone = (w, children_cpu() - cpu);
            }
        }
        for (dut, best) in [("model", &mut model), ("verilator", &mut lockstep)] {
            let (w, cpu, c) = regress(dut);
            if w < best.0 {
                *best = (w, cpu);
            }
            exits.push(c);
        }
    }
    println!("regress seeds 1..={seeds}, every parameter at its default (the twin under a top without parameters: one library): {ticks} ticks on the RTL, one job, fastest wall of {rounds} (regress exits {exits:?})");
    println!("| what | wall s | against Verilator alone | CPU s (all processes) | against Verilator alone |");
    println!("|---|---:|---:|---:|---:|");
    let row = |what: &str, (w, c): (f64, f64)| {
        println!(
            "| {what} | {w:.2} | {:.2}x | {c:.2} | {:.2}x |",
            w / alone.0,
            c / alone.1
        )
    };
    row(
        "Verilator alone (the RTL library, stimuli in memory, outputs folded)",
        alone,
    );
    if built {
        row("Verilator alone as its own testbench (the same library, a process a seed reading its vector file)", files_alone);
    }
    row(
        "pmu50 regress --dut model (the model, coverage, checks)",
        model,
    );
    row(
        "pmu50 regress --dut verilator (model + RTL in lockstep, the 23 output ports compared)",
        lockstep,
    );
    if built {
        println!("regress --dut verilator adds {:+.0} % wall, {:+.0} % CPU to Verilator alone replaying the stimulus files (goal: at most +10 %)", (lockstep.0 / files_alone.0 - 1.0) * 100.0, (lockstep.1 / files_alone.1 - 1.0) * 100.0);
    }
    println!("regress --dut verilator adds {:+.0} % wall, {:+.0} % CPU to Verilator stepped in memory (a lower bound: its stimuli come from the model, untimed); goal: at most 1.25x wall, now {:.2}x", (lockstep.0 / alone.0 - 1.0) * 100.0, (lockstep.1 / alone.1 - 1.0) * 100.0, lockstep.0 / alone.0);
}

/// The twin under a top `pmu50` without parameters (the twin's module renamed `pmu50_twin`):
/// an RTL that fixes every parameter at its default. Returns its file list.
fn fixed_twin(root: &Path, dir: &Path) -> std::path::PathBuf {
    let hdl = root.join("hdl");
    let mut list = String::new();
    for f in std::fs::read_to_string(hdl.join("pmu50.f"))
        .expect("hdl/pmu50.f")
        .lines()
        .map(str::trim)
        .filter(|l| !l.is_empty() && !l.starts_with("//"))
    {
        let text = std::fs::read_to_string(hdl.join(f)).expect("a twin source");
        let name = f.replace('/', "_");
        std::fs::write(
            dir.join(&name),
            text.replace("module pmu50 #(", "module pmu50_twin #("),
        )
        .expect("a copy");
        list.push_str(&name);
        list.push('\n');
    }
    let ports: Vec<String> = ["clk", "rst_n"]
        .iter()
        .map(|s| s.to_string())
        .chain(
            pmu50_core::signals::INPUTS
                .iter()
                .map(|s| s.name.to_string()),
        )
        .chain(
            pmu50_core::signals::OUTPUTS
                .iter()
                .map(|s| s.name.to_string()),
        )
        .collect();
    let decl = |n: &str| -> String {
        let w = |b: u8| {
            if b > 1 {
                format!("[{}:0] ", b - 1)
            } else {
                String::new()
            }
        };
        if let Some(s) = pmu50_core::signals::INPUTS.iter().find(|s| s.name == n) {
            format!(
                "input wire {}{n}",
                w(s.width.bits(&pmu50_core::pmu50::Structural {
                    sync_depth: 2,
                    cnt_width: 16
                }))
            )
        } else if let Some(s) = pmu50_core::signals::OUTPUTS.iter().find(|s| s.name == n) {
            format!(
                "output wire {}{n}",
                w(s.width.bits(&pmu50_core::pmu50::Structural {
                    sync_depth: 2,
                    cnt_width: 16
                }))
            )
        } else {
            format!("input wire {n}")
        }
    };
    let wrapper = format!(
        "// the twin with every parameter fixed (make bench)\nmodule pmu50 (\n    {}\n);\n    pmu50_twin u (\n        {}\n    );\nendmodule\n",
        ports.iter().map(|p| decl(p)).collect::<Vec<_>>().join(",\n    "),
        ports.iter().map(|p| format!(".{p}({p})")).collect::<Vec<_>>().join(", ")
    );
    std::fs::write(dir.join("pmu50_fixed.v"), wrapper).expect("the wrapper");
    list.push_str("pmu50_fixed.v\n");
    let f = dir.join("fixed.f");
    std::fs::write(&f, list).expect("the file list");
    f
}
