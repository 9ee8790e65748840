//! VCD output of a run, with its GTKWave save file.
//!
//! Hierarchy = the model's structure (docs/signals.md):
//! - `pmu50`: the core's ports (inputs and outputs), names exactly as the HDL contract;
//! - `pmu50.<block>`: every register of that block (`pmu50::Regs` field paths);
//! - `pmu50.internals`: combinational signals of the cycle (`kon`, `fig17`, ...);
//! - `env`: analog values as `real` (θ, sin2, cos2, Vs2, Vp, Vr, θ1, θm).
//!
//! Time convention: docs/spec.md 6.1. Timescale: the largest of 1 us, 100 ns, 10 ns, 1 ns that
//! divides the clock period. Reals are rounded (angles to 0.001 deg, volts to 0.1 mV) so that
//! settling tails do not flood the file; only changes are written.

use crate::sim::{Observer, SimError, TickView};
use pmu50_core::pmu50::Structural;
use pmu50_waves::gtkw::{Analog, Color, Format, GtkwSave, Trace};
use pmu50_waves::writer::{BitType, SigId, VcdBuilder, VcdWriter};
use pmu50_waves::{TimeUnit, Timescale};
use crate::fsout::AtomicFile;
use std::io::BufWriter;
use std::path::{Path, PathBuf};

const VERSION: &str = concat!("pmu50 reference model ", env!("CARGO_PKG_VERSION"));

struct Ids {
    inputs: Vec<SigId>,
    ports: Vec<SigId>,
    regs: Vec<SigId>,
    internals: Vec<SigId>,
    env: Vec<SigId>,
}

pub struct VcdObserver {
    w: Option<VcdWriter<BufWriter<AtomicFile>>>,
    /// The complete VCD (temporary file) after `finish`, and the save file, for the caller to
    /// rename into place (crate::fsout).
    file: Option<AtomicFile>,
    gtkw: Option<GtkwSave>,
    ids: Ids,
    unit_ns: u64,
    s: Structural,
    path: PathBuf,
}

fn err(path: &Path, e: impl std::fmt::Display) -> SimError {
    SimError::Observer(format!("{}: {e}", path.display()))
}

/// Timescale for a clock period in ns.
pub fn timescale_for(clock_ns: u64) -> (Timescale, u64) {
    for (unit, ns, ts) in [
        (1_000u64, 1_000u64, Timescale::new(1, TimeUnit::Us)),
        (100, 100, Timescale::new(100, TimeUnit::Ns)),
        (10, 10, Timescale::new(10, TimeUnit::Ns)),
    ] {
        if clock_ns.is_multiple_of(unit) {
            return (ts, ns);
        }
    }
    (Timescale::new(1, TimeUnit::Ns), 1)
}

fn round(v: f64, q: f64) -> f64 {
    let r = (v / q).round() * q;
    if r == 0.0 { 0.0 } else { r }
}

fn env_values(v: &TickView<'_>) -> [f64; 8] {
    let e = v.env;
    [
        round(e.theta_deg, 1e-3),
        round(e.sin2_v, 1e-4),
        round(e.cos2_v, 1e-4),
        round(e.vs2_v, 1e-4),
        round(e.vp_v, 1e-4),
        round(e.vr_v, 1e-4),
        round(e.theta1_deg.unwrap_or(0.0), 1e-3),
        round(e.theta_m_deg.unwrap_or(0.0), 1e-3),
    ]
}

const ENV_NAMES: [&str; 8] = ["theta_deg", "sin2_v", "cos2_v", "vs2_v", "vp_v", "vr_v", "theta1_deg", "theta_m_deg"];

impl VcdObserver {
    /// Create `<dir>/<name>.vcd` and `<dir>/<name>.gtkw`. `window` is in ticks.
    pub fn create(dir: &Path, name: &str, s: Structural, clock_ns: u64, window: Option<(u64, u64)>, first: &TickView<'_>) -> Result<VcdObserver, SimError> {
        let path = dir.join(format!("{name}.vcd"));
        let (ts, unit_ns) = timescale_for(clock_ns);
        let mut b = VcdBuilder::new(ts, VERSION).map_err(|e| err(&path, e))?;
        if let Some((a, z)) = window {
            b.window(a * clock_ns / unit_ns, z * clock_ns / unit_ns).map_err(|e| err(&path, e))?;
        }
        let mut gt = GtkwSave::new(&format!("{name}.vcd")).map_err(|e| err(&path, e))?;
        let vec_or_bit = |b: &mut VcdBuilder, ty: BitType, name: &str, width: u8, v: u64| -> Result<SigId, SimError> {
            if width == 1 {
                b.add_bit(ty, name, (v != 0).into()).map_err(|e| err(&path, e))
            } else {
                b.add_vector(ty, name, u32::from(width) - 1, 0, v).map_err(|e| err(&path, e))
            }
        };
        b.push_scope("pmu50").map_err(|e| err(&path, e))?;
        let inputs = first
            .inputs
            .values()
            .iter()
            .map(|&(n, w, v)| vec_or_bit(&mut b, BitType::Wire, n, w, v))
            .collect::<Result<Vec<_>, _>>()?;
        let ports = first
            .ports
            .values(&s)
            .iter()
            .map(|&(n, w, v)| vec_or_bit(&mut b, BitType::Wire, n, w, v))
            .collect::<Result<Vec<_>, _>>()?;
        let mut regs = Vec::new();
        let values = first.regs.values(&s);
        let mut block = "";
        for r in &values {
            if r.block != block {
                if !block.is_empty() {
                    b.pop_scope().map_err(|e| err(&path, e))?;
                }
                b.push_scope(r.block).map_err(|e| err(&path, e))?;
                block = r.block;
            }
            regs.push(vec_or_bit(&mut b, BitType::Reg, r.name, r.width, r.value)?);
        }
        b.pop_scope().map_err(|e| err(&path, e))?;
        b.push_scope("internals").map_err(|e| err(&path, e))?;
        let internals = first
            .internals
            .values()
            .iter()
            .map(|&(n, w, v)| vec_or_bit(&mut b, BitType::Wire, n, w, v))
            .collect::<Result<Vec<_>, _>>()?;
        b.pop_scope().map_err(|e| err(&path, e))?;
        b.pop_scope().map_err(|e| err(&path, e))?;
        b.push_scope("env").map_err(|e| err(&path, e))?;
        let ev = env_values(first);
        let env = ENV_NAMES.iter().zip(ev).map(|(n, v)| b.add_real(n, v).map_err(|e| err(&path, e))).collect::<Result<Vec<_>, _>>()?;
        b.pop_scope().map_err(|e| err(&path, e))?;

        // GTKWave save file: one group per block, contract ports first.
        let name_of = |b: &VcdBuilder, id: SigId| b.gtkwave_name(id).map_err(|e| err(&path, e));
        let port_names: Vec<(&str, u8)> = first.ports.values(&s).iter().map(|&(n, w, _)| (n, w)).collect();
        let fmt_for = |n: &str, w: u8| match n {
            "cnt_s" | "cnt_c" => Format::SignedDecimal,
            "si" | "cnt_r" | "tmr" | "pw" | "pi" | "ps" | "si_max" | "si_min" | "t1" | "t2" | "cth" | "smp_on" | "fig17" | "fig18" => Format::Decimal,
            _ if w > 1 => Format::Hex,
            _ => Format::Binary,
        };
        let gerr = |e: pmu50_waves::gtkw::GtkwError| err(&path, e);
        gt.begin_group("ports", false).map_err(gerr)?;
        for (id, &(n, _, _)) in inputs.iter().zip(first.inputs.values().iter()) {
            if n == "ig" {
                gt.trace(Trace::new(name_of(&b, *id)?)).map_err(gerr)?;
            }
        }
        for (id, &(n, w)) in ports.iter().zip(&port_names) {
            gt.trace(Trace::new(name_of(&b, *id)?).format(fmt_for(n, w))).map_err(gerr)?;
        }
        gt.end_group().map_err(gerr)?;
        gt.begin_group("inputs", true).map_err(gerr)?;
        for id in &inputs {
            gt.trace(Trace::new(name_of(&b, *id)?)).map_err(gerr)?;
        }
        gt.end_group().map_err(gerr)?;
        let mut block = "";
        for (id, r) in regs.iter().zip(&values) {
            if r.block != block {
                if !block.is_empty() {
                    gt.end_group().map_err(gerr)?;
                }
                gt.begin_group(r.block, r.block == "register_file").map_err(gerr)?;
                block = r.block;
            }
            gt.trace(Trace::new(name_of(&b, *id)?).format(fmt_for(r.name, r.width))).map_err(gerr)?;
        }
        gt.end_group().map_err(gerr)?;
        gt.begin_group("internals", true).map_err(gerr)?;
        for (id, &(n, w, _)) in internals.iter().zip(first.internals.values().iter()) {
            gt.trace(Trace::new(name_of(&b, *id)?).format(fmt_for(n, w))).map_err(gerr)?;
        }
        gt.end_group().map_err(gerr)?;
        gt.begin_group("env", false).map_err(gerr)?;
        let colors = [Color::Yellow, Color::Orange, Color::Green, Color::Red, Color::Violet, Color::Indigo, Color::Blue, Color::Yellow];
        for ((id, n), c) in env.iter().zip(ENV_NAMES).zip(colors) {
            let rows = if n.starts_with("theta") || n.ends_with("2_v") { 6 } else { 3 };
            gt.trace(Trace::new(name_of(&b, *id)?).analog(Analog::Interpolated, rows).color(c)).map_err(gerr)?;
        }
        gt.end_group().map_err(gerr)?;
        gt.size(1400, 900);
        if let Some((a, z)) = window {
            gt.fit(a * clock_ns / unit_ns, z * clock_ns / unit_ns);
        }
        let file = AtomicFile::create(&path).map_err(|e| err(&path, e))?;
        let w = b.start(BufWriter::new(file)).map_err(|e| err(&path, e))?;
        Ok(VcdObserver { w: Some(w), file: None, gtkw: Some(gt), ids: Ids { inputs, ports, regs, internals, env }, unit_ns, s, path })
    }

    /// The complete VCD (after `finish`, still a temporary file) and its save file.
    pub fn into_outputs(self) -> (Option<AtomicFile>, Option<GtkwSave>) {
        (self.file, self.gtkw)
    }

    fn dump(&mut self, v: &TickView<'_>, with_inputs: bool) -> Result<(), SimError> {
        let path = self.path.clone();
        let w = self.w.as_mut().ok_or_else(|| err(&path, "writer already closed"))?;
        w.set_time(v.time_ns / self.unit_ns).map_err(|e| err(&path, e))?;
        for (id, (_, _, val)) in self.ids.ports.iter().zip(v.ports.values(&self.s)) {
            w.change_vector(*id, val).map_err(|e| err(&path, e))?;
        }
        for (id, r) in self.ids.regs.iter().zip(v.regs.values(&self.s)) {
            w.change_vector(*id, r.value).map_err(|e| err(&path, e))?;
        }
        if with_inputs {
            for (id, (_, _, val)) in self.ids.inputs.iter().zip(v.inputs.values()) {
                w.change_vector(*id, val).map_err(|e| err(&path, e))?;
            }
            for (id, (_, _, val)) in self.ids.internals.iter().zip(v.internals.values()) {
                w.change_vector(*id, val).map_err(|e| err(&path, e))?;
            }
            for (id, val) in self.ids.env.iter().zip(env_values(v)) {
                w.change_real(*id, val).map_err(|e| err(&path, e))?;
            }
        }
        Ok(())
    }
}

impl Observer for VcdObserver {
    fn tick(&mut self, v: &TickView<'_>) -> Result<(), SimError> {
        self.dump(v, true)
    }

    fn finish(&mut self, v: &TickView<'_>) -> Result<(), SimError> {
        self.dump(v, false)?;
        let path = self.path.clone();
        let w = self.w.take().ok_or_else(|| err(&path, "writer already closed"))?;
        let out = w.finish().map_err(|e| err(&path, e))?;
        self.file = Some(out.into_inner().map_err(|e| err(&path, e.error()))?);
        Ok(())
    }
}
