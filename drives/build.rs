//! Generates the typed API of every drive described in this folder into OUT_DIR, and
//! `shipped.rs`, the protocol files of `protocols/` as text (what a tool such as `vfd`
//! carries built in, for drive files that name a family without shipping its file). It
//! writes nothing else: the reference pages in `generated-docs/` are refreshed by
//! `cargo run -p vfd-cli -- generate` only, and a test fails when they are stale.
//!
//! Each drive file `<id>.yaml` is compiled only when the crate's feature `<id>` is on (all
//! are by default), so a crate that uses one drive compiles one.

use std::path::PathBuf;

fn main() {
    let manifest = PathBuf::from(
        std::env::var_os("CARGO_MANIFEST_DIR").expect("cargo sets CARGO_MANIFEST_DIR"),
    );
    let out_dir = PathBuf::from(std::env::var_os("OUT_DIR").expect("cargo sets OUT_DIR"));
    println!("cargo:rerun-if-changed={}", manifest.display());
    let builder = match enabled_drives(&manifest) {
        Ok(drives) => drives
            .into_iter()
            .fold(vfd_codegen::Builder::new(), |builder, path| {
                builder.drive(path)
            })
            .out_dir(&out_dir)
            .cargo_metadata(true)
            .display_root(manifest.join(".."))
            .regenerate_command("cargo build -p vfd-drives"),
        Err(error) => panic!(
            "cannot list the drive files in {}: {error}",
            manifest.display()
        ),
    };
    if let Err(error) = builder.generate() {
        vfd_codegen::fail_build(&error);
    }
    if let Err(error) = write_shipped(&manifest.join("protocols"), &out_dir.join("shipped.rs")) {
        panic!("cannot write shipped.rs: {error}");
    }
}

/// The drive files `dir/<id>.yaml` whose feature `<id>` is on (cargo sets
/// `CARGO_FEATURE_<ID>` for each, upper case, `-` as `_`), in name order.
fn enabled_drives(dir: &std::path::Path) -> std::io::Result<Vec<PathBuf>> {
    let mut found: Vec<PathBuf> = std::fs::read_dir(dir)?
        .filter_map(|entry| entry.ok().map(|e| e.path()))
        .filter(|path| path.extension().is_some_and(|ext| ext == "yaml") && path.is_file())
        .filter(|path| {
            let stem = path
                .file_stem()
                .and_then(|s| s.to_str())
                .unwrap_or_default();
            let feature = stem.to_uppercase().replace('-', "_");
            std::env::var_os(format!("CARGO_FEATURE_{feature}")).is_some()
        })
        .collect();
    found.sort();
    Ok(found)
}

/// `PROTOCOL_FILES`: every `protocols/*.yaml` by id, its text included at compile time.
fn write_shipped(dir: &std::path::Path, out: &std::path::Path) -> std::io::Result<()> {
    let mut files: Vec<(String, PathBuf)> = std::fs::read_dir(dir)?
        .filter_map(|entry| entry.ok())
        .filter_map(|entry| {
            let path = entry.path();
            let id = path
                .file_name()?
                .to_str()?
                .strip_suffix(".yaml")?
                .to_owned();
            Some((id, path))
        })
        .collect();
    files.sort();
    let entries: Vec<String> = files
        .iter()
        .map(|(id, path)| {
            format!(
                "    ({id:?}, include_str!({:?})),",
                path.display().to_string()
            )
        })
        .collect();
    let text = format!(
        "/// The protocol files of `drives/protocols/`, by id and text: the families a tool\n\
         /// built with this crate knows without a file of its own (see\n\
         /// `vfd_codegen::compile_with`).\n\
         pub static PROTOCOL_FILES: [(&str, &str); {}] = [\n{}\n];\n",
        files.len(),
        entries.join("\n")
    );
    vfd_codegen::write_if_changed(out, &text)
        .map(|_| ())
        .map_err(|e| std::io::Error::other(e.to_string()))
}
