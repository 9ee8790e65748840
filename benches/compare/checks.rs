//! The checks that every harness computed the same thing: the tracer's frame is in the order of
//! the declarations, its VCD is the one of every value through `Writer::dump_frame`, the twin's
//! traced `$var`s are the counterparts of the tracer's signals, and the output checksums of a
//! stimulus's harnesses agree.

use crate::harness::Meas;
use crate::signals::{declare, frame_values, NSIG};
use crate::stim::Stim;
use pmu50_core::pmu50::Structural;
use pmu50_core::Pmu50;

/// [`frame_values`] writes a tick's values in the order of the declarations, over the first 5000
/// ticks (panics otherwise).
pub fn check_frame_order(st: &Stim) {
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

/// The VCD of every value of every tick through `Writer::dump_frame`, which `CoreTracer` must
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

/// The tracer's VCD (`vcd`) is the one of every value through `dump_frame`; returns the length of
/// its body (the bytes after the header, which every VCD harness writes).
pub fn check_tracer(st: &Stim, vcd: &[u8]) -> usize {
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

/// The output checksums of the table's harnesses, a line per stimulus (`NAME: FIRST (N harnesses
/// equal|DIFFER)`), and whether, for every stimulus, the harnesses that gave a checksum gave the
/// same one.
pub fn checksums(stims: &[Stim], table: &[Vec<Result<Meas, String>>]) -> (bool, Vec<String>) {
    let mut ok = true;
    let mut sums = Vec::new();
    for (j, st) in stims.iter().enumerate() {
        let all: Vec<u64> = table
            .iter()
            .filter_map(|row| row[j].as_ref().ok().and_then(|m| m.checksum))
            .collect();
        let same = all.windows(2).all(|w| w[0] == w[1]);
        ok &= same;
        sums.push(format!(
            "{}: {} ({} harnesses {})",
            st.name,
            all.first().map_or("-".into(), |h| format!("{h:016x}")),
            all.len(),
            if same { "equal" } else { "DIFFER" }
        ));
    }
    (ok, sums)
}

/// Full dotted paths of the `$var`s of a VCD header, one per `$var` line, in file order.
pub fn var_paths(vcd: &[u8]) -> Vec<String> {
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
pub fn same_signals(st: &Stim, twin: &[String]) -> String {
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
