//! Generates the typed API of every drive described in this folder, and (outside CI)
//! refreshes the Markdown pages in `generated-docs/`.

use std::path::PathBuf;

fn main() {
    let manifest = PathBuf::from(
        std::env::var_os("CARGO_MANIFEST_DIR").expect("cargo sets CARGO_MANIFEST_DIR"),
    );
    let out_dir = PathBuf::from(std::env::var_os("OUT_DIR").expect("cargo sets OUT_DIR"));
    println!("cargo:rerun-if-changed={}", manifest.display());
    println!("cargo:rerun-if-env-changed=CI");
    let mut builder = match vfd_codegen::Builder::new().drives_in(&manifest) {
        Ok(builder) => builder
            .out_dir(&out_dir)
            .cargo_metadata(true)
            .display_root(manifest.join(".."))
            .regenerate_command("cargo run -p vfd-cli -- generate")
            .crate_path("vfd_drives")
            .manuals_location("shared/seeds"),
        Err(error) => vfd_codegen::fail_build(&error),
    };
    // The committed pages are refreshed by every local build; in CI they are only
    // compared (tests/tests/generated_docs.rs), so a stale commit fails there.
    let docs = manifest.join("../generated-docs");
    if std::env::var_os("CI").is_none() && docs.is_dir() {
        builder = builder.docs_dir(docs);
    }
    if let Err(error) = builder.generate() {
        vfd_codegen::fail_build(&error);
    }
}
