//! Crates outside this workspace (`fixtures/external-crate/`, `fixtures/computer-link/`,
//! `fixtures/one-drive/`):
//! `cargo test` run on one with its own Cargo.lock (`--locked --offline`), into one folder
//! of the workspace's target directory that they share (what their dependencies have in
//! common is compiled once) and that is kept between runs.

use std::path::Path;
use std::process::Command;

/// What `cargo test` printed in an outside crate that passed.
pub struct Passed {
    /// Its standard output (the test lines).
    pub stdout: String,
    /// Its standard error.
    pub stderr: String,
}

/// Runs `cargo test` in the crate of the fixture folder `fixture` (under `tests/fixtures/`)
/// with its target in `target_tmpdir/outside-crates` (shared by the fixtures); fails the
/// calling test, with both outputs, when the crate does not build or a test fails.
pub fn cargo_test(manifest_dir: &Path, target_tmpdir: &Path, fixture: &str) -> Passed {
    let manifest = manifest_dir
        .join("fixtures")
        .join(fixture)
        .join("Cargo.toml");
    let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
    let output = Command::new(cargo)
        .args(["test", "--locked", "--offline", "--manifest-path"])
        .arg(&manifest)
        .env("CARGO_TARGET_DIR", target_tmpdir.join("outside-crates"))
        .env_remove("OUT_DIR")
        .output()
        .expect("cargo runs");
    let stdout = String::from_utf8_lossy(&output.stdout).into_owned();
    let stderr = String::from_utf8_lossy(&output.stderr).into_owned();
    assert!(
        output.status.success(),
        "`cargo test` failed in {}:\n{stderr}\n{stdout}\n(after dependency changes, refresh its Cargo.lock as its Cargo.toml says)",
        manifest.display()
    );
    Passed { stdout, stderr }
}
