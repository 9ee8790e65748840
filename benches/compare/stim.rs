//! The stimulus every peer replays ([`Stim`], read from a vector file by [`load`]; the scenario
//! file it came from, [`scenario_of`]) and the checksum every peer folds its outputs into
//! ([`mix`]).

use pmu50_core::{Inputs, Outputs, Params};
use std::path::{Path, PathBuf};

/// A stimulus held in memory: its name, its vector file, the parameters and clock period of the
/// file's header, and the inputs of every tick.
pub struct Stim {
    pub name: String,
    pub vec: PathBuf,
    pub params: Params,
    pub clock_ns: u64,
    pub inputs: Vec<Inputs>,
}

/// Read `DIR/NAME.vec`; an error names the file (and the line it could not read).
pub fn load(dir: &Path, name: &str) -> Result<Stim, String> {
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
pub fn mix(h: u64, o: &Outputs) -> u64 {
    let w0 = u64::from(o.flags())
        | u64::from(o.cnt_r) << 18
        | u64::from(o.si) << 26
        | u64::from(o.bus_rdata) << 42;
    let w1 = u64::from(o.cnt_s) | u64::from(o.cnt_c) << 16;
    (h.rotate_left(5) ^ w0).wrapping_add(w1.wrapping_mul(0x9E37_79B9_7F4A_7C15))
}

/// The scenario of a stimulus: `DIR/NAME.toml` (a seeded random one, written by
/// benches/compare.sh), else `scenarios/NAME.toml`.
pub fn scenario_of(st: &Stim, dir: &Path) -> PathBuf {
    let own = dir.join(format!("{}.toml", st.name));
    if own.exists() {
        own
    } else {
        Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("scenarios")
            .join(format!("{}.toml", st.name))
    }
}
