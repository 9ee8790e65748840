//! The Rust tracer in this process: replays through `CoreTracer` of the model's signals
//! ([`crate::signals`]) into a VCD or FST file, `/dev/null`, `std::io::sink` or memory, and the
//! traced edge alone.

use crate::harness::{cpu_now, fmt_bytes, Meas, Sink};
use crate::signals::{declare, NSIG};
use crate::stim::{mix, Stim};
use pmu50_core::{Inputs, Outputs, Pmu50};
use pmu50_testbench::observers::tracer::CoreTracer;
use pmu50_waves::fst::start_fst;
use pmu50_waves::writer::{Emitter, Frame, VcdWriter, Writer};
use std::hint::black_box;
use std::path::{Path, PathBuf};

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

/// The tracer's VCD of one replay, in memory (what [`crate::checks::check_tracer`] compares).
pub fn traced_vcd(st: &Stim) -> Vec<u8> {
    let (b, ids, unit_ns) = declare(st);
    let mut w = b.start(Vec::new()).expect("VCD header");
    let f = w.frame(&ids).unwrap();
    pass_traced_vcd(st, &mut w, f, unit_ns);
    w.finish().expect("VCD written")
}

/// [`pass_traced`] into a VCD writer whose text is thrown away ([`std::io::sink`]).
#[inline(never)]
pub fn pass_sink(st: &Stim) -> u64 {
    let (b, ids, unit_ns) = declare(st);
    let mut w = b.start(std::io::sink()).expect("VCD header");
    let f = w.frame(&ids).unwrap();
    let h = pass_traced_vcd(st, &mut w, f, unit_ns);
    w.finish().expect("VCD written");
    h
}

/// The traced edges of [`pass_traced`] without a writer.
#[inline(never)]
pub fn pass_edge_only(st: &Stim) -> u64 {
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

/// One traced replay, VCD or (`fst`) FST, into `sink`: its CPU time from the header written to
/// the last byte written, the checksum, and the note (signals, and the file's size).
pub fn traced_once(st: &Stim, dir: &Path, fst: bool, sink: Sink) -> Meas {
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
