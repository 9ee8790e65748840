//! C ABI of the PMU 50 digital core (`pmu50_core::Pmu50`), for lockstep co-simulation of the
//! Verilog twin against the Rust reference model (Verilator C++ testbench, SystemVerilog DPI-C,
//! or any simulator that can call C). The header is `hdl/ffi/include/pmu50.h`; the function and
//! struct documentation there is the contract, this file implements it.
//!
//! Rules of the boundary:
//! - No panic crosses it: every entry point runs under `catch_unwind` and returns
//!   `PMU50_ERR_PANIC` (or NULL / 0) instead.
//! - Every pointer is checked for NULL (`PMU50_ERR_NULL`).
//! - Errors leave a message in a thread-local buffer, read with `pmu50_last_error()`; the pointer
//!   stays valid until the next failing call on the same thread.
//! - C booleans are `uint8_t`, any non-zero value is true; outputs are 0 or 1.
//!
//! Build: `cargo build -p pmu50-ffi --release` gives `target/release/libpmu50_ffi.{a,so}`.
//! Link the static library with `-lpthread -ldl -lm`.

#![allow(non_camel_case_types)]

use pmu50_core::pmu50::Structural;
use pmu50_core::{Inputs, Internals, Outputs, Params, Pmu50};
use std::cell::RefCell;
use std::ffi::{c_char, c_int, CStr, CString};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::OnceLock;

pub const PMU50_OK: c_int = 0;
pub const PMU50_ERR_NULL: c_int = -1;
pub const PMU50_ERR_PARAM: c_int = -2;
pub const PMU50_ERR_RANGE: c_int = -3;
pub const PMU50_ERR_PANIC: c_int = -4;
pub const PMU50_ERR_NAME: c_int = -5;

/// Configuration: structural parameters plus reset values of the programmable registers, in
/// ticks (same names as the `// param` lines of a vector file).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct pmu50_params {
    pub sync_depth: u8,
    pub cnt_width: u8,
    pub adaptive: u8,
    pub cth: u8,
    pub pw: u16,
    pub pi: u16,
    pub ps: u16,
    pub si_max: u16,
    pub si_min: u16,
    pub t1: u16,
    pub t2: u16,
    pub smp_on: u16,
}

/// Top-level inputs of one clock cycle (one rising edge).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct pmu50_inputs {
    pub ig: u8,
    pub vs2_ok: u8,
    pub cmp_s: u8,
    pub cmp_c: u8,
    pub bus_we: u8,
    pub bus_addr: u8,
    pub bus_wdata: u16,
}

/// Top-level outputs (Moore), in the order of docs/signals.md and of the vector columns.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct pmu50_outputs {
    pub sig: u8,
    pub vr_hi: u8,
    pub vm_en: u8,
    pub vs1_en: u8,
    pub vs2_en: u8,
    pub vp_en: u8,
    pub rail_hi: u8,
    pub st: u8,
    pub sr: u8,
    pub ps_win: u8,
    pub smp: u8,
    pub cs: u8,
    pub cc: u8,
    pub cnt_s: u16,
    pub cnt_c: u16,
    pub cnt_r: u8,
    pub si: u16,
    pub hist_s: u8,
    pub hist_c: u8,
    pub diag: u8,
    pub quadrant_skip: u8,
    pub bus_rdata: u16,
    pub bus_err: u8,
}

/// Combinational internals of the cycle that ends at the edge (model VCD scope `pmu50.internals`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct pmu50_internals {
    pub kon: u8,
    pub koff: u8,
    pub upd: u8,
    pub first: u8,
    pub chg_s: u8,
    pub chg_c: u8,
    pub skip_clr: u8,
    pub fig17: u8,
    pub fig18: u8,
}

/// Opaque handle.
pub struct pmu50_t {
    core: Pmu50,
    params: Params,
}

// ------------------------------------------------------------------------------------------
// conversions

impl From<Params> for pmu50_params {
    fn from(p: Params) -> Self {
        pmu50_params {
            sync_depth: p.sync_depth,
            cnt_width: p.cnt_width,
            adaptive: u8::from(p.adaptive),
            cth: p.cth,
            pw: p.pw,
            pi: p.pi,
            ps: p.ps,
            si_max: p.si_max,
            si_min: p.si_min,
            t1: p.t1,
            t2: p.t2,
            smp_on: p.smp_on,
        }
    }
}

impl From<pmu50_params> for Params {
    fn from(p: pmu50_params) -> Self {
        Params {
            sync_depth: p.sync_depth,
            cnt_width: p.cnt_width,
            adaptive: p.adaptive != 0,
            pw: p.pw,
            pi: p.pi,
            ps: p.ps,
            si_max: p.si_max,
            si_min: p.si_min,
            t1: p.t1,
            t2: p.t2,
            cth: p.cth,
            smp_on: p.smp_on,
        }
    }
}

impl From<pmu50_inputs> for Inputs {
    fn from(i: pmu50_inputs) -> Self {
        Inputs {
            ig: i.ig != 0,
            vs2_ok: i.vs2_ok != 0,
            cmp_s: i.cmp_s != 0,
            cmp_c: i.cmp_c != 0,
            bus_we: i.bus_we != 0,
            bus_addr: i.bus_addr,
            bus_wdata: i.bus_wdata,
        }
    }
}

impl From<Outputs> for pmu50_outputs {
    fn from(o: Outputs) -> Self {
        let b = u8::from;
        pmu50_outputs {
            sig: b(o.sig),
            vr_hi: b(o.vr_hi),
            vm_en: b(o.vm_en),
            vs1_en: b(o.vs1_en),
            vs2_en: b(o.vs2_en),
            vp_en: b(o.vp_en),
            rail_hi: b(o.rail_hi),
            st: b(o.st),
            sr: b(o.sr),
            ps_win: b(o.ps_win),
            smp: b(o.smp),
            cs: b(o.cs),
            cc: b(o.cc),
            cnt_s: o.cnt_s,
            cnt_c: o.cnt_c,
            cnt_r: o.cnt_r,
            si: o.si,
            hist_s: b(o.hist_s),
            hist_c: b(o.hist_c),
            diag: b(o.diag),
            quadrant_skip: b(o.quadrant_skip),
            bus_rdata: o.bus_rdata,
            bus_err: b(o.bus_err),
        }
    }
}

impl From<Internals> for pmu50_internals {
    fn from(i: Internals) -> Self {
        let b = u8::from;
        pmu50_internals {
            kon: b(i.kon),
            koff: b(i.koff),
            upd: b(i.upd),
            first: b(i.first),
            chg_s: b(i.chg_s),
            chg_c: b(i.chg_c),
            skip_clr: b(i.skip_clr),
            fig17: i.fig17 as u8,
            fig18: i.fig18 as u8,
        }
    }
}

impl pmu50_outputs {
    /// (name, value) of every output, in column order.
    pub fn values(&self) -> [(&'static CStr, u64); 23] {
        fn u<T: Into<u64>>(v: T) -> u64 {
            v.into()
        }
        [
            (c"sig", u(self.sig)),
            (c"vr_hi", u(self.vr_hi)),
            (c"vm_en", u(self.vm_en)),
            (c"vs1_en", u(self.vs1_en)),
            (c"vs2_en", u(self.vs2_en)),
            (c"vp_en", u(self.vp_en)),
            (c"rail_hi", u(self.rail_hi)),
            (c"st", u(self.st)),
            (c"sr", u(self.sr)),
            (c"ps_win", u(self.ps_win)),
            (c"smp", u(self.smp)),
            (c"cs", u(self.cs)),
            (c"cc", u(self.cc)),
            (c"cnt_s", u(self.cnt_s)),
            (c"cnt_c", u(self.cnt_c)),
            (c"cnt_r", u(self.cnt_r)),
            (c"si", u(self.si)),
            (c"hist_s", u(self.hist_s)),
            (c"hist_c", u(self.hist_c)),
            (c"diag", u(self.diag)),
            (c"quadrant_skip", u(self.quadrant_skip)),
            (c"bus_rdata", u(self.bus_rdata)),
            (c"bus_err", u(self.bus_err)),
        ]
    }
}

impl pmu50_internals {
    /// (name, value) of every internal signal.
    pub fn values(&self) -> [(&'static CStr, u64); 9] {
        fn u<T: Into<u64>>(v: T) -> u64 {
            v.into()
        }
        [
            (c"kon", u(self.kon)),
            (c"koff", u(self.koff)),
            (c"upd", u(self.upd)),
            (c"first", u(self.first)),
            (c"chg_s", u(self.chg_s)),
            (c"chg_c", u(self.chg_c)),
            (c"skip_clr", u(self.skip_clr)),
            (c"fig17", u(self.fig17)),
            (c"fig18", u(self.fig18)),
        ]
    }
}

const OUTPUT_WIDTHS: [u8; 23] = [
    1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 0, 0, 8, 16, 1, 1, 1, 1, 16, 1,
];
const INTERNAL_WIDTHS: [u8; 9] = [1, 1, 1, 1, 1, 1, 1, 3, 3];

/// Register names (`block`, `name`, `block.name`) in the order of `Regs::values`.
struct RegName {
    block: CString,
    name: CString,
    full: String,
}

fn reg_names() -> &'static [RegName] {
    static NAMES: OnceLock<Vec<RegName>> = OnceLock::new();
    NAMES.get_or_init(|| {
        let p = Params::default();
        let core = Pmu50::new(p).expect("default parameters are legal");
        let s = core.structural();
        core.regs()
            .values(&s)
            .iter()
            .map(|r| RegName {
                block: CString::new(r.block).unwrap_or_default(),
                name: CString::new(r.name).unwrap_or_default(),
                full: format!("{}.{}", r.block, r.name),
            })
            .collect()
    })
}

/// Index of a register by `name`, `block.name` or `pmu50.block.name`; a bare name must be unique.
pub fn find_register(query: &str) -> Result<usize, String> {
    let q = query.strip_prefix("pmu50.").unwrap_or(query);
    let names = reg_names();
    if let Some(i) = names.iter().position(|r| r.full == q) {
        return Ok(i);
    }
    let hits: Vec<usize> = names
        .iter()
        .enumerate()
        .filter(|(_, r)| r.name.to_str() == Ok(q))
        .map(|(i, _)| i)
        .collect();
    match hits.as_slice() {
        [i] => Ok(*i),
        [] => Err(format!(
            "no register named `{query}`; valid: {}",
            names
                .iter()
                .map(|r| r.full.as_str())
                .collect::<Vec<_>>()
                .join(", ")
        )),
        _ => Err(format!(
            "register name `{query}` is ambiguous: {}",
            hits.iter()
                .map(|&i| names[i].full.as_str())
                .collect::<Vec<_>>()
                .join(", ")
        )),
    }
}

// ------------------------------------------------------------------------------------------
// error reporting

thread_local! {
    static LAST_ERROR: RefCell<CString> = RefCell::new(CString::default());
}

fn set_error(msg: impl Into<String>) {
    let mut m: String = msg.into();
    m.retain(|c| c != '\0');
    let c = CString::new(m).unwrap_or_default();
    LAST_ERROR.with(|e| *e.borrow_mut() = c);
}

fn panic_message(e: &(dyn std::any::Any + Send)) -> String {
    if let Some(s) = e.downcast_ref::<&str>() {
        (*s).to_string()
    } else if let Some(s) = e.downcast_ref::<String>() {
        s.clone()
    } else {
        "unknown panic".to_string()
    }
}

/// Run `f` and turn a panic into `PMU50_ERR_PANIC`.
fn guard(what: &str, f: impl FnOnce() -> c_int) -> c_int {
    match catch_unwind(AssertUnwindSafe(f)) {
        Ok(rc) => rc,
        Err(e) => {
            set_error(format!("{what}: internal panic: {}", panic_message(&*e)));
            PMU50_ERR_PANIC
        }
    }
}

fn null(what: &str, arg: &str) -> c_int {
    set_error(format!("{what}: `{arg}` is NULL"));
    PMU50_ERR_NULL
}

// ------------------------------------------------------------------------------------------
// API

/// Version of this library (static string).
#[no_mangle]
pub extern "C" fn pmu50_version() -> *const c_char {
    static V: &CStr = c"pmu50-ffi 0.1.0 (C ABI 1)";
    V.as_ptr()
}

/// Message of the last failed call on this thread ("" if none). Valid until the next failing
/// call on the same thread.
#[no_mangle]
pub extern "C" fn pmu50_last_error() -> *const c_char {
    LAST_ERROR.with(|e| e.borrow().as_ptr())
}

/// Fill `out` with the default parameters (the patent's values at a 10 us clock).
///
/// # Safety
/// `out` must be NULL or point to writable memory for one `pmu50_params`.
#[no_mangle]
pub unsafe extern "C" fn pmu50_params_default(out: *mut pmu50_params) -> c_int {
    guard("pmu50_params_default", || {
        if out.is_null() {
            return null("pmu50_params_default", "out");
        }
        // SAFETY: checked non-null; the caller guarantees it is writable.
        unsafe { out.write(Params::default().into()) };
        PMU50_OK
    })
}

/// `PMU50_OK` if the parameters are legal (spec section 4), else `PMU50_ERR_PARAM` with the rule
/// in `pmu50_last_error()`.
///
/// # Safety
/// `p` must be NULL or point to a readable `pmu50_params`.
#[no_mangle]
pub unsafe extern "C" fn pmu50_params_validate(p: *const pmu50_params) -> c_int {
    guard("pmu50_params_validate", || {
        if p.is_null() {
            return null("pmu50_params_validate", "p");
        }
        // SAFETY: checked non-null.
        let params: Params = unsafe { p.read() }.into();
        match params.validate() {
            Ok(()) => PMU50_OK,
            Err(e) => {
                set_error(e.to_string());
                PMU50_ERR_PARAM
            }
        }
    })
}

/// New core at power-on reset. NULL on illegal parameters (message in `pmu50_last_error()`).
///
/// # Safety
/// `p` must be NULL or point to a readable `pmu50_params`.
#[no_mangle]
pub unsafe extern "C" fn pmu50_new(p: *const pmu50_params) -> *mut pmu50_t {
    let r = catch_unwind(AssertUnwindSafe(|| {
        if p.is_null() {
            set_error("pmu50_new: `p` is NULL");
            return std::ptr::null_mut();
        }
        // SAFETY: checked non-null.
        let params: Params = unsafe { p.read() }.into();
        match Pmu50::new(params) {
            Ok(core) => Box::into_raw(Box::new(pmu50_t { core, params })),
            Err(e) => {
                set_error(format!("pmu50_new: {e}"));
                std::ptr::null_mut()
            }
        }
    }));
    r.unwrap_or_else(|e| {
        set_error(format!("pmu50_new: internal panic: {}", panic_message(&*e)));
        std::ptr::null_mut()
    })
}

/// Free a core (NULL is ignored).
///
/// # Safety
/// `m` must be NULL or a handle from `pmu50_new` not freed yet.
#[no_mangle]
pub unsafe extern "C" fn pmu50_free(m: *mut pmu50_t) {
    if m.is_null() {
        return;
    }
    let _ = catch_unwind(AssertUnwindSafe(|| {
        // SAFETY: the caller passes a live handle from pmu50_new.
        drop(unsafe { Box::from_raw(m) });
    }));
}

/// Back to power-on reset (same parameters); tick count 0.
///
/// # Safety
/// `m` must be NULL or a live handle.
#[no_mangle]
pub unsafe extern "C" fn pmu50_reset(m: *mut pmu50_t) -> c_int {
    guard("pmu50_reset", || {
        // SAFETY: the caller passes NULL or a live handle.
        let Some(m) = (unsafe { m.as_mut() }) else {
            return null("pmu50_reset", "m");
        };
        m.core.reset();
        PMU50_OK
    })
}

/// Parameters the core was created with.
///
/// # Safety
/// `m` NULL or live; `out` NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn pmu50_get_params(m: *const pmu50_t, out: *mut pmu50_params) -> c_int {
    guard("pmu50_get_params", || {
        // SAFETY: the caller passes NULL or a live handle.
        let Some(m) = (unsafe { m.as_ref() }) else {
            return null("pmu50_get_params", "m");
        };
        if out.is_null() {
            return null("pmu50_get_params", "out");
        }
        // SAFETY: checked non-null.
        unsafe { out.write(m.params.into()) };
        PMU50_OK
    })
}

/// One rising edge with inputs `i`. `after` (may be NULL): outputs after the edge.
///
/// # Safety
/// `m` NULL or live; `i` NULL or readable; `after` NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn pmu50_step(
    m: *mut pmu50_t,
    i: *const pmu50_inputs,
    after: *mut pmu50_outputs,
) -> c_int {
    // SAFETY: forwarded contract.
    unsafe { pmu50_step_traced(m, i, std::ptr::null_mut(), after) }
}

/// One rising edge; `internals` (may be NULL): combinational internals of the cycle that ends at
/// this edge; `after` (may be NULL): outputs after the edge.
///
/// # Safety
/// `m` NULL or live; `i` NULL or readable; `internals`, `after` NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn pmu50_step_traced(
    m: *mut pmu50_t,
    i: *const pmu50_inputs,
    internals: *mut pmu50_internals,
    after: *mut pmu50_outputs,
) -> c_int {
    guard("pmu50_step", || {
        // SAFETY: the caller passes NULL or a live handle.
        let Some(m) = (unsafe { m.as_mut() }) else {
            return null("pmu50_step", "m");
        };
        if i.is_null() {
            return null("pmu50_step", "i");
        }
        // SAFETY: checked non-null.
        let inputs: Inputs = unsafe { i.read() }.into();
        let (_, int, out) = m.core.step_traced(&inputs);
        if !internals.is_null() {
            // SAFETY: checked non-null.
            unsafe { internals.write(int.into()) };
        }
        if !after.is_null() {
            // SAFETY: checked non-null.
            unsafe { after.write(out.into()) };
        }
        PMU50_OK
    })
}

/// Outputs of the current cycle (after the last edge; reset values before the first).
///
/// # Safety
/// `m` NULL or live; `out` NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn pmu50_peek(m: *const pmu50_t, out: *mut pmu50_outputs) -> c_int {
    guard("pmu50_peek", || {
        // SAFETY: the caller passes NULL or a live handle.
        let Some(m) = (unsafe { m.as_ref() }) else {
            return null("pmu50_peek", "m");
        };
        if out.is_null() {
            return null("pmu50_peek", "out");
        }
        // SAFETY: checked non-null.
        unsafe { out.write(m.core.peek().into()) };
        PMU50_OK
    })
}

/// Edges taken since reset (0 for NULL).
///
/// # Safety
/// `m` NULL or live.
#[no_mangle]
pub unsafe extern "C" fn pmu50_tick(m: *const pmu50_t) -> u64 {
    catch_unwind(AssertUnwindSafe(|| {
        // SAFETY: the caller passes NULL or a live handle.
        unsafe { m.as_ref() }.map_or(0, |m| m.core.tick())
    }))
    .unwrap_or(0)
}

/// The register file's read mux at `addr` this cycle (what `bus_rdata` shows one edge later).
///
/// # Safety
/// `m` NULL or live; `out` NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn pmu50_bus_read(m: *const pmu50_t, addr: u8, out: *mut u16) -> c_int {
    guard("pmu50_bus_read", || {
        // SAFETY: the caller passes NULL or a live handle.
        let Some(m) = (unsafe { m.as_ref() }) else {
            return null("pmu50_bus_read", "m");
        };
        if out.is_null() {
            return null("pmu50_bus_read", "out");
        }
        // SAFETY: checked non-null.
        unsafe { out.write(m.core.read(addr)) };
        PMU50_OK
    })
}

/// Number of registers (26).
#[no_mangle]
pub extern "C" fn pmu50_reg_count() -> usize {
    catch_unwind(reg_names).map_or(0, <[RegName]>::len)
}

/// Name of register `index`: `block` (VCD sub-scope, e.g. "updown_counter"), `name` (e.g.
/// "cnt_s"), and its width in this core (`width`); any out pointer may be NULL. The strings are
/// static.
///
/// # Safety
/// `m` NULL or live (NULL: width of the default configuration); out pointers NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn pmu50_reg_info(
    m: *const pmu50_t,
    index: usize,
    block: *mut *const c_char,
    name: *mut *const c_char,
    width: *mut u8,
) -> c_int {
    guard("pmu50_reg_info", || {
        let names = reg_names();
        let Some(r) = names.get(index) else {
            set_error(format!(
                "pmu50_reg_info: index {index} out of range 0..{}",
                names.len()
            ));
            return PMU50_ERR_RANGE;
        };
        // SAFETY: the caller passes NULL or a live handle.
        let s = unsafe { m.as_ref() }.map_or(
            Structural {
                sync_depth: 2,
                cnt_width: 16,
            },
            |m| m.core.structural(),
        );
        let w = reg_widths(&s)[index];
        // SAFETY: each out pointer is checked non-null; the caller guarantees writability.
        unsafe {
            if !block.is_null() {
                block.write(r.block.as_ptr());
            }
            if !name.is_null() {
                name.write(r.name.as_ptr());
            }
            if !width.is_null() {
                width.write(w);
            }
        }
        PMU50_OK
    })
}

fn reg_widths(s: &Structural) -> Vec<u8> {
    let core = Pmu50::new(Params::default()).expect("default parameters are legal");
    core.regs().values(s).iter().map(|r| r.width).collect()
}

/// Value of register `index`.
///
/// # Safety
/// `m` NULL or live; `value` NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn pmu50_reg_get(m: *const pmu50_t, index: usize, value: *mut u64) -> c_int {
    guard("pmu50_reg_get", || {
        // SAFETY: the caller passes NULL or a live handle.
        let Some(m) = (unsafe { m.as_ref() }) else {
            return null("pmu50_reg_get", "m");
        };
        if value.is_null() {
            return null("pmu50_reg_get", "value");
        }
        let vals = m.core.regs().values(&m.core.structural());
        let Some(r) = vals.get(index) else {
            set_error(format!(
                "pmu50_reg_get: index {index} out of range 0..{}",
                vals.len()
            ));
            return PMU50_ERR_RANGE;
        };
        // SAFETY: checked non-null.
        unsafe { value.write(r.value) };
        PMU50_OK
    })
}

/// Index of a register by name: "cnt_s", "updown_counter.cnt_s" or "pmu50.updown_counter.cnt_s".
/// Returns the index (>= 0) or a negative error code (`PMU50_ERR_NAME` unknown or ambiguous).
///
/// # Safety
/// `name` NULL or a NUL-terminated string.
#[no_mangle]
pub unsafe extern "C" fn pmu50_reg_find(name: *const c_char) -> c_int {
    guard("pmu50_reg_find", || {
        if name.is_null() {
            return null("pmu50_reg_find", "name");
        }
        // SAFETY: checked non-null, NUL-terminated by contract.
        let Ok(q) = unsafe { CStr::from_ptr(name) }.to_str() else {
            set_error("pmu50_reg_find: name is not UTF-8");
            return PMU50_ERR_NAME;
        };
        match find_register(q) {
            Ok(i) => c_int::try_from(i).unwrap_or(PMU50_ERR_RANGE),
            Err(e) => {
                set_error(format!("pmu50_reg_find: {e}"));
                PMU50_ERR_NAME
            }
        }
    })
}

/// Value of a register by name (see `pmu50_reg_find`).
///
/// # Safety
/// `m` NULL or live; `name` NULL or NUL-terminated; `value` NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn pmu50_reg_get_by_name(
    m: *const pmu50_t,
    name: *const c_char,
    value: *mut u64,
) -> c_int {
    // SAFETY: forwarded contract.
    let i = unsafe { pmu50_reg_find(name) };
    if i < 0 {
        return i;
    }
    // SAFETY: forwarded contract; i >= 0.
    unsafe { pmu50_reg_get(m, i as usize, value) }
}

/// Number of top-level outputs (23).
#[no_mangle]
pub extern "C" fn pmu50_output_count() -> usize {
    OUTPUT_WIDTHS.len()
}

/// Name (static) and width of output `index` in the core `m` (NULL: default configuration, cnt
/// width 16); out pointers may be NULL.
///
/// # Safety
/// `m` NULL or live; out pointers NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn pmu50_output_info(
    m: *const pmu50_t,
    index: usize,
    name: *mut *const c_char,
    width: *mut u8,
) -> c_int {
    guard("pmu50_output_info", || {
        // SAFETY: the caller passes NULL or a live handle.
        let cw = unsafe { m.as_ref() }.map_or(16, |m| m.core.structural().cnt_width);
        let widths = OUTPUT_WIDTHS.map(|w| if w == 0 { cw } else { w });
        // SAFETY: the caller passes NULL or writable out pointers.
        unsafe { write_info("pmu50_output_info", &pmu50_outputs::default().values(), &widths, index, name, width) }
    })
}

/// Value of output `index` of an outputs struct.
///
/// # Safety
/// `o` NULL or readable; `value` NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn pmu50_output_get(
    o: *const pmu50_outputs,
    index: usize,
    value: *mut u64,
) -> c_int {
    guard("pmu50_output_get", || {
        // SAFETY: the caller passes NULL or a readable struct.
        let Some(o) = (unsafe { o.as_ref() }) else {
            return null("pmu50_output_get", "o");
        };
        // SAFETY: the caller passes NULL or a writable pointer.
        unsafe { write_value("pmu50_output_get", &o.values(), index, value) }
    })
}

/// Number of internal signals (9).
#[no_mangle]
pub extern "C" fn pmu50_internal_count() -> usize {
    INTERNAL_WIDTHS.len()
}

/// Name (static) and width of internal signal `index`; out pointers may be NULL.
///
/// # Safety
/// Out pointers NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn pmu50_internal_info(
    index: usize,
    name: *mut *const c_char,
    width: *mut u8,
) -> c_int {
    guard("pmu50_internal_info", || {
        // SAFETY: the caller passes NULL or writable out pointers.
        unsafe { write_info("pmu50_internal_info", &pmu50_internals::default().values(), &INTERNAL_WIDTHS, index, name, width) }
    })
}

/// Value of internal signal `index` of an internals struct.
///
/// # Safety
/// `x` NULL or readable; `value` NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn pmu50_internal_get(
    x: *const pmu50_internals,
    index: usize,
    value: *mut u64,
) -> c_int {
    guard("pmu50_internal_get", || {
        // SAFETY: the caller passes NULL or a readable struct.
        let Some(x) = (unsafe { x.as_ref() }) else {
            return null("pmu50_internal_get", "x");
        };
        // SAFETY: the caller passes NULL or a writable pointer.
        unsafe { write_value("pmu50_internal_get", &x.values(), index, value) }
    })
}

/// Shared body of the indexed value getters: value `index` of `vals` into `value`.
///
/// # Safety
/// `value` NULL or writable.
unsafe fn write_value(what: &str, vals: &[(&'static CStr, u64)], index: usize, value: *mut u64) -> c_int {
    if value.is_null() {
        return null(what, "value");
    }
    let Some((_, v)) = vals.get(index) else {
        set_error(format!("{what}: index {index} out of range 0..{}", vals.len()));
        return PMU50_ERR_RANGE;
    };
    // SAFETY: checked non-null; the caller guarantees writable.
    unsafe { value.write(*v) };
    PMU50_OK
}

/// Shared body of the name/width getters; out pointers may be NULL.
///
/// # Safety
/// `name` and `width` NULL or writable.
unsafe fn write_info(what: &str, vals: &[(&'static CStr, u64)], widths: &[u8], index: usize, name: *mut *const c_char, width: *mut u8) -> c_int {
    let (Some((n, _)), Some(&w)) = (vals.get(index), widths.get(index)) else {
        set_error(format!("{what}: index {index} out of range 0..{}", vals.len()));
        return PMU50_ERR_RANGE;
    };
    // SAFETY: checked non-null; the caller guarantees writable.
    unsafe {
        if !name.is_null() {
            name.write(n.as_ptr());
        }
        if !width.is_null() {
            width.write(w);
        }
    }
    PMU50_OK
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::ptr;

    fn last_error() -> String {
        // SAFETY: pmu50_last_error returns a valid NUL-terminated string.
        unsafe { CStr::from_ptr(pmu50_last_error()) }
            .to_string_lossy()
            .into_owned()
    }

    #[test]
    fn illegal_params_give_null_and_a_message() {
        let mut p = pmu50_params::default();
        // SAFETY: valid pointers.
        unsafe {
            assert_eq!(pmu50_params_default(&mut p), PMU50_OK);
            p.si_min = 0;
            assert!(pmu50_new(&p).is_null());
            assert!(last_error().contains("min"), "{}", last_error());
            assert_eq!(pmu50_params_validate(&p), PMU50_ERR_PARAM);
            assert!(pmu50_new(ptr::null()).is_null());
        }
    }

    #[test]
    fn null_handles_are_refused() {
        let i = pmu50_inputs::default();
        let mut o = pmu50_outputs::default();
        let mut v = 0u64;
        // SAFETY: NULL handles are part of the contract.
        unsafe {
            assert_eq!(pmu50_step(ptr::null_mut(), &i, &mut o), PMU50_ERR_NULL);
            assert_eq!(pmu50_peek(ptr::null(), &mut o), PMU50_ERR_NULL);
            assert_eq!(pmu50_reset(ptr::null_mut()), PMU50_ERR_NULL);
            assert_eq!(pmu50_reg_get(ptr::null(), 0, &mut v), PMU50_ERR_NULL);
            assert_eq!(pmu50_reg_find(ptr::null()), PMU50_ERR_NULL);
            pmu50_free(ptr::null_mut());
        }
    }

    #[test]
    fn step_matches_the_core_and_registers_resolve_by_name() {
        let mut p = pmu50_params::default();
        // SAFETY: valid pointers; the handle is freed at the end.
        unsafe {
            pmu50_params_default(&mut p);
            let m = pmu50_new(&p);
            assert!(!m.is_null());
            let mut core = Pmu50::new(Params::default()).unwrap();
            let mut o = pmu50_outputs::default();
            let mut x = pmu50_internals::default();
            for k in 0..5000u32 {
                let i = pmu50_inputs {
                    ig: u8::from(k % 3000 > 1500),
                    vs2_ok: 1,
                    cmp_s: u8::from(k % 700 > 350),
                    cmp_c: u8::from(k % 500 > 250),
                    ..Default::default()
                };
                assert_eq!(pmu50_step_traced(m, &i, &mut x, &mut o), PMU50_OK);
                let (_, int, out) = core.step_traced(&i.into());
                assert_eq!(o, out.into());
                assert_eq!(x, int.into());
            }
            assert_eq!(pmu50_tick(m), 5000);
            let idx = pmu50_reg_find(c"updown_counter.cnt_s".as_ptr());
            assert!(idx >= 0);
            assert_eq!(pmu50_reg_find(c"cnt_s".as_ptr()), idx);
            assert_eq!(pmu50_reg_find(c"pmu50.updown_counter.cnt_s".as_ptr()), idx);
            assert_eq!(pmu50_reg_find(c"nope".as_ptr()), PMU50_ERR_NAME);
            let mut v = 0u64;
            assert_eq!(pmu50_reg_get_by_name(m, c"si".as_ptr(), &mut v), PMU50_OK);
            assert_eq!(v, u64::from(o.si));
            let mut w = 0u8;
            let mut b: *const c_char = ptr::null();
            assert_eq!(
                pmu50_reg_info(m, 0, &mut b, ptr::null_mut(), &mut w),
                PMU50_OK
            );
            assert_eq!(CStr::from_ptr(b).to_str().unwrap(), "action_switching");
            assert_eq!(w, 2);
            assert_eq!(pmu50_reg_count(), 26);
            let mut q = pmu50_params::default();
            assert_eq!(pmu50_get_params(m, &mut q), PMU50_OK);
            assert_eq!(q, p);
            pmu50_free(m);
        }
    }
}
