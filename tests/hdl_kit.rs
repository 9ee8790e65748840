//! The HDL kit the binary carries (verif/src/hdl_kit.rs) is the checkout's hdl/, file for file.

use std::path::Path;

/// The kit carries every file of the kit's folders that git tracks (a file added to hdl/
/// and not to [`FILES`] fails here), and each is the file on disk.
#[test]
fn the_kit_carries_every_tracked_file_of_hdl() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let out = std::process::Command::new("git")
        .args(["ls-files", "hdl"])
        .current_dir(root)
        .output();
    let Ok(out) = out else { return };
    if !out.status.success() {
        return; // not a git checkout (a packaged source): nothing to compare with
    }
    let tracked: Vec<String> = String::from_utf8_lossy(&out.stdout)
        .lines()
        .map(|l| l.trim_start_matches("hdl/").to_string())
        .filter(|p| {
            // the C ABI crate, the Python benches, the bench harness and the kit's own test RTL
            // (hdl/alt_sv: an RTL unlike the twin for the tests) are not part of the kit
            !["ffi/", "cocotb/", "uvm/", "bench/", "alt_sv/"]
                .iter()
                .any(|x| p.starts_with(x))
        })
        .collect();
    let carried: Vec<&str> = pmu50_verif::hdl_kit::FILES
        .iter()
        .map(|(p, _)| *p)
        .collect();
    for t in &tracked {
        assert!(
            carried.contains(&t.as_str()),
            "hdl/{t} is tracked but not carried by verif/src/hdl_kit.rs"
        );
    }
    for (p, text) in pmu50_verif::hdl_kit::FILES {
        assert_eq!(
            std::fs::read_to_string(root.join("hdl").join(p)).unwrap(),
            *text,
            "hdl/{p}"
        );
    }
}
