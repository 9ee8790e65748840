//! Replays a vector file (docs/spec.md 6.2) on the model: the counterexamples of the formal kit
//! (hdl/formal/run.py writes `cex.vec`: the stimulus of the failing trace and the outputs of the
//! RTL under test) become a run of the model.
//!
//! ```text
//! cargo run -p pmu50-ffi --example formal_replay -- FILE.vec [-o MODEL.vec]
//! ```
//!
//! Steps `Pmu50Spec` with the file's parameters and inputs and compares its outputs with the
//! file's, tick by tick. Prints `MATCH ticks=<n>` (exit 0) or, at the first differing tick, one
//! `DIFF tick=<k> signal=<name> file=<hex> model=<hex>` line per differing output (exit 1);
//! exit 2 on bad input. With `-o`, writes the same stimulus with the model's outputs: a vector
//! file that hdl/scripts/run_vectors.sh replays on an RTL as a regression test.

use pmu50_core::{Inputs, Outputs, Params, Pmu50Spec};
use std::process::ExitCode;

const OUT_NAMES: [&str; 23] = [
    "sig",
    "vr_hi",
    "vm_en",
    "vs1_en",
    "vs2_en",
    "vp_en",
    "rail_hi",
    "st",
    "sr",
    "ps_win",
    "smp",
    "cs",
    "cc",
    "cnt_s",
    "cnt_c",
    "cnt_r",
    "si",
    "hist_s",
    "hist_c",
    "diag",
    "quadrant_skip",
    "bus_rdata",
    "bus_err",
];
const OUT_DIGITS: [usize; 23] = [
    1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 4, 4, 2, 4, 1, 1, 1, 1, 4, 1,
];

fn outs(o: &Outputs) -> [u16; 23] {
    let b = u16::from;
    [
        b(o.sig),
        b(o.vr_hi),
        b(o.vm_en),
        b(o.vs1_en),
        b(o.vs2_en),
        b(o.vp_en),
        b(o.rail_hi),
        b(o.st),
        b(o.sr),
        b(o.ps_win),
        b(o.smp),
        b(o.cs),
        b(o.cc),
        o.cnt_s,
        o.cnt_c,
        u16::from(o.cnt_r),
        o.si,
        b(o.hist_s),
        b(o.hist_c),
        b(o.diag),
        b(o.quadrant_skip),
        o.bus_rdata,
        b(o.bus_err),
    ]
}

fn fail(msg: String) -> ExitCode {
    eprintln!("formal_replay: {msg}");
    ExitCode::from(2)
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let (path, out) = match args.as_slice() {
        [p] => (p.clone(), None),
        [p, o, f] if o == "-o" => (p.clone(), Some(f.clone())),
        _ => return fail("usage: formal_replay FILE.vec [-o MODEL.vec]".into()),
    };
    let text = match std::fs::read_to_string(&path) {
        Ok(t) => t,
        Err(e) => return fail(format!("cannot read {path}: {e}")),
    };
    let mut p = Params::default();
    let mut header = Vec::new();
    let mut rows = Vec::new();
    for (n, line) in text.lines().enumerate() {
        if let Some(h) = line.strip_prefix("//") {
            header.push(line.to_string());
            let f: Vec<&str> = h.split_whitespace().collect();
            if f.len() == 3 && f[0] == "param" {
                let v: u64 = match f[2].parse() {
                    Ok(v) => v,
                    Err(_) => {
                        return fail(format!(
                            "{path}:{}: parameter {} is not a number: {}",
                            n + 1,
                            f[1],
                            f[2]
                        ))
                    }
                };
                if let Err(e) = p.set_hdl_parameter(f[1], v) {
                    return fail(format!("{path}:{}: {e}", n + 1));
                }
            }
            continue;
        }
        let v: Result<Vec<u16>, _> = line
            .split_whitespace()
            .map(|x| u16::from_str_radix(x, 16))
            .collect();
        match v {
            Ok(v) if v.len() == 30 => rows.push(v),
            Ok(v) if v.is_empty() => {}
            _ => return fail(format!("{path}:{}: expected 30 hexadecimal fields", n + 1)),
        }
    }
    let mut m = match Pmu50Spec::new(p) {
        Ok(m) => m,
        Err(e) => return fail(format!("{path}: parameters not legal: {e}")),
    };
    let mut model_rows = Vec::new();
    let mut first_diff = None;
    for (k, r) in rows.iter().enumerate() {
        let i = Inputs {
            ig: r[0] != 0,
            vs2_ok: r[1] != 0,
            cmp_s: r[2] != 0,
            cmp_c: r[3] != 0,
            bus_we: r[4] != 0,
            bus_addr: r[5] as u8,
            bus_wdata: r[6],
        };
        let o = outs(&m.step(&i));
        if first_diff.is_none() && o[..] != r[7..] {
            first_diff = Some(k + 1);
            for (j, name) in OUT_NAMES.iter().enumerate() {
                if o[j] != r[7 + j] {
                    println!(
                        "DIFF tick={} signal={} file={:x} model={:x}",
                        k + 1,
                        name,
                        r[7 + j],
                        o[j]
                    );
                }
            }
        }
        let ins: Vec<String> = [
            (r[0], 1),
            (r[1], 1),
            (r[2], 1),
            (r[3], 1),
            (r[4], 1),
            (r[5], 2),
            (r[6], 4),
        ]
        .iter()
        .map(|&(v, d)| format!("{v:0d$x}"))
        .collect();
        let os: Vec<String> = o
            .iter()
            .zip(OUT_DIGITS)
            .map(|(&v, d)| format!("{v:0d$x}"))
            .collect();
        model_rows.push(format!("{} {}", ins.join(" "), os.join(" ")));
    }
    if let Some(o) = out {
        let body = format!("{}\n{}\n", header.join("\n"), model_rows.join("\n"));
        let tmp = format!("{o}.tmp");
        if let Err(e) = std::fs::write(&tmp, body).and_then(|_| std::fs::rename(&tmp, &o)) {
            return fail(format!("cannot write {o}: {e}"));
        }
    }
    match first_diff {
        None => {
            println!("MATCH ticks={}", rows.len());
            ExitCode::SUCCESS
        }
        Some(_) => ExitCode::from(1),
    }
}
