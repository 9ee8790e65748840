//! The RTL as a shared library (hdl/tb/lockstep/dut_lib.cpp, built by Verilator): its entry
//! points, loaded and checked against the interface version this worker speaks.

use pmu50_core::params::Params;
use pmu50_core::signals::{self};
use std::ffi::{c_char, c_void, CStr};
use std::path::Path;

/// Interface version of hdl/tb/lockstep/dut_lib.cpp this worker speaks.
pub(super) const DUT_ABI: u32 = 4;

pub(super) type DutNew = unsafe extern "C" fn() -> *mut c_void;
pub(super) type DutFree = unsafe extern "C" fn(*mut c_void);
pub(super) type DutState = unsafe extern "C" fn(*mut c_void, *mut u64, *mut u64);
pub(super) type DutTick =
    unsafe extern "C" fn(*mut c_void, *const u64, *mut u64, *mut u64, *mut u64);
pub(super) type DutStep = unsafe extern "C" fn(*mut c_void, *const u64, u64) -> u64;
pub(super) type DutCovWrite = unsafe extern "C" fn(*mut c_void, *const c_char) -> i32;
pub(super) type DutVcdOpen = unsafe extern "C" fn(*mut c_void, *const c_char, u64) -> i32;

/// A loaded RTL library and where each of its values is in the model's signal table.
pub(super) struct DutLib {
    pub(super) new: DutNew,
    pub(super) free: DutFree,
    pub(super) state: DutState,
    pub(super) tick: DutTick,
    pub(super) step: DutStep,
    /// Whether the library counts code coverage, and its writer.
    pub(super) has_coverage: bool,
    pub(super) cov_write: DutCovWrite,
    /// The VCD of a build with tracing: open (-1 without tracing) and close.
    pub(super) vcd_open: DutVcdOpen,
    pub(super) vcd_close: DutFree,
    /// The Verilog parameters the library was built with (name, value).
    pub(super) params: Vec<(String, u64)>,
    /// For each mapped register of the library, its index in [`signals::REGISTERS`].
    pub(super) regs: Vec<usize>,
    /// For each mapped internal, its index in [`signals::INTERNALS`].
    pub(super) internals: Vec<usize>,
    pub(super) _lib: libloading::Library,
}

impl DutLib {
    pub(super) fn load(path: &Path) -> Result<DutLib, String> {
        // SAFETY: loading runs the library's static constructors; the library is one the
        // regression built (dut_lib.cpp with the Verilator output and runtime).
        let lib = unsafe { libloading::Library::new(path) }
            .map_err(|e| format!("cannot load {}: {e}", path.display()))?;
        // SAFETY: the symbols have the types of dut_lib.cpp (checked by its interface version).
        unsafe {
            let sym = |name: &str| -> Result<*const c_void, String> {
                let s: libloading::Symbol<*const c_void> = lib
                    .get(name.as_bytes())
                    .map_err(|e| format!("{}: no `{name}`: {e}", path.display()))?;
                Ok(*s)
            };
            let abi: unsafe extern "C" fn() -> u32 = std::mem::transmute(sym("pmu50_dut_abi")?);
            if abi() != DUT_ABI {
                return Err(format!(
                    "{}: interface version {}, this pmu50 speaks {DUT_ABI} (rebuild it)",
                    path.display(),
                    abi()
                ));
            }
            let count: unsafe extern "C" fn(u32) -> u32 =
                std::mem::transmute(sym("pmu50_dut_count")?);
            let name: unsafe extern "C" fn(u32, u32) -> *const c_char =
                std::mem::transmute(sym("pmu50_dut_name")?);
            let param: unsafe extern "C" fn(u32) -> u64 =
                std::mem::transmute(sym("pmu50_dut_param")?);
            let names = |group: u32| -> Vec<String> {
                (0..count(group))
                    .map(|i| {
                        let p = name(group, i);
                        if p.is_null() {
                            String::new()
                        } else {
                            CStr::from_ptr(p).to_string_lossy().into_owned()
                        }
                    })
                    .collect()
            };
            // The ports are in the order of the model's signal table; mapped values are a subset.
            let same = |group: u32, model: Vec<String>, what: &str| -> Result<(), String> {
                let lib_names = names(group);
                if lib_names == model {
                    Ok(())
                } else {
                    Err(format!("{}: its {what} are {lib_names:?}, the model's signal table has {model:?} (rebuild it)", path.display()))
                }
            };
            same(
                0,
                signals::INPUTS.iter().map(|s| s.name.to_string()).collect(),
                "inputs",
            )?;
            same(
                1,
                signals::OUTPUTS
                    .iter()
                    .map(|s| s.name.to_string())
                    .collect(),
                "outputs",
            )?;
            let index =
                |group: u32, model: Vec<String>, what: &str| -> Result<Vec<usize>, String> {
                    names(group)
                        .iter()
                        .map(|n| {
                            model.iter().position(|m| m == n).ok_or_else(|| {
                                format!(
                                    "{}: mapped {what} `{n}` is not in the model's signal table",
                                    path.display()
                                )
                            })
                        })
                        .collect()
                };
            let regs = index(
                2,
                signals::REGISTERS.iter().map(|s| s.path()).collect(),
                "register",
            )?;
            let internals = index(
                3,
                signals::INTERNALS
                    .iter()
                    .map(|s| s.name.to_string())
                    .collect(),
                "internal",
            )?;
            let params = names(4)
                .into_iter()
                .enumerate()
                .map(|(i, n)| (n, param(i as u32)))
                .collect();
            Ok(DutLib {
                new: std::mem::transmute::<*const c_void, DutNew>(sym("pmu50_dut_new")?),
                free: std::mem::transmute::<*const c_void, DutFree>(sym("pmu50_dut_free")?),
                state: std::mem::transmute::<*const c_void, DutState>(sym("pmu50_dut_state")?),
                tick: std::mem::transmute::<*const c_void, DutTick>(sym("pmu50_dut_tick")?),
                step: std::mem::transmute::<*const c_void, DutStep>(sym("pmu50_dut_step")?),
                has_coverage: std::mem::transmute::<*const c_void, unsafe extern "C" fn() -> u32>(
                    sym("pmu50_dut_has_coverage")?,
                )() == 1,
                cov_write: std::mem::transmute::<*const c_void, DutCovWrite>(sym(
                    "pmu50_dut_cov_write",
                )?),
                vcd_open: std::mem::transmute::<*const c_void, DutVcdOpen>(sym(
                    "pmu50_dut_vcd_open",
                )?),
                vcd_close: std::mem::transmute::<*const c_void, DutFree>(sym(
                    "pmu50_dut_vcd_close",
                )?),
                params,
                regs,
                internals,
                _lib: lib,
            })
        }
    }

    /// Whether the library was built for `p`: every parameter it was built with has `p`'s value.
    pub(super) fn check_params(&self, p: &Params) -> Result<(), String> {
        let want = p.hdl_parameters();
        for (n, v) in &self.params {
            match want.iter().find(|(w, _)| w == n) {
                Some((_, pv)) if pv == v => {}
                Some((_, pv)) => {
                    return Err(format!(
                        "the library was built with {n}={v}, the seed needs {n}={pv}"
                    ))
                }
                None => {
                    return Err(format!(
                        "the library was built with parameter {n}, which the model does not have"
                    ))
                }
            }
        }
        Ok(())
    }
}

/// A DUT handle, freed when dropped.
pub(super) struct Handle<'a>(pub(super) &'a DutLib, pub(super) *mut c_void);

impl<'a> Handle<'a> {
    /// A DUT after reset.
    pub(super) fn new(lib: &'a DutLib) -> Handle<'a> {
        // SAFETY: a function of the library, no arguments.
        Handle(lib, unsafe { (lib.new)() })
    }
}

impl Drop for Handle<'_> {
    fn drop(&mut self) {
        // SAFETY: a handle of this library's pmu50_dut_new, freed once.
        unsafe { (self.0.free)(self.1) }
    }
}
