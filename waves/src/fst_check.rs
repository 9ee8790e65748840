//! Structural check of an FST before `wellen` (fst-reader) reads it: the FST form of
//! [`crate::validate`].
//!
//! fst-reader trusts every size and count in the file: it allocates what a block declares before
//! it looks at the data (`Vec::with_capacity(n)`, `vec![0; n]`, a decompression buffer of the
//! declared length) and subtracts lengths without checking them. One damaged byte then asks for
//! hundreds of gigabytes (the process aborts, which no panic guard can catch), or makes it panic.
//! [`check`] walks the blocks the way fst-reader does and refuses, with the byte offset, every
//! declaration that does not fit:
//!
//! * every block (a type byte, a big-endian u64 length that counts itself, its data) lies inside
//!   the file, has a known type and at least its fixed fields; the first is the header (329);
//! * a compressed section declares no more than its compression can produce from its bytes
//!   (zlib/gzip 1032:1, LZ4 255:1), and the decompressed sections together stay within the
//!   reader's byte limit ([`crate::reader::ReadLimits::max_file_bytes`], the same limit as a VCD's
//!   size: memory stays proportional to it);
//! * counts (signals, time steps, blackouts) are at most the bytes that hold them;
//! * the geometry (each signal's width) is decoded and every width is at most
//!   [`crate::reader::ReadLimits::max_var_width`]; every value-change block has the geometry's
//!   number of signals and a time table of at least one entry.
//!
//! What the check cannot see (the hierarchy's own widths, the packed value changes) is checked
//! after wellen has read the header ([`crate::reader`]), and wellen runs under a panic guard.

use std::fmt;

/// Largest output of zlib/gzip (deflate) per input byte: 1032:1 (zlib's documented bound).
const DEFLATE_RATIO: u64 = 1032;
/// Largest output of an LZ4 block per input byte (a match length costs one byte per 255).
const LZ4_RATIO: u64 = 256;
/// FST's header block length (`FST_HDR_SIZE` less the type byte).
const HEADER_LEN: u64 = 329;

/// A refused FST: what is wrong, at which byte.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct FstProblem {
    /// byte offset in the file of the block (or field) concerned
    pub offset: u64,
    /// what is wrong
    pub what: String,
}

impl fmt::Display for FstProblem {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "byte {}: {}", self.offset, self.what)
    }
}

/// What the check learnt about a good file.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct FstLayout {
    /// Width in bits of each signal handle (0-based) from the geometry; `None` for a real,
    /// `Some(0)` for a variable-length (string) signal.
    pub widths: Vec<Option<u32>>,
    /// Bytes the declared sections decompress to, and the tables fst-reader allocates for them.
    pub decoded_bytes: u64,
    /// Time-table entries over all value-change blocks.
    pub time_steps: u64,
}

fn be64(b: &[u8], at: u64) -> Option<u64> {
    let at = usize::try_from(at).ok()?;
    let s = b.get(at..at.checked_add(8)?)?;
    Some(u64::from_be_bytes(s.try_into().ok()?))
}

/// FST's varint (LEB128, least significant group first); returns the value and its length.
fn varint(b: &[u8], at: u64) -> Option<(u64, u64)> {
    let mut v = 0u64;
    let start = usize::try_from(at).ok()?;
    for k in 0..10usize {
        let byte = *b.get(start.checked_add(k)?)?;
        v |= u64::from(byte & 0x7f).checked_shl(7 * k as u32)?;
        if byte & 0x80 == 0 {
            return Some((v, k as u64 + 1));
        }
    }
    None
}

/// Checks `b` (a whole FST file) against `max_decoded` bytes of decompressed data and
/// `max_width` bits per signal.
pub fn check(b: &[u8], max_decoded: u64, max_width: u32) -> Result<FstLayout, FstProblem> {
    let size = b.len() as u64;
    let bad = |offset: u64, what: String| Err(FstProblem { offset, what });
    let mut layout = FstLayout::default();
    let mut decoded = 0u64;
    // `n` decoded bytes more (or table bytes): within the limit?
    let mut add = |offset: u64, n: u64, what: &str| -> Result<(), FstProblem> {
        decoded = decoded.saturating_add(n);
        if decoded > max_decoded {
            return Err(FstProblem { offset, what: format!("{what} would make the decompressed data more than the limit of {max_decoded} bytes (pmu50 diff --max-bytes raises it)") });
        }
        Ok(())
    };
    let (mut header_vars, mut header_handles) = (0u64, 0u64);
    let mut geometry: Option<Vec<Option<u32>>> = None;
    let mut hierarchy_len: Option<u64> = None;
    let mut vc_blocks = 0u64;
    let mut vc_at: Vec<(u64, u8, u64)> = Vec::new();
    let mut pos = 0u64;
    while pos < size {
        let tpe = b[pos as usize];
        let Some(len) = be64(b, pos + 1) else {
            return bad(
                pos,
                format!(
                    "block of type {tpe} is cut off: its length field needs 8 bytes, {} are left",
                    size - pos - 1
                ),
            );
        };
        let start = pos + 1; // the section's first byte: its length field
        if len < 8 || len > size - start {
            return bad(pos, format!("block of type {tpe} declares {len} bytes, but {} are left in the file (at least 8)", size - start));
        }
        let end = start + len;
        let need = |min: u64| -> Result<(), FstProblem> {
            if len < min {
                Err(FstProblem {
                    offset: pos,
                    what: format!(
                        "block of type {tpe} has {len} bytes, less than its fixed fields ({min})"
                    ),
                })
            } else {
                Ok(())
            }
        };
        if pos == 0 && tpe != 0 {
            return bad(
                0,
                format!("the first block has type {tpe}, not the header block (0)"),
            );
        }
        match tpe {
            0 => {
                if pos != 0 {
                    return bad(pos, "a second header block".into());
                }
                if len != HEADER_LEN {
                    return bad(pos, format!("the header block has {len} bytes, not {HEADER_LEN}"));
                }
                // start, end, endian test (f64), memory used, scopes, vars, max handle, blocks
                header_vars = be64(b, start + 48).unwrap_or(0);
                header_handles = be64(b, start + 56).unwrap_or(0);
            }
            // value-change blocks: FST_BL_VCDATA, _DYN_ALIAS, _DYN_ALIAS2; checked after the
            // walk, once the geometry (which GTKWave's writer puts after them) is known
            1 | 5 | 8 => {
                need(32 + 3 + 1 + 8 + 24)?;
                vc_at.push((pos, tpe, len));
            }
            2 => {
                // blackouts: a varint count, then a byte and a varint each
                let Some((count, _)) = varint(b, start + 8) else { return bad(start + 8, "blackout count is not a valid varint".into()) };
                if count > len / 2 {
                    return bad(start + 8, format!("{count} blackouts declared in a block of {len} bytes"));
                }
                add(start + 8, count.saturating_mul(16), "the blackouts")?;
            }
            3 => {
                need(24 + 1)?;
                let (u, handles) = (be64(b, start + 8).unwrap_or(0), be64(b, start + 16).unwrap_or(0));
                let c = len - 24;
                if u != c && u > c.saturating_mul(DEFLATE_RATIO) {
                    return bad(start + 8, format!("geometry declares {u} bytes from {c} compressed bytes (zlib gives at most {DEFLATE_RATIO}:1)"));
                }
                if handles > u {
                    return bad(start + 16, format!("geometry declares {handles} signals in {u} bytes (each takes at least one)"));
                }
                add(start + 8, u.saturating_add(handles.saturating_mul(8)), "the geometry")?;
                let data = &b[(start + 24) as usize..end as usize];
                let raw;
                let bytes: &[u8] = if u == c {
                    data
                } else {
                    raw = miniz_oxide::inflate::decompress_to_vec_zlib_with_limit(data, u as usize).map_err(|e| FstProblem { offset: start + 24, what: format!("geometry does not decompress: {:?}", e.status) })?;
                    if raw.len() as u64 != u {
                        return bad(start + 24, format!("geometry decompresses to {} bytes, not the {u} declared", raw.len()));
                    }
                    &raw
                };
                let mut widths = Vec::with_capacity(handles as usize);
                let mut at = 0u64;
                for h in 0..handles {
                    let Some((v, n)) = varint(bytes, at) else { return bad(start + 24, format!("geometry ends before signal {h} of {handles}")) };
                    at += n;
                    let w = match v {
                        0 => None,
                        0xffff_ffff => Some(0),
                        v if v > u64::from(max_width) => {
                            return bad(start + 24, format!("signal handle {} is declared with {v} bits; the limit is {max_width} bits", h + 1));
                        }
                        v => Some(v as u32),
                    };
                    widths.push(w);
                }
                geometry = Some(widths);
            }
            4 | 6 | 7 => {
                need(16 + 1)?;
                let u = be64(b, start + 8).unwrap_or(0);
                let c = len - 16;
                let limit = match tpe {
                    4 => {
                        need(16 + 10)?;
                        (c - 10).saturating_mul(DEFLATE_RATIO)
                    }
                    6 => c.saturating_mul(LZ4_RATIO),
                    _ => {
                        let Some((lvl1, n)) = varint(b, start + 16) else { return bad(start + 16, "hierarchy size is not a valid varint".into()) };
                        if lvl1 > c.saturating_sub(n).saturating_mul(LZ4_RATIO) {
                            return bad(start + 16, format!("hierarchy declares {lvl1} bytes after its first LZ4 pass from {} bytes (LZ4 gives at most {LZ4_RATIO}:1)", c.saturating_sub(n)));
                        }
                        add(start + 16, lvl1, "the hierarchy")?;
                        lvl1.saturating_mul(LZ4_RATIO)
                    }
                };
                if u > limit {
                    return bad(start + 8, format!("hierarchy declares {u} bytes from {c} compressed bytes (more than its compression can give)"));
                }
                add(start + 8, u, "the hierarchy")?;
                hierarchy_len = Some(u);
            }
            254 => return bad(pos, "a gzip-wrapped FST (block type 254) is not read; unwrap it first (GTKWave's fst2vcd reads it)".into()),
            255 => {}
            t => return bad(pos, format!("unknown block type {t} (FST has 0-8, 254 and 255)")),
        }
        pos = end;
    }
    for (pos, tpe, len) in vc_at {
        let (start, end) = (pos + 1, pos + 1 + len);
        let (t0, t1) = (
            be64(b, start + 8).unwrap_or(0),
            be64(b, start + 16).unwrap_or(0),
        );
        if t1 < t0 {
            return bad(
                pos,
                format!("value-change block ends at time {t1}, before its start {t0}"),
            );
        }
        // the time table: its three sizes are the block's last 24 bytes
        let (tu, tc, items) = (
            be64(b, end - 24).unwrap_or(0),
            be64(b, end - 16).unwrap_or(0),
            be64(b, end - 8).unwrap_or(0),
        );
        if tc > len - 24 - 32 {
            return bad(
                end - 16,
                format!("time table of {tc} compressed bytes does not fit in its block of {len}"),
            );
        }
        if tu != tc && tu > tc.saturating_mul(DEFLATE_RATIO) {
            return bad(end - 24, format!("time table declares {tu} bytes from {tc} compressed bytes (zlib gives at most {DEFLATE_RATIO}:1)"));
        }
        if items > tu {
            return bad(
                end - 8,
                format!(
                    "time table declares {items} entries in {tu} bytes (each takes at least one)"
                ),
            );
        }
        if items == 0 {
            return bad(end - 8, "value-change block without a time step (readers need at least one entry; wellen panics on none)".into());
        }
        add(
            end - 24,
            tu.saturating_add(items.saturating_mul(16)),
            "the time table",
        )?;
        layout.time_steps = layout.time_steps.saturating_add(items);
        // the frame (initial values): three varints after the 32 bytes of fixed fields
        let Some((fu, n1)) = varint(b, start + 32) else {
            return bad(start + 32, "frame sizes are not valid varints".into());
        };
        let Some((fc, n2)) = varint(b, start + 32 + n1) else {
            return bad(start + 32, "frame sizes are not valid varints".into());
        };
        let Some((fh, n3)) = varint(b, start + 32 + n1 + n2) else {
            return bad(start + 32, "frame sizes are not valid varints".into());
        };
        let frame = start + 32 + n1 + n2 + n3;
        let time_at = end - 24 - tc;
        if fc > time_at.saturating_sub(frame) {
            return bad(
                start + 32,
                format!("frame of {fc} compressed bytes does not fit in its block"),
            );
        }
        if fu != fc && fu > fc.saturating_mul(DEFLATE_RATIO) {
            return bad(start + 32, format!("frame declares {fu} bytes from {fc} compressed bytes (zlib gives at most {DEFLATE_RATIO}:1)"));
        }
        add(start + 32, fu, "the frame")?;
        let signals = geometry.as_ref().map(|g| g.len() as u64);
        let Some(signals) = signals else {
            return bad(
                pos,
                "the file has no geometry block (the signals' widths): damaged or not finished"
                    .into(),
            );
        };
        if fh != signals {
            return bad(
                start + 32,
                format!("frame has {fh} signals, the geometry {signals}"),
            );
        }
        let vc = frame + fc;
        let Some((vh, n4)) = varint(b, vc) else {
            return bad(vc, "value-change signal count is not a valid varint".into());
        };
        if vh != signals {
            return bad(
                vc,
                format!("value changes of {vh} signals, the geometry has {signals}"),
            );
        }
        // per signal: three u32 pointers and a 12-byte location (fst-reader's tables)
        add(vc, vh.saturating_mul(24), "the value-change tables")?;
        // the chain of offsets: its length is the u64 just before the time table
        let chain_len_at = time_at.checked_sub(8).filter(|&c| c > vc + n4);
        let Some(chain_len_at) = chain_len_at else {
            return bad(vc, "no room for the chain of value-change offsets".into());
        };
        let chain = be64(b, chain_len_at).unwrap_or(u64::MAX);
        let vc_start = vc + n4;
        if chain > chain_len_at - (vc_start + 1) {
            return bad(chain_len_at, format!("chain of value-change offsets declares {chain} bytes, more than the block holds"));
        }
        let chain_start = chain_len_at - chain;
        let data_len = chain_start - vc_start;
        if data_len > u64::from(u32::MAX) {
            return bad(
                vc_start,
                format!(
                    "value changes of {data_len} bytes in one block (FST's offsets are 32 bits)"
                ),
            );
        }
        let locs = chain_offsets(
            &b[chain_start as usize..chain_len_at as usize],
            tpe == 8,
            signals,
            data_len as u32,
        )
        .map_err(|what| FstProblem {
            offset: chain_start,
            what,
        })?;
        // each signal's packed values: a varint length (0: stored as is), then the data
        let ratio = match b[vc_start as usize] {
            b'4' | b'F' => LZ4_RATIO,
            _ => DEFLATE_RATIO,
        };
        for (off, n) in locs {
            let at = vc_start + u64::from(off);
            let Some((u, skip)) =
                varint(b, at).filter(|&(u, k)| k <= u64::from(n) && u <= u64::from(u32::MAX))
            else {
                return bad(
                    at,
                    "a signal's packed value changes start with no valid length".into(),
                );
            };
            let c = u64::from(n) - skip;
            if u != 0 && u > c.saturating_mul(ratio) {
                return bad(at, format!("a signal's value changes declare {u} bytes from {c} compressed bytes (more than its compression can give)"));
            }
            add(at, u.max(c), "the value changes")?;
        }
        vc_blocks += 1;
    }
    let Some(widths) = geometry else {
        return bad(
            size,
            "the file has no geometry block (the signals' widths): damaged or not finished".into(),
        );
    };
    let Some(hier) = hierarchy_len else {
        return bad(
            size,
            "the file has no hierarchy block: damaged or not finished".into(),
        );
    };
    if vc_blocks == 0 {
        return bad(
            size,
            "the file has no value-change block: damaged or not finished".into(),
        );
    }
    if header_vars > hier || header_handles > hier {
        return bad(49, format!("the header declares {header_vars} variables and {header_handles} handles, more than its hierarchy of {hier} bytes can hold"));
    }
    layout.widths = widths;
    layout.decoded_bytes = decoded;
    Ok(layout)
}

/// The chain of value-change offsets of a block, read as fst-reader reads it (alias2 for block
/// type 8, else alias1), with what it would trip on refused: more entries than `signals`, an
/// offset that does not grow (fst-reader unwraps a zero length), an offset past `data_len`, an
/// alias of a signal that has no offset of its own. Returns each signal's (offset, length) in
/// the block's value-change data.
fn chain_offsets(
    mut c: &[u8],
    alias2: bool,
    signals: u64,
    data_len: u32,
) -> Result<Vec<(u32, u32)>, String> {
    let mut locs: Vec<(u32, u32)> = Vec::new();
    let mut offset: Option<u32> = None;
    let mut idx = 0u64;
    // signals with an offset of their own, and the aliases (signal, target)
    let mut has_offset = vec![false; signals as usize];
    let mut aliases: Vec<(u64, u64)> = Vec::new();
    let mut prev_alias = 0u64;
    let cut = || "chain of value-change offsets ends inside a number".to_string();
    while let Some(&kind) = c.first() {
        if idx >= signals {
            return Err(format!(
                "chain of value-change offsets lists more than the {signals} signals"
            ));
        }
        // Some(step): a new offset `step` bytes after the previous one; else an alias or a gap
        let mut step: Option<i64> = None;
        if alias2 {
            if kind & 1 == 1 {
                let shval = signed_varint(&mut c).ok_or_else(cut)? >> 1;
                if shval > 0 {
                    step = Some(shval);
                } else {
                    if shval < 0 {
                        prev_alias = (-(shval + 1)) as u64;
                    }
                    aliases.push((idx, prev_alias));
                    idx += 1;
                }
            } else {
                let (v, n) = varint(c, 0)
                    .filter(|&(v, _)| v <= u64::from(u32::MAX))
                    .ok_or_else(cut)?;
                c = &c[n as usize..];
                idx += v >> 1;
            }
        } else {
            let (raw, n) = varint(c, 0)
                .filter(|&(v, _)| v <= u64::from(u32::MAX))
                .ok_or_else(cut)?;
            c = &c[n as usize..];
            if raw == 0 {
                let (a, n) = varint(c, 0)
                    .filter(|&(v, _)| v <= u64::from(u32::MAX))
                    .ok_or_else(cut)?;
                c = &c[n as usize..];
                if a == 0 {
                    return Err(
                        "chain of value-change offsets: alias 0 (aliases count from 1)".into(),
                    );
                }
                aliases.push((idx, a - 1));
                idx += 1;
            } else if raw & 1 == 1 {
                step = Some((raw >> 1) as i64);
            } else {
                idx += raw >> 1;
            }
        }
        if let Some(step) = step {
            let prev = offset.unwrap_or(0);
            let next = i64::from(prev).saturating_add(step);
            if step <= 0 || next >= i64::from(data_len) {
                return Err(format!("chain of value-change offsets: offset {next} after {prev} (offsets grow, within the {data_len} bytes of value changes)"));
            }
            if let Some(p) = offset {
                locs.push((p, next as u32 - p));
            }
            offset = Some(next as u32);
            has_offset[idx as usize] = true;
            idx += 1;
        }
        if idx > signals {
            return Err(format!(
                "chain of value-change offsets lists more than the {signals} signals"
            ));
        }
    }
    if let Some(p) = offset {
        locs.push((p, data_len - p));
    }
    if let Some(&(i, t)) = aliases
        .iter()
        .find(|&&(_, t)| !has_offset.get(t as usize).copied().unwrap_or(false))
    {
        return Err(format!("chain of value-change offsets: signal handle {} is an alias of handle {}, which has no value changes of its own", i + 1, t + 1));
    }
    Ok(locs)
}

/// FST's signed varint (LEB128, sign in bit 6 of the last byte), as fst-reader reads chain entries.
fn signed_varint(c: &mut &[u8]) -> Option<i64> {
    let mut res = 0u64;
    for k in 0..10u32 {
        let byte = *c.get(k as usize)?;
        res |= u64::from(byte & 0x7f).checked_shl(7 * k).unwrap_or(0);
        if byte & 0x80 == 0 {
            if byte & 0x40 != 0 && 7 * (k + 1) < 64 {
                res |= u64::MAX << (7 * (k + 1));
            }
            *c = &c[k as usize + 1..];
            return Some(res as i64);
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::varint;

    #[test]
    fn varints_read_like_fst_and_refuse_overlong_ones() {
        assert_eq!(varint(&[0x05], 0), Some((5, 1)));
        assert_eq!(varint(&[0x81, 0x01], 0), Some((129, 2)));
        assert_eq!(varint(&[0x80; 11], 0), None);
        assert_eq!(varint(&[0x80], 0), None);
    }
}
