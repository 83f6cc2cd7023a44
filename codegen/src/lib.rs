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

pub mod diagnostics;
pub mod emit;
mod frames;
pub mod ir;
mod load;
mod naming;
pub mod parse;
mod protocols;
mod validate;

pub use diagnostics::{Diagnostic, Diagnostics};
pub use ir::DriveIr;

use std::fmt;
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

/// Everything generated for one drive.
#[derive(Debug, Clone)]
pub struct GeneratedDrive {
    /// The IR.
    pub ir: DriveIr,
    /// The Rust module, formatted, with its `@generated` header.
    pub rust: String,
    /// The Markdown reference page.
    pub markdown: String,
    /// Files the output depends on.
    pub inputs: Vec<PathBuf>,
}

/// Everything generated in one run.
#[derive(Debug, Clone)]
pub struct Generated {
    /// Per drive, in the order given.
    pub drives: Vec<GeneratedDrive>,
    /// The Markdown index page.
    pub index: String,
}

/// Why generation failed.
#[derive(Debug)]
pub enum Error {
    /// The descriptions have problems; nothing was written.
    Invalid(Diagnostics),
    /// A file could not be read or written.
    Io {
        /// The file.
        path: PathBuf,
        /// The error.
        source: std::io::Error,
    },
    /// An emitter failed (a bug in the generator, not in the description).
    Emit(String),
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Error::Invalid(diagnostics) => write!(f, "{diagnostics}"),
            Error::Io { path, source } => write!(f, "{}: {source}", path.display()),
            Error::Emit(message) => write!(f, "internal generator error: {message}"),
        }
    }
}

impl std::error::Error for Error {}

/// Fails a build script with the error's messages as `cargo:warning` lines (so they show
/// in the build output with their file:line:column) and a non-zero exit.
pub fn fail_build(error: &Error) -> ! {
    for line in error.to_string().lines() {
        println!("cargo:warning={line}");
    }
    eprintln!("{error}");
    std::process::exit(1)
}

/// Configures and runs generation, for build scripts and tools.
#[derive(Debug, Clone, Default)]
pub struct Builder {
    drives: Vec<PathBuf>,
    protocols_dir: Option<PathBuf>,
    out_dir: Option<PathBuf>,
    docs_dir: Option<PathBuf>,
    cargo_metadata: bool,
    display_root: Option<PathBuf>,
}

impl Builder {
    /// A builder with no drives.
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds one drive file.
    pub fn drive(mut self, path: impl Into<PathBuf>) -> Self {
        self.drives.push(path.into());
        self
    }

    /// Adds every `*.yaml` file directly inside `dir`, in name order.
    pub fn drives_in(mut self, dir: impl AsRef<Path>) -> Result<Self, Error> {
        let dir = dir.as_ref();
        let entries = std::fs::read_dir(dir).map_err(|source| Error::Io {
            path: dir.to_owned(),
            source,
        })?;
        let mut found: Vec<PathBuf> = entries
            .filter_map(|entry| entry.ok().map(|e| e.path()))
            .filter(|path| path.extension().is_some_and(|ext| ext == "yaml") && path.is_file())
            .collect();
        found.sort();
        self.drives.extend(found);
        Ok(self)
    }

    /// Where protocol files are found (default: `protocols/` next to each drive file).
    pub fn protocols_dir(mut self, dir: impl Into<PathBuf>) -> Self {
        self.protocols_dir = Some(dir.into());
        self
    }

    /// Writes `<id>.rs` per drive and `drives.rs` (which includes them all) into `dir`.
    pub fn out_dir(mut self, dir: impl Into<PathBuf>) -> Self {
        self.out_dir = Some(dir.into());
        self
    }

    /// Writes `<id>.md` per drive and `README.md` (the index) into `dir`.
    pub fn docs_dir(mut self, dir: impl Into<PathBuf>) -> Self {
        self.docs_dir = Some(dir.into());
        self
    }

    /// Shows drive file paths relative to `root` in generated output (headers, docs), so
    /// the output does not depend on where the repository is checked out.
    pub fn display_root(mut self, root: impl Into<PathBuf>) -> Self {
        self.display_root = Some(root.into());
        self
    }

    /// Prints `cargo:rerun-if-changed` for every input (for build scripts).
    pub fn cargo_metadata(mut self, on: bool) -> Self {
        self.cargo_metadata = on;
        self
    }

    /// Generates everything in memory, then writes files that changed. When any
    /// description is invalid, every problem is returned and nothing is written.
    pub fn generate(&self) -> Result<Generated, Error> {
        let generated = self.generate_in_memory()?;
        if self.cargo_metadata {
            for drive in &generated.drives {
                for input in &drive.inputs {
                    println!("cargo:rerun-if-changed={}", input.display());
                }
            }
            if let Some(dir) = &self.protocols_dir {
                println!("cargo:rerun-if-changed={}", dir.display());
            }
        }
        if let Some(dir) = &self.out_dir {
            let mut includes =
                String::from("// @generated by vfd-codegen: one include per described drive.\n");
            for drive in &generated.drives {
                let name = format!("{}.rs", drive.ir.id);
                write_if_changed(&dir.join(&name), &drive.rust)?;
                includes.push_str(&format!(
                    "include!(concat!(env!(\"OUT_DIR\"), \"/{name}\"));\n"
                ));
            }
            let all: Vec<String> = generated
                .drives
                .iter()
                .map(|d| format!("&{}::DRIVE", d.ir.module))
                .collect();
            includes.push_str(&format!(
                "/// Every described drive.\npub static ALL_DRIVES: [&::vfd_runtime::DriveInfo; {}] = [{}];\n",
                all.len(),
                all.join(", ")
            ));
            write_if_changed(&dir.join("drives.rs"), &includes)?;
        }
        if let Some(dir) = &self.docs_dir {
            for drive in &generated.drives {
                write_if_changed(&dir.join(format!("{}.md", drive.ir.id)), &drive.markdown)?;
            }
            write_if_changed(&dir.join("README.md"), &generated.index)?;
        }
        Ok(generated)
    }

    /// Generates everything without writing files.
    pub fn generate_in_memory(&self) -> Result<Generated, Error> {
        let mut diagnostics = Diagnostics::default();
        let mut irs = Vec::new();
        for path in &self.drives {
            match compile(path, self.protocols_dir.as_deref()) {
                Ok(ir) => irs.push(ir),
                Err(more) => diagnostics.items.extend(more.items),
            }
        }
        if !diagnostics.is_empty() {
            return Err(Error::Invalid(diagnostics));
        }
        let mut drives = Vec::new();
        for mut ir in irs {
            let inputs = inputs_of(&ir, self.protocols_dir.as_deref());
            if let Some(root) = &self.display_root {
                let root = root.canonicalize().unwrap_or_else(|_| root.clone());
                let file = PathBuf::from(&ir.file);
                let file = file.canonicalize().unwrap_or(file);
                if let Ok(relative) = file.strip_prefix(&root) {
                    ir.file = relative.display().to_string().replace('\\', "/");
                }
            }
            let rust =
                emit::rust::format_file(&ir, emit::rust::drive_module(&ir)).map_err(Error::Emit)?;
            let markdown = emit::markdown::drive_page(&ir).map_err(Error::Emit)?;
            drives.push(GeneratedDrive {
                ir,
                rust,
                markdown,
                inputs,
            });
        }
        let irs: Vec<DriveIr> = drives.iter().map(|d| d.ir.clone()).collect();
        let index = emit::markdown::index_page(&irs).map_err(Error::Emit)?;
        Ok(Generated { drives, index })
    }
}

/// Writes `contents` to `path` unless the file already holds exactly that (keeps builds
/// incremental). Creates the parent folder.
pub fn write_if_changed(path: &Path, contents: &str) -> Result<bool, Error> {
    if std::fs::read_to_string(path).is_ok_and(|old| old == contents) {
        return Ok(false);
    }
    if let Some(parent) = path.parent() {
        std::fs::create_dir_all(parent).map_err(|source| Error::Io {
            path: parent.to_owned(),
            source,
        })?;
    }
    std::fs::write(path, contents).map_err(|source| Error::Io {
        path: path.to_owned(),
        source,
    })?;
    Ok(true)
}

/// Golden tests for one drive as a formatted Rust file (for the workspace test crate).
pub fn golden_tests_file(drive: &DriveIr, drive_path: &str) -> Result<String, Error> {
    let tokens = emit::tests::golden_tests(drive, drive_path);
    let file: syn::File =
        syn::parse2(tokens).map_err(|e| Error::Emit(format!("golden tests do not parse: {e}")))?;
    Ok(format!(
        "{}{}",
        emit::rust::header(drive),
        prettyplease::unparse(&file)
    ))
}
