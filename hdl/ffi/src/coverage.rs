//! C ABI of the functional coverage model (crate `pmu50-coverage`): a coverage handle sampled at
//! every edge of a core handle, its bins and hits by index, `coverage.json` written and merged.
//! The same rules as the rest of the boundary (crate root): no panic crosses it, NULL pointers
//! and strings that are not UTF-8 give an error code with the reason in `pmu50_last_error()`.

use crate::core_abi::{
    guard, null, pmu50_params, pmu50_t, set_error, PMU50_ERR_NAME, PMU50_ERR_PARAM,
    PMU50_ERR_RANGE, PMU50_OK,
};
use crate::mirror::{pmu50_inputs, pmu50_internals, pmu50_outputs};
use pmu50_core::pmu50::Structural;
use pmu50_core::Inputs;
use pmu50_coverage::db::{self, DbError};
use pmu50_coverage::{layout, Coverage, Edge, Kind};
use std::ffi::{c_char, c_int, CStr, CString};
use std::panic::catch_unwind;
use std::path::Path;
use std::sync::OnceLock;

/// A file could not be read, written or renamed.
pub const PMU50_ERR_IO: c_int = -6;
/// A string argument is not UTF-8, or is empty where a value is needed.
pub const PMU50_ERR_TEXT: c_int = -7;
/// A coverage file is corrupt, of another model or format, or counts a run twice.
pub const PMU50_ERR_COVERAGE: c_int = -8;

/// Opaque coverage handle.
pub struct pmu50_coverage_t {
    cov: Coverage,
    structural: Structural,
    edges: u64,
}

struct BinNames {
    names: Vec<CString>,
    unreachable: Vec<Option<CString>>,
    model: CString,
}

fn bin_names() -> &'static BinNames {
    static N: OnceLock<BinNames> = OnceLock::new();
    N.get_or_init(|| {
        let l = layout();
        let c = |s: &str| CString::new(s).unwrap_or_default();
        BinNames {
            names: l.bins.iter().map(|b| c(&b.name)).collect(),
            unreachable: l.bins.iter().map(|b| b.unreachable.map(c)).collect(),
            model: c(&pmu50_coverage::model_id(l)),
        }
    })
}

/// A C string argument as UTF-8 text (not empty).
///
/// # Safety
/// `s` NULL or NUL-terminated.
unsafe fn text<'a>(what: &str, arg: &str, s: *const c_char) -> Result<&'a str, c_int> {
    if s.is_null() {
        return Err(null(what, arg));
    }
    // SAFETY: non-null and NUL-terminated by contract.
    match unsafe { CStr::from_ptr(s) }.to_str() {
        Ok("") => {
            set_error(format!("{what}: `{arg}` is empty"));
            Err(PMU50_ERR_TEXT)
        }
        Ok(t) => Ok(t),
        Err(e) => {
            set_error(format!("{what}: `{arg}` is not UTF-8 ({e})"));
            Err(PMU50_ERR_TEXT)
        }
    }
}

fn db_error(what: &str, e: DbError) -> c_int {
    let code = if matches!(e, DbError::Io { .. }) {
        PMU50_ERR_IO
    } else {
        PMU50_ERR_COVERAGE
    };
    set_error(format!("{what}: {e}"));
    code
}

/// Empty coverage for a core of parameters `p` at clock period `clock_ns`; samples the
/// configuration. NULL if `p` is NULL or illegal (see `pmu50_last_error()`).
///
/// # Safety
/// `p` NULL or a readable `pmu50_params`.
#[no_mangle]
pub unsafe extern "C" fn pmu50_coverage_new(
    p: *const pmu50_params,
    clock_ns: u64,
) -> *mut pmu50_coverage_t {
    // SAFETY: forwarded contract.
    unsafe {
        crate::core_abi::new_handle("pmu50_coverage_new", p, |params| {
            params.validate().map_err(|e| e.to_string())?;
            let structural = Structural {
                sync_depth: params.sync_depth,
                cnt_width: params.cnt_width,
            };
            Ok(pmu50_coverage_t {
                cov: Coverage::new(&params, clock_ns),
                structural,
                edges: 0,
            })
        })
    }
}

/// Free a coverage handle (NULL is ignored).
///
/// # Safety
/// `c` NULL or a handle from `pmu50_coverage_new` not freed yet.
#[no_mangle]
pub unsafe extern "C" fn pmu50_coverage_free(c: *mut pmu50_coverage_t) {
    // SAFETY: forwarded contract.
    unsafe { crate::core_abi::free_handle(c) }
}

/// One rising edge of core `m` with inputs `i`, sampled into `c` (`pmu50_step` plus sampling).
///
/// # Safety
/// `c`, `m` NULL or live; `i` NULL or readable; `after` NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn pmu50_coverage_step(
    c: *mut pmu50_coverage_t,
    m: *mut pmu50_t,
    i: *const pmu50_inputs,
    after: *mut pmu50_outputs,
) -> c_int {
    // SAFETY: forwarded contract.
    unsafe { pmu50_coverage_step_traced(c, m, i, std::ptr::null_mut(), after) }
}

/// As `pmu50_coverage_step`, with the internals of the cycle (`pmu50_step_traced` plus sampling).
///
/// # Safety
/// `c`, `m` NULL or live; `i` NULL or readable; `internals`, `after` NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn pmu50_coverage_step_traced(
    c: *mut pmu50_coverage_t,
    m: *mut pmu50_t,
    i: *const pmu50_inputs,
    internals: *mut pmu50_internals,
    after: *mut pmu50_outputs,
) -> c_int {
    const WHAT: &str = "pmu50_coverage_step";
    guard(WHAT, || {
        // SAFETY: NULL or live handles, by contract.
        let (Some(c), Some(m)) = (unsafe { c.as_mut() }, unsafe { m.as_mut() }) else {
            return null(WHAT, if c.is_null() { "c" } else { "m" });
        };
        if i.is_null() {
            return null(WHAT, "i");
        }
        let s = m.core.structural();
        if (s.sync_depth, s.cnt_width) != (c.structural.sync_depth, c.structural.cnt_width) {
            set_error(format!(
                "{WHAT}: the coverage was made for sync_depth {} cnt_width {}, the core has sync_depth {} cnt_width {}",
                c.structural.sync_depth, c.structural.cnt_width, s.sync_depth, s.cnt_width
            ));
            return PMU50_ERR_PARAM;
        }
        // SAFETY: checked non-null.
        let inputs: Inputs = unsafe { i.read() }.into();
        let before = *m.core.regs();
        let pmu50_core::TracedStep {
            before: out,
            internals: n,
            after: after_out,
            ..
        } = m.core.step_traced(&inputs);
        m.last = Some(n);
        c.cov.sample(&Edge {
            before: &before,
            after: m.core.regs(),
            out: &out,
            inputs: &inputs,
            internals: &n,
        });
        c.edges += 1;
        // SAFETY: NULL or writable, by contract.
        unsafe {
            if !internals.is_null() {
                internals.write(n.into());
            }
            if !after.is_null() {
                after.write(after_out.into());
            }
        }
        PMU50_OK
    })
}

/// Edges sampled into `c` (0 for NULL).
///
/// # Safety
/// `c` NULL or live.
#[no_mangle]
pub unsafe extern "C" fn pmu50_coverage_edges(c: *const pmu50_coverage_t) -> u64 {
    // SAFETY: NULL or live, by contract.
    unsafe { c.as_ref() }.map_or(0, |c| c.edges)
}

/// Number of bins of the model (points, then crosses).
#[no_mangle]
pub extern "C" fn pmu50_coverage_bin_count() -> usize {
    catch_unwind(|| layout().bins.len()).unwrap_or(0)
}

/// The model's identity (static string), carried by every coverage file.
#[no_mangle]
pub extern "C" fn pmu50_coverage_model() -> *const c_char {
    catch_unwind(|| bin_names().model.as_ptr()).unwrap_or(c"".as_ptr())
}

/// Bin `index`: `name` (static, `group.point.bin` or `cross.<name>.<a>*<b>`), `is_cross`, and
/// `unreachable` (static reason, or NULL for a bin that can be hit); out pointers may be NULL.
///
/// # Safety
/// Out pointers NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn pmu50_coverage_bin_info(
    index: usize,
    name: *mut *const c_char,
    is_cross: *mut u8,
    unreachable: *mut *const c_char,
) -> c_int {
    guard("pmu50_coverage_bin_info", || {
        let l = layout();
        let Some(b) = l.bins.get(index) else {
            set_error(format!(
                "pmu50_coverage_bin_info: index {index} out of range 0..{}",
                l.bins.len()
            ));
            return PMU50_ERR_RANGE;
        };
        let n = bin_names();
        // SAFETY: NULL or writable, by contract.
        unsafe {
            if !name.is_null() {
                name.write(n.names[index].as_ptr());
            }
            if !is_cross.is_null() {
                is_cross.write(u8::from(b.kind == Kind::Cross));
            }
            if !unreachable.is_null() {
                unreachable.write(
                    n.unreachable[index]
                        .as_ref()
                        .map_or(std::ptr::null(), |s| s.as_ptr()),
                );
            }
        }
        PMU50_OK
    })
}

/// Index (>= 0) of the bin named `name`, or a negative error code (`PMU50_ERR_NAME`: no such bin).
///
/// # Safety
/// `name` NULL or NUL-terminated.
#[no_mangle]
pub unsafe extern "C" fn pmu50_coverage_find(name: *const c_char) -> c_int {
    const WHAT: &str = "pmu50_coverage_find";
    guard(WHAT, || {
        // SAFETY: forwarded contract.
        let q = match unsafe { text(WHAT, "name", name) } {
            Ok(q) => q,
            Err(rc) => return rc,
        };
        match layout().bins.iter().position(|b| b.name == q) {
            Some(k) => c_int::try_from(k).unwrap_or(PMU50_ERR_RANGE),
            None => {
                set_error(format!("{WHAT}: no bin named \"{q}\" (names are group.point.bin or cross.<name>.<a>*<b>, see docs/verification.md)"));
                PMU50_ERR_NAME
            }
        }
    })
}

/// Hits of bin `index` in `c`.
///
/// # Safety
/// `c` NULL or live; `hits` NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn pmu50_coverage_hits(
    c: *const pmu50_coverage_t,
    index: usize,
    hits: *mut u64,
) -> c_int {
    guard("pmu50_coverage_hits", || {
        // SAFETY: NULL or live, by contract.
        let Some(c) = (unsafe { c.as_ref() }) else {
            return null("pmu50_coverage_hits", "c");
        };
        if hits.is_null() {
            return null("pmu50_coverage_hits", "hits");
        }
        let Some(&h) = c.cov.hits().get(index) else {
            set_error(format!(
                "pmu50_coverage_hits: index {index} out of range 0..{}",
                c.cov.hits().len()
            ));
            return PMU50_ERR_RANGE;
        };
        // SAFETY: checked non-null.
        unsafe { hits.write(h) };
        PMU50_OK
    })
}

/// Bins of `c` hit at least once (`hit`) and bins that can be hit (`reachable`); out pointers
/// may be NULL.
///
/// # Safety
/// `c` NULL or live; out pointers NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn pmu50_coverage_closure(
    c: *const pmu50_coverage_t,
    hit: *mut usize,
    reachable: *mut usize,
) -> c_int {
    guard("pmu50_coverage_closure", || {
        // SAFETY: NULL or live, by contract.
        let Some(c) = (unsafe { c.as_ref() }) else {
            return null("pmu50_coverage_closure", "c");
        };
        let l = layout();
        let r = l.bins.iter().filter(|b| b.unreachable.is_none()).count();
        let h = l
            .bins
            .iter()
            .zip(c.cov.hits())
            .filter(|(b, h)| b.unreachable.is_none() && **h > 0)
            .count();
        // SAFETY: NULL or writable, by contract.
        unsafe {
            if !hit.is_null() {
                hit.write(h);
            }
            if !reachable.is_null() {
                reachable.write(r);
            }
        }
        PMU50_OK
    })
}

/// Write `coverage.json` of this run to `path` (temporary file renamed into place): the hits of
/// `c` and one run, `run_id` (unique across everything that will be merged) with `verdict`
/// ("pass", "fail", ...).
///
/// # Safety
/// `c` NULL or live; the strings NULL or NUL-terminated.
#[no_mangle]
pub unsafe extern "C" fn pmu50_coverage_write(
    c: *const pmu50_coverage_t,
    path: *const c_char,
    run_id: *const c_char,
    verdict: *const c_char,
) -> c_int {
    const WHAT: &str = "pmu50_coverage_write";
    guard(WHAT, || {
        // SAFETY: NULL or live, by contract.
        let Some(c) = (unsafe { c.as_ref() }) else {
            return null(WHAT, "c");
        };
        // SAFETY: forwarded contract.
        let (path, id, verdict) = match unsafe {
            (
                text(WHAT, "path", path),
                text(WHAT, "run_id", run_id),
                text(WHAT, "verdict", verdict),
            )
        } {
            (Ok(p), Ok(i), Ok(v)) => (p, i, v),
            (Err(rc), _, _) | (_, Err(rc), _) | (_, _, Err(rc)) => return rc,
        };
        // A device, a FIFO or a folder at `path` is refused and left as it is.
        match db::write_file(Path::new(path), &db::of_run(&c.cov, id, verdict).to_text()) {
            Ok(()) => PMU50_OK,
            Err(e) => db_error(WHAT, e),
        }
    })
}

/// Merge `n` coverage files `paths` into `out` (as `pmu50 merge`): hits added bin by bin, runs
/// united. A corrupt or foreign file or a run counted twice gives `PMU50_ERR_COVERAGE` naming
/// the file, and nothing is written.
///
/// # Safety
/// `paths` NULL or `n` readable pointers, each NULL or NUL-terminated; `out` NULL or
/// NUL-terminated.
#[no_mangle]
pub unsafe extern "C" fn pmu50_coverage_merge(
    paths: *const *const c_char,
    n: usize,
    out: *const c_char,
) -> c_int {
    const WHAT: &str = "pmu50_coverage_merge";
    guard(WHAT, || {
        if paths.is_null() {
            return null(WHAT, "paths");
        }
        // SAFETY: forwarded contract.
        let out = match unsafe { text(WHAT, "out", out) } {
            Ok(o) => o,
            Err(rc) => return rc,
        };
        let mut files = Vec::with_capacity(n);
        for k in 0..n {
            // SAFETY: `paths` has n readable entries, by contract.
            match unsafe { text(WHAT, &format!("paths[{k}]"), *paths.add(k)) } {
                Ok(p) => files.push(Path::new(p)),
                Err(rc) => return rc,
            }
        }
        // An output that is one of the inputs, or a device or a FIFO, is refused.
        match db::merge_files(&files, Path::new(out)) {
            Ok(_) => PMU50_OK,
            Err(e) => db_error(WHAT, e),
        }
    })
}
