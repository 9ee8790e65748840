//! The compare loop of a lockstep: the Rust core and the RTL library side by side, every output
//! after every edge and what a map names; the RTL alone for a probe, a trace or the bench.

use super::ffi::*;
use super::protocol::*;
use super::vectors::*;
use pmu50_core::params::Params;
use pmu50_core::pmu50::{Inputs, Internals, Outputs, Regs};
use pmu50_core::signals::{self, Signal};
use pmu50_core::Pmu50;
use std::path::Path;

/// The parameters from their HDL values (the order of [`Params::hdl_parameters`]).
pub(super) fn params_of(v: &[u64; 12]) -> Result<Params, String> {
    let mut p = Params::default();
    for ((name, _), &value) in Params::default().hdl_parameters().iter().zip(v) {
        p.set_hdl_parameter(name, value)
            .map_err(|e| e.to_string())?;
    }
    Ok(p)
}

/// The differences between the model and the RTL in one group, at the table indices `at`.
pub(super) fn compare<T>(
    out: &mut Vec<Mismatch>,
    table: &[Signal<T>],
    at: &[usize],
    model: &T,
    rtl: &[u64],
) {
    for (&j, &g) in at.iter().zip(rtl) {
        let sig = &table[j];
        let e = (sig.get)(model);
        if e != g {
            out.push(Mismatch {
                signal: sig.path(),
                expected: e,
                got: g,
            });
        }
    }
}

/// The values of a group in the order of its signal table. Inlined with the table a constant,
/// the compiler turns each `get` into a direct load (no call through the table's pointers).
#[inline(always)]
pub(super) fn words<T, const N: usize>(table: &'static [Signal<T>], model: &T) -> [u64; N] {
    std::array::from_fn(|j| (table[j].get)(model))
}

/// Whether two arrays are equal, without a call to `memcmp` (which is what `==` on arrays this
/// long becomes, at a third of the lockstep's time): one vectorised pass.
#[inline(always)]
pub(super) fn same(a: &[u64], b: &[u64]) -> bool {
    a.iter().zip(b).fold(0, |acc, (x, y)| acc | (x ^ y)) == 0
}

/// The seven input values of a packed word, in the order of [`signals::INPUTS`].
pub(super) fn input_words(w: u32) -> (Inputs, [u64; signals::N_INPUTS]) {
    let i = unpack(w);
    (
        i,
        [
            u64::from(i.ig),
            u64::from(i.vs2_ok),
            u64::from(i.cmp_s),
            u64::from(i.cmp_c),
            u64::from(i.bus_we),
            u64::from(i.bus_addr),
            u64::from(i.bus_wdata),
        ],
    )
}

/// Verilator alone on a stimulus (the peer of `make bench`'s lockstep row): the RTL library at
/// `lib` stepped on `inputs` as a plain harness does (two evaluations a tick, the outputs
/// folded, nothing compared). Returns the fold.
pub fn replay_alone(lib: &Path, inputs: &[u32]) -> Result<u64, String> {
    let lib = DutLib::load(lib)?;
    let dut = Handle::new(&lib);
    let words: Vec<[u64; signals::N_INPUTS]> = inputs.iter().map(|&w| input_words(w).1).collect();
    let mut acc = 0xcbf2_9ce4_8422_2325u64;
    for w in &words {
        // SAFETY: an input array of the library's count (checked at load).
        acc = unsafe { (lib.step)(dut.1, w.as_ptr(), acc) };
    }
    Ok(acc)
}

/// Step the core and the RTL on `inputs`. Every output, and every mapped register and internal,
/// is compared at every tick, as whole arrays; a group that differs is compared value by value,
/// which names the divergent signals.
pub(super) fn lockstep(lib: &DutLib, params: Params, inputs: &[u32]) -> Reply {
    lockstep_on(lib, &Handle::new(lib), params, inputs)
}

/// [`lockstep`], then the code coverage of the RTL's run written to `out` (a Verilator
/// coverage.dat; the library must be a build with code coverage).
pub(super) fn lockstep_coverage(lib: &DutLib, params: Params, inputs: &[u32], out: &Path) -> Reply {
    if !lib.has_coverage {
        return Reply::Error {
            reason: "the library was built without code coverage (rebuild it)".into(),
        };
    }
    let Ok(path) = std::ffi::CString::new(out.as_os_str().as_encoded_bytes()) else {
        return Reply::Error {
            reason: format!("{}: a path with a NUL byte", out.display()),
        };
    };
    let dut = Handle::new(lib);
    let r = lockstep_on(lib, &dut, params, inputs);
    // SAFETY: a handle of this library and a NUL-terminated path.
    if unsafe { (lib.cov_write)(dut.1, path.as_ptr()) } != 0 {
        return Reply::Error {
            reason: "the library was built without code coverage (rebuild it)".into(),
        };
    }
    r
}

pub(super) fn lockstep_on(lib: &DutLib, dut: &Handle<'_>, params: Params, inputs: &[u32]) -> Reply {
    if let Err(reason) = lib.check_params(&params) {
        return Reply::Error { reason };
    }
    let mut model = match Pmu50::new(params) {
        Ok(m) => m,
        Err(e) => {
            return Reply::Error {
                reason: format!("illegal parameters: {e}"),
            }
        }
    };
    let (nr, nx) = (lib.regs.len(), lib.internals.len());
    let mut out = [0u64; signals::N_OUTPUTS];
    let mut regs = [0u64; signals::N_REGISTERS];
    let mut x = [0u64; signals::N_INTERNALS];
    let mut expect_regs = [0u64; signals::N_REGISTERS];
    let mut expect_x = [0u64; signals::N_INTERNALS];
    let all_outputs: Vec<usize> = (0..signals::N_OUTPUTS).collect();
    let mut mm = Vec::new();
    // SAFETY: arrays of at least the library's counts (checked at load).
    unsafe { (lib.state)(dut.1, out.as_mut_ptr(), regs.as_mut_ptr()) };
    compare(&mut mm, signals::OUTPUTS, &all_outputs, &model.peek(), &out);
    compare(
        &mut mm,
        signals::REGISTERS,
        &lib.regs,
        model.regs(),
        &regs[..nr],
    );
    if !mm.is_empty() {
        return Reply::Diverged {
            tick: 0,
            combinational: false,
            mismatches: mm,
        };
    }
    for (k, &w) in inputs.iter().enumerate() {
        let k = k as u64;
        let (i, word) = input_words(w);
        // SAFETY: arrays of at least the library's counts (checked at load).
        unsafe {
            (lib.tick)(
                dut.1,
                word.as_ptr(),
                x.as_mut_ptr(),
                out.as_mut_ptr(),
                regs.as_mut_ptr(),
            )
        };
        // the internals are built only when the map compares some (the untraced edge is faster)
        let after = if nx > 0 {
            let step = model.step_traced(&i);
            // the mapped internals of cycle k, before edge k+1
            let all =
                words::<Internals, { signals::N_INTERNALS }>(signals::INTERNALS, &step.internals);
            for (d, &j) in expect_x.iter_mut().zip(&lib.internals) {
                *d = all[j];
            }
            if !same(&expect_x[..nx], &x[..nx]) {
                compare::<Internals>(
                    &mut mm,
                    signals::INTERNALS,
                    &lib.internals,
                    &step.internals,
                    &x[..nx],
                );
                return Reply::Diverged {
                    tick: k,
                    combinational: true,
                    mismatches: mm,
                };
            }
            step.after
        } else {
            model.step(&i)
        };
        // outputs (and mapped registers) after edge k+1
        let mut equal = same(
            &words::<Outputs, { signals::N_OUTPUTS }>(signals::OUTPUTS, &after),
            &out,
        );
        if nr > 0 {
            let all = words::<Regs, { signals::N_REGISTERS }>(signals::REGISTERS, model.regs());
            for (d, &j) in expect_regs.iter_mut().zip(&lib.regs) {
                *d = all[j];
            }
            equal &= same(&expect_regs[..nr], &regs[..nr]);
        }
        if !equal {
            compare::<Outputs>(&mut mm, signals::OUTPUTS, &all_outputs, &after, &out);
            compare::<Regs>(
                &mut mm,
                signals::REGISTERS,
                &lib.regs,
                model.regs(),
                &regs[..nr],
            );
            return Reply::Diverged {
                tick: k + 1,
                combinational: false,
                mismatches: mm,
            };
        }
    }
    Reply::Pass {
        ticks: inputs.len() as u64,
    }
}

/// Step the RTL alone on `inputs` (at most `ticks` of them), calling `each` with the edge
/// number and the outputs and mapped registers after it (edge 0: after reset).
pub(super) fn step_alone(
    lib: &DutLib,
    inputs: &[u32],
    ticks: usize,
    mut each: impl FnMut(u64, &[u64], &[u64]),
) {
    let dut = Handle::new(lib);
    let (mut x, mut out, mut regs) = (
        [0u64; signals::N_INTERNALS],
        [0u64; signals::N_OUTPUTS],
        [0u64; signals::N_REGISTERS],
    );
    let nr = lib.regs.len();
    // SAFETY: arrays of at least the library's counts (checked at load).
    unsafe { (lib.state)(dut.1, out.as_mut_ptr(), regs.as_mut_ptr()) };
    each(0, &out, &regs[..nr]);
    for (k, &w) in inputs.iter().take(ticks).enumerate() {
        let (_, word) = input_words(w);
        // SAFETY: as above.
        unsafe {
            (lib.tick)(
                dut.1,
                word.as_ptr(),
                x.as_mut_ptr(),
                out.as_mut_ptr(),
                regs.as_mut_ptr(),
            )
        };
        each(k as u64 + 1, &out, &regs[..nr]);
    }
}

/// Step the RTL alone on `inputs` and return `bus_rdata` after each tick (the register bus
/// read back after reset: what an RTL without parameters fixes).
pub(super) fn probe(lib: &DutLib, inputs: &[u32]) -> Reply {
    let rdata = signals::OUTPUTS
        .iter()
        .position(|s| s.name == "bus_rdata")
        .unwrap_or(0);
    let mut v = Vec::with_capacity(inputs.len());
    step_alone(lib, inputs, inputs.len(), |edge, out, _| {
        if edge > 0 {
            v.push(out[rdata]);
        }
    });
    Reply::Probe { rdata: v }
}

/// Step the RTL alone on `inputs` and return its outputs and mapped registers after each edge
/// `from..=to` (edge 0: after reset).
pub(super) fn trace(lib: &DutLib, inputs: &[u32], from: u64, to: u64) -> Reply {
    let mut values = Vec::new();
    step_alone(
        lib,
        inputs,
        usize::try_from(to).unwrap_or(usize::MAX),
        |edge, out, regs| {
            if (from..=to).contains(&edge) {
                values.push(out.iter().chain(regs).copied().collect::<Vec<u64>>());
            }
        },
    );
    Reply::Trace {
        from,
        regs: lib
            .regs
            .iter()
            .map(|&j| signals::REGISTERS[j].path())
            .collect(),
        values,
    }
}

/// Step the RTL alone on `inputs` (a build with tracing) and write its own waveform of ticks
/// `from..=to` (a tick `ns` nanoseconds long) to `out`.
pub(super) fn vcd(lib: &DutLib, inputs: &[u32], from: u64, to: u64, ns: u64, out: &Path) -> Reply {
    let Ok(path) = std::ffi::CString::new(out.as_os_str().as_encoded_bytes()) else {
        return Reply::Error {
            reason: format!("{}: a path with a NUL byte", out.display()),
        };
    };
    let dut = Handle::new(lib);
    let (mut x, mut o, mut regs) = (
        [0u64; signals::N_INTERNALS],
        [0u64; signals::N_OUTPUTS],
        [0u64; signals::N_REGISTERS],
    );
    let mut open = false;
    let last = to.min(inputs.len().saturating_sub(1) as u64);
    for (k, &w) in inputs.iter().enumerate().take(last as usize + 1) {
        if k as u64 == from {
            // SAFETY: a handle of this library and a NUL-terminated path.
            if unsafe { (lib.vcd_open)(dut.1, path.as_ptr(), ns) } != 0 {
                return Reply::Error {
                    reason: "the library was built without tracing (rebuild it)".into(),
                };
            }
            open = true;
        }
        let (_, word) = input_words(w);
        // SAFETY: arrays of at least the library's counts (checked at load).
        unsafe {
            (lib.tick)(
                dut.1,
                word.as_ptr(),
                x.as_mut_ptr(),
                o.as_mut_ptr(),
                regs.as_mut_ptr(),
            )
        };
    }
    if open {
        // SAFETY: a handle of this library with its VCD open.
        unsafe { (lib.vcd_close)(dut.1) };
    }
    Reply::Pass {
        ticks: last.saturating_sub(from) + 1,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parameters_come_back_from_their_hdl_values() {
        let p = Params::default();
        let v: Vec<u64> = p.hdl_parameters().iter().map(|(_, v)| *v).collect();
        assert_eq!(params_of(&v.try_into().unwrap()).unwrap(), p);
        let mut bad = [0u64; 12];
        bad[2] = 2;
        assert!(params_of(&bad).unwrap_err().contains("ADAPTIVE"));
    }
}
