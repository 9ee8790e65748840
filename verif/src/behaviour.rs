//! `pmu50 rtl-map`: a map proposed from what the RTL does, not only from what it is called.
//!
//! The RTL (a Verilator build with tracing) and the model are run on the same discovery runs:
//! one that writes each parameter register through the bus and back, reads every address, makes
//! the register bank refuse illegal values, and lets Vs2 fail through key-off strobes; then
//! directed regression seeds at the RTL's default parameters (key cycles, the shaft turning both
//! ways, Vs2 faults, the interval adapting), some aimed at the quadrant-skip clear and at dead
//! strobes. The RTL's own waveform of every run (every signal Verilator keeps, as in a failure's
//! `rtl.vcd`) is read back, one sample a tick: the registers after edge k, the combinational
//! values of cycle k.
//!
//! For each model register and internal, the candidates are the RTL's signals of its width, the
//! fields of packed structs (`cfg_q.pw`), the elements of small arrays and, for a one-bit value,
//! the bits of vectors (`sign_q[0]`). A candidate is proposed only when its sequence equals the
//! model's at every tick of every run (registers after each edge, internals before it): what
//! lockstep would refute is never proposed (a next-state signal, one tick early, is not a
//! register). Among the equal ones the name decides (the twin gets its own names); a model value
//! that never changed in the runs is matched by name among the equal candidates, and says so.
//! Each entry carries its evidence as a comment: the ticks and runs it was equal over, how often
//! it changed, and what the runs did to it (bus writes followed, counts up and down).

use crate::dut::{DutError, VerilatorDut};
use crate::gen::{Action, Bias, Pins, Stimulus};
use crate::map::{name_score, Entry, RtlMap};
use crate::rtl::{self, Design, Fixed};
use crate::shape::Shape;
use pmu50_core::params::Params;
use pmu50_core::pmu50::Structural;
use pmu50_core::signals;
use pmu50_testbench::scenario::Scenario;
use pmu50_testbench::sim::{self, Observer, SimError, SimOptions, TickView};
use std::path::Path;

/// Directed regression seeds run beside the bus run.
const SEEDS: u64 = 4;
/// Seeds aimed at the bins that tell similar values apart.
const AIMED: u64 = 4;
/// Ticks of a discovery run at most.
const MAX_TICKS: u64 = 20_000;

/// One proposed entry and why.
#[derive(Clone, Debug, PartialEq)]
pub struct Found {
    pub entry: Entry,
    pub evidence: String,
}

/// A model value's sequence over the runs, and what the runs did to it.
struct Target {
    /// `timing_generator.tmr` or `kon`.
    model: String,
    block: &'static str,
    var: &'static str,
    width: u32,
    register: bool,
    values: Vec<u64>,
}

/// The model's registers after each edge k and internals of cycle k, k = 0..ticks.
struct Record {
    regs: Vec<[u64; signals::N_REGISTERS]>,
    internals: Vec<[u64; signals::N_INTERNALS]>,
}

impl Observer for Record {
    fn tick(&mut self, v: &TickView<'_>) -> Result<(), SimError> {
        self.regs
            .push(std::array::from_fn(|j| (signals::REGISTERS[j].get)(v.regs)));
        self.internals.push(std::array::from_fn(|j| {
            (signals::INTERNALS[j].get)(v.internals)
        }));
        Ok(())
    }
}

/// A candidate RTL value: a signal of the waveform and the bits of it.
struct Candidate {
    /// The map's name: `pmu50.u_regs.cfg_q.pw`.
    name: String,
    module: String,
    is_port: bool,
    width: u32,
    values: Vec<Option<u64>>,
}

/// The discovery runs' scenarios for an RTL whose parameters are `p`.
fn runs(p: &Params) -> Vec<Stimulus> {
    let fixed = Fixed {
        values: p
            .hdl_parameters()
            .iter()
            .map(|(n, v)| (n.to_string(), *v))
            .collect(),
    };
    let mut v = Vec::new();
    // the bus: key on, each parameter register written to another value and back (a legal
    // change where the set allows it), every address read, refused writes, STATUS cleared
    let mut bus = Stimulus::generate(1, &Bias::uniform().fixing(&fixed));
    bus.params = *p;
    let mut t = 0u64;
    let mut ev = vec![(0, Action::Ig(true))];
    let regs: [(&'static str, u64); 10] = [
        ("CTRL", u64::from(p.adaptive)),
        ("PW", u64::from(p.pw)),
        ("PI", u64::from(p.pi)),
        ("PS", u64::from(p.ps)),
        ("SI_MAX", u64::from(p.si_max)),
        ("SI_MIN", u64::from(p.si_min)),
        ("T1", u64::from(p.t1)),
        ("T2", u64::from(p.t2)),
        ("CTH", u64::from(p.cth)),
        ("SMP_ON", u64::from(p.smp_on)),
    ];
    t += 40;
    for (reg, now) in regs {
        let other = if reg == "CTRL" {
            now ^ 1
        } else if reg == "SI_MAX" {
            now + 3
        } else if now > 2 {
            now - 1
        } else {
            now + 1
        };
        ev.push((
            t,
            Action::Write {
                reg,
                value: other as u16,
            },
        ));
        ev.push((
            t + 7,
            Action::Write {
                reg,
                value: now as u16,
            },
        ));
        t += 20;
    }
    // refused: illegal values (CTH 0, SI_MIN 0), each followed by the clear of STATUS
    ev.push((
        t,
        Action::Write {
            reg: "CTH",
            value: 0,
        },
    ));
    ev.push((
        t + 5,
        Action::Write {
            reg: "STATUS",
            value: 0x0220,
        },
    ));
    t += 20;
    for a in 0u8..=0x16 {
        ev.push((t, Action::Read { addr: a }));
        t += 3;
    }
    ev.push((
        t,
        Action::Write {
            reg: "SI_MIN",
            value: 0,
        },
    ));
    ev.push((
        t + 5,
        Action::Write {
            reg: "STATUS",
            value: 0x0200,
        },
    ));
    t += 20;
    // key off: the sampling strobes, with Vs2 failing through a few of them (a strobe with Sr
    // low takes no sample), then working again
    ev.push((t, Action::Ig(false)));
    let every = u64::from(p.si_max.max(p.smp_on)).max(1);
    ev.push((t + 10, Action::Fault(true)));
    ev.push((t + 10 + 3 * every, Action::Fault(false)));
    t += 10 + 6 * every;
    bus.events = ev;
    bus.ticks = t;
    bus.motion = vec![crate::gen::Motion::Hold { ticks: t }];
    v.push(bus);
    // directed regression seeds at these parameters (each aimed at a bin of an empty coverage)
    let none = vec![0u64; pmu50_coverage::layout().bins.len()];
    for seed in 1..=SEEDS {
        let s = Stimulus::generate(seed, &Bias::directed(&none, Pins::default()).fixing(&fixed));
        let ticks = s.ticks.min(MAX_TICKS);
        v.push(crate::triage::truncate(&s, ticks));
    }
    // seeds aimed at what tells similar values apart: the W1C of STATUS.quadrant_skip (a skip,
    // then the MPU's clear), strobes while Vs2 is dead or its power-good drops (a strobe that
    // takes no sample)
    let aims: Vec<&str> = pmu50_coverage::layout()
        .bins
        .iter()
        .filter(|b| {
            ["skip_clear", "dead_strobe", "pg_drop"]
                .iter()
                .any(|a| b.name.contains(a))
        })
        .map(|b| b.name.as_str())
        .collect();
    for seed in 1..=AIMED {
        let s = Stimulus::generate(
            seed,
            &Bias::from_missing(aims.iter().copied()).fixing(&fixed),
        );
        let ticks = s.ticks.min(MAX_TICKS);
        v.push(crate::triage::truncate(&s, ticks));
    }
    v
}

/// A VCD value (`Value::Bits`, most significant first, maybe shortened) as the bits
/// `lsb..lsb+width` of a `full`-bit value; `None` with an x or z there.
fn bits_of(v: &pmu50_waves::Value, full: u32, lsb: u32, width: u32) -> Option<u64> {
    let pmu50_waves::Value::Bits(b) = v else {
        return None;
    };
    let b = b.as_bytes();
    let mut out = 0u64;
    for k in 0..width {
        let pos = lsb + k; // from the least significant end
        let c = if (pos as usize) < b.len() {
            b[b.len() - 1 - pos as usize]
        } else if pos < full {
            // a shortened value is extended with its first character (0 for 1)
            match b.first() {
                Some(b'1') | None => b'0',
                Some(&c) => c,
            }
        } else {
            b'0'
        };
        match c {
            b'0' => {}
            b'1' => out |= 1 << k,
            _ => return None,
        }
    }
    Some(out)
}

/// The candidates of one run: every signal of the RTL's waveform below the top (not the top's
/// ports, which the regression compares anyway), its fields, elements and bits, sampled at
/// each tick.
fn candidates(vcd: &Path, d: &Design, ticks: u64) -> Result<Vec<Candidate>, String> {
    let w = pmu50_waves::reader::Waveform::open(vcd).map_err(|e| e.to_string())?;
    let mut out = Vec::new();
    for (i, info) in w.signals().iter().enumerate() {
        // Verilator names the top `pmu50` twice (the handle, then the module)
        let path = info
            .path
            .strip_prefix("TOP.")
            .unwrap_or(&info.path)
            .replacen("pmu50.pmu50.", "pmu50.", 1);
        let depth = path.matches('.').count();
        if depth < 2 || info.width == 0 || info.width > 4096 {
            continue;
        }
        // only what a map can name: a variable of the elaboration (Verilator keeps in its
        // waveform some wires its elaboration folds into the port they drive)
        let Some(sig) = d.signal(&path) else {
            continue;
        };
        let sig = Some(sig);
        let full = info.width;
        // the parts to sample: (suffix, lsb, width)
        let mut parts: Vec<(String, u32, u32)> = vec![(String::new(), 0, full)];
        match sig.map(|s| &s.shape) {
            Some(shape @ Shape::Struct { .. }) | Some(shape @ Shape::Packed { .. }) => {
                for (suffix, sel) in shape.fields(16) {
                    if sel.elements.is_empty() {
                        parts.push((suffix, sel.lsb, sel.width));
                    }
                }
            }
            _ => {}
        }
        if (2..=32).contains(&full) {
            let (msb, lsb) = info.index.unwrap_or((i64::from(full) - 1, 0));
            for k in 0..full {
                // the declared index of bit k (from the least significant end)
                let idx = if msb >= lsb {
                    lsb + i64::from(k)
                } else {
                    lsb - i64::from(k)
                };
                parts.push((format!("[{idx}]"), k, 1));
            }
        }
        parts.retain(|(_, _, w)| *w <= 64);
        let changes = w.changes_at(i);
        for (suffix, lsb, width) in parts {
            let mut values = Vec::with_capacity(ticks as usize);
            let mut c = 0usize;
            let mut now: Option<u64> = None;
            for t in 0..ticks {
                while c < changes.len() && changes[c].0 <= t {
                    now = bits_of(&changes[c].1, full, lsb, width);
                    c += 1;
                }
                values.push(now);
            }
            out.push(Candidate {
                name: format!("{path}{suffix}"),
                module: sig.map(|s| s.module.clone()).unwrap_or_default(),
                is_port: sig.is_some_and(|s| s.is_port),
                width,
                values,
            });
        }
    }
    Ok(out)
}

/// Propose a map for the RTL of `list` by its behaviour ([the module's documentation](self)).
pub fn propose(list: &Path) -> Result<(RtlMap, Vec<Found>), DutError> {
    let dut = VerilatorDut::prepare(list, None, Pins::default())?;
    let fl = rtl::FileList::read(list).map_err(rtl::RtlError::from)?;
    let work = tempfile::Builder::new()
        .prefix("pmu50-rtlmap.")
        .tempdir()
        .map_err(|e| DutError::Tool(format!("a scratch folder: {e}")))?;
    let design = rtl::elaborate(&fl, &[], &work.path().join("xml"))?;
    let p = dut.default_params();
    let s = Structural {
        sync_depth: p.sync_depth,
        cnt_width: p.cnt_width,
    };
    let mut targets: Vec<Target> = signals::REGISTERS
        .iter()
        .map(|r| Target {
            model: r.path(),
            block: r.scope,
            var: r.name,
            width: u32::from(r.width.bits(&s)),
            register: true,
            values: Vec::new(),
        })
        .chain(signals::INTERNALS.iter().map(|x| Target {
            model: x.name.to_string(),
            block: "",
            var: x.name,
            width: u32::from(x.width.bits(&s)),
            register: false,
            values: Vec::new(),
        }))
        .collect();
    let mut cands: Vec<Candidate> = Vec::new();
    let stims = runs(&p);
    let mut total = 0u64;
    for (k, stim) in stims.iter().enumerate() {
        let name = format!("discovery_{k}");
        let text = stim.to_toml(&name);
        let path = work.path().join(format!("{name}.toml"));
        let sc = Scenario::parse(&text, &path.display().to_string(), &name, &path)
            .map_err(|e| DutError::Tool(e.to_string()))?;
        let mut rec = crate::lockstep::InputRecorder::default();
        let mut model = Record {
            regs: Vec::new(),
            internals: Vec::new(),
        };
        sim::run(&sc, SimOptions::default(), &mut [&mut rec, &mut model])
            .map_err(|e| DutError::Tool(e.to_string()))?;
        let ticks = rec.inputs.len() as u64;
        let vcd = work.path().join(format!("{name}.vcd"));
        dut.rtl_vcd(
            &sc.params,
            &rec.inputs,
            (0, ticks.saturating_sub(1)),
            1,
            &vcd,
        )?;
        let run = candidates(&vcd, &design, ticks).map_err(DutError::Tool)?;
        let _ = std::fs::remove_file(&vcd);
        for t in targets.iter_mut() {
            for tick in 0..ticks as usize {
                let v = if t.register {
                    let j = signals::REGISTERS
                        .iter()
                        .position(|r| r.path() == t.model)
                        .unwrap_or(0);
                    model.regs.get(tick).map_or(0, |r| r[j])
                } else {
                    let j = signals::INTERNALS
                        .iter()
                        .position(|x| x.name == t.model)
                        .unwrap_or(0);
                    model.internals.get(tick).map_or(0, |x| x[j])
                };
                t.values.push(v);
            }
        }
        if k == 0 {
            cands = run;
        } else {
            // the same signals in every run (one build): append by name
            let mut by_name: std::collections::HashMap<String, Candidate> =
                run.into_iter().map(|c| (c.name.clone(), c)).collect();
            for c in cands.iter_mut() {
                match by_name.remove(&c.name) {
                    Some(r) => c.values.extend(r.values),
                    None => c.values.extend(std::iter::repeat_n(None, ticks as usize)),
                }
            }
        }
        total += ticks;
    }
    let runs = stims.len();
    let mut map = RtlMap::default();
    let mut found = Vec::new();
    let mut taken: Vec<String> = Vec::new();
    for t in &targets {
        let changes = t.values.windows(2).filter(|w| w[0] != w[1]).count();
        let equal: Vec<&Candidate> = cands
            .iter()
            .filter(|c| {
                c.width == t.width
                    && !taken.contains(&c.name)
                    && c.values.len() == t.values.len()
                    && c.values.iter().zip(&t.values).all(|(a, b)| *a == Some(*b))
            })
            .collect();
        let mut ranked: Vec<(f64, &Candidate)> = equal
            .iter()
            .map(|c| {
                (
                    name_score(&c.name, &c.module, c.is_port, t.block, t.var),
                    *c,
                )
            })
            .collect();
        // whole signals before their parts, then the shorter name
        ranked.sort_by(|a, b| {
            b.0.total_cmp(&a.0)
                .then(a.1.name.contains('[').cmp(&b.1.name.contains('[')))
                .then(a.1.name.len().cmp(&b.1.name.len()))
                .then(a.1.name.cmp(&b.1.name))
        });
        let Some((score, best)) = ranked.first() else {
            continue;
        };
        if changes == 0 && *score < 0.75 {
            // nothing told it apart, and the name does not either
            continue;
        }
        let also: Vec<String> = ranked
            .iter()
            .skip(1)
            .take(3)
            .map(|(_, c)| c.name.clone())
            .collect();
        let what = evidence(t, changes);
        let evidence = if changes == 0 {
            format!("never changed in the {runs} discovery runs ({total} ticks): matched by name among the signals equal to it")
        } else {
            format!(
                "equal to the model {} at all {total} ticks of {runs} discovery runs, {changes} changes{what}",
                if t.register {
                    "after every edge"
                } else {
                    "before every edge"
                }
            )
        };
        let evidence = if also.is_empty() {
            evidence
        } else {
            format!("{evidence}; also equal: {}", also.join(", "))
        };
        taken.push(best.name.clone());
        let entry = Entry {
            model: t.model.clone(),
            rtl: best.name.clone(),
        };
        if t.register {
            map.registers.push(entry.clone());
        } else {
            map.internals.push(entry.clone());
        }
        found.push(Found { entry, evidence });
    }
    Ok((map, found))
}

/// What the runs did to a model value, for its evidence: bus writes followed, counts up and
/// down.
fn evidence(t: &Target, changes: usize) -> String {
    if t.block == "register_file" && !["bus_err", "rdata"].contains(&t.var) {
        return format!(" (each a bus write to it, {changes} followed)");
    }
    if matches!(t.var, "cnt_s" | "cnt_c" | "cnt_r" | "tmr") {
        let w = t.width;
        let mask = if w >= 64 { u64::MAX } else { (1 << w) - 1 };
        let (mut up, mut down) = (0, 0);
        for p in t.values.windows(2) {
            if p[1] == (p[0].wrapping_add(1) & mask) {
                up += 1;
            } else if p[1] == (p[0].wrapping_sub(1) & mask) {
                down += 1;
            }
        }
        if up + down > 0 {
            return format!(" (counts up {up} and down {down} times with the runs)");
        }
    }
    String::new()
}

/// The proposal as TOML, each entry with its evidence, and the model names left out listed
/// with the reason.
pub fn proposal_toml(map: &RtlMap, found: &[Found]) -> String {
    let mut s = String::from("# pmu50 rtl-map: a proposed map (model registers and internals -> RTL signals), found by\n# running the RTL and the model side by side: an entry is proposed only when the RTL signal\n# equals the model's value at every tick of every discovery run. Review it: `pmu50 regress\n# --map FILE` compares every entry after every edge (registers) or before it (internals).\n\n[registers]\n");
    let note = |model: &str| -> String {
        found
            .iter()
            .find(|f| f.entry.model == model)
            .map_or(String::new(), |f| format!("  # {}", f.evidence))
    };
    for r in signals::REGISTERS {
        let k = r.path();
        match map.registers.iter().find(|e| e.model == k) {
            Some(e) => s.push_str(&format!("\"{}\" = \"{}\"{}\n", e.model, e.rtl, note(&k))),
            None => s.push_str(&format!(
                "# \"{k}\" = ?  (no RTL signal equals it at every tick of the discovery runs)\n"
            )),
        }
    }
    s.push_str("\n[internals]\n");
    for x in signals::INTERNALS {
        match map.internals.iter().find(|e| e.model == x.name) {
            Some(e) => s.push_str(&format!("{} = \"{}\"{}\n", e.model, e.rtl, note(x.name))),
            None => s.push_str(&format!(
                "# {} = ?  (no RTL signal equals it at every tick of the discovery runs)\n",
                x.name
            )),
        }
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn vcd_values_give_their_bits_even_shortened() {
        let v = pmu50_waves::Value::Bits("101".into());
        assert_eq!(bits_of(&v, 8, 0, 3), Some(5));
        assert_eq!(bits_of(&v, 8, 1, 2), Some(2));
        assert_eq!(bits_of(&v, 8, 3, 5), Some(0));
        let x = pmu50_waves::Value::Bits("x1".into());
        assert_eq!(bits_of(&x, 4, 0, 1), Some(1));
        assert_eq!(bits_of(&x, 4, 0, 2), None);
    }

    #[test]
    fn the_bus_run_writes_every_parameter_register_and_reads_every_address() {
        let p = Params::default();
        let r = runs(&p);
        assert_eq!(r.len() as u64, 1 + SEEDS + AIMED);
        let writes: Vec<&str> = r[0]
            .events
            .iter()
            .filter_map(|(_, a)| match a {
                Action::Write { reg, .. } => Some(*reg),
                _ => None,
            })
            .collect();
        for reg in [
            "CTRL", "PW", "PI", "PS", "SI_MAX", "SI_MIN", "T1", "T2", "CTH", "SMP_ON", "STATUS",
        ] {
            assert!(writes.contains(&reg), "{reg}");
        }
        assert!(r.iter().all(|s| s.ticks <= MAX_TICKS && s.params == p));
    }
}
