//! The modules of each crate use each other without circles (see
//! `vfd_tests::module_graph` for what counts as a use).

use std::path::Path;
use vfd_tests::module_graph::assert_no_module_cycle;

fn crate_src(folder: &str) -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("..")
        .join(folder)
        .join("src")
}

#[test]
fn runtime_modules_form_no_circle() {
    assert_no_module_cycle(&crate_src("runtime"));
}

#[test]
fn codegen_modules_form_no_circle() {
    assert_no_module_cycle(&crate_src("codegen"));
}
