//! Generates the typed API of every drive described in this folder into OUT_DIR. It
//! writes nothing else: the reference pages in `generated-docs/` are refreshed by
//! `cargo run -p vfd-cli -- generate` only, and a test fails when they are stale.

use std::path::PathBuf;

fn main() {
    let manifest = PathBuf::from(
        std::env::var_os("CARGO_MANIFEST_DIR").expect("cargo sets CARGO_MANIFEST_DIR"),
    );
    let out_dir = PathBuf::from(std::env::var_os("OUT_DIR").expect("cargo sets OUT_DIR"));
    println!("cargo:rerun-if-changed={}", manifest.display());
    let builder = match vfd_codegen::Builder::new().drives_in(&manifest) {
        Ok(builder) => builder
            .out_dir(&out_dir)
            .cargo_metadata(true)
            .display_root(manifest.join(".."))
            .regenerate_command("cargo build -p vfd-drives"),
        Err(error) => vfd_codegen::fail_build(&error),
    };
    if let Err(error) = builder.generate() {
        vfd_codegen::fail_build(&error);
    }
}
