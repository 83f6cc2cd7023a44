//! The [`Builder`]: runs the pipeline for a set of drive files and writes the outputs (Rust
//! modules, the shared frame layouts, golden tests, reference pages), only files whose
//! contents changed, and nothing at all when a description has problems.

use crate::diagnostics::Diagnostics;
use crate::ir::{DriveIr, ProtocolFileIr};
use crate::output_names::OutputNames;
use crate::{compile_with_warnings, emit, inputs_of, load};
use std::path::{Path, PathBuf};

/// Everything generated for one drive.
#[derive(Debug, Clone)]
pub struct GeneratedDrive {
    /// The IR.
    pub ir: DriveIr,
    /// The Rust module, formatted, with its `@generated` header.
    pub rust: String,
    /// The Markdown reference page.
    pub markdown: String,
    /// Golden-frame tests, formatted (only when [`Builder::golden_tests`] is on).
    pub golden_tests: Option<String>,
    /// Files the output depends on.
    pub inputs: Vec<PathBuf>,
    /// The description's warnings (they do not stop generation).
    pub warnings: Diagnostics,
}

/// Everything generated in one run.
#[derive(Debug, Clone)]
pub struct Generated {
    /// Per drive, in the order given.
    pub drives: Vec<GeneratedDrive>,
    /// The frame layouts of every protocol file the drives use, each once, as a formatted
    /// Rust file (`layouts.rs`, included by `drives.rs` beside the drive modules).
    pub layouts: String,
    /// The Markdown index page.
    pub index: String,
    /// Files [`Builder::generate`] wrote because their contents changed, in writing order
    /// (files already up to date are left alone and not listed).
    pub written: Vec<PathBuf>,
}

/// Why generation failed.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// The descriptions have problems; nothing was written.
    #[error("{0}")]
    Invalid(Diagnostics),
    /// A file could not be read or written.
    #[error("{}: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The error.
        #[source]
        source: std::io::Error,
    },
    /// An emitter failed (a bug in the generator, not in the description).
    #[error("internal generator error: {0}")]
    Emit(String),
}

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
    names: OutputNames,
    golden_tests: bool,
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

    /// The command that regenerates the output, named in `@generated` headers (Rust files,
    /// reference pages, golden tests), e.g. `cargo run -p my-cli -- generate`. Default: the
    /// headers say "regenerate with vfd-codegen".
    pub fn regenerate_command(mut self, command: impl Into<String>) -> Self {
        self.names.regenerate_command = Some(command.into());
        self
    }

    /// The Rust path through which golden tests and reference pages reach the generated drive
    /// modules (like prost's `extern_path`). Default `crate`: the including crate's root holds
    /// them. Give the crate's name (`my_drives`) when the golden tests are compiled in another
    /// crate, e.g. its integration tests.
    pub fn crate_path(mut self, path: impl Into<String>) -> Self {
        self.names.crate_path = path.into();
        self
    }

    /// The folder shown in front of manual file names on reference pages, e.g.
    /// `docs/manuals` (nothing is read from it). Default: the file name alone.
    pub fn manuals_location(mut self, folder: impl Into<String>) -> Self {
        self.names.manuals_location = Some(folder.into());
        self
    }

    /// Also generates golden-frame tests, one `#[test]` per example of the manual. With
    /// [`out_dir`](Self::out_dir), writes `<id>_golden.rs` per drive and `golden.rs`, which
    /// wraps each in `mod <id>`; include that in a module of its own, in a crate that depends
    /// on `vfd-runtime` with its `testing` feature (they call `vfd_runtime::testing`):
    ///
    /// ```ignore
    /// // tests/golden.rs
    /// mod golden { include!(concat!(env!("OUT_DIR"), "/golden.rs")); }
    /// ```
    ///
    /// The tests reach the drive modules through [`crate_path`](Self::crate_path).
    pub fn golden_tests(mut self, on: bool) -> Self {
        self.golden_tests = on;
        self
    }

    /// The names generated output uses for anything outside the descriptions.
    pub fn output_names(&self) -> &OutputNames {
        &self.names
    }

    /// Prints `cargo:rerun-if-changed` for every input (for build scripts).
    pub fn cargo_metadata(mut self, on: bool) -> Self {
        self.cargo_metadata = on;
        self
    }

    /// Generates everything in memory, then writes files that changed (listed in
    /// [`Generated::written`]). When any description is invalid, every problem is returned
    /// and nothing is written.
    pub fn generate(&self) -> Result<Generated, Error> {
        let mut generated = self.generate_in_memory()?;
        let mut written = Vec::new();
        let mut write = |path: PathBuf, contents: &str| -> Result<(), Error> {
            if write_if_changed(&path, contents)? {
                written.push(path);
            }
            Ok(())
        };
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
            let mut includes = String::from(
                "// @generated by vfd-codegen: the shared frame layouts and one include per described drive.\n",
            );
            write(dir.join("layouts.rs"), &generated.layouts)?;
            includes.push_str("include!(concat!(env!(\"OUT_DIR\"), \"/layouts.rs\"));\n");
            for drive in &generated.drives {
                let name = format!("{}.rs", drive.ir.id);
                write(dir.join(&name), &drive.rust)?;
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
            write(dir.join("drives.rs"), &includes)?;
            if self.golden_tests {
                let mut modules = String::from(
                    "// @generated by vfd-codegen: golden-frame tests, one module per described drive.\n",
                );
                for drive in &generated.drives {
                    let name = format!("{}_golden.rs", drive.ir.id);
                    let tests = drive.golden_tests.as_deref().unwrap_or_default();
                    write(dir.join(&name), tests)?;
                    modules.push_str(&format!(
                        "/// Golden frames of `{}`.\nmod {} {{\n    include!(concat!(env!(\"OUT_DIR\"), \"/{name}\"));\n}}\n",
                        drive.ir.file.replace('\\', "/"),
                        drive.ir.module
                    ));
                }
                write(dir.join("golden.rs"), &modules)?;
            }
        }
        if let Some(dir) = &self.docs_dir {
            for drive in &generated.drives {
                write(dir.join(format!("{}.md", drive.ir.id)), &drive.markdown)?;
            }
            write(dir.join("README.md"), &generated.index)?;
        }
        generated.written = written;
        Ok(generated)
    }

    /// Generates everything without writing files.
    pub fn generate_in_memory(&self) -> Result<Generated, Error> {
        let mut diagnostics = Diagnostics::default();
        let mut irs = Vec::new();
        for path in &self.drives {
            let compiled = compile_with_warnings(path, self.protocols_dir.as_deref());
            match compiled.drive {
                Ok(ir) => irs.push((ir, compiled.warnings)),
                Err(more) => diagnostics.items.extend(more.items),
            }
        }
        if !diagnostics.is_empty() {
            return Err(Error::Invalid(diagnostics));
        }
        let mut drives = Vec::new();
        for (mut ir, warnings) in irs {
            let inputs = inputs_of(&ir, self.protocols_dir.as_deref());
            let names = OutputNames {
                protocols_location: self.protocols_location(Path::new(&ir.file)),
                ..self.names.clone()
            };
            if let Some(root) = &self.display_root {
                let root = root.canonicalize().unwrap_or_else(|_| root.clone());
                let file = PathBuf::from(&ir.file);
                let file = file.canonicalize().unwrap_or(file);
                if let Ok(relative) = file.strip_prefix(&root) {
                    ir.file = relative.display().to_string().replace('\\', "/");
                }
            }
            let rust = emit::rust::format_file(
                &header(&ir.file, &names),
                emit::rust::drive_module(&ir, emit::rust::Layouts::Beside),
            )
            .map_err(Error::Emit)?;
            let markdown = emit::markdown::drive_page_with(&ir, &names).map_err(Error::Emit)?;
            let golden_tests = if self.golden_tests {
                Some(golden_tests_file(&ir, &names)?)
            } else {
                None
            };
            drives.push(GeneratedDrive {
                ir,
                rust,
                markdown,
                golden_tests,
                inputs,
                warnings,
            });
        }
        let irs: Vec<DriveIr> = drives.iter().map(|d| d.ir.clone()).collect();
        let index = emit::markdown::index_page_with(&irs, &self.names).map_err(Error::Emit)?;
        // One module per protocol file, with every layout some drive uses (drives may use
        // different subsets of a shared file's commands).
        let mut merged: Vec<ProtocolFileIr> = Vec::new();
        for file in irs.iter().flat_map(|ir| &ir.protocol_files) {
            match merged.iter_mut().find(|f| f.id == file.id) {
                Some(known) => {
                    for layout in &file.layouts {
                        if !known.layouts.iter().any(|l| l.name == layout.name) {
                            known.layouts.push(layout.clone());
                        }
                    }
                }
                None => merged.push(file.clone()),
            }
        }
        let files: Vec<&ProtocolFileIr> = merged.iter().collect();
        let layouts = emit::rust::format_file(
            &format!(
                "// @generated by vfd-codegen from the protocol files. Do not edit: change the YAML and {}.\n\n",
                self.names.regenerate_hint()
            ),
            emit::rust::layouts_module(&files),
        )
        .map_err(Error::Emit)?;
        Ok(Generated {
            drives,
            layouts,
            index,
            written: Vec::new(),
        })
    }
}

impl Builder {
    /// The protocol folder of the drive at `drive_file` relative to the display root, when
    /// it lies under it.
    fn protocols_location(&self, drive_file: &Path) -> Option<String> {
        let root = self.display_root.as_ref()?;
        let root = root.canonicalize().unwrap_or_else(|_| root.clone());
        let dir = match &self.protocols_dir {
            Some(dir) => dir.clone(),
            None => load::default_protocols_dir(drive_file),
        };
        let dir = dir.canonicalize().unwrap_or(dir);
        let relative = dir.strip_prefix(&root).ok()?;
        Some(relative.display().to_string().replace('\\', "/"))
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

/// Golden tests for one drive as a formatted Rust file, reaching the drive module through
/// `names.crate_path` (see [`Builder::golden_tests`]).
pub fn golden_tests_file(drive: &DriveIr, names: &OutputNames) -> Result<String, Error> {
    let tokens = emit::tests::golden_tests(drive, &names.module_path(&drive.module));
    let file: syn::File =
        syn::parse2(tokens).map_err(|e| Error::Emit(format!("golden tests do not parse: {e}")))?;
    Ok(format!(
        "{}{}",
        header(&drive.file, names),
        prettyplease::unparse(&file)
    ))
}

/// The `@generated` comment every generated Rust file starts with, naming the drive file
/// and how to regenerate.
pub(crate) fn header(drive_file: &str, names: &OutputNames) -> String {
    format!(
        "// @generated by vfd-codegen from {}. Do not edit: change the YAML and {}.\n\n",
        drive_file.replace('\\', "/"),
        names.regenerate_hint()
    )
}

#[cfg(test)]
mod tests {
    use super::Builder;
    use crate::validate::testing::valid_with;
    use std::path::Path;

    /// A drive id with `-` names files as written and the Rust module with `_`.
    #[test]
    fn a_kebab_case_drive_id_becomes_a_snake_case_module() {
        let dir = std::env::temp_dir().join(format!("vfd-kebab-id-{}", std::process::id()));
        let out = dir.join("out");
        std::fs::create_dir_all(&out).unwrap();
        let file = dir.join("vf-as1.yaml");
        std::fs::write(&file, valid_with(&[("id: test_drive", "id: vf-as1")])).unwrap();
        let generated = Builder::new()
            .drive(&file)
            .protocols_dir(Path::new(env!("CARGO_MANIFEST_DIR")).join("../drives/protocols"))
            .out_dir(&out)
            .docs_dir(&out)
            .golden_tests(true)
            .generate()
            .unwrap_or_else(|error| panic!("a kebab-case drive id generates:\n{error}"));
        let drive = &generated.drives[0];
        assert_eq!(
            (drive.ir.id.as_str(), drive.ir.module.as_str()),
            ("vf-as1", "vf_as1")
        );
        assert!(drive.rust.contains("pub mod vf_as1 {"), "{}", drive.rust);
        let includes = std::fs::read_to_string(out.join("drives.rs")).unwrap();
        assert!(includes.contains("/vf-as1.rs\""), "{includes}");
        assert!(includes.contains("&vf_as1::DRIVE"), "{includes}");
        let golden = std::fs::read_to_string(out.join("golden.rs")).unwrap();
        assert!(golden.contains("mod vf_as1 {"), "{golden}");
        for name in ["vf-as1.rs", "vf-as1_golden.rs", "vf-as1.md"] {
            assert!(out.join(name).is_file(), "{name} written");
        }
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
