//! The drives `vfd` knows: the ones compiled into it, drive files in the search path
//! (`--drives DIR`, repeatable, and the `VFD_DRIVES` environment variable), and any drive
//! file named by its path. A file is compiled when the command starts, its protocol files
//! found as the generator finds them (`protocols/` next to it, or `--protocols DIR`, then
//! the protocol files shipped inside `vfd`), with exactly the diagnostics of `vfd check`:
//! with a problem on the wire (framing, checksums, registers, codes, the frames and values
//! of the manual's examples), the command stops before it opens or sends anything. Problems
//! only in parts that document the drive or rehearse it on the virtual drive (an example's
//! `not_simulated` or `settings`, the behaviour model, errata) are reported on standard
//! error, and the command goes on without those parts (`vfd_codegen::Compiled::usable`).

use crate::Failure;
use std::path::{Path, PathBuf};
use std::sync::OnceLock;
use vfd_runtime::DriveInfo;

/// The environment variable holding more folders of drive files, separated as `PATH` is.
pub const DRIVES_VARIABLE: &str = "VFD_DRIVES";

/// Where drive and protocol files are looked up, set once from the command line.
#[derive(Debug, Default)]
pub struct Places {
    /// Folders of drive files (`--drives`, then `VFD_DRIVES`).
    pub drives: Vec<PathBuf>,
    /// The folder of protocol files (`--protocols`), instead of `protocols/` next to each
    /// drive file.
    pub protocols: Option<PathBuf>,
}

static PLACES: OnceLock<Places> = OnceLock::new();

/// Sets where drive files are looked up: `drives` (from the command line) and then the
/// folders of `VFD_DRIVES`; `protocols` for every drive file. Called once, at start.
pub fn set_places(mut drives: Vec<PathBuf>, protocols: Option<PathBuf>) {
    if let Some(more) = std::env::var_os(DRIVES_VARIABLE) {
        drives.extend(std::env::split_paths(&more).filter(|p| !p.as_os_str().is_empty()));
    }
    let _ = PLACES.set(Places { drives, protocols });
}

fn places() -> &'static Places {
    PLACES.get_or_init(Places::default)
}

/// Compiles the drive file at `path` as `vfd check` does: its protocol files from
/// `--protocols`, else `protocols/` next to it, then the ones shipped inside `vfd`.
pub fn compile(path: &Path) -> vfd_codegen::Compiled {
    vfd_codegen::compile_with(
        path,
        places().protocols.as_deref(),
        &vfd_drives::PROTOCOL_FILES,
    )
}

/// The drive in the file at `path`, compiled now; a failure carries every diagnostic, the
/// errors and then the warnings, as `vfd check` prints them. (A file without errors is
/// used as it is; its warnings are `vfd check`'s to show. A file whose errors are all off
/// the wire is used without the parts that have them, after a warning saying so.)
pub fn load(path: &Path) -> Result<&'static DriveInfo, Failure> {
    load_file(path)
        .map(|loaded| loaded.drive)
        .map_err(|refused| refused.failure(path))
}

/// Why a drive file cannot be used: its errors, and the warnings it also earns.
struct Refused {
    errors: vfd_codegen::Diagnostics,
    warnings: vfd_codegen::Diagnostics,
}

impl Refused {
    /// The failure a command ends with: every diagnostic, and the command that lists them.
    fn failure(&self, path: &Path) -> Failure {
        let mut text = self.errors.to_string();
        if !self.warnings.items.is_empty() {
            text = format!("{text}\n{}", self.warnings);
        }
        Failure::new(format!(
            "{} cannot be used: it has {} problem(s)\n{text}",
            path.display(),
            self.errors.items.len()
        ))
        .hint(format!(
            "fix them and run `vfd check {}`; nothing was opened or sent",
            path.display()
        ))
    }
}

/// A drive file compiled for use.
#[derive(Clone, Copy)]
struct Loaded {
    drive: &'static DriveInfo,
    /// Errors it has off the wire, left out with the parts that have them.
    off_the_wire: usize,
}

/// The drive files compiled so far, by their canonical paths.
type Cache = std::sync::Mutex<Vec<(PathBuf, Loaded)>>;
static LOADED: OnceLock<Cache> = OnceLock::new();

/// How a command line names `drive` so that it is found again: its id where the id finds
/// this very drive (compiled in, or in the search path), else the path of the file it was
/// loaded from (a drive named by its path: its id alone finds nothing).
pub fn name_for(drive: &DriveInfo) -> String {
    let by_id = self::drive(drive.id).ok();
    if by_id.is_some_and(|found| std::ptr::eq(found, drive)) {
        return drive.id.to_owned();
    }
    LOADED
        .get()
        .and_then(|loaded| loaded.lock().ok())
        .and_then(|list| {
            list.iter()
                .find(|(_, loaded)| std::ptr::eq(loaded.drive, drive))
                .map(|(path, _)| path.display().to_string())
        })
        .unwrap_or_else(|| drive.id.to_owned())
}

/// The drive in the file at `path`, compiled once per process. A file with errors off the
/// wire only is used without the parts that have them; the first time, a warning on
/// standard error names them.
fn load_file(path: &Path) -> Result<Loaded, Refused> {
    let loaded = LOADED.get_or_init(Default::default);
    let key = path.canonicalize().unwrap_or_else(|_| path.to_owned());
    let known = loaded
        .lock()
        .ok()
        .and_then(|list| list.iter().find(|(p, _)| *p == key).map(|(_, d)| *d));
    if let Some(drive) = known {
        return Ok(drive);
    }
    let compiled = compile(path);
    let (ir, off_the_wire) = match (compiled.drive, compiled.usable) {
        (Ok(ir), _) => (ir, 0),
        (Err(errors), Some(usable)) => {
            warn_off_the_wire(path, &errors);
            (usable, errors.items.len())
        }
        (Err(errors), None) => {
            return Err(Refused {
                errors,
                warnings: compiled.warnings,
            })
        }
    };
    let found = Loaded {
        drive: vfd_codegen::drive_info(&ir),
        off_the_wire,
    };
    if let Ok(mut list) = loaded.lock() {
        list.push((key, found));
    }
    Ok(found)
}

/// Says on standard error that the file at `path` has `errors` that do not concern the wire,
/// where they are, and that the command goes on without the parts that have them.
fn warn_off_the_wire(path: &Path, errors: &vfd_codegen::Diagnostics) {
    let mut places: Vec<&str> = errors.items.iter().map(|d| d.path.as_str()).collect();
    places.dedup();
    eprintln!(
        "vfd: warning: {} has {} problem(s) that do not concern the wire, at {}; going on without those parts (`vfd check {}` lists them)",
        path.display(),
        errors.items.len(),
        places.join(", "),
        path.display()
    );
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

/// The drive files in the search path, in folder order then by name.
pub fn search_path_files() -> Vec<PathBuf> {
    let mut files = Vec::new();
    for dir in &places().drives {
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

/// The search path's folders, for a message.
pub fn search_path() -> &'static [PathBuf] {
    &places().drives
}

/// A drive of the search path and what became of it.
pub enum Found {
    /// The file compiled (possibly with problems off the wire, left out: their count).
    Drive(PathBuf, &'static DriveInfo, usize),
    /// The file has problems (`vfd check FILE` lists them).
    Broken(PathBuf, usize),
}

/// Every drive file of the search path, compiled.
pub fn search_path_drives() -> Vec<Found> {
    search_path_files()
        .into_iter()
        .map(|file| match load_file(&file) {
            Ok(loaded) => Found::Drive(file, loaded.drive, loaded.off_the_wire),
            Err(refused) => Found::Broken(file, refused.errors.items.len()),
        })
        .collect()
}

/// The drive `name` names: a drive file by its path, a compiled-in drive by its id
/// (case-insensitive), or a drive file of the search path by its id (a file named
/// `<id>.yaml` is tried first).
pub fn drive(name: &str) -> Result<&'static DriveInfo, Failure> {
    if is_path(name) {
        let path = Path::new(name);
        if !path.is_file() {
            return Err(Failure::new(format!("no drive file {name}"))
                .hint("give the path of a drive description (.yaml), or a drive id (`vfd list`)"));
        }
        return load(path);
    }
    if let Some(drive) = vfd_drives::ALL_DRIVES
        .iter()
        .copied()
        .find(|d| d.id.eq_ignore_ascii_case(name))
    {
        return Ok(drive);
    }
    let files = search_path_files();
    let named = |file: &PathBuf| {
        file.file_stem()
            .and_then(|s| s.to_str())
            .is_some_and(|stem| stem.eq_ignore_ascii_case(name))
    };
    let mut broken = None;
    for file in files.iter().filter(|f| named(f)).chain(files.iter()) {
        match load_file(file) {
            Ok(loaded) if loaded.drive.id.eq_ignore_ascii_case(name) => return Ok(loaded.drive),
            Ok(_) => {}
            // A file that has problems and names this drive (by its file name or its
            // `drive.id`) is the one meant: say what is wrong with it, not that the drive
            // is unknown.
            Err(refused) if broken.is_none() && (named(file) || declares_id(file, name)) => {
                broken = Some(refused.failure(file));
            }
            Err(_) => {}
        }
    }
    if let Some(failure) = broken {
        return Err(failure);
    }
    Err(
        Failure::new(format!("unknown drive `{name}`")).hint(format!(
        "described drives: {}{} (`vfd list`); or give the path of a drive file (./my_drive.yaml)",
        drive_ids(),
        if search_path().is_empty() {
            String::new()
        } else {
            format!(
                "; searched {} too",
                search_path()
                    .iter()
                    .map(|p| p.display().to_string())
                    .collect::<Vec<_>>()
                    .join(", ")
            )
        }
    )),
    )
}

/// Whether the drive file at `path` says its `drive.id` is `name` (read as text, for a
/// file that does not compile).
fn declares_id(path: &Path, name: &str) -> bool {
    let Ok(source) = vfd_codegen::yaml::SourceFile::read(path) else {
        return false;
    };
    source
        .tree()
        .and_then(|tree| tree.find("drive.id"))
        .and_then(|id| id.text())
        .is_some_and(|id| id.eq_ignore_ascii_case(name))
}

/// Every drive `vfd` knows without a path: compiled in, then the search path's (a file
/// whose id is built in is left out: by id, the built-in drive is meant).
pub fn all_drives() -> Vec<&'static DriveInfo> {
    let mut all: Vec<&'static DriveInfo> = vfd_drives::ALL_DRIVES.to_vec();
    for found in search_path_drives() {
        if let Found::Drive(_, drive, _) = found {
            if !all.iter().any(|d| d.id == drive.id) {
                all.push(drive);
            }
        }
    }
    all
}

/// The ids of the compiled-in drives, comma-separated.
pub fn drive_ids() -> String {
    let ids: Vec<&str> = vfd_drives::ALL_DRIVES.iter().map(|d| d.id).collect();
    ids.join(", ")
}
