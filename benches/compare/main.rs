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
//! The harnesses of a stimulus are timed in [`harness::rounds`] rounds each, interleaved (round 1 of
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
//!
//! One file per job, each importing only files named after it here: this one, the table (its
//! rows, in what order, against which row each ratio is taken) and what the command line selects;
//! `wall.rs`, the wall-time table; `peers/`, each peer's harness (`model.rs` the Rust model's
//! passes, `tracer.rs` the Rust tracer's, `twin.rs` Verilator's and Icarus's, `pmu50.rs`
//! `pmu50 run` and the park children); `checks.rs`, the checks that the peers agree (a twin's
//! note is one); `signals.rs`, the model's traced signals the tracer writes and the checks
//! compare; `harness.rs`, the measuring; `stim.rs`, the stimulus and the checksum.

mod checks;
mod harness;
mod peers;
mod signals;
mod stim;
mod wall;

use checks::{check_frame_order, check_tracer, checksums};
use harness::{
    alone, fmt_rate, interleaved, page_cache_ns_per_byte, pass_rounds, Meas, Round, Sink,
};
use peers::model::{pass_kernel, pass_spec};
use peers::pmu50::{park, park_child, pmu50_run};
use peers::tracer::{pass_edge_only, pass_sink, traced_once, traced_vcd};
use peers::twin::{icarus, verilator, verilator_all};
use pmu50_core::Pmu50;
use std::path::{Path, PathBuf};
use stim::{load, Stim};
use wall::wall_table;

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
            check_tracer(st, &traced_vcd(st));
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
            check_tracer(st, &traced_vcd(st));
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
    let (row_verilator, row_trace, row_all, row_run, row_icarus) = (2, 3, 8, 9, 10);
    let mut table: Vec<Vec<Result<Meas, String>>> = vec![Vec::new(); labels.len()];
    // bytes of VCD body per tick of each stimulus (the tracer's and Verilator's)
    let mut vcd_bytes = Vec::new();
    for st in &stims {
        eprintln!("compare: {} ({} ticks)", st.name, st.inputs.len());
        check_frame_order(st);
        let body = check_tracer(st, &traced_vcd(st));
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

    // Checksums: every harness of a stimulus must agree, and the untraced Verilator must have run.
    let (mut ok, sums) = checksums(&stims, &table);
    ok &= table[row_verilator].iter().all(Result::is_ok);

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
        .map(|(j, st)| match (&table[row_run][j], &table[row_all][j], &table[row_trace][j]) {
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
