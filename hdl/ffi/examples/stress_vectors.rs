//! Core-level stress vectors for the HDL co-simulation: seeded random stimuli applied directly to
//! the core's ports (no environment model), covering what scenario files cannot express: bus
//! reads of every address (the read mux, CNT_S/CNT_C sign extension, CFG, unmapped = 0), writes
//! while the core's `sig` is 0, writes to read-only and unmapped addresses, illegal values,
//! STATUS write-1-to-clear at random, `ig` glitches shorter than the synchronizer, `vs2_ok`
//! drop-outs, comparator noise, shaft motion from standstill to quadrant-skipping speed, and every
//! structural configuration (SYNC_DEPTH 1..4, CNT_W 2..16).
//!
//! ```text
//! cargo run --release -p pmu50-ffi --example stress_vectors -- --seed 7 [--ticks 30000] -o F.vec [--vcd F.vcd]
//! ```
//!
//! Writes the vector file of docs/spec.md 6.2 (same header and columns as `pmu50 vectors`) and,
//! with `--vcd`, the model's waveform with the hierarchy of the model's VCD (scope `pmu50`: ports;
//! `pmu50.<block>`: registers; `pmu50.internals`), for `pmu50 diff` (method 3). Clock 10 us.

use pmu50_core::pmu50::Structural;
use pmu50_core::signals;
use pmu50_core::{Inputs, Params, Pmu50};
use std::fmt::Write as _;
use std::io::{BufWriter, Write};
use std::process::ExitCode;

const CLOCK_NS: u64 = 10_000;

use pmu50_core::rng::{ParamRanges, SplitMix64 as Rng};

/// Legal random parameters (ticks), narrow counters half the time.
fn random_params(r: &mut Rng) -> Params {
    r.legal_params(&ParamRanges {
        pw: 6,
        pi: 12,
        ps: 6,
        si_min_over_wt: 150,
        si_max_over_min: 300,
        narrow_cnt: (500, 1000),
        narrow_cnt_max: 15,
        adaptive: (850, 1000),
        t1: 200,
        t2: 150,
        cth: 6,
        smp_on: 20,
    })
}

/// Stimulus generator state.
struct Stim {
    rng: Rng,
    ig: bool,
    seg_left: u64,
    pos: i64, // shaft angle in milli-quadrants
    vel: i64, // milli-quadrants per tick
    vel_left: u64,
    fault_left: u64,
}

impl Stim {
    fn next(&mut self, sig: bool, regs: &pmu50_core::Regs) -> Inputs {
        let r = &mut self.rng;
        // Ignition: long key-off periods (several intervals), shorter key-on periods, glitches.
        if self.seg_left == 0 {
            self.ig = !self.ig;
            let si_max = u64::from(regs.register_file.si_max.max(1));
            self.seg_left = if self.ig {
                r.range(30, 1500)
            } else {
                r.range(si_max, 10 * si_max).min(12_000)
            };
        }
        self.seg_left -= 1;
        let ig = if r.chance(3, 1000) { !self.ig } else { self.ig };
        // Motion: standstill, slow, fast, quadrant-skipping; both directions.
        if self.vel_left == 0 {
            self.vel = match r.range(0, 24) {
                0..=9 => 0,
                10..=17 => r.range(1, 40) as i64,
                18..=23 => r.range(40, 400) as i64,
                _ => r.range(400, 2500) as i64,
            } * if r.chance(500, 1000) { 1 } else { -1 };
            self.vel_left = r.range(50, 4000);
        }
        self.vel_left -= 1;
        self.pos += self.vel;
        let q = self.pos.div_euclid(1000).rem_euclid(4);
        let mut cmp_s = q == 0 || q == 1;
        let mut cmp_c = q == 0 || q == 3;
        if r.chance(5, 1000) {
            cmp_s = !cmp_s;
        }
        if r.chance(5, 1000) {
            cmp_c = !cmp_c;
        }
        // Vs2 power-good: drop-outs and single-tick glitches.
        if self.fault_left == 0 && r.chance(1, 1000) {
            self.fault_left = r.range(1, 3000);
        }
        let vs2_ok = if self.fault_left > 0 {
            self.fault_left -= 1;
            false
        } else {
            !r.chance(2, 1000)
        };
        // Bus: reads of every address every tick, writes (mostly while the key is on).
        let mut i = Inputs {
            ig,
            vs2_ok,
            cmp_s,
            cmp_c,
            ..Inputs::default()
        };
        i.bus_addr = match r.range(0, 9) {
            0..=6 => r.range(0, 0x14) as u8,
            7 => r.range(0x15, 0x1F) as u8,
            _ => r.range(0, 255) as u8,
        };
        i.bus_wdata = r.next() as u16;
        // Writes are likelier around the key edges (the synchronizer is in transition: sig != ig),
        // where a write races the key: refused while sig = 0, SI_MAX written in the key-off cycle.
        let p_write = if sig != self.ig {
            200
        } else if sig {
            15
        } else {
            2
        };
        let sticky = regs.register_file.bus_err || regs.updown_counter.quadrant_skip;
        if sig && sticky && r.chance(4, 1000) {
            // the MPU clears the sticky bits now and then (STATUS W1C: bit 5 quadrant_skip, bit 9 bus_err)
            i.bus_we = true;
            i.bus_addr = 0x14;
            i.bus_wdata = [0x220, 0x200, 0x020, 0xFFFF][r.range(0, 3) as usize];
        } else if r.chance(p_write, 1000) {
            i.bus_we = true;
            i.bus_addr = if sig != self.ig && r.chance(500, 1000) {
                0x06
            } else if r.chance(900, 1000) {
                r.range(0x02, 0x0B) as u8
            } else if r.chance(500, 1000) {
                0x14
            } else {
                r.range(0, 255) as u8
            };
            let f = &regs.register_file;
            let cur = match i.bus_addr {
                0x02 => u16::from(f.adaptive),
                0x03 => f.pw,
                0x04 => f.pi,
                0x05 => f.ps,
                0x06 => f.si_max,
                0x07 => f.si_min,
                0x08 => f.t1,
                0x09 => f.t2,
                0x0A => u16::from(f.cth),
                0x0B => f.smp_on,
                _ => 0,
            };
            i.bus_wdata = match r.range(0, 9) {
                0..=5 => (i64::from(cur) + r.range(0, 80) as i64 - 40).clamp(0, 700) as u16,
                6 => 0,
                7 => r.range(0, 0x3FF) as u16,
                8 => cur,
                _ => r.next() as u16,
            };
        }
        i
    }
}

// ---------------------------------------------------------------------------------- VCD
struct Vcd {
    out: BufWriter<std::fs::File>,
    last: Vec<Option<u64>>,
    widths: Vec<u8>,
}

fn vcd_id(n: usize) -> String {
    let mut n = n;
    let mut s = String::new();
    loop {
        s.push((b'!' + (n % 94) as u8) as char);
        n /= 94;
        if n == 0 {
            break;
        }
        n -= 1;
    }
    s
}

impl Vcd {
    fn value(&mut self, idx: usize, v: u64, text: &mut String) {
        if self.last[idx] == Some(v) {
            return;
        }
        self.last[idx] = Some(v);
        let w = self.widths[idx];
        if w == 1 {
            let _ = writeln!(text, "{}{}", v & 1, vcd_id(idx));
        } else {
            let _ = writeln!(text, "b{:b} {}", v, vcd_id(idx));
        }
    }
}

fn arg(args: &[String], name: &str) -> Option<String> {
    args.iter()
        .position(|a| a == name)
        .and_then(|i| args.get(i + 1))
        .cloned()
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().collect();
    let (Some(seed), Some(out)) = (arg(&args, "--seed"), arg(&args, "-o")) else {
        eprintln!("usage: stress_vectors --seed N [--ticks N] -o FILE.vec [--vcd FILE.vcd]");
        return ExitCode::from(2);
    };
    let Ok(seed) = seed.parse::<u64>() else {
        eprintln!("--seed: not a number");
        return ExitCode::from(2);
    };
    let ticks: u64 = arg(&args, "--ticks")
        .and_then(|t| t.parse().ok())
        .unwrap_or(30_000);
    match run(seed, ticks, &out, arg(&args, "--vcd").as_deref()) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(2)
        }
    }
}

fn run(seed: u64, ticks: u64, out: &str, vcd_path: Option<&str>) -> Result<(), String> {
    let mut r = Rng(seed ^ 0x5354_5245_5353_0050);
    let p = random_params(&mut r);
    let mut core = Pmu50::new(p).map_err(|e| e.to_string())?;
    let s = Structural {
        sync_depth: p.sync_depth,
        cnt_width: p.cnt_width,
    };
    let name = format!("stress_{seed}");
    let mut stim = Stim {
        rng: r,
        ig: false,
        seg_left: 0,
        pos: 0,
        vel: 0,
        vel_left: 0,
        fault_left: 0,
    };
    stim.pos = stim.rng.range(0, 3999) as i64;
    stim.ig = stim.rng.chance(500, 1000);

    let io = |e: std::io::Error| format!("{out}: {e}");
    let mut f = BufWriter::new(std::fs::File::create(out).map_err(io)?);
    let mut h = String::new();
    h += "// pmu50 vectors v1\n";
    h += &format!("// scenario {name}\n");
    h += &format!("// clock_ns {CLOCK_NS}\n");
    for (n, v) in p.hdl_parameters() {
        h += &format!("// param {n} {v}\n");
    }
    h += &format!(
        "// ticks {ticks}\n// fields {}\n",
        signals::N_INPUTS + signals::N_OUTPUTS
    );
    let ins: Vec<&str> = Inputs::default().values().iter().map(|v| v.0).collect();
    let outs: Vec<&str> = core.peek().values(&s).iter().map(|v| v.0).collect();
    h += &format!("// columns {} | {}\n", ins.join(" "), outs.join(" "));
    f.write_all(h.as_bytes()).map_err(io)?;

    // VCD header: same hierarchy as the model's VCD.
    let mut vcd = match vcd_path {
        None => None,
        Some(vp) => {
            let vio = |e: std::io::Error| format!("{vp}: {e}");
            let mut w = BufWriter::new(std::fs::File::create(vp).map_err(vio)?);
            let mut d = String::from("$version pmu50-ffi stress_vectors $end\n$timescale 1us $end\n$scope module pmu50 $end\n");
            let mut widths = Vec::new();
            let mut decl = |d: &mut String, kind: &str, n: &str, wdt: u8| {
                let id = vcd_id(widths.len());
                if wdt == 1 {
                    let _ = writeln!(d, "$var {kind} 1 {id} {n} $end");
                } else {
                    let _ = writeln!(d, "$var {kind} {wdt} {id} {n} [{}:0] $end", wdt - 1);
                }
                widths.push(wdt);
            };
            for (n, wdt, _) in Inputs::default().values() {
                decl(&mut d, "wire", n, wdt);
            }
            for (n, wdt, _) in core.peek().values(&s) {
                decl(&mut d, "wire", n, wdt);
            }
            let mut block = "";
            for rv in core.regs().values(&s) {
                if rv.block != block {
                    if !block.is_empty() {
                        d += "$upscope $end\n";
                    }
                    let _ = writeln!(d, "$scope module {} $end", rv.block);
                    block = rv.block;
                }
                decl(&mut d, "reg", rv.name, rv.width);
            }
            d += "$upscope $end\n$scope module internals $end\n";
            for (n, wdt, _) in pmu50_core::Internals::default().values() {
                decl(&mut d, "wire", n, wdt);
            }
            d += "$upscope $end\n$upscope $end\n$enddefinitions $end\n";
            w.write_all(d.as_bytes()).map_err(vio)?;
            let n = widths.len();
            Some(Vcd {
                out: w,
                last: vec![None; n],
                widths,
            })
        }
    };
    let n_in = signals::N_INPUTS;
    let n_out = signals::N_OUTPUTS;
    let n_reg = core.regs().values(&s).len();

    let t_us = CLOCK_NS / 1000;
    for k in 0..ticks {
        let before = core.peek();
        let regs_before = *core.regs();
        let i = stim.next(before.sig, &regs_before);
        let pmu50_core::TracedStep {
            internals, after, ..
        } = core.step_traced(&i);
        let mut l = String::with_capacity(96);
        for (_, w, v) in i.values() {
            let _ = write!(l, "{:0d$x} ", v, d = usize::from(w).div_ceil(4));
        }
        for (_, w, v) in after.values(&s) {
            let _ = write!(l, "{:0d$x} ", v, d = usize::from(w).div_ceil(4));
        }
        l.pop();
        l.push('\n');
        f.write_all(l.as_bytes()).map_err(io)?;
        if let Some(v) = vcd.as_mut() {
            // time k*T: state after edge k (before this step), inputs and internals of cycle k
            let mut t = String::new();
            for (j, (_, _, x)) in i.values().iter().enumerate() {
                v.value(j, *x, &mut t);
            }
            for (j, (_, _, x)) in before.values(&s).iter().enumerate() {
                v.value(n_in + j, *x, &mut t);
            }
            for (j, rv) in regs_before.values(&s).iter().enumerate() {
                v.value(n_in + n_out + j, rv.value, &mut t);
            }
            for (j, (_, _, x)) in internals.values().iter().enumerate() {
                v.value(n_in + n_out + n_reg + j, *x, &mut t);
            }
            if !t.is_empty() || k == 0 {
                let head = if k == 0 {
                    "#0\n$dumpvars\n".to_string()
                } else {
                    format!("#{}\n", k * t_us)
                };
                let tail = if k == 0 { "$end\n" } else { "" };
                v.out
                    .write_all(format!("{head}{t}{tail}").as_bytes())
                    .map_err(|e| e.to_string())?;
            }
        }
    }
    if let Some(mut v) = vcd {
        // final time stamp: ports and registers after the last edge; inputs/internals hold
        let mut t = String::new();
        for (j, (_, _, x)) in core.peek().values(&s).iter().enumerate() {
            v.value(n_in + j, *x, &mut t);
        }
        for (j, rv) in core.regs().values(&s).iter().enumerate() {
            v.value(n_in + n_out + j, rv.value, &mut t);
        }
        v.out
            .write_all(format!("#{}\n{t}", ticks * t_us).as_bytes())
            .map_err(|e| e.to_string())?;
        v.out.flush().map_err(|e| e.to_string())?;
    }
    f.flush().map_err(io)?;
    println!("wrote {out} ({ticks} ticks, {name})");
    Ok(())
}
