//! The stimulus of a lockstep: one packed word of the core's inputs per tick ([`pack`]),
//! recorded from the model's bench run ([`InputRecorder`]) or read from a vector file.

use pmu50_core::params::Params;
use pmu50_core::pmu50::Inputs;
use pmu50_core::signals;
use pmu50_testbench::sim::{Observer, SimError, TickView};

use std::path::Path;

/// One tick's inputs as a word: `ig`, `vs2_ok`, `cmp_s`, `cmp_c`, `bus_we` in bits 0-4,
/// `bus_addr` in bits 8-15, `bus_wdata` in bits 16-31.
pub fn pack(i: &Inputs) -> u32 {
    u32::from(i.ig)
        | u32::from(i.vs2_ok) << 1
        | u32::from(i.cmp_s) << 2
        | u32::from(i.cmp_c) << 3
        | u32::from(i.bus_we) << 4
        | u32::from(i.bus_addr) << 8
        | u32::from(i.bus_wdata) << 16
}

/// The inverse of [`pack`].
pub fn unpack(w: u32) -> Inputs {
    Inputs {
        ig: w & 1 != 0,
        vs2_ok: w & 2 != 0,
        cmp_s: w & 4 != 0,
        cmp_c: w & 8 != 0,
        bus_we: w & 16 != 0,
        bus_addr: (w >> 8) as u8,
        bus_wdata: (w >> 16) as u16,
    }
}

/// Most ticks a stimulus may hold in memory (4 bytes a tick: 1 GiB).
pub const MAX_TICKS: usize = 1 << 28;

/// Records the core's inputs of every tick of a bench run: the stimulus the RTL replays.
///
/// It lets the bench skip repeated periods (docs/spec.md 5.1, key off and key on) and fills
/// them in by copying the last period's inputs ([`Observer::replay`]): the bench skips a period
/// only when its start state equals the one a period earlier with the same inputs ahead, so
/// tick `k + j·len + i` of a skipped stretch has the inputs of tick `k - len + i`
/// (`tests/regress.rs` compares the recording with one of every tick stepped).
#[derive(Default)]
pub struct InputRecorder {
    pub inputs: Vec<u32>,
}

pub(super) fn too_long() -> SimError {
    SimError::observer(
        "lockstep stimulus",
        format!("more than {MAX_TICKS} ticks to hold in memory for the DUT"),
    )
}

impl Observer for InputRecorder {
    fn tick(&mut self, v: &TickView<'_>) -> Result<(), SimError> {
        if self.inputs.len() >= MAX_TICKS {
            return Err(too_long());
        }
        self.inputs.push(pack(v.inputs));
        Ok(())
    }
    fn replays_periods(&self) -> bool {
        true
    }
    fn can_replay(&self, k: u64, len: u64) -> bool {
        self.inputs.len() as u64 == k && len > 0 && k >= len
    }
    fn replay(&mut self, k: u64, periods: u64, len: u64) -> Result<(), SimError> {
        let total = periods
            .checked_mul(len)
            .and_then(|n| n.checked_add(k))
            .filter(|&n| n <= MAX_TICKS as u64)
            .ok_or_else(too_long)?;
        let (from, len) = ((k - len) as usize, len as usize);
        self.inputs.reserve((total - k) as usize);
        for _ in 0..periods {
            self.inputs.extend_from_within(from..from + len);
        }
        Ok(())
    }
}

/// A vector file's stimulus (docs/spec.md 6.2): its parameters, clock and scenario name, and the
/// inputs of every tick packed ([`pack`]). The expected-output columns are not read: the model
/// computes them.
pub struct VectorInputs {
    pub params: Params,
    pub clock_ns: u64,
    pub scenario: String,
    pub inputs: Vec<u32>,
}

/// The model's functional coverage over a vector file's inputs: every edge sampled (no
/// skipping), as the regression samples a seed.
pub fn model_coverage(v: &VectorInputs) -> Result<pmu50_coverage::Coverage, String> {
    let mut core = pmu50_core::Pmu50::new(v.params).map_err(|e| e.to_string())?;
    let mut cov = pmu50_coverage::Coverage::new(&v.params, v.clock_ns);
    for &w in &v.inputs {
        cov.step(&mut core, &unpack(w));
    }
    Ok(cov)
}

/// Read a vector file's header and input columns; an error names the line.
pub fn read_vector_inputs(path: &Path) -> Result<VectorInputs, String> {
    use std::io::BufRead;
    if let Some(kind) = pmu50_testbench::atomic_file::special_kind(path) {
        return Err(format!("{}: is {kind}, not a vector file", path.display()));
    }
    let f = std::fs::File::open(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let mut v = VectorInputs {
        params: Params::default(),
        clock_ns: 10_000,
        scenario: "?".into(),
        inputs: Vec::new(),
    };
    let mut ticks = None;
    for (n, line) in std::io::BufReader::new(f).lines().enumerate() {
        let line = line.map_err(|e| format!("{}:{}: {e}", path.display(), n + 1))?;
        let l = line.trim();
        if l.is_empty() {
            continue;
        }
        if let Some(h) = l.strip_prefix("//") {
            let w: Vec<&str> = h.split_whitespace().collect();
            match w.as_slice() {
                ["param", "CLOCK_US", x] => {
                    v.clock_ns = x
                        .parse::<u64>()
                        .map_err(|e| format!("{}:{}: CLOCK_US {x}: {e}", path.display(), n + 1))?
                        * 1000
                }
                ["param", name, x] => {
                    let x: u64 = x.parse().map_err(|e| {
                        format!("{}:{}: param {name} {x}: {e}", path.display(), n + 1)
                    })?;
                    v.params
                        .set_hdl_parameter(name, x)
                        .map_err(|e| format!("{}:{}: {e}", path.display(), n + 1))?;
                }
                ["clock_ns", x] => {
                    v.clock_ns = x
                        .parse()
                        .map_err(|e| format!("{}:{}: clock_ns {x}: {e}", path.display(), n + 1))?
                }
                ["scenario", x] => v.scenario = x.to_string(),
                ["ticks", x] => ticks = x.parse::<u64>().ok(),
                _ => {}
            }
            continue;
        }
        let f: Vec<u64> = l
            .split_whitespace()
            .take(signals::N_INPUTS)
            .map(|x| u64::from_str_radix(x, 16))
            .collect::<Result<_, _>>()
            .map_err(|e| format!("{}:{}: not a vector line: {e}", path.display(), n + 1))?;
        if f.len() < signals::N_INPUTS {
            return Err(format!(
                "{}:{}: {} fields, a vector line has {} inputs and the outputs",
                path.display(),
                n + 1,
                f.len(),
                signals::N_INPUTS
            ));
        }
        if v.inputs.len() >= MAX_TICKS {
            return Err(too_long().to_string());
        }
        let i = Inputs {
            ig: f[0] & 1 != 0,
            vs2_ok: f[1] & 1 != 0,
            cmp_s: f[2] & 1 != 0,
            cmp_c: f[3] & 1 != 0,
            bus_we: f[4] & 1 != 0,
            bus_addr: f[5] as u8,
            bus_wdata: f[6] as u16,
        };
        v.inputs.push(pack(&i));
    }
    if let Some(t) = ticks {
        if t != v.inputs.len() as u64 {
            return Err(format!(
                "{}: {} vector lines, the header says ticks {t}",
                path.display(),
                v.inputs.len()
            ));
        }
    }
    v.params
        .validate()
        .map_err(|e| format!("{}: illegal parameters: {e}", path.display()))?;
    Ok(v)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pack_and_unpack_are_inverse_on_every_field() {
        let i = Inputs {
            ig: true,
            vs2_ok: false,
            cmp_s: true,
            cmp_c: true,
            bus_we: true,
            bus_addr: 0xA5,
            bus_wdata: 0xBEEF,
        };
        assert_eq!(unpack(pack(&i)), i);
        let z = Inputs::default();
        assert_eq!(unpack(pack(&z)), z);
        for bit in 0..5 {
            let w = 1u32 << bit;
            assert_eq!(pack(&unpack(w)), w, "bit {bit}");
        }
    }
}
