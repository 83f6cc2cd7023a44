//! Generates one golden-frame test per example of every drive in `drives/`
//! (`golden.rs` in OUT_DIR, included by `tests/golden.rs`).

use std::path::PathBuf;

fn main() {
    let manifest = PathBuf::from(
        std::env::var_os("CARGO_MANIFEST_DIR").expect("cargo sets CARGO_MANIFEST_DIR"),
    );
    let out_dir = PathBuf::from(std::env::var_os("OUT_DIR").expect("cargo sets OUT_DIR"));
    let drives_dir = manifest.join("../drives");
    println!("cargo:rerun-if-changed={}", drives_dir.display());
    let builder = match vfd_codegen::Builder::new().drives_in(&drives_dir) {
        Ok(builder) => builder
            .out_dir(&out_dir)
            .golden_tests(true)
            .crate_path("vfd_drives")
            .regenerate_command("cargo build -p vfd-tests")
            .display_root(manifest.join(".."))
            .cargo_metadata(true),
        Err(error) => vfd_codegen::fail_build(&error),
    };
    if let Err(error) = builder.generate() {
        vfd_codegen::fail_build(&error);
    }
}
