//! FST output ([GTKWave's Fast Signal Trace format], written by the `fst-writer` crate) behind the
//! same checked writer as VCD: [`start_fst`] turns a [`VcdBuilder`]'s declarations into an FST
//! header and returns a [`Writer`] over [`FstOut`], so every check of [`crate::writer`] (time
//! order, one change per step, widths, finite reals, handles, frames) holds for FST exactly as
//! for VCD. The hierarchy, names, widths, initial values and value changes are the same as in
//! the VCD of the same calls; [`crate::reader::Waveform`] (wellen) reads both, which a test
//! checks signal by signal.
//!
//! With a time window the full dump at the window start is the FST's initial frame (FST has no
//! "nothing before" state; wellen reports those values from time 0).
//!
//! FST stores its timescale as a power of ten of a second, so `10 ns` is written as 10^-8 s and
//! the time values are the same numbers as in the VCD.
//!
//! [GTKWave's Fast Signal Trace format]: https://gtkwave.sourceforge.net/

use std::fs::File;
use std::io::BufWriter;
use std::path::Path;

use fst_writer::{FstBodyWriter, FstFileType, FstInfo, FstScopeType, FstSignalId, FstSignalType, FstVarDirection, FstVarType};

use crate::writer::{format_real_bits, Declaration, Emitter, Result, ValueRef, VcdBuilder, WriteError, Writer};

/// Value-change data kept in memory before it is compressed and written as one FST block.
const FST_BLOCK: usize = 32 << 20;

fn fst_err(e: fst_writer::FstWriteError) -> WriteError {
    match e {
        fst_writer::FstWriteError::Io(e) => WriteError::Io(e),
        e => WriteError::Fst(e.to_string()),
    }
}

/// FST emitter: value changes go to `fst-writer`'s block buffer, which is compressed and written
/// every [`FST_BLOCK`] bytes and at the end.
pub struct FstOut {
    body: FstBodyWriter<BufWriter<File>>,
    ids: Vec<FstSignalId>,
    widths: Vec<u32>,
    real: Vec<bool>,
    /// time multiplier (1: FST takes any power of ten)
    scale: u64,
    /// start time of the file: the full dump at this time is FST's initial frame
    start: u64,
    scratch: Vec<u8>,
}

/// The checked FST writer.
pub type FstWriter = Writer<FstOut>;

/// Write the FST header of `b`'s declarations to `path` (created or truncated) and switch to the
/// value-change phase.
pub fn start_fst(b: VcdBuilder, path: &Path) -> Result<FstWriter> {
    b.complete()?;
    let ts = b.timescale();
    // FST's timescale is any power of ten: 10 ns is 10^-8 s.
    let (exp, scale) = match ts.factor {
        1 => (ts.unit.exponent(), 1),
        10 => (ts.unit.exponent() + 1, 1),
        _ => (ts.unit.exponent() + 2, 1),
    };
    let start = b.window_start();
    let info = FstInfo {
        start_time: start,
        timescale_exponent: exp as i8,
        version: b.version().to_string(),
        date: String::new(),
        file_type: FstFileType::Verilog,
    };
    let mut h = fst_writer::open_fst(path, &info).map_err(fst_err)?;
    let decls = b.declarations();
    let n = decls.iter().filter(|d| matches!(d, Declaration::Var { .. })).count();
    let mut ids = vec![None; n];
    let mut widths = vec![0; n];
    let mut real = vec![false; n];
    for d in decls {
        match d {
            Declaration::Scope(name) => h.scope(name, "", FstScopeType::Module).map_err(fst_err)?,
            Declaration::Upscope => h.up_scope().map_err(fst_err)?,
            Declaration::Var { index, name, width, real: is_real, wire, range } => {
                let (sig, ty) = if is_real {
                    (FstSignalType::real(), FstVarType::Real)
                } else {
                    (FstSignalType::bit_vec(width), if wire { FstVarType::Wire } else { FstVarType::Reg })
                };
                let name = match range {
                    Some((msb, lsb)) if msb == lsb => format!("{name}[{msb}]"),
                    Some((msb, lsb)) => format!("{name}[{msb}:{lsb}]"),
                    None => name,
                };
                ids[index] = Some(h.var(name, sig, ty, FstVarDirection::Implicit, None).map_err(fst_err)?);
                widths[index] = width;
                real[index] = is_real;
            }
        }
    }
    let ids = ids.into_iter().map(|i| i.ok_or_else(|| WriteError::Fst("a declared variable has no FST id".into()))).collect::<Result<Vec<_>>>()?;
    let body = h.finish().map_err(fst_err)?;
    Ok(b.into_writer(FstOut { body, ids, widths, real, scale, start, scratch: Vec::with_capacity(64) }))
}

impl Emitter for FstOut {
    type Output = ();

    fn dump_begin(&mut self, t: u64) -> Result<()> {
        // The writer's first step is at the window start (0 without a window): its values are
        // FST's initial frame at the file's start time.
        if t == self.start {
            Ok(())
        } else {
            self.body.time_change(t * self.scale).map_err(fst_err)
        }
    }

    fn dump_end(&mut self) -> Result<()> {
        Ok(())
    }

    #[inline]
    fn timestamp(&mut self, t: u64) -> Result<()> {
        if self.body.size() >= FST_BLOCK {
            self.body.flush().map_err(fst_err)?;
        }
        self.body.time_change(t * self.scale).map_err(fst_err)
    }

    #[inline]
    fn value(&mut self, i: usize, v: ValueRef<'_>) -> Result<()> {
        let id = self.ids[i];
        match v {
            ValueRef::Int(v) => {
                let w = self.widths[i];
                self.scratch.clear();
                self.scratch.extend((0..w).rev().map(|k| if k < 64 && (v >> k) & 1 == 1 { b'1' } else { b'0' }));
                self.body.signal_change(id, &self.scratch).map_err(fst_err)
            }
            ValueRef::Bits(b) => self.body.signal_change(id, b).map_err(fst_err),
            ValueRef::Real(r) => {
                debug_assert!(self.real[i]);
                self.body.signal_change(id, &format_real_bits(r)).map_err(fst_err)
            }
        }
    }

    fn finish(mut self, closing: Option<u64>) -> Result<()> {
        if let Some(t) = closing {
            self.body.time_change(t * self.scale).map_err(fst_err)?;
        }
        let mut out = self.body.finish().map_err(fst_err)?;
        std::io::Write::flush(&mut out)?;
        Ok(())
    }
}
