//! The drives a program knows, as a value: the ones compiled in, drive files in some
//! folders (the search path), and any drive file named by its path. A file is compiled when
//! it is first asked for (`catalogue/files.rs`), its protocol files found as the generator finds them
//! (a protocols folder when one is given, else `protocols/` next to it, then the protocol
//! files shipped with the drives compiled in), with exactly the diagnostics of `vfd check`:
//! a file with a problem on the wire (framing, checksums, registers, codes, the frames and
//! values of the manual's examples) is refused before anything is opened or sent. Problems
//! only in parts that document the drive or rehearse it on the virtual drive are reported
//! through [`Catalogue::on_warning`], and the drive is used without those parts
//! (`vfd_codegen::Compiled::usable`).
//!
//! Each catalogue compiles a file once and keeps its run-time values (built once, by the
//! compiler's rehearsal where it ran): asked again, by its path or its id, it is found.

mod files;

pub use files::Found;

use crate::SetupError;
use files::Loaded;
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use vfd_runtime::DriveInfo;

/// What is said about a drive file used without some of its parts (see the module).
type Warn = Box<dyn Fn(&str) + Send + Sync>;

/// The drives a program knows (see the module).
pub struct Catalogue {
    /// The drives compiled in.
    builtin: Vec<&'static DriveInfo>,
    /// Protocol files a drive file may name without shipping them.
    shipped: vfd_codegen::Shipped,
    /// Folders of drive files, searched in order.
    folders: Vec<PathBuf>,
    /// The folder of protocol files for every drive file, instead of `protocols/` next to it.
    protocols: Option<PathBuf>,
    /// The drive files compiled so far, by their canonical paths.
    loaded: Mutex<Vec<(PathBuf, Loaded)>>,
    warn: Option<Warn>,
}

impl std::fmt::Debug for Catalogue {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Catalogue")
            .field(
                "builtin",
                &self.builtin.iter().map(|d| d.id).collect::<Vec<_>>(),
            )
            .field("folders", &self.folders)
            .field("protocols", &self.protocols)
            .finish_non_exhaustive()
    }
}

impl Default for Catalogue {
    fn default() -> Catalogue {
        Catalogue::new()
    }
}

impl Catalogue {
    /// The drives of `vfd-drives` (compiled in), with their protocol files for drive files
    /// to name; no folders.
    pub fn new() -> Catalogue {
        Catalogue::with_builtin(vfd_drives::ALL_DRIVES.to_vec(), &vfd_drives::PROTOCOL_FILES)
    }

    /// A catalogue of `builtin` drives, drive files finding the protocol files of `shipped`
    /// (by id) when they do not ship their own.
    pub fn with_builtin(
        builtin: Vec<&'static DriveInfo>,
        shipped: vfd_codegen::Shipped,
    ) -> Catalogue {
        Catalogue {
            builtin,
            shipped,
            folders: Vec::new(),
            protocols: None,
            loaded: Mutex::new(Vec::new()),
            warn: None,
        }
    }

    /// Searches `folders` (in order) for drive files, after those it searches already.
    pub fn with_folders(mut self, folders: impl IntoIterator<Item = PathBuf>) -> Catalogue {
        self.folders.extend(folders);
        self
    }

    /// Takes every drive file's protocol files from `folder` (`None`: from `protocols/` next
    /// to each drive file).
    pub fn with_protocols(mut self, folder: Option<PathBuf>) -> Catalogue {
        self.protocols = folder;
        self
    }

    /// Says through `warn` that a drive file is used without parts that have problems off
    /// the wire (once per file); without it, nothing is said but a `log` warning.
    pub fn on_warning(mut self, warn: impl Fn(&str) + Send + Sync + 'static) -> Catalogue {
        self.warn = Some(Box::new(warn));
        self
    }

    /// The drives compiled in.
    pub fn builtin(&self) -> &[&'static DriveInfo] {
        &self.builtin
    }

    /// The search path's folders.
    pub fn search_path(&self) -> &[PathBuf] {
        &self.folders
    }

    /// Whether `name` names a file rather than a drive id: it has a path separator or a
    /// `.yaml`/`.yml` ending, or a file of that name exists.
    pub fn is_path(name: &str) -> bool {
        name.contains('/')
            || name.contains(std::path::MAIN_SEPARATOR)
            || name.ends_with(".yaml")
            || name.ends_with(".yml")
            || Path::new(name).is_file()
    }

    /// The drive `name` names: a drive file by its path, a compiled-in drive by its id
    /// (case-insensitive), or a drive file of the search path by its id (a file named
    /// `<id>.yaml` is tried first).
    pub fn drive(&self, name: &str) -> Result<&'static DriveInfo, SetupError> {
        if Catalogue::is_path(name) {
            let path = Path::new(name);
            if !path.is_file() {
                return Err(SetupError::new(format!("no drive file {name}")).with_hint(
                    "give the path of a drive description (.yaml), or a drive id (`vfd list`)",
                ));
            }
            return self.load(path);
        }
        if let Some(drive) = self
            .builtin
            .iter()
            .copied()
            .find(|d| d.id.eq_ignore_ascii_case(name))
        {
            return Ok(drive);
        }
        let files = self.search_path_files();
        let named = |file: &PathBuf| {
            file.file_stem()
                .and_then(|s| s.to_str())
                .is_some_and(|stem| stem.eq_ignore_ascii_case(name))
        };
        let mut broken = None;
        for file in files.iter().filter(|f| named(f)).chain(files.iter()) {
            match self.load_file(file) {
                Ok(loaded) if loaded.drive.id.eq_ignore_ascii_case(name) => return Ok(loaded.drive),
                Ok(_) => {}
                // A file that has problems and names this drive (by its file name or its
                // `drive.id`) is the one meant: say what is wrong with it, not that the drive
                // is unknown.
                Err(refused)
                    if broken.is_none() && (named(file) || files::declares_id(file, name)) =>
                {
                    broken = Some(refused.error(file));
                }
                Err(_) => {}
            }
        }
        if let Some(error) = broken {
            return Err(error);
        }
        Err(
            SetupError::new(format!("unknown drive `{name}`")).with_hint(format!(
                "described drives: {}{} (`vfd list`); or give the path of a drive file (./my_drive.yaml)",
                self.drive_ids(),
                if self.folders.is_empty() {
                    String::new()
                } else {
                    format!(
                        "; searched {} too",
                        self.folders
                            .iter()
                            .map(|p| p.display().to_string())
                            .collect::<Vec<_>>()
                            .join(", ")
                    )
                }
            )),
        )
    }

    /// How a command line names `drive` so that it is found again: its id where the id finds
    /// this very drive (compiled in, or in the search path), else the path of the file it was
    /// loaded from (a drive named by its path: its id alone finds nothing).
    pub fn name_for(&self, drive: &DriveInfo) -> String {
        let by_id = self.drive(drive.id).ok();
        if by_id.is_some_and(|found| std::ptr::eq(found, drive)) {
            return drive.id.to_owned();
        }
        self.loaded
            .lock()
            .ok()
            .and_then(|list| {
                list.iter()
                    .find(|(_, loaded)| std::ptr::eq(loaded.drive, drive))
                    .map(|(path, _)| path.display().to_string())
            })
            .unwrap_or_else(|| drive.id.to_owned())
    }

    /// Every drive the catalogue knows without a path: compiled in, then the search path's
    /// (a file whose id is built in is left out: by id, the built-in drive is meant).
    pub fn all_drives(&self) -> Vec<&'static DriveInfo> {
        let mut all: Vec<&'static DriveInfo> = self.builtin.clone();
        for found in self.search_path_drives() {
            if let Found::Drive(_, drive, _) = found {
                if !all.iter().any(|d| d.id == drive.id) {
                    all.push(drive);
                }
            }
        }
        all
    }

    /// The ids of the compiled-in drives, comma-separated.
    pub fn drive_ids(&self) -> String {
        let ids: Vec<&str> = self.builtin.iter().map(|d| d.id).collect();
        ids.join(", ")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_built_in_drive_is_found_by_its_id_in_any_case() {
        let catalogue = Catalogue::new();
        let first = catalogue.builtin()[0];
        let found = catalogue.drive(&first.id.to_uppercase()).unwrap();
        assert!(std::ptr::eq(found, first));
        assert_eq!(catalogue.name_for(found), first.id);
        let unknown = catalogue.drive("no-such-drive").unwrap_err();
        assert_eq!(unknown.message(), "unknown drive `no-such-drive`");
        assert!(unknown.hint().unwrap().contains(first.id));
    }

    #[test]
    fn a_drive_file_is_compiled_once_per_catalogue() {
        let file = Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("..")
            .join("drives")
            .join("fc51.yaml");
        let catalogue = Catalogue::new();
        let once = catalogue.load(&file).unwrap();
        let again = catalogue
            .drive(&file.to_string_lossy())
            .expect("found again by its path");
        assert!(
            std::ptr::eq(once, again),
            "the same values, not built twice"
        );
        assert_eq!(catalogue.loaded.lock().unwrap().len(), 1);
        // Another catalogue compiles it for itself.
        let other = Catalogue::new().load(&file).unwrap();
        assert!(!std::ptr::eq(once, other));
        // A file not built in is named by its path.
        assert_ne!(catalogue.name_for(once), once.id);
    }
}
