//! Vector export for HDL testbenches (docs/spec.md 6.2): per tick the core's inputs and the
//! outputs expected after the edge, as whitespace-separated hex fields, `$readmemh`-friendly.
//! Columns and their widths come from the signal table (`pmu50_core::signals`).

use crate::scenario::Scenario;
use crate::sim::{Observer, SimError, TickView};
use pmu50_core::pmu50::Structural;
use pmu50_core::signals;
use pmu50_core::Inputs;
use std::io::Write;

pub struct VectorWriter<W: Write> {
    out: W,
    structural: Structural,
    pending: Option<Inputs>,
    buf: Vec<u8>,
}

fn io(e: std::io::Error) -> SimError {
    SimError::observer("vector file", e)
}

/// Hex digits needed for a field of `width` bits.
fn digits(width: u8) -> usize {
    usize::from(width).div_ceil(4).max(1)
}

/// Bytes of each vector line of `sc` (every field has a fixed number of hex digits, a separator
/// or the newline after it): what [`VectorWriter`] writes per tick.
pub fn line_bytes(sc: &Scenario) -> u64 {
    let s = Structural {
        sync_depth: sc.params.sync_depth,
        cnt_width: sc.params.cnt_width,
    };
    let ins = signals::INPUTS
        .iter()
        .map(|sig| digits(sig.bits(&s)) as u64 + 1);
    let outs = signals::OUTPUTS
        .iter()
        .map(|sig| digits(sig.bits(&s)) as u64 + 1);
    ins.chain(outs).sum()
}

impl<W: Write> VectorWriter<W> {
    pub fn new(mut out: W, sc: &Scenario) -> Result<Self, SimError> {
        let p = &sc.params;
        let s = Structural {
            sync_depth: p.sync_depth,
            cnt_width: p.cnt_width,
        };
        let mut h = String::new();
        h += "// pmu50 vectors v1\n";
        h += &format!("// scenario {}\n", sc.name);
        h += &format!("// clock_ns {}\n", sc.clock_ns());
        for (n, v) in p.hdl_parameters() {
            h += &format!("// param {n} {v}\n");
        }
        h += &format!("// ticks {}\n", sc.ticks);
        let ins: Vec<&str> = signals::INPUTS.iter().map(|sig| sig.name).collect();
        let outs: Vec<&str> = signals::OUTPUTS.iter().map(|sig| sig.name).collect();
        h += &format!("// fields {}\n", ins.len() + outs.len());
        h += &format!("// columns {} | {}\n", ins.join(" "), outs.join(" "));
        out.write_all(h.as_bytes()).map_err(io)?;
        Ok(VectorWriter {
            out,
            structural: s,
            pending: None,
            buf: Vec::with_capacity(128),
        })
    }

    fn line(&mut self, i: &Inputs, v: &TickView<'_>) -> Result<(), SimError> {
        // Fields as fixed-width lower-case hex, written into a reused buffer (one write a line).
        fn hex(buf: &mut Vec<u8>, value: u64, digits: usize) {
            const HEX: &[u8; 16] = b"0123456789abcdef";
            for k in (0..digits).rev() {
                buf.push(HEX[((value >> (4 * k)) & 0xF) as usize]);
            }
            buf.push(b' ');
        }
        let mut l = std::mem::take(&mut self.buf);
        l.clear();
        for sig in signals::INPUTS {
            hex(&mut l, (sig.get)(i), digits(sig.bits(&self.structural)));
        }
        for sig in signals::OUTPUTS {
            hex(
                &mut l,
                (sig.get)(v.ports),
                digits(sig.bits(&self.structural)),
            );
        }
        l.pop();
        l.push(b'\n');
        let r = self.out.write_all(&l).map_err(io);
        self.buf = l;
        r
    }
}

impl<W: Write> VectorWriter<W> {
    /// The writer, after `finish` (for the caller to rename the file into place).
    pub fn into_inner(self) -> W {
        self.out
    }
}

impl<W: Write> Observer for VectorWriter<W> {
    fn tick(&mut self, v: &TickView<'_>) -> Result<(), SimError> {
        if let Some(i) = self.pending.take() {
            self.line(&i, v)?;
        }
        self.pending = Some(*v.inputs);
        Ok(())
    }
    fn finish(&mut self, v: &TickView<'_>) -> Result<(), SimError> {
        if let Some(i) = self.pending.take() {
            self.line(&i, v)?;
        }
        self.out.flush().map_err(io)
    }
}
