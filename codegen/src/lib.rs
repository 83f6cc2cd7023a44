//! Reads YAML drive descriptions, validates them, and generates typed Rust register APIs,
//! Markdown reference pages and golden-frame tests.
//!
//! # Code overview
//!
//! [`compile`] runs the stages in this order; no stage imports a later one (a workspace
//! test, `tests/tests/module_graph.rs`, keeps it so). Every problem goes into one
//! [`Diagnostics`] sink with file:line:column and a YAML path, and nothing is emitted from a
//! description that has any.
//!
//! | # | Stage | Module | Input | Output |
//! |---|---|---|---|---|
//! | 1 | parse | `parse/` (`tree.rs`: the YAML read once into positioned nodes; `reader/`: nodes -> `model/` types, one file per section of the format, every problem collected) | file text | `SourceFile` + `parse::model::DriveFile` / `ProtocolFile` |
//! | 2 | load | `load/` (`based_on.rs`: a protocol file merged with the file it is `based_on`) | a drive file path | `LoadedDrive`: the drive and the protocol files it names, parsed |
//! | 3 | lower protocols | `protocols/` | `LoadedDrive` | `LoweredProtocol`s: each protocol file plus the drive's error table, address maps and pre-steps, as the runtime's own `vfd_runtime::Protocol` |
//! | 4 | decode examples | `frames.rs` | the drive's examples + lowered protocols | every example frame decoded **once** into the runtime's `vfd_runtime::meaning::FrameMeaning` |
//! | 5 | validate | `validate/` (one file per check) | `validate::Context` (stages 2-4) | problems, or nothing |
//! | 6 | IR | [`ir`] (`ir/types/`, `ir/lower/`) | `validate::Context` | [`DriveIr`]: plain, ordered, typed, serialisable; dump it with `vfd generate --dump-ir DRIVE` |
//! | 7 | emit | `emit/` (`rust/`, `live/`, `markdown/`, `tests.rs`, `words.rs`) | [`DriveIr`] only | Rust tokens (quote, then prettyplease), the same drive as run-time values ([`drive_info`]), Markdown (minijinja), golden tests |
//! | 8 | rehearse | `rehearse.rs` (`rehearse/prepare.rs`: the state an example's frames show; `rehearse/difference.rs`: what differs) | [`DriveIr`] and the drive file | each example's request played to the virtual drive built from the IR (stage 7's run-time values), in the state its frames show: its reply must be the example's, byte for byte (silence for `no_reply: true`); a warning names what differs, unless the example says why (`not_simulated:`) |
//!
//! A description with errors only in parts that do not reach the wire (examples'
//! `not_simulated` and `settings`, the behaviour model, errata: `off_the_wire.rs`) is still
//! lowered without those parts ([`Compiled::usable`]), so that a tool at a bus reports the
//! problems and goes on.
//!
//! [`Builder`] (`builder.rs`) runs stages 1-7 for many drives and writes files, and
//! [`OutputNames`] says how the output names anything outside a description. [`schemas`]
//! (`schema.rs`) derives the JSON Schema of drive and protocol files from `parse/model/`.
//!
//! Where to go for common changes:
//! - **A new check**: a file in `validate/` with its own tests, added to the list in
//!   `validate/mod.rs`; a fixture pair in `tests/fixtures/broken/`.
//! - **A new warning**: a file in `validate/` whose function pushes diagnostics made with
//!   `SourceFile::warning`, named once in the `warnings!` list in `validate/mod.rs`; a
//!   fixture pair in `tests/fixtures/warnings/`.
//! - **A new key in drive files**: `parse/model/` (an enum if its values are enumerated;
//!   a `///` comment, which becomes the key's schema description; a new type derives
//!   `JsonSchema`), then `ir/types/` + `ir/lower/`, then the emitters that show it;
//!   `vfd generate` refreshes `drives/schema/` and the README's key tables.
//! - **A new part kind or framing feature**: the runtime first (`vfd_runtime::layout` and
//!   its codec), then `parse/model/` (protocol-file types), `protocols/` (lowering and its
//!   checks), `emit/rust/bake.rs` (how the value becomes Rust) and
//!   `emit/markdown/layouts.rs` (how the page describes it).
//! - **Generated Rust**: `emit/rust/` has one file per kind of item (registers, bit fields,
//!   code tables, protocols); runtime values become tokens through `bake.rs` only.
//! - **Reference pages**: `templates/*.md.j2`, fed by `emit/markdown/view/`; sentences
//!   shared with the Rust docs live in `emit/words.rs`.
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

#![warn(missing_docs)]
// Diagnostics are the error path of a build-time tool; their size does not matter.
#![allow(clippy::result_large_err)]

mod builder;
mod diagnostics;
mod emit;
pub use emit::wrap::unwrap_markdown;
mod frames;
pub mod ir;
mod load;
mod naming;
mod off_the_wire;
mod output_names;
mod parse;
mod protocols;
mod rehearse;
mod schema;
mod validate;

pub use builder::{
    fail_build, golden_tests_file, write_if_changed, Builder, Error, Generated, GeneratedDrive,
};
pub use diagnostics::{Diagnostic, Diagnostics, Position, Severity};
pub use ir::DriveIr;
pub use load::Shipped;
pub use output_names::OutputNames;
/// The positioned YAML reader drive files are read with, for the project's other YAML
/// files (`vfd serve`'s plant files): a file read once into nodes that keep their
/// positions, read into a serde model type with every problem collected as a
/// [`Diagnostic`] at file:line:column, unknown keys with "did you mean".
pub mod yaml {
    pub use crate::parse::model::OR_SCALAR;
    pub use crate::parse::reader::closest;
    pub use crate::parse::tree::{Node, Value};
    pub use crate::parse::{Read, SourceFile};
}
pub use schema::{
    key_tables, schemas, with_key_tables, Schemas, DRIVE_SCHEMA_PATH, KEY_TABLES_BEGIN,
    KEY_TABLES_END, PROTOCOL_SCHEMA_PATH,
};

use std::path::{Path, PathBuf};

/// Reads, validates and lowers one drive file. `protocols_dir` defaults to the
/// `protocols/` folder next to the drive file. Warnings are left out: see
/// [`compile_with_warnings`].
pub fn compile(path: &Path, protocols_dir: Option<&Path>) -> Result<DriveIr, Diagnostics> {
    compile_with(path, protocols_dir, &[]).drive
}

/// Like [`compile`], keeping the warnings: what `vfd check` prints.
pub fn compile_with_warnings(path: &Path, protocols_dir: Option<&Path>) -> Compiled {
    compile_with(path, protocols_dir, &[])
}

/// Like [`compile_with_warnings`], and a protocol file found in neither `protocols_dir`
/// nor the default folder is taken from `shipped` (protocol files a tool carries built in,
/// by id), as the installed `vfd` finds the protocol families it knows.
pub fn compile_with(path: &Path, protocols_dir: Option<&Path>, shipped: Shipped) -> Compiled {
    match parse::SourceFile::read(path) {
        Ok(source) => compile_source(source, protocols_dir, shipped),
        Err(problem) => Compiled {
            drive: Err(Diagnostics {
                items: vec![problem],
            }),
            warnings: Diagnostics::default(),
            usable: None,
            runtime: None,
        },
    }
}

/// Like [`compile`], for a drive file already in memory.
pub fn compile_text(
    path: &Path,
    text: String,
    protocols_dir: Option<&Path>,
) -> Result<DriveIr, Diagnostics> {
    compile_source(parse::SourceFile::from_text(path, text), protocols_dir, &[]).drive
}

/// A drive file compiled (or refused), with the warnings its description earns.
#[derive(Debug, Clone)]
pub struct Compiled {
    /// The drive's IR, or its errors.
    pub drive: Result<DriveIr, Diagnostics>,
    /// Warnings: things that are valid but do not do what they seem to. They never stop
    /// generation; `vfd check --deny-warnings` fails on them. Printed after the errors.
    pub warnings: Diagnostics,
    /// When `drive` has errors and none of them concerns the wire (they lie in parts that
    /// document the drive or rehearse it on the virtual drive: an example's
    /// `not_simulated`, `settings` or words, the behaviour model, errata), the drive
    /// without those parts: what a tool at a bus may use after reporting the problems.
    /// `None` when the drive compiled, or a problem concerns the wire.
    pub usable: Option<DriveIr>,
    /// The run-time values ([`drive_info`]) of the IR in `drive` or `usable`, where the
    /// rehearsal of the examples built them: a tool that runs the drive takes these rather
    /// than building (and leaking) them a second time. `None` when nothing built them.
    pub runtime: Option<&'static vfd_runtime::DriveInfo>,
}

impl Compiled {
    /// The run-time values of the drive a tool may use (`drive`, else `usable`): the ones
    /// the rehearsal built, else built now (and leaked, as [`drive_info`] says: call it once
    /// per file and keep the result). `None` when the file cannot be used.
    pub fn drive_info(&self) -> Option<&'static vfd_runtime::DriveInfo> {
        let ir = self.drive.as_ref().ok().or(self.usable.as_ref())?;
        Some(self.runtime.unwrap_or_else(|| drive_info(ir)))
    }
}

/// The pipeline, stage by stage: parse and load, lower protocols, decode examples,
/// validate (errors, then warnings), lower to the IR, rehearse the examples against the
/// virtual drive. Every problem of every stage is collected; the IR is built only from a
/// description without errors.
fn compile_source(
    source: parse::SourceFile,
    protocols_dir: Option<&Path>,
    shipped: Shipped,
) -> Compiled {
    let mut diagnostics = Diagnostics::default();
    let Some(drive) = load::load(source, protocols_dir, shipped, &mut diagnostics) else {
        return Compiled {
            drive: Err(diagnostics),
            warnings: Diagnostics::default(),
            usable: None,
            runtime: None,
        };
    };
    let read_problems = diagnostics.items.len();
    let protocols = protocols::lower(&drive, &mut diagnostics);
    let frames = frames::decode_examples(&drive.model, &protocols);
    let context = validate::Context {
        source: drive.source,
        model: drive.model,
        protocols,
        frames,
    };
    validate::check(&context, &mut diagnostics);
    validate::warn(&context, &mut diagnostics);
    diagnostics.leave_out_consequences(read_problems, &drive.incomplete);
    let attach = |diagnostics: &mut Diagnostics| {
        diagnostics.attach_sources(|path| {
            drive
                .sources
                .iter()
                .find(|file| file.path == path)
                .map(|file| file.text.as_str())
        });
    };
    attach(&mut diagnostics);
    let mut warnings = diagnostics.take_warnings();
    if !diagnostics.is_empty() {
        return Compiled {
            usable: off_the_wire::usable(&context, &diagnostics),
            drive: Err(diagnostics),
            warnings,
            runtime: None,
        };
    }
    let ir = ir::lower(&context);
    let mut runtime = None;
    rehearse::examples(
        &context.source,
        &context.model,
        &ir,
        &mut runtime,
        &mut diagnostics,
    );
    attach(&mut diagnostics);
    warnings.items.extend(diagnostics.take_warnings().items);
    attach(&mut warnings);
    if !diagnostics.is_empty() {
        let usable = off_the_wire::none_concern_the_wire(&context, &diagnostics).then_some(ir);
        return Compiled {
            runtime: runtime.filter(|_| usable.is_some()),
            usable,
            drive: Err(diagnostics),
            warnings,
        };
    }
    Compiled {
        drive: Ok(ir),
        warnings,
        usable: None,
        runtime,
    }
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

/// The drive as the runtime's data, built while the program runs: the same
/// [`vfd_runtime::DriveInfo`] the generated module's `DRIVE` static holds (a test compares
/// the two for every drive file of the repository), for tools that load a description
/// file when they start. The values are leaked (the runtime's types hold `'static`
/// references): build each drive once per process.
pub fn drive_info(drive: &DriveIr) -> &'static vfd_runtime::DriveInfo {
    emit::live::drive_info(drive)
}

/// One drive's Markdown reference page.
pub fn markdown_page(drive: &DriveIr, names: &OutputNames) -> Result<String, Error> {
    emit::markdown::drive_page_with(drive, names).map_err(Error::Emit)
}

/// The files a drive's output depends on: the drive file, its protocol files and the
/// files they are `based_on`.
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
    for base in drive
        .protocol_files
        .iter()
        .filter_map(|f| f.based_on.as_ref())
    {
        let path = dir.join(format!("{base}.yaml"));
        if !inputs.contains(&path) {
            inputs.push(path);
        }
    }
    inputs
}
