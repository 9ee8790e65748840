//! The Verilog twin, run as child processes: the Verilator harnesses (untraced, `--trace` of the
//! tracer's signals into a file or `/dev/null`, `--trace` of every variable) and Icarus's `vvp`.

use crate::checks::{same_signals, var_paths};
use crate::harness::{external, fmt_bytes, rounds, rusage, Meas, Round, Sink};
use crate::stim::Stim;
use std::path::Path;
use std::process::Command;

/// Rounds of the Verilator harness, untraced (`reps` replays per round, chosen from one replay)
/// or with `--trace` (one replay per round into a VCD; the note, from the last round's VCD,
/// counts its `$var`s against the Rust tracer's signals).
pub fn verilator<'a>(
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
pub fn verilator_all<'a>(st: &'a Stim, dir: &Path) -> Result<Round<'a>, String> {
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

/// One replay under Icarus (`vvp DIR/iv_NAME.vvp`), which compares every output with the vector
/// file itself: the child's CPU time, no checksum.
pub fn icarus(st: &Stim, dir: &Path) -> Result<Meas, String> {
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
