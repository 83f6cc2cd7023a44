//! A crate outside this workspace (`fixtures/external-crate/`) describes its own drive with
//! a shared protocol file, generates the typed API and golden tests in its build script,
//! expands the drive with `include_drive!`, and passes its golden tests. It depends only on
//! vfd-runtime (feature `testing`), vfd-macros and, to build, vfd-codegen.
//!
//! The crate is built with its own Cargo.lock (`--locked --offline`) into a folder of the
//! workspace's target directory, kept between runs.

use std::path::Path;
use vfd_tests::out_of_tree::{cargo_test, Passed};

/// One golden test per example frame (3), bit-field example (1) and value example (1) of
/// `fixtures/external-crate/demo_pump.yaml`.
const GOLDEN_TESTS: usize = 5;

#[test]
fn an_outside_crate_generates_builds_and_passes_its_golden_tests() {
    let started = std::time::Instant::now();
    let Passed { stdout, stderr } = cargo_test(
        Path::new(env!("CARGO_MANIFEST_DIR")),
        Path::new(env!("CARGO_TARGET_TMPDIR")),
        "external-crate",
    );
    eprintln!(
        "cargo test in the outside crate took {:.1?}",
        started.elapsed()
    );
    let passed: Vec<&str> = stdout
        .lines()
        .filter(|line| line.starts_with("test demo_pump::") && line.ends_with("... ok"))
        .collect();
    assert_eq!(
        passed.len(),
        GOLDEN_TESTS,
        "golden tests passed in the outside crate:\n{}\n\nstdout:\n{stdout}\nstderr:\n{stderr}",
        passed.join("\n")
    );
    assert!(
        stdout.contains("test tests::build_script_and_macro_give_the_same_api ... ok"),
        "the include_drive! comparison did not run:\n{stdout}"
    );
}
