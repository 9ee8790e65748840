//! `pmu50 dut-worker`: the worker process that serves lockstep requests on its stdin.

use super::compare::*;
use super::ffi::*;
use super::protocol::*;
use super::vectors::*;
use std::collections::HashMap;
use std::io::{Read, Write};
use std::os::fd::FromRawFd;
use std::os::unix::ffi::OsStringExt;
use std::path::{Path, PathBuf};

/// `pmu50 dut-worker`: serve requests on stdin until it closes. Exit 0 at the end of the input,
/// 2 on a broken request.
pub fn worker_main() -> i32 {
    // Replies go to a copy of stdout; the RTL's own output (its $display) goes to stderr.
    // SAFETY: dup/dup2 on the process's standard descriptors.
    let proto = unsafe {
        let fd = libc::dup(1);
        if fd < 0 || libc::dup2(2, 1) < 0 {
            return 2;
        }
        std::fs::File::from_raw_fd(fd)
    };
    let mut reply = std::io::BufWriter::new(proto);
    let mut input = std::io::BufReader::with_capacity(1 << 20, std::io::stdin().lock());
    let mut libs: HashMap<PathBuf, Result<DutLib, String>> = HashMap::new();
    loop {
        let mut magic = [0u8; 4];
        match input.read_exact(&mut magic) {
            Ok(()) => {}
            Err(e) if e.kind() == std::io::ErrorKind::UnexpectedEof => return 0,
            Err(_) => return 2,
        }
        let request = (|| -> std::io::Result<Received> {
            if &magic != MAGIC {
                return Err(std::io::Error::other("not a lockstep request"));
            }
            let kind = match read_exact(&mut input, 1)?[0] {
                0 => Request::Lockstep,
                1 => Request::Probe,
                2 => Request::Trace,
                3 => Request::LockstepCoverage,
                4 => Request::Vcd,
                k => return Err(std::io::Error::other(format!("unknown request kind {k}"))),
            };
            let len = u32::from_le_bytes(read_exact(&mut input, 4)?.try_into().unwrap_or([0; 4]))
                as usize;
            if len > 1 << 16 {
                return Err(std::io::Error::other("library path longer than 64 KiB"));
            }
            let path = PathBuf::from(std::ffi::OsString::from_vec(read_exact(&mut input, len)?));
            let mut hdl = [0u64; 12];
            for (d, v) in hdl.iter_mut().zip(u64s(&read_exact(&mut input, 96)?)) {
                *d = v;
            }
            let ticks = u64::from_le_bytes(read_exact(&mut input, 8)?.try_into().unwrap_or([0; 8]));
            let ticks = usize::try_from(ticks).map_err(std::io::Error::other)?;
            if ticks > MAX_TICKS {
                return Err(std::io::Error::other(format!(
                    "{ticks} ticks, at most {MAX_TICKS}"
                )));
            }
            let inputs = read_exact(&mut input, ticks * 4)?
                .chunks_exact(4)
                .map(|c| u32::from_le_bytes(c.try_into().unwrap_or([0; 4])))
                .collect();
            let window = match kind {
                Request::Trace => {
                    let w: Vec<u64> = u64s(&read_exact(&mut input, 16)?).collect();
                    (w[0], w[1], 0)
                }
                Request::Vcd => {
                    let w: Vec<u64> = u64s(&read_exact(&mut input, 24)?).collect();
                    (w[0], w[1], w[2])
                }
                _ => (0, 0, 0),
            };
            let cov = if matches!(kind, Request::LockstepCoverage | Request::Vcd) {
                let len =
                    u32::from_le_bytes(read_exact(&mut input, 4)?.try_into().unwrap_or([0; 4]))
                        as usize;
                if len > 1 << 16 {
                    return Err(std::io::Error::other("coverage path longer than 64 KiB"));
                }
                Some(PathBuf::from(std::ffi::OsString::from_vec(read_exact(
                    &mut input, len,
                )?)))
            } else {
                None
            };
            Ok((kind, path, hdl, inputs, window, cov))
        })();
        let Ok((kind, path, hdl, inputs, (from, to, ns), cov)) = request else {
            return 2;
        };
        let answer = match (
            &*libs
                .entry(path.clone())
                .or_insert_with(|| DutLib::load(&path)),
            params_of(&hdl),
            kind,
        ) {
            (Ok(lib), _, Request::Probe) => probe(lib, &inputs),
            (Ok(lib), _, Request::Trace) => {
                trace(lib, &inputs, from, to.min(from.saturating_add(100_000)))
            }
            (Ok(lib), Ok(p), Request::Lockstep) => lockstep(lib, p, &inputs),
            (Ok(lib), _, Request::Vcd) => vcd(
                lib,
                &inputs,
                from,
                to,
                ns,
                cov.as_deref().unwrap_or(Path::new("")),
            ),
            (Ok(lib), Ok(p), Request::LockstepCoverage) => {
                lockstep_coverage(lib, p, &inputs, cov.as_deref().unwrap_or(Path::new("")))
            }
            (Err(e), _, _) => Reply::Error { reason: e.clone() },
            (_, Err(e), _) => Reply::Error { reason: e },
        };
        let line = serde_json::to_string(&answer)
            .unwrap_or_else(|e| format!("{{\"error\":{{\"reason\":\"{e}\"}}}}"));
        if reply
            .write_all(line.as_bytes())
            .and_then(|()| reply.write_all(b"\n"))
            .and_then(|()| reply.flush())
            .is_err()
        {
            return 0;
        }
    }
}
