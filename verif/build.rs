//! The git commit the kit is built from, for the provenance of what it writes
//! (`src/provenance.rs`): `PMU50_GIT_COMMIT`, empty outside a git checkout.

fn main() {
    let git = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../.git");
    // a new commit or checkout rewrites HEAD or a ref
    for p in ["HEAD", "refs/heads", "packed-refs"] {
        if git.join(p).exists() {
            println!("cargo:rerun-if-changed={}", git.join(p).display());
        }
    }
    let commit = std::process::Command::new("git")
        .args(["rev-parse", "--short=12", "HEAD"])
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .ok()
        .filter(|o| o.status.success())
        .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_string())
        .unwrap_or_default();
    println!("cargo:rustc-env=PMU50_GIT_COMMIT={commit}");
}
