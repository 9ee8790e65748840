//! `make bench` (benches/compare.sh builds the harnesses, then runs this): the Rust model and the
//! Verilog twin side by side, on the same stimulus held in memory, in one run, in one table.
//!
//!   cargo bench --bench compare -- --dir hdl/build/bench --stim keyoff_turns --stim random_7 \
//!       [--icarus keyoff_turns] [--seconds 1.0] [--rounds 15] [--quick | --quick-traced | --quick-vcd | --quick-run | --quick-wall]
//!
//! For each stimulus NAME, `DIR/NAME.vec` is a vector file (`pmu50 vectors`): its inputs are the
//! stimulus, its `// param` lines the parameters. Harnesses, each replaying the stimulus from reset
//! one rising edge per line, repeated until about `--seconds` of CPU time:
//!
//! | harness | what runs |
//! |---|---|
//! | readable model | `Pmu50Spec::step`: the per-block specification (`pmu50::eval`) |
//! | fast kernel | `Pmu50::step`: `rtl_model/core/src/kernel.rs` |
//! | Verilator -O3 | `DIR/vl_NAME/bench` (hdl/bench/bench.cpp), untraced |
//! | Verilator -O3 --trace | `DIR/vlt_NAME/bench --trace`: VCD of the twin's counterparts of the Rust tracer's 65 signals (hdl/bench/trace.vlt); the note says how many `$var`s it dumps and names any of the 65 without a counterpart |
//! | Rust tracer VCD / FST | `pmu50_testbench::observers::tracer::CoreTracer` in one run (VCD: `CoreTracer::text_run`, the checked `pmu50_waves` writer's text buffer lent to the tracer's frame, each changed value's line written at once; FST: `CoreTracer::run`, the writer lent to the frame; both comparing only what the edge can have changed) of the model's signals: ports, registers, internals, as `pmu50 run` declares them (without the analog `env` reals, which the twin does not have). Before timing, the run checks that its VCD is byte for byte the one of `Writer::dump_frame` with every value of every tick |
//! | ... to /dev/null | the same two VCD harnesses (Verilator --trace, Rust tracer VCD) writing to `/dev/null`: the same writes, which the kernel throws away, so the row is the tracer's own cost without the page cache's (both sides write the same 8 MB of keyoff_turns to a file, a large part of the Rust tracer's time) |
//! | Verilator -O3 --trace, every variable | `DIR/vla_NAME/bench --trace` (build.sh --trace-all): the VCD of all 371 `$var`s of the twin, as `verilator --trace` dumps without a configuration file |
//! | pmu50 run --trace all | `target/release/pmu50 run SCENARIO --trace all` as a user runs it (SCENARIO: `DIR/NAME.toml`, else `scenarios/NAME.toml`): the child process's whole CPU time (start, scenario, environment models, the VCD of every signal with the analog `env` reals, the save file); its ratio to both Verilator --trace rows is printed after the table |
//! | page cache | after the table: the CPU cost per byte of writing a new 8 MiB file in 1 MiB writes, and what it comes to per tick for each stimulus's VCD (the same bytes for every VCD harness) |
//! | Icarus | `vvp DIR/iv_NAME.vvp +vec=DIR/NAME.vec` (hdl/tb/tb_vectors.v, which compares every output with the file: for scale) |
//!
//! `--quick-traced` prints only the Rust tracer's rows, with two parts of its tick: the traced
//! edge alone (`Pmu50::step_traced`, no writer) and the tracer writing to `std::io::sink`.
//! `--quick-vcd` prints only the Rust tracer's VCD into a file (the table's row, for a profiler:
//! `perf record` sees nothing else) and how many of the stimulus's edges are wide.
//! `--quick-run` prints only the `pmu50 run --trace all` row against both Verilator --trace
//! rows (interleaved rounds, as in the table; needs only `DIR/vlt_NAME` and `DIR/vla_NAME`).
//!
//! `--quick-wall` prints only the wall-time table (below).
//!
//! Wall time, after the table: what a user waits for, whole processes side by side in
//! interleaved rounds (the fastest wall time of each counts, printed with that round's CPU
//! time, the process's user + system time of all its threads): `pmu50 run SCENARIO --trace all`
//! with its waveform writer on a thread of its own (the default on a machine with two cores or
//! more) and on the bench's thread (`PMU50_WRITER_THREAD=0`), against Verilator's harness with
//! `--trace` of every variable built with `--threads 1` and `--threads 2` (`DIR/vlw1_NAME/bench`,
//! `DIR/vlw2_NAME/bench`: benches/verilator_threads.sh, which also makes the harness time its
//! replay loop by the wall clock; Verilator 5 has no other threading of a VCD:
//! `--trace-threads` offloads FST only). Verilator's best of the two is the one the ratio is
//! taken against, and the line says which; a second ratio is taken against the fastest replay
//! loop alone. Both processes read their
//! stimulus (a scenario file and the environment models, a vector file) and write the VCD of
//! every variable; `pmu50 run` also writes the save file, and syncs both files to the disk
//! before renaming them into place (the harness neither): two more rows are the same run into
//! `/dev/shm` (memory), without the disk's share, and on the disk without the flush
//! (`PMU50_SYNC=0`: renamed all the same). Verilator's replay loop alone (timed by the wall
//! clock) is printed beside it.
//!
//! The harnesses of a stimulus are timed in [`rounds`] rounds each, interleaved (round 1 of
//! every harness, then round 2, ...), and the fastest round of each counts.
//!
//! Every harness folds the 23 outputs after every edge into a checksum (packing and mixing as in
//! hdl/bench/bench.cpp); the run fails (exit 1) unless all checksums of a stimulus agree. Times are
//! process CPU seconds (`clock_gettime(CLOCK_PROCESS_CPUTIME_ID)`, `getrusage` for children).
//!
//! Park figures (docs/spec.md 5.1): a parked car, key off, motor still, for 1 h, 1 d and 30 d, and
//! `scenarios/park_30d.toml` (30 days with a disturbance every 6 h), through the simulator with
//! fast-forward and period skip (`pmu50_testbench::sim::run` as `pmu50 run` with trace = none), each in a
//! child process for its CPU time and peak memory.

use pmu50_core::pmu50::Structural;
use pmu50_core::{Inputs, Internals, Outputs, Params, Pmu50, Pmu50Spec, Regs};
use pmu50_testbench::observers::tracer::CoreTracer;
use pmu50_testbench::scenario::Scenario;
use pmu50_testbench::sim::{run, SimOptions};
use pmu50_waves::fst::start_fst;
use pmu50_waves::writer::{BitType, Emitter, Frame, SigId, VcdBuilder, VcdWriter, Writer};
use pmu50_waves::{TimeUnit, Timescale};
use std::hint::black_box;
use std::path::{Path, PathBuf};
use std::process::Command;
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

/// (CPU seconds, peak resident KiB) of `who` (RUSAGE_SELF or RUSAGE_CHILDREN).
fn rusage(who: libc::c_int) -> (f64, i64) {
    // SAFETY: getrusage fills a zeroed rusage struct through a valid pointer.
    let mut u: libc::rusage = unsafe { std::mem::zeroed() };
    unsafe { libc::getrusage(who, &mut u) };
    let t = |v: libc::timeval| v.tv_sec as f64 + v.tv_usec as f64 * 1e-6;
    (t(u.ru_utime) + t(u.ru_stime), u.ru_maxrss)
}

struct Stim {
    name: String,
    vec: PathBuf,
    params: Params,
    clock_ns: u64,
    inputs: Vec<Inputs>,
}

fn load(dir: &Path, name: &str) -> Result<Stim, String> {
    let vec = dir.join(format!("{name}.vec"));
    let text = std::fs::read_to_string(&vec)
        .map_err(|e| format!("{}: {e} (benches/compare.sh writes it)", vec.display()))?;
    let mut p = Params::default();
    let mut clock_ns = 10_000;
    let mut inputs = Vec::new();
    for (n, line) in text.lines().enumerate() {
        let bad = || format!("{}:{}: cannot read `{line}`", vec.display(), n + 1);
        if let Some(rest) = line.strip_prefix("// param ") {
            let mut it = rest.split_whitespace();
            let (k, v) = (
                it.next().ok_or_else(bad)?,
                it.next()
                    .ok_or_else(bad)?
                    .parse::<u64>()
                    .map_err(|_| bad())?,
            );
            p.set_hdl_parameter(k, v)
                .map_err(|e| format!("{}:{}: {e}", vec.display(), n + 1))?;
        } else if let Some(rest) = line.strip_prefix("// clock_ns ") {
            clock_ns = rest.trim().parse().map_err(|_| bad())?;
        } else if !line.starts_with("//") && !line.trim().is_empty() {
            let f: Vec<u32> = line
                .split_whitespace()
                .take(7)
                .map(|x| u32::from_str_radix(x, 16))
                .collect::<Result<_, _>>()
                .map_err(|_| bad())?;
            if f.len() != 7 {
                return Err(bad());
            }
            inputs.push(Inputs {
                ig: f[0] & 1 == 1,
                vs2_ok: f[1] & 1 == 1,
                cmp_s: f[2] & 1 == 1,
                cmp_c: f[3] & 1 == 1,
                bus_we: f[4] & 1 == 1,
                bus_addr: f[5] as u8,
                bus_wdata: f[6] as u16,
            });
        }
    }
    p.validate()
        .map_err(|e| format!("{}: {e}", vec.display()))?;
    Ok(Stim {
        name: name.to_string(),
        vec,
        params: p,
        clock_ns,
        inputs,
    })
}

/// The 23 outputs after an edge folded into the checksum (the same function as
/// hdl/bench/bench.cpp's `mix`: its `flags`, bit k the k-th one-bit output from `sig` to
/// `bus_err`, is [`Outputs::flags`], gathered from three loads instead of eighteen; the test
/// `output_flags_are_the_one_bit_outputs_in_port_order` in
/// rtl_model/core/tests/kernel_equivalence.rs checks it against the C++ definition written out).
#[inline(always)]
fn mix(h: u64, o: &Outputs) -> u64 {
    let w0 = u64::from(o.flags())
        | u64::from(o.cnt_r) << 18
        | u64::from(o.si) << 26
        | u64::from(o.bus_rdata) << 42;
    let w1 = u64::from(o.cnt_s) | u64::from(o.cnt_c) << 16;
    (h.rotate_left(5) ^ w0).wrapping_add(w1.wrapping_mul(0x9E37_79B9_7F4A_7C15))
}

#[derive(Clone, Debug)]
struct Meas {
    ticks: u64,
    cpu: f64,
    checksum: Option<u64>,
    note: String,
}

impl Meas {
    fn rate(&self) -> f64 {
        self.ticks as f64 / self.cpu.max(1e-9)
    }
}

/// Rounds per measurement: every harness is timed in this many rounds and the fastest round
/// counts. On a shared machine the load only ever slows a round down, so the best round is the
/// one least disturbed; all harnesses are measured the same way, so their ratios stay fair.
const ROUNDS: u32 = 15;

/// [`ROUNDS`], or the `--rounds N` of the command line (1 for profiling under callgrind); a
/// value that is not a whole number of at least 1 ends the run with exit 2.
fn rounds() -> u32 {
    static R: std::sync::OnceLock<u32> = std::sync::OnceLock::new();
    *R.get_or_init(|| {
        let a: Vec<String> = std::env::args().collect();
        let Some(k) = a.iter().position(|x| x == "--rounds") else {
            return ROUNDS;
        };
        match a
            .get(k + 1)
            .and_then(|v| v.parse().ok())
            .filter(|&n: &u32| n > 0)
        {
            Some(n) => n,
            None => {
                eprintln!(
                    "compare: --rounds needs a whole number of at least 1, got {:?}",
                    a.get(k + 1)
                );
                std::process::exit(2);
            }
        }
    })
}

/// One round of one harness (a closure that times one round and returns its measurement).
type Round<'a> = Box<dyn FnMut() -> Result<Meas, String> + 'a>;

/// The rounds of the table's harnesses of one stimulus, run interleaved: round 1 of every
/// harness, then round 2 of every harness, and so on. A slow phase of the shared machine then
/// falls on the neighbouring rounds of all harnesses rather than on every round of one, which
/// kept the ratios of earlier runs from repeating; the fastest round of each harness counts.
fn interleaved(mut harnesses: Vec<Result<Round<'_>, String>>) -> Vec<Result<Meas, String>> {
    let mut best: Vec<Result<Option<Meas>, String>> = harnesses
        .iter()
        .map(|h| h.as_ref().map(|_| None).map_err(String::clone))
        .collect();
    for _ in 0..rounds() {
        for (h, b) in harnesses.iter_mut().zip(best.iter_mut()) {
            let (Ok(round), Ok(kept)) = (h, &mut *b) else {
                continue;
            };
            match round() {
                Ok(m) if kept.as_ref().is_none_or(|k| m.rate() > k.rate()) => *kept = Some(m),
                Ok(_) => {}
                Err(e) => *b = Err(e),
            }
        }
    }
    best.into_iter()
        .map(|b| b.and_then(|m| m.ok_or_else(|| "no round".to_string())))
        .collect()
}

/// A round of an in-process pass: the number of replays per round is chosen first so that
/// a round takes about `seconds / rounds` CPU seconds; each round checks the checksum.
fn pass_rounds<'a>(st: &'a Stim, seconds: f64, pass: fn(&Stim) -> u64) -> Round<'a> {
    let t0 = cpu_now();
    let h = black_box(pass(st));
    let one = (cpu_now() - t0).max(1e-6);
    let reps = ((seconds / f64::from(rounds()) / one).ceil() as u64).clamp(1, 1_000_000);
    Box::new(move || {
        let t0 = cpu_now();
        let mut last = 0;
        for _ in 0..reps {
            last = black_box(pass(black_box(st)));
        }
        let cpu = cpu_now() - t0;
        if last != h {
            return Err(format!(
                "{}: a replay from reset gave checksum {last:016x}, the first {h:016x}",
                st.name
            ));
        }
        Ok(Meas {
            ticks: reps * st.inputs.len() as u64,
            cpu,
            checksum: Some(last),
            note: String::new(),
        })
    })
}

/// One harness alone, for `--quick` and `--quick-traced`: its fastest round.
fn alone(round: Round<'_>) -> Meas {
    match interleaved(vec![Ok(round)]).pop() {
        Some(Ok(m)) => m,
        Some(Err(e)) => {
            eprintln!("compare: {e}");
            std::process::exit(1);
        }
        None => unreachable!("one harness gives one result"),
    }
}

#[inline(never)]
fn pass_spec(st: &Stim) -> u64 {
    let mut m = Pmu50Spec::new(st.params).expect("legal parameters");
    st.inputs.iter().fold(0, |h, i| mix(h, &m.step(i)))
}

#[inline(never)]
fn pass_kernel(st: &Stim) -> u64 {
    let mut m = Pmu50::new(st.params).expect("legal parameters");
    st.inputs.iter().fold(0, |h, i| mix(h, &m.step(i)))
}

/// Number of signals the Rust tracer writes per tick.
const NSIG: usize = 7 + 23 + 26 + 9;

/// Every traced value of a tick, in declaration order: inputs, ports, registers (the order of
/// `Regs::values`), internals.
#[inline(always)]
fn frame_values(v: &mut [u64; NSIG], i: &Inputs, o: &Outputs, r: &Regs, x: &Internals) {
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

/// Declarations of the model's VCD (src/observers/waveform.rs) without the `env` reals.
fn declare(st: &Stim) -> (VcdBuilder, Vec<SigId>, u64) {
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

/// The body of [`pass_traced`] and [`pass_traced_vcd`]: a tracer on `$frame` opens its run on
/// `$w` with `$open` (`run` or `text_run`, whose run types differ), steps every input, then
/// moves the writer to the end of the stimulus; the checksum of the outputs.
macro_rules! traced_pass {
    ($st:expr, $w:expr, $frame:expr, $unit_ns:expr, $open:ident) => {{
        let (st, w, unit_ns): (&Stim, _, u64) = ($st, $w, $unit_ns);
        let mut tr = CoreTracer::new($frame, Pmu50::new(st.params).expect("legal parameters"))
            .expect("a frame of the 65 signals");
        let mut run = tr.$open(w).expect("the tracer's frame is this writer's");
        let h = traced_steps(st, unit_ns, |t, i| {
            *run.step(t, i)
                .expect("traced values fit their declarations")
        });
        drop(run);
        w.set_time(st.inputs.len() as u64 * (st.clock_ns / unit_ns))
            .expect("time moves forward");
        h
    }};
}

/// One traced replay into `w` through [`CoreTracer`]; returns the checksum.
#[inline(never)]
fn pass_traced<E: Emitter>(st: &Stim, w: &mut Writer<E>, frame: Frame, unit_ns: u64) -> u64 {
    traced_pass!(st, w, frame, unit_ns, run)
}

/// [`pass_traced`] for a VCD: the tracer's text run ([`CoreTracer::text_run`]), each step's
/// changed values written at once.
#[inline(never)]
fn pass_traced_vcd<W: std::io::Write>(
    st: &Stim,
    w: &mut VcdWriter<W>,
    frame: Frame,
    unit_ns: u64,
) -> u64 {
    traced_pass!(st, w, frame, unit_ns, text_run)
}

/// Every input of the stimulus through `step` (time in the VCD's units, inputs; the outputs
/// after the edge); the checksum of the outputs.
#[inline(always)]
fn traced_steps(st: &Stim, unit_ns: u64, mut step: impl FnMut(u64, &Inputs) -> Outputs) -> u64 {
    let dt = st.clock_ns / unit_ns;
    st.inputs
        .iter()
        .enumerate()
        .fold(0, |h, (k, i)| mix(h, &step(k as u64 * dt, i)))
}

/// The VCD of every value of every tick through `Writer::dump_frame`, which [`CoreTracer`] must
/// write byte for byte.
fn vcd_every_value(st: &Stim) -> Vec<u8> {
    let (b, ids, unit_ns) = declare(st);
    let mut w = b.start(Vec::new()).expect("VCD header");
    let mut f = w.frame(&ids).unwrap();
    let mut m = Pmu50::new(st.params).expect("legal parameters");
    let mut vals = [0u64; NSIG];
    let dt = st.clock_ns / unit_ns;
    for (k, i) in st.inputs.iter().enumerate() {
        let regs = *m.regs();
        let pmu50_core::TracedStep {
            before,
            internals: x,
            ..
        } = m.step_traced(i);
        frame_values(&mut vals, i, &before, &regs, &x);
        w.dump_frame(&mut f, k as u64 * dt, &vals)
            .expect("traced values fit their declarations");
    }
    w.set_time(st.inputs.len() as u64 * dt)
        .expect("time moves forward");
    w.finish().expect("VCD written")
}

/// The tracer's VCD is the one of every value through `dump_frame`; returns the length of its
/// body (the bytes after the header, which every VCD harness writes).
fn check_tracer(st: &Stim) -> usize {
    let (b, ids, unit_ns) = declare(st);
    let mut w = b.start(Vec::new()).expect("VCD header");
    let f = w.frame(&ids).unwrap();
    pass_traced_vcd(st, &mut w, f, unit_ns);
    let vcd = w.finish().expect("VCD written");
    assert!(
        vcd == vcd_every_value(st),
        "{}: the CoreTracer VCD differs from dump_frame's with every value",
        st.name
    );
    let end = b"$enddefinitions $end\n";
    let header = vcd
        .windows(end.len())
        .position(|w| w == end)
        .expect("a VCD header")
        + end.len();
    vcd.len() - header
}

/// [`pass_traced`] into a VCD writer whose text is thrown away ([`std::io::sink`]).
#[inline(never)]
fn pass_sink(st: &Stim) -> u64 {
    let (b, ids, unit_ns) = declare(st);
    let mut w = b.start(std::io::sink()).expect("VCD header");
    let f = w.frame(&ids).unwrap();
    let h = pass_traced_vcd(st, &mut w, f, unit_ns);
    w.finish().expect("VCD written");
    h
}

/// The traced edges of [`pass_traced`] without a writer.
#[inline(never)]
fn pass_edge_only(st: &Stim) -> u64 {
    let mut m = Pmu50::new(st.params).expect("legal parameters");
    let mut h = 0;
    for i in &st.inputs {
        let regs = *m.regs();
        let pmu50_core::TracedStep {
            before,
            internals: x,
            after,
            ..
        } = m.step_traced(i);
        black_box((&regs, &before, &x));
        h = mix(h, &after);
    }
    h
}

fn check_frame_order(st: &Stim) {
    // The hand-written frame order is the order of the declarations (Regs::values and friends).
    let s = Structural {
        sync_depth: st.params.sync_depth,
        cnt_width: st.params.cnt_width,
    };
    let mut m = Pmu50::new(st.params).unwrap();
    for i in st.inputs.iter().take(5000) {
        let regs = *m.regs();
        let pmu50_core::TracedStep {
            before,
            internals: x,
            ..
        } = m.step_traced(i);
        let mut v = [0u64; NSIG];
        frame_values(&mut v, i, &before, &regs, &x);
        let want: Vec<u64> = i
            .values()
            .iter()
            .map(|t| t.2)
            .chain(before.values(&s).iter().map(|t| t.2))
            .chain(regs.values(&s).iter().map(|r| r.value))
            .chain(x.values().iter().map(|t| t.2))
            .collect();
        assert_eq!(
            v.to_vec(),
            want,
            "frame_values order differs from the declarations"
        );
    }
}

/// Where a traced harness writes its waveform.
#[derive(Clone, Copy, PartialEq)]
enum Sink {
    /// a file in the bench directory (removed after the last round)
    File,
    /// `/dev/null`: the same writes, which the kernel throws away (no page cache): the
    /// tracer's own cost, without the disk's
    Null,
}

fn traced_once(st: &Stim, dir: &Path, fst: bool, sink: Sink) -> Meas {
    let (b, ids, unit_ns) = declare(st);
    let path = match sink {
        Sink::File => dir.join(format!(
            "rust_{}.{}",
            st.name,
            if fst { "fst" } else { "vcd" }
        )),
        Sink::Null => PathBuf::from("/dev/null"),
    };
    // The clock starts after the file is created and the header written, and stops after the
    // last byte is written, as in hdl/bench/bench.cpp (`tfp->open` before `t0`, `tfp->close`
    // before `t1`).
    let (h, cpu) = if fst {
        let mut w = start_fst(b, &path).expect("FST file");
        let f = w.frame(&ids).unwrap();
        let t0 = cpu_now();
        let h = pass_traced(st, &mut w, f, unit_ns);
        w.finish().expect("FST written");
        (h, cpu_now() - t0)
    } else {
        // (create and truncate leave /dev/null as it is)
        let file = std::fs::OpenOptions::new()
            .write(true)
            .create(true)
            .truncate(true)
            .open(&path)
            .expect("VCD file");
        let mut w = b.start(file).expect("VCD header");
        let f = w.frame(&ids).unwrap();
        let t0 = cpu_now();
        let h = pass_traced_vcd(st, &mut w, f, unit_ns);
        w.finish().expect("VCD written");
        (h, cpu_now() - t0)
    };
    let note = match sink {
        Sink::File => {
            let bytes = std::fs::metadata(&path).map(|m| m.len()).unwrap_or(0);
            if std::env::var_os("PMU50_BENCH_KEEP").is_none() {
                let _ = std::fs::remove_file(&path);
            }
            format!("{NSIG} signals, {}", fmt_bytes(bytes))
        }
        Sink::Null => format!("{NSIG} signals"),
    };
    Meas {
        ticks: st.inputs.len() as u64,
        cpu,
        checksum: Some(h),
        note,
    }
}

/// Run a harness binary that prints `ticks=N cpu_s=S checksum=H`.
fn external(bin: &Path, args: &[String]) -> Result<Meas, String> {
    let out = Command::new(bin)
        .args(args)
        .output()
        .map_err(|e| format!("{}: {e}", bin.display()))?;
    let text = String::from_utf8_lossy(&out.stdout).to_string();
    if !out.status.success() {
        return Err(format!(
            "{} failed: {}{}",
            bin.display(),
            text,
            String::from_utf8_lossy(&out.stderr)
        ));
    }
    let field = |k: &str| {
        text.split_whitespace()
            .find_map(|w| w.strip_prefix(k))
            .map(str::to_string)
            .ok_or_else(|| format!("{}: no `{k}` in `{text}`", bin.display()))
    };
    Ok(Meas {
        ticks: field("ticks=")?.parse().map_err(|e| format!("{e}"))?,
        cpu: field("cpu_s=")?.parse().map_err(|e| format!("{e}"))?,
        checksum: Some(u64::from_str_radix(&field("checksum=")?, 16).map_err(|e| format!("{e}"))?),
        note: String::new(),
    })
}

/// Rounds of the Verilator harness, untraced (`reps` replays per round, chosen from one replay)
/// or with `--trace` (one replay per round into a VCD; the note, from the last round's VCD,
/// counts its `$var`s against the Rust tracer's signals).
fn verilator<'a>(
    st: &'a Stim,
    dir: &Path,
    seconds: f64,
    trace: Option<Sink>,
) -> Result<Round<'a>, String> {
    let bin = dir.join(format!(
        "{}_{}/bench",
        if trace.is_some() { "vlt" } else { "vl" },
        st.name
    ));
    let vec = st.vec.display().to_string();
    if trace == Some(Sink::Null) {
        return Ok(Box::new(move || {
            external(
                &bin,
                &[
                    vec.clone(),
                    "1".into(),
                    "--trace".into(),
                    "/dev/null".into(),
                ],
            )
        }));
    }
    if trace.is_some() {
        let vcd = dir.join(format!("verilator_{}.vcd", st.name));
        let mut left = rounds();
        let mut note: Option<String> = None;
        return Ok(Box::new(move || {
            let mut m = external(
                &bin,
                &[
                    vec.clone(),
                    "1".into(),
                    "--trace".into(),
                    vcd.display().to_string(),
                ],
            )?;
            let n = note.get_or_insert_with(|| {
                let bytes = std::fs::metadata(&vcd).map(|m| m.len()).unwrap_or(0);
                let twin = std::fs::read(&vcd)
                    .map(|b| var_paths(&b))
                    .unwrap_or_default();
                format!("{}, {}", same_signals(st, &twin), fmt_bytes(bytes))
            });
            m.note = n.clone();
            left -= 1;
            if left == 0 {
                let _ = std::fs::remove_file(&vcd);
            }
            Ok(m)
        }));
    }
    let one = external(&bin, &[vec.clone(), "1".into()])?;
    let reps =
        ((seconds / f64::from(rounds()) / one.cpu.max(1e-6)).ceil() as u64).clamp(1, 100_000);
    Ok(Box::new(move || {
        external(&bin, &[vec.clone(), reps.to_string()])
    }))
}

/// Rounds of the Verilator harness built with every variable traced (`DIR/vla_NAME/bench`,
/// `hdl/bench/build.sh --trace-all`: the 371 `$var`s of `verilator --trace` without a
/// configuration file), one replay per round into a VCD.
fn verilator_all<'a>(st: &'a Stim, dir: &Path) -> Result<Round<'a>, String> {
    let bin = dir.join(format!("vla_{}/bench", st.name));
    let vec = st.vec.display().to_string();
    let vcd = dir.join(format!("verilator_all_{}.vcd", st.name));
    let mut left = rounds();
    let mut note: Option<String> = None;
    Ok(Box::new(move || {
        let mut m = external(
            &bin,
            &[
                vec.clone(),
                "1".into(),
                "--trace".into(),
                vcd.display().to_string(),
            ],
        )?;
        let n = note.get_or_insert_with(|| {
            let bytes = std::fs::metadata(&vcd).map(|m| m.len()).unwrap_or(0);
            let vars = std::fs::read(&vcd)
                .map(|b| var_paths(&b).len())
                .unwrap_or(0);
            format!("{vars} $var lines, {}", fmt_bytes(bytes))
        });
        m.note = n.clone();
        left -= 1;
        if left == 0 {
            let _ = std::fs::remove_file(&vcd);
        }
        Ok(m)
    }))
}

/// The scenario of a stimulus: `DIR/NAME.toml` (a seeded random one, written by
/// benches/compare.sh), else `scenarios/NAME.toml`.
fn scenario_of(st: &Stim, dir: &Path) -> PathBuf {
    let own = dir.join(format!("{}.toml", st.name));
    if own.exists() {
        own
    } else {
        Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("scenarios")
            .join(format!("{}.toml", st.name))
    }
}

/// Rounds of `pmu50 run SCENARIO --trace all` as a user runs it (`target/release/pmu50`, built
/// by benches/compare.sh): the whole child process's CPU time (start, scenario, environment
/// models, the VCD of every signal with the analog reals, its .gtkw), for the stimulus's ticks.
fn pmu50_run<'a>(st: &'a Stim, dir: &Path) -> Result<Round<'a>, String> {
    let bin = Path::new(env!("CARGO_MANIFEST_DIR")).join("target/release/pmu50");
    let sc = scenario_of(st, dir);
    let out = dir.join("pmu50_run");
    let vcd = out.join(format!("{}.vcd", st.name));
    let mut note: Option<String> = None;
    Ok(Box::new(move || {
        let (c0, _) = rusage(libc::RUSAGE_CHILDREN);
        let o = Command::new(&bin)
            .arg("run")
            .arg(&sc)
            .arg("--out-dir")
            .arg(&out)
            .args(["--trace", "all"])
            .output()
            .map_err(|e| format!("{}: {e}", bin.display()))?;
        let (c1, _) = rusage(libc::RUSAGE_CHILDREN);
        if !o.status.success() {
            return Err(format!(
                "pmu50 run {} failed: {}",
                sc.display(),
                String::from_utf8_lossy(&o.stderr)
            ));
        }
        let n = note.get_or_insert_with(|| {
            let bytes = std::fs::metadata(&vcd).map(|m| m.len()).unwrap_or(0);
            let vars = std::fs::read(&vcd)
                .map(|b| var_paths(&b).len())
                .unwrap_or(0);
            format!(
                "whole process; {vars} $var lines with the env reals, {}",
                fmt_bytes(bytes)
            )
        });
        Ok(Meas {
            ticks: st.inputs.len() as u64,
            cpu: c1 - c0,
            checksum: None,
            note: n.clone(),
        })
    }))
}

/// Full dotted paths of the `$var`s of a VCD header, one per `$var` line, in file order.
fn var_paths(vcd: &[u8]) -> Vec<String> {
    let mut scopes: Vec<String> = Vec::new();
    let mut paths = Vec::new();
    for line in String::from_utf8_lossy(vcd).lines() {
        let t: Vec<&str> = line.split_whitespace().collect();
        match t.first().copied() {
            Some("$scope") if t.len() > 2 => scopes.push(t[2].to_string()),
            Some("$upscope") => {
                scopes.pop();
            }
            Some("$var") if t.len() > 4 => paths.push(
                scopes
                    .iter()
                    .map(String::as_str)
                    .chain([t[4]])
                    .collect::<Vec<_>>()
                    .join("."),
            ),
            Some("$enddefinitions") => break,
            _ => {}
        }
    }
    paths
}

/// Note of the Verilator --trace row: how many `$var` lines the twin dumps and whether they are
/// the counterparts of the Rust tracer's signals (the twin module's `X`, `pmu50.pmu50.X` under
/// the harness's top name, for the model's `pmu50.X`; hdl/bench/trace.vlt), naming the tracer's
/// signals without a counterpart and the twin's extra ones.
fn same_signals(st: &Stim, twin: &[String]) -> String {
    let (b, _, _) = declare(st);
    let rust = b
        .start(Vec::new())
        .and_then(|w| w.finish())
        .map(|v| var_paths(&v))
        .unwrap_or_default();
    let mapped: Vec<String> = twin
        .iter()
        .map(|p| {
            p.strip_prefix("pmu50.pmu50.")
                .map_or_else(|| format!("(twin) {p}"), |r| format!("pmu50.{r}"))
        })
        .collect();
    let missing: Vec<&str> = rust
        .iter()
        .filter(|p| !mapped.contains(p))
        .map(String::as_str)
        .collect();
    let extra = mapped.iter().filter(|p| !rust.contains(p)).count();
    let mut note = format!("{} $var lines", twin.len());
    if missing.is_empty() && extra == 0 && twin.len() == rust.len() {
        note += &format!(
            ", the counterparts of the Rust tracer's {} signals",
            rust.len()
        );
    } else {
        note += &format!(" for the Rust tracer's {}", rust.len());
        if !missing.is_empty() {
            note += &format!(
                ", {} without counterpart: {}",
                missing.len(),
                missing.join(" ")
            );
        }
        if extra > 0 {
            note += &format!(", {extra} not in the Rust tracer");
        }
    }
    note
}

fn icarus(st: &Stim, dir: &Path) -> Result<Meas, String> {
    let vvp = dir.join(format!("iv_{}.vvp", st.name));
    let (c0, _) = rusage(libc::RUSAGE_CHILDREN);
    let out = Command::new("vvp")
        .arg("-n")
        .arg(&vvp)
        .arg(format!("+vec={}", st.vec.display()))
        .output()
        .map_err(|e| format!("vvp: {e}"))?;
    let (c1, _) = rusage(libc::RUSAGE_CHILDREN);
    let text = String::from_utf8_lossy(&out.stdout);
    if !text.lines().any(|l| l.starts_with("PASS ticks=")) {
        return Err(format!(
            "Icarus replay of {} did not pass: {}",
            st.vec.display(),
            text.lines().take(5).collect::<Vec<_>>().join(" / ")
        ));
    }
    Ok(Meas {
        ticks: st.inputs.len() as u64,
        cpu: c1 - c0,
        checksum: None,
        note: "outputs == vector file".into(),
    })
}

/// Child process: a parked car for `secs` seconds through the simulator with fast-forward, or
/// (`secs` = 0) the scenario file `file`.
fn park_child(secs: u64, file: Option<&str>) {
    let sc = match file {
        Some(f) => Scenario::load(Path::new(f)).unwrap_or_else(|e| panic!("{e}")),
        None => {
            let text = format!(
                "name = \"park_{secs}s\"\ndescription = \"parked: key off, motor still\"\nduration = \"{secs} s\"\n\n[motor]\nstart_deg = 37.0\nsegments = [ {{ kind = \"hold\", duration = \"{secs} s\" }} ]\n"
            );
            Scenario::parse(&text, "park.toml", "park", Path::new("park.toml"))
                .unwrap_or_else(|e| panic!("{e}"))
        }
    };
    let t0 = cpu_now();
    let r = run(&sc, SimOptions { fast_forward: true }, &mut []).unwrap_or_else(|e| panic!("{e}"));
    let cpu = cpu_now() - t0;
    let (_, rss) = rusage(libc::RUSAGE_SELF);
    println!(
        "park cpu_s={cpu:.9} maxrss_kib={rss} ticks={} evaluated={} pulses={}",
        r.ticks,
        r.evaluated_ticks,
        r.pulses.len()
    );
}

/// (CPU seconds, peak MiB, ticks, evaluated ticks) of a park child.
fn park(args: &[&str]) -> Result<(f64, f64, f64, f64), String> {
    let exe = std::env::current_exe().map_err(|e| e.to_string())?;
    let out = Command::new(exe)
        .arg("--park-child")
        .args(args)
        .output()
        .map_err(|e| e.to_string())?;
    let text = String::from_utf8_lossy(&out.stdout).to_string();
    if !out.status.success() {
        return Err(format!(
            "park {args:?} failed: {text}{}",
            String::from_utf8_lossy(&out.stderr)
        ));
    }
    let field = |k: &str| {
        text.split_whitespace()
            .find_map(|w| w.strip_prefix(k))
            .and_then(|v| v.parse::<f64>().ok())
            .ok_or_else(|| format!("park: no `{k}` in `{text}`"))
    };
    Ok((
        field("cpu_s=")?,
        field("maxrss_kib=")? / 1024.0,
        field("ticks=")?,
        field("evaluated=")?,
    ))
}

fn fmt_bytes(b: u64) -> String {
    if b >= 1_000_000 {
        format!("{:.1} MB", b as f64 / 1e6)
    } else {
        format!("{:.0} kB", b as f64 / 1e3)
    }
}

fn fmt_rate(r: f64) -> String {
    if r >= 1e6 {
        format!("{:.1} M", r / 1e6)
    } else {
        format!("{:.0} k", r / 1e3)
    }
}

/// One whole process of the wall-time table: its wall time and CPU time (user + system, every
/// thread), in seconds, and what it printed.
#[derive(Clone, Debug)]
struct Proc {
    wall: f64,
    cpu: f64,
    stdout: String,
}

/// Run `cmd` to its end, timed.
fn timed(cmd: &mut Command) -> Result<Proc, String> {
    let (c0, _) = rusage(libc::RUSAGE_CHILDREN);
    let t0 = Instant::now();
    let o = cmd.output().map_err(|e| format!("{cmd:?}: {e}"))?;
    let wall = t0.elapsed().as_secs_f64();
    let (c1, _) = rusage(libc::RUSAGE_CHILDREN);
    if !o.status.success() {
        return Err(format!(
            "{cmd:?} failed: {}{}",
            String::from_utf8_lossy(&o.stdout),
            String::from_utf8_lossy(&o.stderr)
        ));
    }
    Ok(Proc {
        wall,
        cpu: c1 - c0,
        stdout: String::from_utf8_lossy(&o.stdout).into_owned(),
    })
}

/// [`timed`], but a process still running after `limit` seconds is killed (`Ok(None)`): a
/// Verilator model on two threads waits for its other thread by spinning, which on a machine
/// busy with other work can take minutes instead of milliseconds.
fn timed_within(cmd: &mut Command, limit: f64) -> Result<Option<Proc>, String> {
    use std::io::Read;
    let (c0, _) = rusage(libc::RUSAGE_CHILDREN);
    let t0 = Instant::now();
    let mut child = cmd
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::null())
        .spawn()
        .map_err(|e| format!("{cmd:?}: {e}"))?;
    let status = loop {
        if let Some(st) = child.try_wait().map_err(|e| format!("{cmd:?}: {e}"))? {
            break st;
        }
        if t0.elapsed().as_secs_f64() > limit {
            let _ = child.kill();
            let _ = child.wait();
            return Ok(None);
        }
        std::thread::sleep(std::time::Duration::from_micros(200));
    };
    let wall = t0.elapsed().as_secs_f64();
    let (c1, _) = rusage(libc::RUSAGE_CHILDREN);
    let mut stdout = String::new();
    if let Some(mut o) = child.stdout.take() {
        let _ = o.read_to_string(&mut stdout);
    }
    if !status.success() {
        return Err(format!("{cmd:?} failed: {stdout}"));
    }
    Ok(Some(Proc {
        wall,
        cpu: c1 - c0,
        stdout,
    }))
}

/// The rows of the wall-time table (see the module documentation).
const WALL_ROWS: [&str; 6] = [
    "pmu50 run --trace all, writer thread",
    "pmu50 run --trace all, one thread (PMU50_WRITER_THREAD=0)",
    "Verilator -O3 --trace, every variable",
    "Verilator -O3 --trace --threads 2, every variable",
    "pmu50 run --trace all, writer thread, into /dev/shm",
    "pmu50 run --trace all, writer thread, no flush (PMU50_SYNC=0)",
];

/// The harness directory of each Verilator row of [`WALL_ROWS`] (benches/verilator_threads.sh).
const WALL_VERILATOR: [&str; 2] = ["vlw1", "vlw2"];

/// The wall-time table of the stimuli and its ratio lines.
fn wall_table(stims: &[Stim], dir: &Path) -> Result<String, String> {
    let bin = Path::new(env!("CARGO_MANIFEST_DIR")).join("target/release/pmu50");
    let mut out = format!(
        "\nwall time, whole processes side by side, fastest of {} interleaved rounds; CPU: that round's user + system time, every thread; loop: Verilator's replay loop alone by the wall clock (file opened to file closed); ratio = Verilator's best traced whole process / this row's wall time; machine: {} CPUs, load average {} at the start\n\n",
        rounds(),
        std::thread::available_parallelism().map_or(0, |n| n.get()),
        std::fs::read_to_string("/proc/loadavg").unwrap_or_default().split_whitespace().take(3).collect::<Vec<_>>().join(" ")
    );
    let w0 = WALL_ROWS.iter().map(|l| l.len()).max().unwrap_or(0);
    out += &format!("| {:w0$} |", "harness");
    for st in stims {
        out += &format!(" {} wall | CPU | loop | ratio |", st.name);
    }
    out += "\n";
    out += &format!("|{}|", "-".repeat(w0 + 2));
    for _ in stims {
        out += "---:|---:|---:|---:|";
    }
    out += "\n";
    let mut cells: Vec<Vec<Option<Proc>>> = vec![Vec::new(); WALL_ROWS.len()];
    let mut lines = Vec::new();
    // the replay loop's wall time a Verilator harness printed
    let loop_s = |p: &Proc| {
        p.stdout
            .split_whitespace()
            .find_map(|w| w.strip_prefix("cpu_s="))
            .and_then(|v| v.parse::<f64>().ok())
    };
    for st in stims {
        let sc = scenario_of(st, dir);
        let vec = st.vec.display().to_string();
        let outd = dir.join("pmu50_wall");
        let vcd = dir.join(format!("verilator_wall_{}.vcd", st.name));
        let run_as = |thread: &str, sync: &str| -> Result<Option<Proc>, String> {
            timed(
                Command::new(&bin)
                    .arg("run")
                    .arg(&sc)
                    .arg("--out-dir")
                    .arg(&outd)
                    .args(["--trace", "all"])
                    .env("PMU50_WRITER_THREAD", thread)
                    .env("PMU50_SYNC", sync),
            )
            .map(Some)
        };
        let run = |thread: &str| run_as(thread, "1");
        // a harness that ran out of time once (more than 20 times the single-threaded one's
        // wall time, at least 2 s) is not run again
        let mut gave_up = [false; 2];
        let mut vl = |j: usize, limit: f64| -> Result<Option<Proc>, String> {
            let b = dir.join(format!("{}_{}/bench", WALL_VERILATOR[j], st.name));
            if !b.exists() || gave_up[j] {
                return Ok(None);
            }
            let p = timed_within(
                Command::new(&b).arg(&vec).arg("1").arg("--trace").arg(&vcd),
                limit,
            )?;
            gave_up[j] = p.is_none();
            Ok(p)
        };
        // the same run into memory (tmpfs): without the disk's share of syncing and renaming
        let shm = Path::new("/dev/shm")
            .is_dir()
            .then(|| Path::new("/dev/shm").join(format!("pmu50_wall_{}", std::process::id())));
        let run_shm = || -> Result<Option<Proc>, String> {
            let Some(d) = shm.as_ref() else {
                return Ok(None);
            };
            timed(
                Command::new(&bin)
                    .arg("run")
                    .arg(&sc)
                    .arg("--out-dir")
                    .arg(d)
                    .args(["--trace", "all"])
                    .env("PMU50_WRITER_THREAD", "1")
                    .env("PMU50_SYNC", "1"),
            )
            .map(Some)
        };
        let mut best: Vec<Option<Proc>> = vec![None; WALL_ROWS.len()];
        for _ in 0..rounds() {
            let one = vl(0, 60.0)?;
            let limit = one.as_ref().map_or(60.0, |p| (20.0 * p.wall).max(2.0));
            let round = [
                run("1")?,
                run("0")?,
                one,
                vl(1, limit)?,
                run_shm()?,
                run_as("1", "0")?,
            ];
            for (b, p) in best.iter_mut().zip(round) {
                if let Some(p) = p {
                    if b.as_ref().is_none_or(|b| p.wall < b.wall) {
                        *b = Some(p);
                    }
                }
            }
        }
        let _ = std::fs::remove_file(&vcd);
        if let Some(d) = shm.as_ref() {
            let _ = std::fs::remove_dir_all(d);
        }
        for (j, g) in gave_up.iter().enumerate() {
            if *g {
                lines.push(format!("{}: {} stopped: it ran 20 times as long as the single-threaded build (at least 2 s), its threads spinning for each other on the busy machine", st.name, WALL_ROWS[2 + j]));
            }
        }
        // Verilator's best traced run
        let (vrow, vbest) = best[2..4]
            .iter()
            .enumerate()
            .filter_map(|(j, p)| p.as_ref().map(|p| (j + 2, p.clone())))
            .min_by(|a, b| a.1.wall.total_cmp(&b.1.wall))
            .ok_or_else(|| format!("{}: no Verilator harness of the wall-time table (DIR/vlw1_{}/bench: benches/verilator_threads.sh)", st.name, st.name))?;
        let best_loop = best[2..4]
            .iter()
            .flatten()
            .filter_map(loop_s)
            .fold(f64::INFINITY, f64::min);
        if let (Some(r), Some(one)) = (&best[0], &best[1]) {
            lines.push(format!(
                "{}: pmu50 run --trace all {:.1} ms wall ({:.1} ms CPU), {:.2}x Verilator's best traced run ({}: {:.1} ms wall, {:.1} ms CPU), {:.2}x Verilator's fastest replay loop alone ({:.1} ms wall); one thread {:.1} ms wall ({:.1} ms CPU), {:.2}x and {:.2}x",
                st.name,
                r.wall * 1e3,
                r.cpu * 1e3,
                vbest.wall / r.wall,
                WALL_ROWS[vrow],
                vbest.wall * 1e3,
                vbest.cpu * 1e3,
                best_loop / r.wall,
                best_loop * 1e3,
                one.wall * 1e3,
                one.cpu * 1e3,
                vbest.wall / one.wall,
                best_loop / one.wall
            ));
        }
        if let Some(n) = &best[5] {
            lines.push(format!(
                "{}: without the flush to the disk before the renames (PMU50_SYNC=0, writer thread) {:.1} ms wall ({:.1} ms CPU), {:.2}x Verilator's best traced run",
                st.name,
                n.wall * 1e3,
                n.cpu * 1e3,
                vbest.wall / n.wall
            ));
        }
        for (row, b) in cells.iter_mut().zip(best) {
            row.push(b);
        }
    }
    for (r, label) in WALL_ROWS.iter().enumerate() {
        out += &format!("| {label:w0$} |");
        for j in 0..stims.len() {
            match &cells[r][j] {
                Some(p) => {
                    let vref = cells[2..4]
                        .iter()
                        .filter_map(|row| row[j].as_ref().map(|p| p.wall))
                        .fold(f64::INFINITY, f64::min);
                    let lp = if (2..4).contains(&r) {
                        loop_s(p).map_or("-".into(), |l| format!("{:.1} ms", l * 1e3))
                    } else {
                        "-".to_string()
                    };
                    out += &format!(
                        " {:.1} ms | {:.1} ms | {lp} | {:.2}x |",
                        p.wall * 1e3,
                        p.cpu * 1e3,
                        vref / p.wall
                    );
                }
                None => out += " - | - | - | - |",
            }
        }
        out += "\n";
    }
    out += "\n";
    for l in lines {
        out += &l;
        out += "\n";
    }
    Ok(out)
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    if let Some(k) = args.iter().position(|a| a == "--park-child") {
        match args.get(k + 1).map(String::as_str) {
            Some("--file") => park_child(0, args.get(k + 2).map(String::as_str)),
            a => park_child(
                a.and_then(|s| s.parse().ok())
                    .expect("--park-child SECONDS | --file PATH"),
                None,
            ),
        }
        return;
    }
    let mut dir = PathBuf::from("hdl/build/bench");
    let mut stims = Vec::new();
    let mut iv = Vec::new();
    let mut seconds = 1.0;
    let mut quick = false;
    let mut k = 1;
    while k < args.len() {
        match args[k].as_str() {
            "--dir" => {
                dir = PathBuf::from(&args[k + 1]);
                k += 1;
            }
            "--stim" => {
                stims.push(args[k + 1].clone());
                k += 1;
            }
            "--icarus" => {
                iv.push(args[k + 1].clone());
                k += 1;
            }
            "--seconds" => {
                seconds = args[k + 1].parse().expect("--seconds S");
                k += 1;
            }
            "--quick" => quick = true,
            _ => {} // `--bench` from cargo
        }
        k += 1;
    }
    if stims.is_empty() {
        eprintln!("compare: no --stim given (run benches/compare.sh, or make bench)");
        std::process::exit(2);
    }
    let stims: Vec<Stim> = match stims.iter().map(|n| load(&dir, n)).collect() {
        Ok(s) => s,
        Err(e) => {
            eprintln!("compare: {e}");
            std::process::exit(2);
        }
    };
    if args.iter().any(|a| a == "--quick-vcd") {
        // Only the Rust tracer's VCD into a file (for tuning it, under perf): how many of the
        // stimulus's edges are wide, then the best of `--rounds` replays.
        for st in &stims {
            check_tracer(st);
            let mut m = Pmu50::new(st.params).expect("legal parameters");
            let (mut wide, mut narrow_upd) = (0, 0);
            for i in &st.inputs {
                let pmu50_core::TracedStep {
                    internals: x,
                    wide: w,
                    ..
                } = m.step_traced(i);
                wide += u32::from(w);
                narrow_upd += u32::from(!w && x.upd);
            }
            let v = alone(Box::new(|| Ok(traced_once(st, &dir, false, Sink::File))));
            println!("{}: tracer VCD {} ({:.1} ns a tick; {} ticks, {wide} wide edges, {narrow_upd} narrow with a sample; checksum {:016x})", st.name, fmt_rate(v.rate()), 1e9 / v.rate(), st.inputs.len(), v.checksum.unwrap_or(0));
        }
        return;
    }
    if args.iter().any(|a| a == "--quick-wall") {
        match wall_table(&stims, &dir) {
            Ok(t) => println!("{t}"),
            Err(e) => {
                eprintln!("compare: {e}");
                std::process::exit(1);
            }
        }
        return;
    }
    if args.iter().any(|a| a == "--quick-run") {
        // Only pmu50 run --trace all and the two Verilator --trace harnesses it is quoted against.
        for st in &stims {
            let dir = &dir;
            let m = interleaved(vec![
                pmu50_run(st, dir),
                verilator_all(st, dir),
                verilator(st, dir, seconds, Some(Sink::File)),
            ]);
            match (&m[0], &m[1], &m[2]) {
                (Ok(r), Ok(a), Ok(t)) => println!(
                    "{}: pmu50 run --trace all {:.1} ns a tick ({:.2} ms), Verilator --trace of every variable {:.1} ns ({:.2}x), of the same signals {:.1} ns ({:.2}x)",
                    st.name,
                    1e9 / r.rate(),
                    r.cpu * 1e3,
                    1e9 / a.rate(),
                    r.rate() / a.rate(),
                    1e9 / t.rate(),
                    r.rate() / t.rate()
                ),
                _ => {
                    for e in m.iter().filter_map(|x| x.as_ref().err()) {
                        eprintln!("compare: {e}");
                    }
                    std::process::exit(1);
                }
            }
        }
        return;
    }
    if args.iter().any(|a| a == "--quick-traced") {
        // Only the Rust tracer (for tuning it): ticks per CPU-second, VCD and FST.
        for st in &stims {
            check_tracer(st);
            // the parts of a traced tick: the traced edge alone, then with the VCD text thrown away
            let edge = alone(pass_rounds(st, seconds / 2.0, pass_edge_only));
            let sink = alone(pass_rounds(st, seconds / 2.0, pass_sink));
            println!(
                "{}: traced edge only {}, tracer VCD to io::sink {}",
                st.name,
                fmt_rate(edge.rate()),
                fmt_rate(sink.rate())
            );
            let v = alone(Box::new(|| Ok(traced_once(st, &dir, false, Sink::File))));
            let f = alone(Box::new(|| Ok(traced_once(st, &dir, true, Sink::File))));
            println!(
                "{}: tracer VCD {} FST {} ({}; {}; checksum {:016x})",
                st.name,
                fmt_rate(v.rate()),
                fmt_rate(f.rate()),
                v.note,
                f.note,
                v.checksum.unwrap_or(0)
            );
        }
        return;
    }
    if quick {
        // Only the two Rust models (for tuning the kernel): ticks per CPU-second.
        for st in &stims {
            let a = alone(pass_rounds(st, seconds, pass_spec));
            let b = alone(pass_rounds(st, seconds, pass_kernel));
            println!(
                "{}: spec {} kernel {} ({:.2}x; checksums {:016x} {:016x})",
                st.name,
                fmt_rate(a.rate()),
                fmt_rate(b.rate()),
                b.rate() / a.rate(),
                a.checksum.unwrap_or(0),
                b.checksum.unwrap_or(0)
            );
        }
        return;
    }
    let labels = [
        "readable model (Pmu50Spec, per-block eval)",
        "fast kernel (Pmu50::step, kernel.rs)",
        "Verilator -O3",
        "Verilator -O3 --trace (VCD)",
        "Rust tracer VCD (CoreTracer + pmu50_waves)",
        "Rust tracer FST (CoreTracer + pmu50_waves)",
        "Verilator -O3 --trace, VCD to /dev/null",
        "Rust tracer VCD to /dev/null",
        "Verilator -O3 --trace, every variable (VCD)",
        "pmu50 run --trace all (VCD)",
        "Icarus Verilog (vvp), for scale",
    ];
    // the row each ratio is taken against: Verilator -O3, Verilator --trace to a file, to
    // /dev/null, every variable (pmu50 run: the same signals' ratio follows the table)
    let base = [2, 2, 2, 3, 3, 3, 6, 6, 8, 8, 2];
    let (row_all, row_run, row_icarus) = (8, 9, 10);
    let mut table: Vec<Vec<Result<Meas, String>>> = vec![Vec::new(); labels.len()];
    // bytes of VCD body per tick of each stimulus (the tracer's and Verilator's)
    let mut vcd_bytes = Vec::new();
    for st in &stims {
        eprintln!("compare: {} ({} ticks)", st.name, st.inputs.len());
        check_frame_order(st);
        let body = check_tracer(st);
        vcd_bytes.push(body as f64 / st.inputs.len() as f64);
        let dir = &dir;
        let harnesses: Vec<Result<Round<'_>, String>> = vec![
            Ok(pass_rounds(st, seconds, pass_spec)),
            Ok(pass_rounds(st, seconds, pass_kernel)),
            verilator(st, dir, seconds, None),
            verilator(st, dir, seconds, Some(Sink::File)),
            Ok(Box::new(move || {
                Ok(traced_once(st, dir, false, Sink::File))
            })),
            Ok(Box::new(move || Ok(traced_once(st, dir, true, Sink::File)))),
            verilator(st, dir, seconds, Some(Sink::Null)),
            Ok(Box::new(move || {
                Ok(traced_once(st, dir, false, Sink::Null))
            })),
            verilator_all(st, dir),
            pmu50_run(st, dir),
        ];
        for (row, m) in table.iter_mut().zip(interleaved(harnesses)) {
            row.push(m);
        }
        table[row_icarus].push(if iv.contains(&st.name) {
            icarus(st, dir)
        } else {
            Err("not run (slow; see --icarus)".into())
        });
    }

    // Checksums: every harness of a stimulus must agree.
    let mut ok = true;
    let mut sums = Vec::new();
    for (j, st) in stims.iter().enumerate() {
        let all: Vec<u64> = table
            .iter()
            .filter_map(|row| row[j].as_ref().ok().and_then(|m| m.checksum))
            .collect();
        let same = all.windows(2).all(|w| w[0] == w[1]);
        ok &= same && table[2][j].is_ok();
        sums.push(format!(
            "{}: {} ({} harnesses {})",
            st.name,
            all.first().map_or("-".into(), |h| format!("{h:016x}")),
            all.len(),
            if same { "equal" } else { "DIFFER" }
        ));
    }

    let w0 = labels.iter().map(|l| l.len()).max().unwrap_or(0);
    let mut out = String::new();
    out += "ticks per CPU-second, same stimulus held in memory, measured in this run; ratio = this row / Verilator -O3 (untraced rows), / Verilator -O3 --trace (traced rows, VCD and FST to a file), / Verilator -O3 --trace to /dev/null (the rows to /dev/null: the same writes, without the page cache)\n\n";
    out += &format!("| {:w0$} |", "harness");
    for st in &stims {
        out += &format!(" {} ({} ticks) | ratio |", st.name, st.inputs.len());
    }
    out += " notes |\n";
    out += &format!("|{}|", "-".repeat(w0 + 2));
    for _ in &stims {
        out += "---:|---:|";
    }
    out += "---|\n";
    for (r, label) in labels.iter().enumerate() {
        out += &format!("| {label:w0$} |");
        let base = base[r];
        let mut notes = Vec::new();
        for j in 0..stims.len() {
            match &table[r][j] {
                Ok(m) => {
                    let ratio = table[base][j]
                        .as_ref()
                        .map(|b| format!("{:.1}x", m.rate() / b.rate()))
                        .unwrap_or_else(|_| "-".into());
                    out += &format!(" {} | {} |", fmt_rate(m.rate()), ratio);
                    if !m.note.is_empty() {
                        notes.push(format!("{}: {}", stims[j].name, m.note));
                    }
                }
                Err(e) => {
                    out += " - | - |";
                    notes.push(format!("{}: {e}", stims[j].name));
                }
            }
        }
        out += &format!(" {} |\n", notes.join("; "));
    }
    out += &format!("\noutput checksums: {}\n", sums.join("; "));
    // pmu50 run as a user runs it, against both Verilator --trace builds
    let ratios: Vec<String> = stims
        .iter()
        .enumerate()
        .map(|(j, st)| match (&table[row_run][j], &table[row_all][j], &table[3][j]) {
            (Ok(r), Ok(a), Ok(t)) => format!("{}: {:.2}x Verilator --trace of every variable, {:.2}x Verilator --trace of the same signals", st.name, r.rate() / a.rate(), r.rate() / t.rate()),
            _ => format!("{}: not measured", st.name),
        })
        .collect();
    out += &format!("\npmu50 run --trace all, whole process, against the Verilator --trace harnesses' replay loop: {}\n", ratios.join("; "));
    match wall_table(&stims, &dir) {
        Ok(t) => out += &t,
        Err(e) => {
            out += &format!("\nwall time: not measured: {e}\n");
            ok = false;
        }
    }

    // The page cache's share of a VCD written to a file, the same for both sides.
    match page_cache_ns_per_byte(&dir) {
        Ok(ns) => {
            let per_tick: Vec<String> = stims
                .iter()
                .zip(&vcd_bytes)
                .map(|(st, &b)| {
                    format!(
                        "{}: {:.1} bytes of VCD a tick, {:.0} ns",
                        st.name,
                        b,
                        b * ns
                    )
                })
                .collect();
            out += &format!("\npage cache: writing a new 8 MiB file costs {ns:.2} ns of CPU per byte (1 MiB writes, best of 15); {}\n", per_tick.join("; "));
        }
        Err(e) => out += &format!("\npage cache: not measured: {e}\n"),
    }

    // Park figures.
    out += "\npark (key off; pmu50 simulator with fast-forward and period skip, no waveform, as `pmu50 run` with trace = none; one child process each, its CPU time and peak memory):\n";
    let park_30d = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("scenarios/park_30d.toml")
        .display()
        .to_string();
    let runs: [(&str, Vec<&str>); 4] = [
        ("1 h still", vec!["3600"]),
        ("1 d still", vec!["86400"]),
        ("30 d still", vec!["2592000"]),
        (
            "scenarios/park_30d.toml (a bump or turn by hand every 6 h)",
            vec!["--file", &park_30d],
        ),
    ];
    for (label, a) in &runs {
        match park(a) {
            Ok((cpu, mib, ticks, evaluated)) => {
                out += &format!("  {label}: {:.3} ms CPU, peak {mib:.0} MiB, {evaluated:.0} of {ticks:.3e} ticks evaluated\n", cpu * 1e3);
            }
            Err(e) => {
                out += &format!("  {label}: failed: {e}\n");
                ok = false;
            }
        }
    }
    println!("{out}");
    if !ok {
        eprintln!("compare: FAIL: the harnesses do not agree (or Verilator did not run)");
        std::process::exit(1);
    }
}

/// CPU nanoseconds per byte of writing 8 MiB into a new file of `dir` in 1 MiB writes (the
/// writers' buffer size), the best of fifteen: the page cache's cost, which every VCD harness
/// pays for its bytes.
fn page_cache_ns_per_byte(dir: &Path) -> std::io::Result<f64> {
    use std::io::Write;
    let path = dir.join("page_cache.bin");
    let chunk = vec![b'0'; 1 << 20];
    let mut best = f64::MAX;
    for _ in 0..15 {
        let mut f = std::fs::File::create(&path)?;
        let t0 = cpu_now();
        for _ in 0..8 {
            f.write_all(&chunk)?;
        }
        f.flush()?;
        drop(f);
        best = best.min(cpu_now() - t0);
        std::fs::remove_file(&path)?;
    }
    Ok(best * 1e9 / (8.0 * chunk.len() as f64))
}
