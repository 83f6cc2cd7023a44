//! Reads YAML drive descriptions, validates them, and generates typed Rust register APIs,
//! Markdown reference pages and golden-frame tests.
//!
//! The pipeline runs in stages, one module each:
//!
//! 1. **parse** ([`parse`], [`model`], [`positions`]): YAML to serde types, with a
//!    path-to-position index so every later message can name file, line and column;
//! 2. **validate** ([`load`], [`protocols`], [`validate`], [`ranges`]): protocol files
//!    resolved into runtime layouts, then every check run and every problem collected;
//! 3. **IR** ([`ir`]): names, ranges and example frames resolved into plain, ordered data;
//! 4. **emit** ([`emit_rust`], [`emit_markdown`], [`emit_tests`]): `quote!` + prettyplease
//!    for Rust, minijinja for Markdown.
//!
//! Use it from a build script like `prost-build`:
//!
//! ```no_run
//! // build.rs
//! let out_dir = std::path::PathBuf::from(std::env::var_os("OUT_DIR").unwrap());
//! if let Err(error) = vfd_codegen::Builder::new()
//!     .drive("drives/my_drive.yaml")
//!     .out_dir(&out_dir)
//!     .cargo_metadata(true)
//!     .generate()
//! {
//!     vfd_codegen::fail_build(&error);
//! }
//! // src/lib.rs: include!(concat!(env!("OUT_DIR"), "/drives.rs"));
//! ```
//!
//! or as a proc-macro: `vfd_macros::include_drive!("drives/my_drive.yaml");`.

// Diagnostics are the error path of a build-time tool; their size does not matter.
#![allow(clippy::result_large_err)]

mod builder;
pub mod diagnostics;
mod emit;
mod frames;
pub mod ir;
mod load;
mod naming;
pub mod parse;
mod protocols;
mod validate;

pub use builder::{
    fail_build, golden_tests_file, write_if_changed, Builder, Error, Generated, GeneratedDrive,
    OutputNames,
};
pub use diagnostics::{Diagnostic, Diagnostics};
pub use ir::DriveIr;

use std::path::{Path, PathBuf};

/// Reads, validates and lowers one drive file. `protocols_dir` defaults to the
/// `protocols/` folder next to the drive file.
pub fn compile(path: &Path, protocols_dir: Option<&Path>) -> Result<DriveIr, Diagnostics> {
    let source = parse::SourceFile::read(path).map_err(|problem| Diagnostics {
        items: vec![problem],
    })?;
    compile_source(source, protocols_dir)
}

/// Like [`compile`], for a drive file already in memory.
pub fn compile_text(
    path: &Path,
    text: String,
    protocols_dir: Option<&Path>,
) -> Result<DriveIr, Diagnostics> {
    compile_source(parse::SourceFile::from_text(path, text), protocols_dir)
}

/// The pipeline, stage by stage: parse and load, lower protocols, decode examples,
/// validate, lower to the IR. Every problem of every stage is collected; the IR is built
/// only from a description without problems.
fn compile_source(
    source: parse::SourceFile,
    protocols_dir: Option<&Path>,
) -> Result<DriveIr, Diagnostics> {
    let mut diagnostics = Diagnostics::default();
    let Some(drive) = load::load(source, protocols_dir, &mut diagnostics) else {
        return Err(diagnostics);
    };
    let protocols = protocols::lower(&drive, &mut diagnostics);
    let frames = frames::decode_examples(&drive.model, &protocols);
    let context = validate::Context {
        source: drive.source,
        model: drive.model,
        protocols,
        frames,
    };
    validate::check(&context, &mut diagnostics);
    if !diagnostics.is_empty() {
        diagnostics.attach_sources(|path| {
            drive
                .sources
                .iter()
                .find(|file| file.path == path)
                .map(|file| file.text.as_str())
        });
        return Err(diagnostics);
    }
    Ok(ir::lower(&context))
}

/// One drive's Rust module as tokens, holding its own frame layouts: what
/// `vfd_macros::include_drive!` expands to.
pub fn rust_tokens(drive: &DriveIr) -> proc_macro2::TokenStream {
    emit::rust::drive_module(drive, emit::rust::Layouts::Inside)
}

/// One drive's Rust module as a formatted file with its own frame layouts and an
/// `@generated` header naming `names`' regenerate command.
pub fn rust_file(drive: &DriveIr, names: &OutputNames) -> Result<String, Error> {
    emit::rust::format_file(&builder::header(&drive.file, names), rust_tokens(drive))
        .map_err(Error::Emit)
}

/// One drive's Markdown reference page.
pub fn markdown_page(drive: &DriveIr, names: &OutputNames) -> Result<String, Error> {
    emit::markdown::drive_page_with(drive, names).map_err(Error::Emit)
}

/// The files a drive's output depends on: the drive file and its protocol files.
pub fn inputs_of(drive: &DriveIr, protocols_dir: Option<&Path>) -> Vec<PathBuf> {
    let path = PathBuf::from(&drive.file);
    let dir = protocols_dir
        .map(Path::to_owned)
        .unwrap_or_else(|| load::default_protocols_dir(&path));
    let mut inputs = vec![path];
    inputs.extend(
        drive
            .protocols
            .iter()
            .map(|p| dir.join(format!("{}.yaml", p.uses))),
    );
    inputs
}
