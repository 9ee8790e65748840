//! The core's half of the C ABI (`pmu50_t`, `pmu50_params`, stepping, registers, checks) and
//! the rules of the boundary that the coverage half shares (crate root: lib.rs).

pub use crate::mirror::{pmu50_inputs, pmu50_internals, pmu50_outputs};
use pmu50_core::pmu50::Structural;
use pmu50_core::signals;
use pmu50_core::{Inputs, Internals, Params, Pmu50};
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

/// Opaque handle.
pub struct pmu50_t {
    pub(crate) core: Pmu50,
    params: Params,
    /// Internals of the cycle that ended at the last edge (`None` before the first edge).
    pub(crate) last: Option<Internals>,
    /// Report of the last `pmu50_check` (one `MISMATCH` line per difference).
    report: CString,
}

// ------------------------------------------------------------------------------------------
// conversions

/// A C field of `pmu50_params` read as the parameter's type (a C boolean: any non-zero is true).
trait FromC<C> {
    fn from_c(c: C) -> Self;
}

impl FromC<u8> for bool {
    fn from_c(c: u8) -> bool {
        c != 0
    }
}

impl<T> FromC<T> for T {
    fn from_c(c: T) -> T {
        c
    }
}

/// The conversions of `pmu50_params`, generated from the parameter table (the struct itself is
/// the header's, whose field order is the ABI).
macro_rules! params_conversions {
    (structural: [$(($sf:ident, $st:ty, $sh:literal, $sd:literal, $sdoc:literal),)*],
     programmable: [$(($f:ident, $t:ty, $h:literal, $d:literal, $a:ident, $doc:literal),)*]) => {
        impl From<Params> for pmu50_params {
            fn from(p: Params) -> Self {
                pmu50_params { $($sf: p.$sf.into(),)* $($f: p.$f.into(),)* }
            }
        }

        impl From<pmu50_params> for Params {
            fn from(p: pmu50_params) -> Self {
                Params { $($sf: FromC::from_c(p.$sf),)* $($f: FromC::from_c(p.$f),)* }
            }
        }
    };
}

pmu50_core::param_table!(params_conversions);

/// NUL-terminated copies of the table's names (static for the life of the library).
struct Names {
    outputs: Vec<CString>,
    internals: Vec<CString>,
    reg_scopes: Vec<CString>,
    reg_names: Vec<CString>,
}

fn names() -> &'static Names {
    static NAMES: OnceLock<Names> = OnceLock::new();
    NAMES.get_or_init(|| {
        let c = |s: &str| CString::new(s).unwrap_or_default();
        Names {
            outputs: signals::OUTPUTS.iter().map(|s| c(s.name)).collect(),
            internals: signals::INTERNALS.iter().map(|s| c(s.name)).collect(),
            reg_scopes: signals::REGISTERS.iter().map(|s| c(s.scope)).collect(),
            reg_names: signals::REGISTERS.iter().map(|s| c(s.name)).collect(),
        }
    })
}

/// Index of a register by `name`, `block.name` or `pmu50.block.name`; a bare name must be unique.
pub fn find_register(query: &str) -> Result<usize, String> {
    signals::find_register(query).map_err(|e| e.to_string())
}

/// One difference found by [`check`].
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Mismatch {
    /// Tick the value belongs to (edge number; for internals the cycle before that edge).
    pub tick: u64,
    /// Path below `pmu50`: `si`, `drive_interval.si`, `internals.fig17`.
    pub signal: String,
    pub width: u8,
    /// The model's value.
    pub expected: u64,
    /// The RTL's value.
    pub got: u64,
}

impl std::fmt::Display for Mismatch {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let d = usize::from(self.width).div_ceil(4).max(1);
        write!(
            f,
            "MISMATCH tick={} signal={} expected={:0d$x} got={:0d$x}",
            self.tick, self.signal, self.expected, self.got
        )
    }
}

/// The lockstep comparison (verification method 2), once for every testbench: the RTL's
/// outputs and registers after the last edge and its internals of the cycle before that edge,
/// each optional, against the model's. Differences in table order.
pub fn check(
    m: &pmu50_t,
    outputs: Option<&pmu50_outputs>,
    regs: Option<&[u64; signals::N_REGISTERS]>,
    internals: Option<&pmu50_internals>,
) -> Result<Vec<Mismatch>, String> {
    let s = m.core.structural();
    let tick = m.core.tick();
    let mut out = Vec::new();
    if let Some(rtl) = outputs {
        let model = pmu50_outputs::from(m.core.peek()).values();
        for ((sig, &e), g) in signals::OUTPUTS.iter().zip(&model).zip(rtl.values()) {
            if e != g {
                out.push(Mismatch {
                    tick,
                    signal: sig.path(),
                    width: sig.bits(&s),
                    expected: e,
                    got: g,
                });
            }
        }
    }
    if let Some(rtl) = regs {
        for (sig, &g) in signals::REGISTERS.iter().zip(rtl) {
            let e = (sig.get)(m.core.regs());
            if e != g {
                out.push(Mismatch {
                    tick,
                    signal: sig.path(),
                    width: sig.bits(&s),
                    expected: e,
                    got: g,
                });
            }
        }
    }
    if let Some(rtl) = internals {
        let Some(last) = m.last else {
            return Err(
                "internals can only be compared after a step (pmu50_step_traced)".to_string(),
            );
        };
        let model = pmu50_internals::from(last).values();
        for ((sig, &e), g) in signals::INTERNALS.iter().zip(&model).zip(rtl.values()) {
            if e != g {
                out.push(Mismatch {
                    tick: tick - 1,
                    signal: sig.path(),
                    width: sig.bits(&s),
                    expected: e,
                    got: g,
                });
            }
        }
    }
    Ok(out)
}

// ------------------------------------------------------------------------------------------
// error reporting

thread_local! {
    static LAST_ERROR: RefCell<CString> = RefCell::new(CString::default());
}

pub(crate) fn set_error(msg: impl Into<String>) {
    let mut m: String = msg.into();
    m.retain(|c| c != '\0');
    let c = CString::new(m).unwrap_or_default();
    LAST_ERROR.with(|e| *e.borrow_mut() = c);
}

pub(crate) fn panic_message(e: &(dyn std::any::Any + Send)) -> &str {
    pmu50_core::panic_payload_text(e).unwrap_or("unknown panic")
}

/// Run `f` and turn a panic into `PMU50_ERR_PANIC`.
pub(crate) fn guard(what: &str, f: impl FnOnce() -> c_int) -> c_int {
    match catch_unwind(AssertUnwindSafe(f)) {
        Ok(rc) => rc,
        Err(e) => {
            set_error(format!("{what}: internal panic: {}", panic_message(&*e)));
            PMU50_ERR_PANIC
        }
    }
}

pub(crate) fn null(what: &str, arg: &str) -> c_int {
    set_error(format!("{what}: `{arg}` is NULL"));
    PMU50_ERR_NULL
}

/// `guard` around `f` on the live core behind `m`; a NULL `m` is refused (`PMU50_ERR_NULL`).
///
/// # Safety
/// `m` NULL or live.
unsafe fn with_live(what: &str, m: *mut pmu50_t, f: impl FnOnce(&mut pmu50_t) -> c_int) -> c_int {
    guard(what, || {
        // SAFETY: the caller passes NULL or a live handle.
        match unsafe { m.as_mut() } {
            Some(m) => f(m),
            None => null(what, "m"),
        }
    })
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
    // SAFETY: forwarded contract.
    unsafe {
        new_handle("pmu50_new", p, |params| {
            Pmu50::new(params)
                .map(|core| pmu50_t {
                    core,
                    params,
                    last: None,
                    report: CString::default(),
                })
                .map_err(|e| e.to_string())
        })
    }
}

/// Free a core (NULL is ignored).
///
/// # Safety
/// `m` must be NULL or a handle from `pmu50_new` not freed yet.
#[no_mangle]
pub unsafe extern "C" fn pmu50_free(m: *mut pmu50_t) {
    // SAFETY: forwarded contract.
    unsafe { free_handle(m) }
}

/// Back to power-on reset (same parameters); tick count 0.
///
/// # Safety
/// `m` must be NULL or a live handle.
#[no_mangle]
pub unsafe extern "C" fn pmu50_reset(m: *mut pmu50_t) -> c_int {
    // SAFETY: forwarded contract.
    unsafe {
        with_live("pmu50_reset", m, |m| {
            m.core.reset();
            m.last = None;
            PMU50_OK
        })
    }
}

/// Parameters the core was created with.
///
/// # Safety
/// `m` NULL or live; `out` NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn pmu50_get_params(m: *const pmu50_t, out: *mut pmu50_params) -> c_int {
    // SAFETY: forwarded contract.
    unsafe { get_into("pmu50_get_params", m, "out", out, |m| Ok(m.params.into())) }
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
    let step = |m: &mut pmu50_t| {
        if i.is_null() {
            return null("pmu50_step", "i");
        }
        // SAFETY: checked non-null.
        let inputs: Inputs = unsafe { i.read() }.into();
        let pmu50_core::TracedStep {
            internals: int,
            after: out,
            ..
        } = m.core.step_traced(&inputs);
        m.last = Some(int);
        if !internals.is_null() {
            // SAFETY: checked non-null.
            unsafe { internals.write(int.into()) };
        }
        if !after.is_null() {
            // SAFETY: checked non-null.
            unsafe { after.write(out.into()) };
        }
        PMU50_OK
    };
    // SAFETY: forwarded contract.
    unsafe { with_live("pmu50_step", m, step) }
}

/// Outputs of the current cycle (after the last edge; reset values before the first).
///
/// # Safety
/// `m` NULL or live; `out` NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn pmu50_peek(m: *const pmu50_t, out: *mut pmu50_outputs) -> c_int {
    // SAFETY: forwarded contract.
    unsafe { get_into("pmu50_peek", m, "out", out, |m| Ok(m.core.peek().into())) }
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
    // SAFETY: forwarded contract.
    unsafe { get_into("pmu50_bus_read", m, "out", out, |m| Ok(m.core.read(addr))) }
}

/// Number of registers (`PMU50_REG_COUNT`).
#[no_mangle]
pub extern "C" fn pmu50_reg_count() -> usize {
    signals::N_REGISTERS
}

/// The structural parameters of `m`, or the default configuration's for NULL.
///
/// # Safety
/// `m` NULL or live.
unsafe fn structural_of(m: *const pmu50_t) -> Structural {
    let d = Params::default();
    // SAFETY: the caller passes NULL or a live handle.
    unsafe { m.as_ref() }.map_or(
        Structural {
            sync_depth: d.sync_depth,
            cnt_width: d.cnt_width,
        },
        |m| m.core.structural(),
    )
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
        let Some(r) = entry("pmu50_reg_info", signals::REGISTERS, index) else {
            return PMU50_ERR_RANGE;
        };
        // SAFETY: forwarded contract.
        let w = r.bits(&unsafe { structural_of(m) });
        let n = names();
        // SAFETY: each out pointer is checked non-null; the caller guarantees writability.
        unsafe {
            if !block.is_null() {
                block.write(n.reg_scopes[index].as_ptr());
            }
            if !name.is_null() {
                name.write(n.reg_names[index].as_ptr());
            }
            if !width.is_null() {
                width.write(w);
            }
        }
        PMU50_OK
    })
}

/// Value of register `index`.
///
/// # Safety
/// `m` NULL or live; `value` NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn pmu50_reg_get(m: *const pmu50_t, index: usize, value: *mut u64) -> c_int {
    // SAFETY: forwarded contract.
    unsafe {
        get_into("pmu50_reg_get", m, "value", value, |m| {
            entry("pmu50_reg_get", signals::REGISTERS, index)
                .map(|r| (r.get)(m.core.regs()))
                .ok_or(PMU50_ERR_RANGE)
        })
    }
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

/// Number of top-level outputs (`PMU50_OUTPUT_COUNT`).
#[no_mangle]
pub extern "C" fn pmu50_output_count() -> usize {
    signals::N_OUTPUTS
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
        // SAFETY: forwarded contract.
        let s = unsafe { structural_of(m) };
        let Some(sig) = entry("pmu50_output_info", signals::OUTPUTS, index) else {
            return PMU50_ERR_RANGE;
        };
        // SAFETY: the caller passes NULL or writable out pointers.
        unsafe { write_info(&names().outputs[index], sig.bits(&s), name, width) }
    })
}

/// Number of internal signals (`PMU50_INTERNAL_COUNT`).
#[no_mangle]
pub extern "C" fn pmu50_internal_count() -> usize {
    signals::N_INTERNALS
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
        let Some(sig) = entry("pmu50_internal_info", signals::INTERNALS, index) else {
            return PMU50_ERR_RANGE;
        };
        // Internals have fixed widths.
        // SAFETY: forwarded contract (NULL core: default configuration).
        let w = sig.bits(&unsafe { structural_of(std::ptr::null()) });
        // SAFETY: the caller passes NULL or writable out pointers.
        unsafe { write_info(&names().internals[index], w, name, width) }
    })
}

/// The value getter and setter by index of a C mirror struct (`pmu50_outputs`,
/// `pmu50_internals`): `$get(s, index, value)` and `$set(s, index, value)`; `$arg` is the
/// struct's argument name in the header, for the NULL message.
macro_rules! indexed_accessors {
    ($(#[$get_doc:meta])* $get:ident, $(#[$set_doc:meta])* $set:ident, $c:ty, $arg:literal, $len:expr) => {
        $(#[$get_doc])*
        ///
        /// # Safety
        /// `s` NULL or readable; `value` NULL or writable.
        #[no_mangle]
        pub unsafe extern "C" fn $get(s: *const $c, index: usize, value: *mut u64) -> c_int {
            guard(stringify!($get), || {
                // SAFETY: the caller passes NULL or a readable struct.
                let Some(s) = (unsafe { s.as_ref() }) else {
                    return null(stringify!($get), $arg);
                };
                // SAFETY: the caller passes NULL or a writable pointer.
                unsafe { write_value(stringify!($get), s.get(index), $len, index, value) }
            })
        }

        $(#[$set_doc])*
        ///
        /// # Safety
        /// `s` NULL or writable.
        #[no_mangle]
        pub unsafe extern "C" fn $set(s: *mut $c, index: usize, value: u64) -> c_int {
            guard(stringify!($set), || {
                // SAFETY: the caller passes NULL or a writable struct.
                let Some(s) = (unsafe { s.as_mut() }) else {
                    return null(stringify!($set), $arg);
                };
                if !s.set(index, value) {
                    set_error(format!("{}: index {index} out of range 0..{}", stringify!($set), $len));
                    return PMU50_ERR_RANGE;
                }
                PMU50_OK
            })
        }
    };
}

indexed_accessors!(
    /// Value of output `index` of an outputs struct.
    pmu50_output_get,
    /// Set output `index` of an outputs struct (low bits of `value`), e.g. to fill it from an RTL
    /// simulator by index.
    pmu50_output_set,
    pmu50_outputs,
    "o",
    signals::N_OUTPUTS
);

indexed_accessors!(
    /// Value of internal signal `index` of an internals struct.
    pmu50_internal_get,
    /// Set internal signal `index` of an internals struct.
    pmu50_internal_set,
    pmu50_internals,
    "x",
    signals::N_INTERNALS
);

/// Lockstep compare (verification method 2): the RTL's values against the model's. Each set is
/// optional (NULL: not compared): `rtl_outputs` and `rtl_regs` (`PMU50_REG_COUNT` values in
/// register index order) after the last edge, `rtl_internals` of the cycle that ended at the last
/// edge (sampled before it). Returns the number of differing signals (0: all equal) or a negative
/// error code; the report, one line per difference, is in `pmu50_check_report(m)`.
///
/// # Safety
/// `m` NULL or live; `rtl_outputs`, `rtl_internals` NULL or readable; `rtl_regs` NULL or
/// `PMU50_REG_COUNT` readable values.
#[no_mangle]
pub unsafe extern "C" fn pmu50_check(
    m: *mut pmu50_t,
    rtl_outputs: *const pmu50_outputs,
    rtl_regs: *const u64,
    rtl_internals: *const pmu50_internals,
) -> c_int {
    let compare = |m: &mut pmu50_t| {
        // SAFETY: NULL or readable, by contract (`rtl_regs`: PMU50_REG_COUNT values).
        let (o, r, x) = unsafe {
            (
                rtl_outputs.as_ref(),
                rtl_regs.cast::<[u64; signals::N_REGISTERS]>().as_ref(),
                rtl_internals.as_ref(),
            )
        };
        match check(m, o, r, x) {
            Ok(diffs) => {
                let text: String = diffs.iter().map(|d| format!("{d}\n")).collect();
                m.report = CString::new(text).unwrap_or_default();
                c_int::try_from(diffs.len()).unwrap_or(c_int::MAX)
            }
            Err(e) => {
                set_error(format!("pmu50_check: {e}"));
                PMU50_ERR_RANGE
            }
        }
    };
    // SAFETY: forwarded contract.
    unsafe { with_live("pmu50_check", m, compare) }
}

/// Report of the last `pmu50_check` on `m`: one line per difference,
/// `MISMATCH tick=<k> signal=<path> expected=<model, hex> got=<rtl, hex>`; "" when equal or NULL.
/// Valid until the next `pmu50_check` on `m`.
///
/// # Safety
/// `m` NULL or live.
#[no_mangle]
pub unsafe extern "C" fn pmu50_check_report(m: *const pmu50_t) -> *const c_char {
    // SAFETY: the caller passes NULL or a live handle.
    unsafe { m.as_ref() }.map_or(c"".as_ptr(), |m| m.report.as_ptr())
}

/// Shared body of the getters that write one value of a live core to `out` (named `arg` in
/// the header); `f` gives the value or an error code (its message set).
///
/// # Safety
/// `m` NULL or live; `out` NULL or writable.
unsafe fn get_into<T>(
    what: &str,
    m: *const pmu50_t,
    arg: &str,
    out: *mut T,
    f: impl FnOnce(&pmu50_t) -> Result<T, c_int>,
) -> c_int {
    guard(what, || {
        // SAFETY: the caller passes NULL or a live handle.
        let Some(m) = (unsafe { m.as_ref() }) else {
            return null(what, "m");
        };
        if out.is_null() {
            return null(what, arg);
        }
        match f(m) {
            Ok(v) => {
                // SAFETY: checked non-null; the caller guarantees writable.
                unsafe { out.write(v) };
                PMU50_OK
            }
            Err(rc) => rc,
        }
    })
}

/// Shared body of the constructors: a new handle from the parameters `p` (NULL, with the
/// message in `pmu50_last_error()`, when `p` is NULL, `make` refuses them or panics).
///
/// # Safety
/// `p` NULL or a readable `pmu50_params`.
pub(crate) unsafe fn new_handle<T>(
    what: &str,
    p: *const pmu50_params,
    make: impl FnOnce(Params) -> Result<T, String>,
) -> *mut T {
    let r = catch_unwind(AssertUnwindSafe(|| {
        if p.is_null() {
            set_error(format!("{what}: `p` is NULL"));
            return std::ptr::null_mut();
        }
        // SAFETY: checked non-null.
        match make(unsafe { p.read() }.into()) {
            Ok(h) => Box::into_raw(Box::new(h)),
            Err(e) => {
                set_error(format!("{what}: {e}"));
                std::ptr::null_mut()
            }
        }
    }));
    r.unwrap_or_else(|e| {
        set_error(format!("{what}: internal panic: {}", panic_message(&*e)));
        std::ptr::null_mut()
    })
}

/// Shared body of the destructors (NULL is ignored).
///
/// # Safety
/// `h` NULL or a handle from `new_handle` not freed yet.
pub(crate) unsafe fn free_handle<T>(h: *mut T) {
    if h.is_null() {
        return;
    }
    let _ = catch_unwind(AssertUnwindSafe(|| {
        // SAFETY: a live handle from new_handle, by contract.
        drop(unsafe { Box::from_raw(h) });
    }));
}

/// Entry `index` of a signal table; out of range: `None`, with the error "`what`: index ... out
/// of range 0..len" set (the caller returns `PMU50_ERR_RANGE`).
fn entry<'t, T>(what: &str, table: &'t [T], index: usize) -> Option<&'t T> {
    let e = table.get(index);
    if e.is_none() {
        set_error(format!(
            "{what}: index {index} out of range 0..{}",
            table.len()
        ));
    }
    e
}

/// Shared body of the indexed value getters.
///
/// # Safety
/// `value` NULL or writable.
unsafe fn write_value(
    what: &str,
    v: Option<u64>,
    len: usize,
    index: usize,
    value: *mut u64,
) -> c_int {
    if value.is_null() {
        return null(what, "value");
    }
    let Some(v) = v else {
        set_error(format!("{what}: index {index} out of range 0..{len}"));
        return PMU50_ERR_RANGE;
    };
    // SAFETY: checked non-null; the caller guarantees writable.
    unsafe { value.write(v) };
    PMU50_OK
}

/// Shared body of the name/width getters; out pointers may be NULL.
///
/// # Safety
/// `name` and `width` NULL or writable.
unsafe fn write_info(n: &'static CStr, w: u8, name: *mut *const c_char, width: *mut u8) -> c_int {
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

    /// The default parameters as the C ABI gives them and a handle made from them (the test
    /// frees it with `pmu50_free`).
    fn default_handle() -> (pmu50_params, *mut pmu50_t) {
        let mut p = pmu50_params::default();
        // SAFETY: valid pointers.
        unsafe {
            assert_eq!(pmu50_params_default(&mut p), PMU50_OK);
            let m = pmu50_new(&p);
            assert!(!m.is_null());
            (p, m)
        }
    }

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
        let (p, m) = default_handle();
        // SAFETY: valid pointers; the handle is freed at the end.
        unsafe {
            let mut core = Pmu50::new(Params::default()).unwrap();
            let mut o = pmu50_outputs::default();
            let mut x = pmu50_internals::default();
            for k in 0..5000u32 {
                let core_in = Inputs {
                    ig: k % 3000 > 1500,
                    vs2_ok: true,
                    cmp_s: k % 700 > 350,
                    cmp_c: k % 500 > 250,
                    ..Default::default()
                };
                let i = pmu50_inputs::from(core_in);
                assert_eq!(pmu50_step_traced(m, &i, &mut x, &mut o), PMU50_OK);
                let pmu50_core::TracedStep {
                    internals: int,
                    after: out,
                    ..
                } = core.step_traced(&i.into());
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
            let si = signals::OUTPUTS
                .iter()
                .position(|s| s.name == "si")
                .unwrap();
            assert_eq!(Some(v), o.get(si));
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

    #[test]
    fn check_names_tick_signal_expected_and_got() {
        let (_, m) = default_handle();
        // SAFETY: valid pointers; the handle is freed at the end.
        unsafe {
            let on = pmu50_inputs::from(Inputs {
                ig: true,
                vs2_ok: true,
                ..Default::default()
            });
            let mut after = pmu50_outputs::default();
            let mut x = pmu50_internals::default();
            let mut regs = [0u64; signals::N_REGISTERS];
            for _ in 0..3 {
                assert_eq!(pmu50_step_traced(m, &on, &mut x, &mut after), PMU50_OK);
            }
            for (k, r) in regs.iter_mut().enumerate() {
                assert_eq!(pmu50_reg_get(m, k, r), PMU50_OK);
            }
            // The model's own values: no difference.
            assert_eq!(pmu50_check(m, &after, regs.as_ptr(), &x), 0);
            assert_eq!(CStr::from_ptr(pmu50_check_report(m)).to_str().unwrap(), "");
            // One output, one register and one internal wrong.
            let si_out = signals::OUTPUTS
                .iter()
                .position(|s| s.name == "si")
                .unwrap();
            let si_reg = find_register("drive_interval.si").unwrap();
            let fig17 = signals::INTERNALS
                .iter()
                .position(|s| s.name == "fig17")
                .unwrap();
            let (mut o2, mut r2, mut x2) = (after, regs, x);
            assert_eq!(pmu50_output_set(&mut o2, si_out, 0x1b8), PMU50_OK);
            r2[si_reg] = 0x1b8;
            assert_eq!(pmu50_internal_set(&mut x2, fig17, 6), PMU50_OK);
            assert_eq!(pmu50_check(m, &o2, r2.as_ptr(), &x2), 3);
            let report = CStr::from_ptr(pmu50_check_report(m))
                .to_str()
                .unwrap()
                .to_string();
            assert_eq!(
                report,
                "MISMATCH tick=3 signal=si expected=0294 got=01b8\n\
                 MISMATCH tick=3 signal=drive_interval.si expected=0294 got=01b8\n\
                 MISMATCH tick=2 signal=internals.fig17 expected=0 got=6\n"
            );
            // Each set is optional.
            assert_eq!(pmu50_check(m, ptr::null(), ptr::null(), &x2), 1);
            assert_eq!(
                pmu50_check(ptr::null_mut(), &o2, ptr::null(), ptr::null()),
                PMU50_ERR_NULL
            );
            pmu50_reset(m);
            assert_eq!(
                pmu50_check(m, ptr::null(), ptr::null(), &x),
                PMU50_ERR_RANGE,
                "no internals before a step"
            );
            assert!(last_error().contains("after a step"), "{}", last_error());
            pmu50_free(m);
        }
    }
}
