//! The HDL kit the binary carries (hdl/ of the repository: the Verilog twin, its file list and
//! map, the mutants, the FuseSoC core, the testbenches, the scripts and the formal kit), so that
//! an installed `pmu50` works without the checkout it was built from:
//! - [`hdl_dir`] is the checkout's hdl/ when it is there (or `PMU50_HDL_DIR`), else the kit
//!   unpacked once into the cache folder;
//! - `pmu50 hdl export DIR` writes it for an HDL team to take into its own repository.

use std::path::{Path, PathBuf};

/// Every file of the kit: its path below hdl/ and its text.
pub const FILES: &[(&str, &str)] = &[
    ("README.md", include_str!("../../hdl/README.md")),
    ("SYNTH.md", include_str!("../../hdl/SYNTH.md")),
    ("cosim.sh", include_str!("../../hdl/cosim.sh")),
    ("fusesoc_sim.sh", include_str!("../../hdl/fusesoc_sim.sh")),
    ("gls.sh", include_str!("../../hdl/gls.sh")),
    ("install_test.sh", include_str!("../../hdl/install_test.sh")),
    (
        "regress_smoke.sh",
        include_str!("../../hdl/regress_smoke.sh"),
    ),
    ("mutants.txt", include_str!("../../hdl/mutants.txt")),
    ("cosim_first.txt", include_str!("../../hdl/cosim_first.txt")),
    ("pmu50.core", include_str!("../../hdl/pmu50.core")),
    ("pmu50.f", include_str!("../../hdl/pmu50.f")),
    (
        "coverage-waivers.toml",
        include_str!("../../hdl/coverage-waivers.toml"),
    ),
    ("pmu50.map.toml", include_str!("../../hdl/pmu50.map.toml")),
    ("pmu50.v", include_str!("../../hdl/pmu50.v")),
    (
        "rtl/action_switching_56a.v",
        include_str!("../../hdl/rtl/action_switching_56a.v"),
    ),
    (
        "rtl/comparator_latch_58ab.v",
        include_str!("../../hdl/rtl/comparator_latch_58ab.v"),
    ),
    (
        "rtl/count_diagnosis.v",
        include_str!("../../hdl/rtl/count_diagnosis.v"),
    ),
    (
        "rtl/drive_interval_changing_56b.v",
        include_str!("../../hdl/rtl/drive_interval_changing_56b.v"),
    ),
    (
        "rtl/register_file.v",
        include_str!("../../hdl/rtl/register_file.v"),
    ),
    (
        "rtl/sensor_power_determination_57.v",
        include_str!("../../hdl/rtl/sensor_power_determination_57.v"),
    ),
    (
        "rtl/timing_generator_56.v",
        include_str!("../../hdl/rtl/timing_generator_56.v"),
    ),
    (
        "rtl/updown_counter_58cd.v",
        include_str!("../../hdl/rtl/updown_counter_58cd.v"),
    ),
    (
        "scenarios/hdl_bus.toml",
        include_str!("../../hdl/scenarios/hdl_bus.toml"),
    ),
    (
        "scenarios/hdl_cnt_r_sat.toml",
        include_str!("../../hdl/scenarios/hdl_cnt_r_sat.toml"),
    ),
    (
        "scripts/common.sh",
        include_str!("../../hdl/scripts/common.sh"),
    ),
    (
        "scripts/run_lockstep_dpi.sh",
        include_str!("../../hdl/scripts/run_lockstep_dpi.sh"),
    ),
    (
        "scripts/run_vectors.sh",
        include_str!("../../hdl/scripts/run_vectors.sh"),
    ),
    (
        "scripts/synth.sh",
        include_str!("../../hdl/scripts/synth.sh"),
    ),
    ("tb/tb_vectors.v", include_str!("../../hdl/tb/tb_vectors.v")),
    (
        "tb/lockstep/dut_lib.cpp",
        include_str!("../../hdl/tb/lockstep/dut_lib.cpp"),
    ),
    (
        "tb/lockstep/pmu50_dpi.c",
        include_str!("../../hdl/tb/lockstep/pmu50_dpi.c"),
    ),
    (
        "tb/lockstep/replay_main.cpp",
        include_str!("../../hdl/tb/lockstep/replay_main.cpp"),
    ),
    (
        "tb/lockstep/tb_lockstep_dpi.sv",
        include_str!("../../hdl/tb/lockstep/tb_lockstep_dpi.sv"),
    ),
    (
        "formal/pmu50.sby.j2",
        include_str!("../../hdl/formal/pmu50.sby.j2"),
    ),
    (
        "formal/pmu50_formal.sv",
        include_str!("../../hdl/formal/pmu50_formal.sv"),
    ),
    (
        "formal/requirements.txt",
        include_str!("../../hdl/formal/requirements.txt"),
    ),
    ("formal/run.py", include_str!("../../hdl/formal/run.py")),
    (
        "formal/coverage.py",
        include_str!("../../hdl/formal/coverage.py"),
    ),
    (
        "formal/pmu50_cov.sv",
        include_str!("../../hdl/formal/pmu50_cov.sv"),
    ),
    (
        "formal/pmu50_cov_top.sv",
        include_str!("../../hdl/formal/pmu50_cov_top.sv"),
    ),
    (
        "formal/pmu50_cov.json",
        include_str!("../../hdl/formal/pmu50_cov.json"),
    ),
    (
        "formal/pmu50_contract.json",
        include_str!("../../hdl/formal/pmu50_contract.json"),
    ),
    (
        "tb/coverage/cov_main.cpp",
        include_str!("../../hdl/tb/coverage/cov_main.cpp"),
    ),
    (
        "formal/pmu50_formal/__init__.py",
        include_str!("../../hdl/formal/pmu50_formal/__init__.py"),
    ),
    (
        "formal/pmu50_formal/common.py",
        include_str!("../../hdl/formal/pmu50_formal/common.py"),
    ),
    (
        "formal/pmu50_formal/aiger.py",
        include_str!("../../hdl/formal/pmu50_formal/aiger.py"),
    ),
    (
        "formal/pmu50_formal/kit.py",
        include_str!("../../hdl/formal/pmu50_formal/kit.py"),
    ),
    (
        "formal/pmu50_formal/coverage.py",
        include_str!("../../hdl/formal/pmu50_formal/coverage.py"),
    ),
    (
        "formal/conftest.py",
        include_str!("../../hdl/formal/conftest.py"),
    ),
    (
        "formal/deep/cnt_r_sat_at_min.toml",
        include_str!("../../hdl/formal/deep/cnt_r_sat_at_min.toml"),
    ),
    (
        "formal/deep/cnt_r_sat_expanding.toml",
        include_str!("../../hdl/formal/deep/cnt_r_sat_expanding.toml"),
    ),
    (
        "formal/deep/wrap_w16.toml",
        include_str!("../../hdl/formal/deep/wrap_w16.toml"),
    ),
    (
        "formal/deep/wrap_w4_clock5us.toml",
        include_str!("../../hdl/formal/deep/wrap_w4_clock5us.toml"),
    ),
    (
        "formal/deep/wrap_w8_clock20us.toml",
        include_str!("../../hdl/formal/deep/wrap_w8_clock20us.toml"),
    ),
    (
        "formal/tests/test_formal.py",
        include_str!("../../hdl/formal/tests/test_formal.py"),
    ),
    (
        "formal/tests/test_coverage.py",
        include_str!("../../hdl/formal/tests/test_coverage.py"),
    ),
    (
        "formal/pmu50_formal/bind.py",
        include_str!("../../hdl/formal/pmu50_formal/bind.py"),
    ),
    (
        "formal/pmu50_formal/frontend.py",
        include_str!("../../hdl/formal/pmu50_formal/frontend.py"),
    ),
    (
        "formal/pmu50_port_view.sv",
        include_str!("../../hdl/formal/pmu50_port_view.sv"),
    ),
    (
        "formal/tests/test_any_rtl.py",
        include_str!("../../hdl/formal/tests/test_any_rtl.py"),
    ),
    (
        "tb/coverage/ref_main.cpp",
        include_str!("../../hdl/tb/coverage/ref_main.cpp"),
    ),
    (
        "tb/coverage/requirements.txt",
        include_str!("../../hdl/tb/coverage/requirements.txt"),
    ),
    ("tb/tb_xprop.v", include_str!("../../hdl/tb/tb_xprop.v")),
];

/// Scripts, written executable.
fn executable(path: &str) -> bool {
    path.ends_with(".sh") || path.ends_with(".py")
}

/// Where the HDL kit is: `PMU50_HDL_DIR`, or the carried kit unpacked into the cache folder
/// (`PMU50_CACHE_DIR`, `$XDG_CACHE_HOME/pmu50`, `~/.cache/pmu50`), named by the hash of its
/// contents. The binary never looks for the checkout it was built from.
pub fn hdl_dir() -> PathBuf {
    if let Some(d) = std::env::var_os("PMU50_HDL_DIR").filter(|v| !v.is_empty()) {
        return PathBuf::from(d);
    }
    let dir = crate::cache::cache_dir().join(format!("hdl-{:016x}", key()));
    // leased for the process: `pmu50 cache clean` removes the kits no process uses
    crate::cache::lease_for_process(&dir);
    if !dir.join("pmu50.f").is_file() {
        let _ = write(&dir);
    }
    dir
}

/// A hash of the kit's contents (the name of its unpacked copy).
fn key() -> u64 {
    let parts: Vec<&[u8]> = FILES
        .iter()
        .flat_map(|(p, t)| [p.as_bytes(), t.as_bytes()])
        .collect();
    crate::cache::fnv(&parts)
}

/// Write the kit into `dir` (created), each file atomically.
pub fn write(dir: &Path) -> Result<usize, pmu50_testbench::atomic_file::OutputError> {
    let mut batch = pmu50_testbench::atomic_file::Batch::new();
    for (path, text) in FILES {
        let dest = dir.join(path);
        if let Some(parent) = dest.parent() {
            pmu50_testbench::atomic_file::create_dir(parent)?;
        }
        batch.add(pmu50_testbench::atomic_file::write_atomic(
            &dest,
            text.as_bytes(),
        )?);
    }
    batch.commit()?;
    for (path, _) in FILES.iter().filter(|(p, _)| executable(p)) {
        use std::os::unix::fs::PermissionsExt;
        let _ = std::fs::set_permissions(dir.join(path), std::fs::Permissions::from_mode(0o755));
    }
    Ok(FILES.len())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_exported_kit_has_the_twin_and_executable_scripts() {
        let d = tempfile::tempdir().unwrap();
        assert_eq!(write(d.path()).unwrap(), FILES.len());
        assert!(d.path().join("rtl/register_file.v").is_file());
        use std::os::unix::fs::PermissionsExt;
        assert_ne!(
            std::fs::metadata(d.path().join("gls.sh"))
                .unwrap()
                .permissions()
                .mode()
                & 0o111,
            0
        );
    }
}
