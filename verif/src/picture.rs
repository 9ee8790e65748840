//! The picture of a failure: an SVG timing diagram of the shrunk repro around the first
//! divergence, for `failures/<signature>/divergence.svg` and the failure's row of report.html.
//!
//! One column per edge (tick k: the values after rising edge k, the inputs sampled by it), the
//! first divergence marked in red. Rows, top to bottom: the inputs that drove the run (key,
//! comparators, Vs2 power-good), the register bus whenever the run uses it (write enable,
//! address, write data, and the read data as the model and the DUT have it: reads too), every
//! signal that differs at the failing tick as the model has it and as the DUT has it (from the
//! DUT's trace where the backend gives one; otherwise the DUT's value at the divergence), then
//! the ports that pace the core (`sig`, `st`, `smp`, `sr`) and the registers of the block that
//! diverged, as the model has them. It needs nothing but a browser: no script, no external
//! file.

use crate::check::Failure;
use crate::dut::DutTrace;
use pmu50_core::pmu50::Structural;
use pmu50_core::signals::{self, Width};
use pmu50_testbench::plot::svg::{Anchor, Svg};
use pmu50_testbench::scenario::Scenario;
use pmu50_testbench::sim::{self, Observer, SimError, SimOptions, TickView};

/// Edges shown before and after the divergence.
const BEFORE: u64 = 24;
const AFTER: u64 = 4;

/// One row: a name, a width in bits and a value per column (`None`: unknown).
struct Row {
    name: String,
    bits: u8,
    values: Vec<Option<u64>>,
    /// Drawn in red where it differs from this other row (the DUT against the model).
    against: Option<usize>,
}

/// The model's values over the window: by signal path, a value per edge.
pub(crate) struct Capture {
    from: u64,
    to: u64,
    pub(crate) inputs: Vec<[u64; signals::N_INPUTS]>,
    outputs: Vec<[u64; signals::N_OUTPUTS]>,
    regs: Vec<[u64; signals::N_REGISTERS]>,
    internals: Vec<[u64; signals::N_INTERNALS]>,
    s: Structural,
}

impl Capture {
    fn col(&self, edge: u64) -> Option<usize> {
        (self.from..=self.to)
            .contains(&edge)
            .then(|| (edge - self.from) as usize)
    }

    /// The model's values of edges `from..=to` of `sc`.
    pub(crate) fn run(sc: &Scenario, from: u64, to: u64) -> Result<Capture, SimError> {
        let n = (to - from + 1) as usize;
        let mut cap = Capture {
            from,
            to,
            inputs: vec![[0; signals::N_INPUTS]; n],
            outputs: vec![[0; signals::N_OUTPUTS]; n],
            regs: vec![[0; signals::N_REGISTERS]; n],
            internals: vec![[0; signals::N_INTERNALS]; n],
            s: Structural {
                sync_depth: sc.params.sync_depth,
                cnt_width: sc.params.cnt_width,
            },
        };
        let mut short = sc.clone();
        short.ticks = sc.ticks.min(to + 1);
        sim::run(&short, SimOptions::default(), &mut [&mut cap])?;
        Ok(cap)
    }

    /// A signal by its model path (`si`, `drive_interval.si`, `internals.kon`, `in bus_addr`):
    /// its width and its value per edge.
    pub(crate) fn values(&self, p: &str) -> Option<(u8, Vec<Option<u64>>)> {
        let bits = |w: Width| w.bits(&self.s);
        if let Some(name) = p.strip_prefix("in ") {
            let j = signals::INPUTS.iter().position(|x| x.name == name)?;
            return Some((
                bits(signals::INPUTS[j].width),
                self.inputs.iter().map(|v| Some(v[j])).collect(),
            ));
        }
        if let Some(j) = signals::OUTPUTS.iter().position(|x| x.path() == p) {
            return Some((
                bits(signals::OUTPUTS[j].width),
                self.outputs.iter().map(|v| Some(v[j])).collect(),
            ));
        }
        if let Some(j) = signals::REGISTERS.iter().position(|x| x.path() == p) {
            return Some((
                bits(signals::REGISTERS[j].width),
                self.regs.iter().map(|v| Some(v[j])).collect(),
            ));
        }
        if let Some(j) = signals::INTERNALS.iter().position(|x| x.path() == p) {
            return Some((
                bits(signals::INTERNALS[j].width),
                self.internals.iter().map(|v| Some(v[j])).collect(),
            ));
        }
        None
    }

    /// Whether the run drives the register bus in the window (a write, or a read of an
    /// address other than 0).
    pub(crate) fn uses_bus(&self) -> bool {
        self.inputs.iter().any(|i| i[4] != 0 || i[5] != 0)
    }
}

/// The DUT's values of signal `p` (model path) over edges `from..=to`, from its trace.
pub(crate) fn dut_values(t: &DutTrace, p: &str, from: u64, to: u64) -> Option<Vec<Option<u64>>> {
    let v = t.signals.iter().find(|(nm, _)| nm == p).map(|(_, v)| v)?;
    Some(
        (from..=to)
            .map(|e| {
                e.checked_sub(t.from)
                    .and_then(|i| v.get(i as usize).copied())
            })
            .collect(),
    )
}

/// The model paths of the signals that differ at a failure's tick (the first one alone where
/// the failure names no set).
pub(crate) fn diverging(f: &Failure) -> Vec<String> {
    let all: Vec<&String> = if f.diverging.is_empty() {
        vec![&f.signal]
    } else {
        f.diverging.iter().collect()
    };
    all.iter()
        .map(|s| s.trim_start_matches("pmu50.").to_string())
        .collect()
}

impl Observer for Capture {
    fn tick(&mut self, v: &TickView<'_>) -> Result<(), SimError> {
        // values during tick k are those after edge k; the inputs of tick k are sampled by edge k+1
        if let Some(c) = self.col(v.tick) {
            self.outputs[c] = std::array::from_fn(|j| (signals::OUTPUTS[j].get)(v.ports));
            self.regs[c] = std::array::from_fn(|j| (signals::REGISTERS[j].get)(v.regs));
            self.internals[c] = std::array::from_fn(|j| (signals::INTERNALS[j].get)(v.internals));
        }
        if let Some(c) = self.col(v.tick + 1) {
            self.inputs[c] = std::array::from_fn(|j| (signals::INPUTS[j].get)(v.inputs));
        }
        Ok(())
    }
    fn finish(&mut self, v: &TickView<'_>) -> Result<(), SimError> {
        if let Some(c) = self.col(v.tick) {
            self.outputs[c] = std::array::from_fn(|j| (signals::OUTPUTS[j].get)(v.ports));
            self.regs[c] = std::array::from_fn(|j| (signals::REGISTERS[j].get)(v.regs));
        }
        Ok(())
    }
}

/// The edges of the picture of a failure at edge `tick` of a run of `ticks`.
pub fn window(tick: u64, ticks: u64) -> (u64, u64) {
    let to = (tick + AFTER).min(ticks).max(tick);
    (tick.saturating_sub(BEFORE), to)
}

/// The SVG of failure `f` of scenario `sc` (a shrunk repro), with the DUT's trace if any.
pub fn divergence_svg(
    sc: &Scenario,
    f: &Failure,
    dut: Option<&DutTrace>,
) -> Result<String, SimError> {
    let (from, to) = window(f.tick, sc.ticks);
    let cap = Capture::run(sc, from, to)?;
    let mut rows: Vec<Row> = Vec::new();
    // inputs: the key, the comparators, Vs2
    for sig in &signals::INPUTS[..4] {
        if let Some((bits, values)) = cap.values(&format!("in {}", sig.name)) {
            rows.push(Row {
                name: format!("in {}", sig.name),
                bits,
                values,
                against: None,
            });
        }
    }
    let dut_row = |rows: &mut Vec<Row>, p: &str, marked: &mut String| {
        let Some((b, values)) = cap.values(p) else {
            return;
        };
        let model_row = rows.len();
        rows.push(Row {
            name: format!("{p} (model)"),
            bits: b,
            values,
            against: None,
        });
        let dut_values = match dut.and_then(|t| dut_values(t, p, from, to)) {
            Some(v) => v,
            None => {
                let got = (format!("pmu50.{p}") == f.signal)
                    .then(|| u64::from_str_radix(f.got.trim_start_matches("0x"), 16).ok())
                    .flatten();
                *marked = " (the DUT's value is known at the divergence only)".into();
                (from..=to)
                    .map(|e| if e == f.tick { got } else { None })
                    .collect()
            }
        };
        rows.push(Row {
            name: format!("{p} (DUT)"),
            bits: b,
            values: dut_values,
            against: Some(model_row),
        });
    };
    let mut marked = String::new();
    let diverging = diverging(f);
    // the bus whenever the run uses it: write enable, address, data, and the read data
    if cap.uses_bus() {
        for sig in &signals::INPUTS[4..] {
            if let Some((bits, values)) = cap.values(&format!("in {}", sig.name)) {
                rows.push(Row {
                    name: format!("in {}", sig.name),
                    bits,
                    values,
                    against: None,
                });
            }
        }
        if !diverging.iter().any(|d| d == "bus_rdata") {
            let mut none = String::new();
            dut_row(&mut rows, "bus_rdata", &mut none);
            if !none.is_empty() && dut.is_none() {
                // no trace: the model's read data alone
                rows.pop();
            }
        }
    }
    // every signal that differs at the failing tick: the model's, then the DUT's
    for p in &diverging {
        dut_row(&mut rows, p, &mut marked);
    }
    // the ports that pace the core, and the block's registers, as the model has them
    for p in ["sig", "st", "smp", "sr"] {
        if !diverging.iter().any(|d| d == p) {
            if let Some((b, values)) = cap.values(p) {
                rows.push(Row {
                    name: p.into(),
                    bits: b,
                    values,
                    against: None,
                });
            }
        }
    }
    for r in signals::REGISTERS
        .iter()
        .filter(|r| r.scope == f.block && !diverging.contains(&r.path()) && !r.free_running)
    {
        if let Some((b, values)) = cap.values(&r.path()) {
            rows.push(Row {
                name: r.path(),
                bits: b,
                values,
                against: None,
            });
        }
    }
    let note = if diverging.len() > 1 {
        format!("{marked}; {} signals differ at this tick", diverging.len())
    } else {
        marked
    };
    Ok(render(sc, f, from, to, &rows, &note))
}

/// A row of the register bus (`in bus_addr`, `bus_rdata (DUT)`, ...): its words are shown in hex.
pub(crate) fn is_bus(name: &str) -> bool {
    ["bus_addr", "bus_wdata", "bus_rdata"]
        .iter()
        .any(|b| name.contains(b))
}

fn render(sc: &Scenario, f: &Failure, from: u64, to: u64, rows: &[Row], note: &str) -> String {
    let n = (to - from + 1) as f64;
    let (left, top, row_h, col_w) = (190.0, 58.0, 24.0, 30.0);
    let width = left + n * col_w + 20.0;
    let height = top + rows.len() as f64 * row_h + 36.0;
    let mut svg = Svg::new(width, height);
    svg.rect(0.0, 0.0, width, height, "#ffffff", None);
    let title = format!(
        "{}: first divergence at tick {} on {} (expected {}, got {}){}",
        sc.name, f.tick, f.signal, f.expected, f.got, note
    );
    svg.text(8.0, 18.0, 13.0, Anchor::Start, "#000000", &title);
    svg.text(8.0, 36.0, 11.0, Anchor::Start, "#444444", &format!("block {}, FIG. path {}; one column per rising edge k (values after edge k, inputs sampled by it), values in decimal, the bus in hex", f.block, f.fig));
    let x_of = |edge: u64| left + (edge - from) as f64 * col_w;
    // the divergence column
    if (from..=to).contains(&f.tick) {
        svg.rect(
            x_of(f.tick),
            top - 6.0,
            col_w,
            rows.len() as f64 * row_h + 6.0,
            "#fde0e0",
            None,
        );
    }
    // tick labels every 4 edges, and at the divergence
    for e in from..=to {
        let x = x_of(e);
        svg.line(
            x,
            top - 6.0,
            x,
            top + rows.len() as f64 * row_h,
            "#eeeeee",
            1.0,
            None,
        );
        if (e - from).is_multiple_of(4) || e == f.tick {
            svg.text(
                x + col_w / 2.0,
                height - 14.0,
                10.0,
                Anchor::Middle,
                if e == f.tick { "#c00000" } else { "#444444" },
                &e.to_string(),
            );
        }
    }
    for (r, row) in rows.iter().enumerate() {
        let y0 = top + r as f64 * row_h;
        // the bus (addresses, data words) in hex as in docs/spec.md, counts and times in decimal
        let hex = is_bus(&row.name);
        let (hi, lo) = (y0 + 4.0, y0 + row_h - 6.0);
        svg.text(
            left - 8.0,
            y0 + row_h / 2.0 + 4.0,
            11.0,
            Anchor::End,
            "#000000",
            &row.name,
        );
        let differs = |c: usize| -> bool {
            row.against.is_some_and(|m| {
                row.values[c].is_some() && rows[m].values.get(c).copied().flatten() != row.values[c]
            })
        };
        for (c, v) in row.values.iter().enumerate() {
            let x = left + c as f64 * col_w;
            let colour = if differs(c) { "#c00000" } else { "#1f4e9c" };
            match v {
                None => svg.rect(x + 1.0, hi, col_w - 2.0, lo - hi, "#f2f2f2", None),
                Some(v) if row.bits == 1 => {
                    let y = if *v != 0 { hi } else { lo };
                    svg.line(x, y, x + col_w, y, colour, 2.0, None);
                    // the edge between two columns
                    if let Some(Some(prev)) = c.checked_sub(1).map(|p| row.values[p]) {
                        if prev != *v {
                            svg.line(x, hi, x, lo, colour, 2.0, None);
                        }
                    }
                }
                Some(v) => {
                    let changed = c == 0 || row.values[c - 1] != Some(*v);
                    svg.line(x, hi, x + col_w, hi, colour, 1.2, None);
                    svg.line(x, lo, x + col_w, lo, colour, 1.2, None);
                    if changed {
                        svg.line(x, hi, x, lo, colour, 1.2, None);
                        let label = if hex {
                            format!("0x{v:x}")
                        } else {
                            v.to_string()
                        };
                        // the columns the value holds for: a label that would run into the
                        // next value is drawn smaller (digits are about 0.62 em wide)
                        let run = row.values[c..]
                            .iter()
                            .take_while(|x| **x == Some(*v))
                            .count() as f64;
                        let fits = (run * col_w - 5.0) / (0.62 * label.len() as f64);
                        svg.text(
                            x + 3.0,
                            lo - 3.0,
                            fits.clamp(6.5, 9.5),
                            Anchor::Start,
                            colour,
                            &label,
                        );
                    }
                }
            }
        }
    }
    svg.finish()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_window_holds_the_divergence_and_stays_in_the_run() {
        assert_eq!(window(100, 1000), (76, 104));
        assert_eq!(window(3, 1000), (0, 7));
        assert_eq!(window(999, 1000), (975, 1000));
    }

    #[test]
    fn a_picture_marks_the_diverging_signal_of_the_model_and_the_dut() {
        let sc = Scenario::parse(
            "duration = \"10 ms\"\n",
            "t.toml",
            "t",
            std::path::Path::new("t.toml"),
        )
        .unwrap();
        let f = Failure {
            kind: "dut".into(),
            tick: 40,
            signal: "pmu50.st".into(),
            expected: "0x1".into(),
            got: "0x0".into(),
            block: "ports".into(),
            fig: "-".into(),
            diverging: Vec::new(),
            detail: String::new(),
        };
        let svg = divergence_svg(&sc, &f, None).unwrap();
        assert!(svg.starts_with("<svg") || svg.contains("<svg"), "an SVG");
        assert!(
            svg.contains("st (model)") && svg.contains("st (DUT)") && svg.contains("in ig"),
            "{svg}"
        );
        assert!(svg.contains("known at the divergence only"));
        // with a trace, the DUT's row is drawn where it differs
        let t = DutTrace {
            from: 0,
            signals: vec![("st".into(), vec![0; 60])],
        };
        let svg = divergence_svg(&sc, &f, Some(&t)).unwrap();
        assert!(svg.contains("#c00000") && !svg.contains("known at the divergence only"));
    }

    #[test]
    fn a_picture_draws_every_diverging_signal_and_the_bus_when_it_only_reads() {
        use crate::gen::{Action, Bias, Motion, Stimulus};
        let mut stim = Stimulus::generate(1, &Bias::uniform());
        stim.params = pmu50_core::Params::default();
        stim.events = vec![(0, Action::Ig(true)), (30, Action::Read { addr: 0x13 })];
        stim.ticks = 60;
        stim.motion = vec![Motion::Hold { ticks: 60 }];
        let text = stim.to_toml("t");
        let sc = Scenario::parse(&text, "t.toml", "t", std::path::Path::new("t.toml")).unwrap();
        let f = Failure {
            kind: "dut".into(),
            tick: 40,
            signal: "pmu50.bus_err".into(),
            expected: "0x0".into(),
            got: "0x1".into(),
            block: "ports".into(),
            fig: "-".into(),
            diverging: vec!["pmu50.bus_err".into(), "pmu50.si".into()],
            detail: String::new(),
        };
        let t = DutTrace {
            from: 0,
            signals: vec![
                ("bus_err".into(), vec![1; 60]),
                ("si".into(), vec![7; 60]),
                ("bus_rdata".into(), vec![0; 60]),
            ],
        };
        let svg = divergence_svg(&sc, &f, Some(&t)).unwrap();
        for row in [
            "in bus_addr",
            "in bus_we",
            "in bus_wdata",
            "bus_rdata (model)",
            "bus_rdata (DUT)",
            "bus_err (model)",
            "bus_err (DUT)",
            "si (model)",
            "si (DUT)",
            "2 signals differ at this tick",
        ] {
            assert!(svg.contains(row), "{row}: {svg}");
        }
        // the address read in hex (as docs/spec.md writes it), the DUT's interval in decimal
        assert!(svg.contains(">0x13</text>"), "{svg}");
        assert!(svg.contains(">7</text>"), "{svg}");
        // a run that never touches the bus (the key stays off: no MPU) draws no bus rows
        stim.events = vec![(0, Action::Ig(false))];
        let text = stim.to_toml("t");
        let sc = Scenario::parse(&text, "t.toml", "t", std::path::Path::new("t.toml")).unwrap();
        let svg = divergence_svg(&sc, &f, Some(&t)).unwrap();
        assert!(!svg.contains("in bus_addr") && svg.contains("si (DUT)"));
    }
}
