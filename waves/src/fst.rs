//! FST output ([GTKWave's Fast Signal Trace format], written by the `fst-writer` crate) behind the
//! same checked writer as VCD: [`start_fst`] turns a [`VcdBuilder`]'s declarations into an FST
//! header and returns a [`Writer`] over [`FstOut`], so every check of [`crate::writer`] (time
//! order, one change per step, widths, finite reals, handles, frames) holds for FST exactly as
//! for VCD. The hierarchy, names, widths, initial values and value changes are the same as in
//! the VCD of the same calls; [`crate::reader::Waveform`] (wellen) reads both, which a test
//! checks signal by signal.
//!
//! With a time window the full dump at the window start is the FST's initial frame, and the file
//! starts at the window start: the header's start time and the first value-change block's start
//! time (the time of that frame) are the window start, as in the VCD, whose first time stamp is
//! the window start. `fst-writer` 0.3 always writes 0 there (and writes its `FstInfo::start_time`
//! into the header's *time zero* field, which viewers add to every displayed time), so
//! [`start_fst`] passes time zero 0 and [`FstOut`] sets both start times when the file is
//! finished ([`set_start_time`]). wellen (fst-reader) and GTKWave then report the frame at the
//! window start, exactly where the VCD has it.
//!
//! FST stores its timescale as a power of ten of a second, so `10 ns` is written as 10^-8 s and
//! the time values are the same numbers as in the VCD.
//!
//! [GTKWave's Fast Signal Trace format]: https://gtkwave.sourceforge.net/

use std::fs::{File, OpenOptions};
use std::io::{BufWriter, Read, Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};

use fst_writer::{
    FstBodyWriter, FstFileType, FstInfo, FstScopeType, FstSignalId, FstSignalType, FstVarDirection,
    FstVarType,
};

use crate::writer::{
    format_real_bits, Declaration, Emitter, Result, ValueRef, VcdBuilder, WriteError, Writer,
};

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
    /// end of the dump window (exclusive; `u64::MAX` without a window)
    end: u64,
    /// a time step after the initial frame was written
    stepped: bool,
    /// the file, reopened at the end to set its start time ([`set_start_time`])
    path: PathBuf,
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
    let end = b.window_end();
    let info = FstInfo {
        // fst-writer writes this into the header's time-zero field (an offset viewers add to
        // every time), not its start time: 0, the file's times are absolute.
        start_time: 0,
        timescale_exponent: exp as i8,
        version: b.version().to_string(),
        date: String::new(),
        file_type: FstFileType::Verilog,
    };
    let mut h = fst_writer::open_fst(path, &info).map_err(fst_err)?;
    let decls = b.declarations();
    let n = decls
        .iter()
        .filter(|d| matches!(d, Declaration::Var { .. }))
        .count();
    let mut ids = vec![None; n];
    let mut widths = vec![0; n];
    let mut real = vec![false; n];
    for d in decls {
        match d {
            Declaration::Scope(name) => h.scope(name, "", FstScopeType::Module).map_err(fst_err)?,
            Declaration::Upscope => h.up_scope().map_err(fst_err)?,
            Declaration::Var {
                index,
                name,
                width,
                real: is_real,
                wire,
                range,
            } => {
                let (sig, ty) = if is_real {
                    (FstSignalType::real(), FstVarType::Real)
                } else {
                    (
                        FstSignalType::bit_vec(width),
                        if wire {
                            FstVarType::Wire
                        } else {
                            FstVarType::Reg
                        },
                    )
                };
                let name = match range {
                    Some((msb, lsb)) if msb == lsb => format!("{name}[{msb}]"),
                    Some((msb, lsb)) => format!("{name}[{msb}:{lsb}]"),
                    None => name,
                };
                ids[index] = Some(
                    h.var(name, sig, ty, FstVarDirection::Implicit, None)
                        .map_err(fst_err)?,
                );
                widths[index] = width;
                real[index] = is_real;
            }
        }
    }
    let ids = ids
        .into_iter()
        .map(|i| i.ok_or_else(|| WriteError::Fst("a declared variable has no FST id".into())))
        .collect::<Result<Vec<_>>>()?;
    let body = h.finish().map_err(fst_err)?;
    Ok(b.into_writer(FstOut {
        body,
        ids,
        widths,
        real,
        scale,
        start,
        end,
        stepped: false,
        path: path.to_path_buf(),
        scratch: Vec::with_capacity(64),
    }))
}

impl Emitter for FstOut {
    type Output = ();

    fn dump_begin(&mut self, t: u64) -> Result<()> {
        // The writer's first step is at the window start (0 without a window): its values are
        // FST's initial frame at the file's start time.
        if t == self.start {
            Ok(())
        } else {
            self.stepped = true;
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
        self.stepped = true;
        self.body.time_change(t * self.scale).map_err(fst_err)
    }

    #[inline]
    fn value(&mut self, i: usize, v: ValueRef<'_>) -> Result<()> {
        let id = self.ids[i];
        match v {
            ValueRef::Int(v) => {
                let w = self.widths[i];
                self.scratch.clear();
                self.scratch.extend((0..w).rev().map(|k| {
                    if k < 64 && (v >> k) & 1 == 1 {
                        b'1'
                    } else {
                        b'0'
                    }
                }));
                self.body.signal_change(id, &self.scratch).map_err(fst_err)
            }
            ValueRef::Bits(b) => self.body.signal_change(id, b).map_err(fst_err),
            ValueRef::Real(r) => {
                debug_assert!(self.real[i]);
                self.body
                    .signal_change(id, &format_real_bits(r))
                    .map_err(fst_err)
            }
        }
    }

    fn finish(mut self, closing: Option<u64>) -> Result<()> {
        match closing {
            Some(t) => self.body.time_change(t * self.scale).map_err(fst_err)?,
            // A file of one time step (a one-tick window): fst-writer fills the initial frame and
            // writes a time table only at a later time step; without one its frame stays all x
            // (GTKWave's fst2vcd shows x and NaN) and its time table is empty (wellen 0.25
            // panics on it). One entry after the start fixes both: the end of the window (the
            // end of the one tick dumped), else one time unit after the start. An entry at the
            // start itself would not do: fst-reader then skips the frame.
            None if !self.stepped => {
                let t = if self.end != u64::MAX {
                    self.end
                } else {
                    self.start + 1
                };
                self.body.time_change(t * self.scale).map_err(fst_err)?;
            }
            None => {}
        }
        let mut out = self.body.finish().map_err(fst_err)?;
        out.flush()?;
        drop(out);
        if self.start > 0 {
            let mut f = OpenOptions::new().read(true).write(true).open(&self.path)?;
            set_start_time(&mut f, self.start)?;
            f.flush()?;
        }
        Ok(())
    }
}

/// FST block types of value-change data (`FST_BL_VCDATA`, `FST_BL_VCDATA_DYN_ALIAS`,
/// `FST_BL_VCDATA_DYN_ALIAS2`; GTKWave's `fstapi.h`).
const FST_VC_BLOCKS: [u8; 3] = [1, 5, 8];

/// Set the start time of a finished FST to `start`: the header's start time (bytes 9..17; every
/// block is a type byte, then a big-endian u64 length that counts itself, then its data) and the
/// start time of the first value-change block, which is the time of its initial frame. An end
/// time before `start` (a file with no time step after its frame) becomes `start`. Later blocks
/// start where the previous one ended and are left as they are.
pub fn set_start_time(f: &mut (impl Read + Write + Seek), start: u64) -> Result<()> {
    let bad = |what: &str| WriteError::Fst(format!("cannot set the FST start time: {what}"));
    let mut head = [0u8; 9];
    let mut pos = 0u64;
    let mut vc_seen = false;
    loop {
        f.seek(SeekFrom::Start(pos))?;
        match f.read_exact(&mut head) {
            Ok(()) => {}
            Err(e) if e.kind() == std::io::ErrorKind::UnexpectedEof => break,
            Err(e) => return Err(e.into()),
        }
        let mut len = [0u8; 8];
        len.copy_from_slice(&head[1..9]);
        let len = u64::from_be_bytes(len);
        let vc = FST_VC_BLOCKS.contains(&head[0]);
        if pos == 0 && head[0] != 0 {
            return Err(bad("the first block is not the header block (type 0)"));
        }
        if pos == 0 || vc {
            // start time, then end time, right after the length
            let mut end = [0u8; 8];
            f.seek(SeekFrom::Start(pos + 17))?;
            f.read_exact(&mut end)?;
            f.seek(SeekFrom::Start(pos + 9))?;
            f.write_all(&start.to_be_bytes())?;
            if u64::from_be_bytes(end) < start {
                f.write_all(&start.to_be_bytes())?;
            }
        }
        if vc {
            vc_seen = true;
            break;
        }
        if len < 8 {
            return Err(bad(&format!("block at byte {pos} has length {len}")));
        }
        pos += 1 + len;
    }
    if vc_seen {
        Ok(())
    } else {
        Err(bad("the file has no value-change block"))
    }
}
