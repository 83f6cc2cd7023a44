//! Drive files as a catalogue compiles them: once per file (by its canonical path), the
//! run-time values kept, a file with problems off the wire used without the parts that have
//! them, a file with problems on the wire refused with every diagnostic.

use super::Catalogue;
use crate::SetupError;
use std::path::{Path, PathBuf};
use vfd_runtime::DriveInfo;

/// A drive file compiled for use.
#[derive(Debug, Clone, Copy)]
pub(super) struct Loaded {
    pub drive: &'static DriveInfo,
    /// Errors it has off the wire, left out with the parts that have them.
    pub off_the_wire: usize,
}

/// Why a drive file cannot be used: its errors, and the warnings it also earns.
pub(super) struct Refused {
    errors: vfd_codegen::Diagnostics,
    warnings: vfd_codegen::Diagnostics,
}

impl Refused {
    /// The error a command ends with: every diagnostic, and the command that lists them.
    pub fn error(&self, path: &Path) -> SetupError {
        let mut text = self.errors.to_string();
        if !self.warnings.items.is_empty() {
            text = format!("{text}\n{}", self.warnings);
        }
        SetupError::new(format!(
            "{} cannot be used: it has {} problem(s)\n{text}",
            path.display(),
            self.errors.items.len()
        ))
        .with_hint(format!(
            "fix them and run `vfd check {}`; nothing was opened or sent",
            path.display()
        ))
    }
}

/// A drive of the search path and what became of it.
pub enum Found {
    /// The file compiled (possibly with problems off the wire, left out: their count).
    Drive(PathBuf, &'static DriveInfo, usize),
    /// The file has problems (`vfd check FILE` lists them).
    Broken(PathBuf, usize),
}

impl Catalogue {
    /// Compiles the drive file at `path` as `vfd check` does: its protocol files from the
    /// catalogue's protocols folder, else `protocols/` next to it, then the shipped ones.
    /// Not kept: [`Catalogue::load`] keeps what it compiles.
    pub fn compile(&self, path: &Path) -> vfd_codegen::Compiled {
        vfd_codegen::compile_with(path, self.protocols.as_deref(), self.shipped)
    }

    /// The drive in the file at `path`, compiled once per catalogue; an error carries every
    /// diagnostic, the errors and then the warnings, as `vfd check` prints them. (A file
    /// without errors is used as it is; its warnings are `vfd check`'s to show. A file whose
    /// errors are all off the wire is used without the parts that have them, after a warning
    /// saying so.)
    pub fn load(&self, path: &Path) -> Result<&'static DriveInfo, SetupError> {
        self.load_file(path)
            .map(|loaded| loaded.drive)
            .map_err(|refused| refused.error(path))
    }

    /// The drive in the file at `path`, compiled once per catalogue. A file with errors off
    /// the wire only is used without the parts that have them; the first time, a warning
    /// names them.
    pub(super) fn load_file(&self, path: &Path) -> Result<Loaded, Refused> {
        let key = path.canonicalize().unwrap_or_else(|_| path.to_owned());
        let known = self
            .loaded
            .lock()
            .ok()
            .and_then(|list| list.iter().find(|(p, _)| *p == key).map(|(_, d)| *d));
        if let Some(drive) = known {
            return Ok(drive);
        }
        let compiled = self.compile(path);
        let (drive, off_the_wire) = match (compiled.drive_info(), &compiled.drive) {
            (Some(drive), Ok(_)) => (drive, 0),
            (Some(drive), Err(errors)) => {
                self.warn_off_the_wire(path, errors);
                (drive, errors.items.len())
            }
            (None, _) => {
                return Err(Refused {
                    errors: compiled.drive.err().unwrap_or_default(),
                    warnings: compiled.warnings,
                })
            }
        };
        let found = Loaded {
            drive,
            off_the_wire,
        };
        if let Ok(mut list) = self.loaded.lock() {
            list.push((key, found));
        }
        Ok(found)
    }

    /// Says that the file at `path` has `errors` that do not concern the wire, where they
    /// are, and that the drive is used without the parts that have them.
    fn warn_off_the_wire(&self, path: &Path, errors: &vfd_codegen::Diagnostics) {
        let mut places: Vec<&str> = errors.items.iter().map(|d| d.path.as_str()).collect();
        places.dedup();
        let text = format!(
            "{} has {} problem(s) that do not concern the wire, at {}; going on without those parts (`vfd check {}` lists them)",
            path.display(),
            errors.items.len(),
            places.join(", "),
            path.display()
        );
        match &self.warn {
            Some(warn) => warn(&text),
            None => log::warn!("{text}"),
        }
    }

    /// The drive files in the search path, in folder order then by name.
    pub fn search_path_files(&self) -> Vec<PathBuf> {
        let mut files = Vec::new();
        for dir in &self.folders {
            let mut here: Vec<PathBuf> = std::fs::read_dir(dir)
                .map(|entries| {
                    entries
                        .filter_map(|e| e.ok().map(|e| e.path()))
                        .filter(|p| p.extension().is_some_and(|e| e == "yaml" || e == "yml"))
                        .collect()
                })
                .unwrap_or_default();
            here.sort();
            files.extend(here);
        }
        files
    }

    /// Every drive file of the search path, compiled.
    pub fn search_path_drives(&self) -> Vec<Found> {
        self.search_path_files()
            .into_iter()
            .map(|file| match self.load_file(&file) {
                Ok(loaded) => Found::Drive(file, loaded.drive, loaded.off_the_wire),
                Err(refused) => Found::Broken(file, refused.errors.items.len()),
            })
            .collect()
    }
}

/// Whether the drive file at `path` says its `drive.id` is `name` (read as text, for a
/// file that does not compile).
pub(super) fn declares_id(path: &Path, name: &str) -> bool {
    let Ok(source) = vfd_codegen::yaml::SourceFile::read(path) else {
        return false;
    };
    source
        .tree()
        .and_then(|tree| tree.find("drive.id"))
        .and_then(|id| id.text())
        .is_some_and(|id| id.eq_ignore_ascii_case(name))
}
