//! GTKWave's own VCD loader (`vcd2lxt2`, same parser family as the viewer)
//! must read written VCDs without a warning, and the values it stores must be
//! the ones written (checked by converting back with `lxt2vcd` and diffing).
//! Skipped, with a printed message, when the Debian `gtkwave` tools are absent.

mod common;

use common::{tool, tools_or_skip};

use std::path::Path;
use std::process::Command;

use pmu50_waves::diff::{diff_files, DiffOptions, Outcome};
use pmu50_waves::writer::{BitType, Logic, VcdBuilder};
use pmu50_waves::{TimeUnit, Timescale};

/// A VCD exercising every declaration kind, x/z, wide vectors, reals and,
/// optionally, a window that starts after 0.
fn write_vcd(path: &Path, window: Option<(u64, u64)>) {
    let mut b = VcdBuilder::new(Timescale::new(10, TimeUnit::Ns), "pmu50-waves tool test").unwrap();
    if let Some((s, e)) = window {
        b.window(s, e).unwrap();
    }
    b.push_scope("pmu50").unwrap();
    let clk = b.add_bit(BitType::Wire, "clk", Logic::Zero).unwrap();
    let rst = b.add_bit(BitType::Reg, "rst_n", Logic::X).unwrap();
    b.push_scope("drive_interval").unwrap();
    let si = b.add_vector(BitType::Reg, "si", 15, 0, 0).unwrap();
    let sel = b.add_vector(BitType::Wire, "sel", 2, 2, 0).unwrap();
    let wide = b.add_vector(BitType::Wire, "wide", 99, 0, 0).unwrap();
    let vout = b.add_real("vout", 0.0).unwrap();
    b.pop_scope().unwrap();
    b.push_scope("regs").unwrap();
    let cnt = b.add_vector(BitType::Reg, "cnt_s", 7, 0, 0).unwrap();
    b.pop_scope().unwrap();
    b.pop_scope().unwrap();
    let mut w = b.start(std::fs::File::create(path).unwrap()).unwrap();
    w.change_bits(si, "xxxxxxxxxxxxxxxx").unwrap();
    for t in 1..200u64 {
        w.set_time(t).unwrap();
        w.change_bool(clk, t % 2 == 1).unwrap();
        if t == 3 {
            w.change_bool(rst, true).unwrap();
        }
        if t % 2 == 1 && t > 3 {
            w.change_vector(cnt, (t / 2) % 256).unwrap();
            w.change_vector(si, (t * 977) % 65536).unwrap();
        }
        if t % 7 == 0 {
            w.change_bit(sel, if t % 14 == 0 { Logic::Z } else { Logic::One })
                .unwrap();
            let bits: String = (0..100)
                .map(|i| if (i + t) % 3 == 0 { '1' } else { '0' })
                .collect();
            w.change_bits(wide, &bits).unwrap();
            w.change_real(vout, t as f64 * 0.25 - 12.0).unwrap();
        }
    }
    w.finish().unwrap();
}

fn check_tool_output(vcd: &Path) {
    let vcd2lxt2 = tool("vcd2lxt2").unwrap();
    let lxt = vcd.with_extension("lxt");
    let out = Command::new(vcd2lxt2).arg(vcd).arg(&lxt).output().unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        out.status.success(),
        "vcd2lxt2 failed\nstdout:\n{stdout}\nstderr:\n{stderr}"
    );
    let bad: Vec<&str> = stderr.lines().filter(|l| !l.trim().is_empty()).collect();
    assert!(bad.is_empty(), "vcd2lxt2 wrote to stderr:\n{stderr}");
    for line in stdout.lines() {
        let l = line.to_ascii_lowercase();
        assert!(
            !l.contains("warning") && !l.contains("error"),
            "vcd2lxt2: {line}"
        );
    }
    assert!(
        stdout.contains("symbols"),
        "unexpected vcd2lxt2 output:\n{stdout}"
    );

    // GTKWave's LXT2 holds the values we wrote: convert back and diff.
    if let Some(lxt2vcd) = tool("lxt2vcd") {
        let back = vcd.with_extension("back.vcd");
        let out = Command::new(lxt2vcd).arg(&lxt).output().unwrap();
        assert!(out.status.success());
        std::fs::write(&back, &out.stdout).unwrap();
        let report = diff_files(vcd, &back, &DiffOptions::default()).unwrap();
        assert_eq!(report.outcome, Outcome::Equal, "{report}");
        assert_eq!(report.signals_compared, 7, "{report}");
    } else {
        println!("lxt2vcd not on PATH: value round trip through LXT2 not checked");
    }
}

#[test]
fn gtkwave_loader_reads_written_vcds_without_warnings() {
    if tools_or_skip(
        "gtkwave_loader_reads_written_vcds_without_warnings",
        &["vcd2lxt2"],
        "`vcd2lxt2` not on PATH (Debian package `gtkwave`)",
    )
    .is_none()
    {
        return;
    }
    let dir = std::env::temp_dir().join(format!("pmu50-waves-tools-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let full = dir.join("full.vcd");
    write_vcd(&full, None);
    check_tool_output(&full);
    let win = dir.join("window.vcd");
    write_vcd(&win, Some((50, 150)));
    check_tool_output(&win);
    let _ = std::fs::remove_dir_all(&dir);
}
