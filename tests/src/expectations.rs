//! Expectation files: committed files (expected diagnostics, generated pages) compared with
//! what the code makes now, or rewritten when `UPDATE_EXPECT` is set, in the manner of
//! rust-analyzer's `ensure_file_contents`.

use std::path::{Path, PathBuf};

/// A committed file whose contents differ from what they should be.
#[derive(Debug)]
pub struct Outdated<'a> {
    /// The file.
    pub path: &'a Path,
    /// What it holds (empty when missing).
    pub committed: String,
    /// What it should hold.
    pub fresh: &'a str,
}

impl Outdated<'_> {
    /// The first line that differs, as `path:line`, with both versions of it.
    pub fn first_difference(&self) -> String {
        let mut committed = self.committed.lines();
        let mut fresh = self.fresh.lines();
        let mut line = 1;
        loop {
            match (committed.next(), fresh.next()) {
                (Some(old), Some(new)) if old == new => line += 1,
                (old, new) => {
                    return format!(
                        "{}:{line}\n  committed: {}\n  now:       {}",
                        self.path.display(),
                        old.unwrap_or("(end of file)"),
                        new.unwrap_or("(end of file)")
                    )
                }
            }
        }
    }
}

/// Whether `UPDATE_EXPECT` is set: rewrite expectation files instead of comparing.
pub fn update_requested() -> bool {
    std::env::var_os("UPDATE_EXPECT").is_some()
}

/// Compares each file with the contents it should have and returns those that differ.
/// Under `UPDATE_EXPECT=1` it rewrites them instead and returns nothing.
#[track_caller]
pub fn outdated_files(files: &[(PathBuf, String)]) -> Vec<Outdated<'_>> {
    let update = update_requested();
    let mut outdated = Vec::new();
    for (path, fresh) in files {
        let committed = std::fs::read_to_string(path).unwrap_or_default();
        if committed == *fresh {
            continue;
        }
        if update {
            std::fs::write(path, fresh)
                .unwrap_or_else(|e| panic!("cannot write {}: {e}", path.display()));
        } else {
            outdated.push(Outdated {
                path,
                committed,
                fresh,
            });
        }
    }
    outdated
}

/// One broken description and the file holding its expected messages.
pub struct Case {
    /// The drive file to compile.
    pub drive: PathBuf,
    /// Where the expected messages live.
    pub expected: PathBuf,
    /// Protocol folder, when not `protocols/` next to the drive file.
    pub protocols: Option<PathBuf>,
}

/// The messages the generator prints for `case`.
pub fn render(case: &Case) -> String {
    match vfd_codegen::compile(&case.drive, case.protocols.as_deref()) {
        Ok(_) => format!(
            "{} unexpectedly validated without problems\n",
            case.drive.display()
        ),
        Err(diagnostics) => format!("{diagnostics}\n"),
    }
}

/// The warnings the generator prints for `case` (a valid description), after its errors
/// if it has any, as `vfd check` prints them.
pub fn render_warnings(case: &Case) -> String {
    let compiled = vfd_codegen::compile_with_warnings(&case.drive, case.protocols.as_deref());
    let errors = match compiled.drive {
        Ok(_) => String::new(),
        Err(diagnostics) => format!("{diagnostics}\n"),
    };
    if compiled.warnings.is_empty() {
        return format!("{errors}{} has no warnings\n", case.drive.display());
    }
    format!("{errors}{}\n", compiled.warnings)
}

/// Checks every case against its expectation file (or rewrites them all under
/// `UPDATE_EXPECT=1`) and reports every difference at once.
#[track_caller]
pub fn check_all(cases: &[Case]) {
    check_all_rendered(cases, render);
}

/// [`check_all`] with the messages `render` gives (such as [`render_warnings`]).
#[track_caller]
pub fn check_all_rendered(cases: &[Case], render: fn(&Case) -> String) {
    let files: Vec<(PathBuf, String)> = cases
        .iter()
        .map(|case| (case.expected.clone(), render(case)))
        .collect();
    let failures: Vec<String> = outdated_files(&files)
        .iter()
        .map(|file| {
            format!(
                "--- {} (expected)\n{}\n+++ actual\n{}",
                file.path.display(),
                file.committed,
                file.fresh
            )
        })
        .collect();
    assert!(
        failures.is_empty(),
        "messages changed (rerun with UPDATE_EXPECT=1 if intended):\n{}",
        failures.join("\n")
    );
}

/// Entries of `dir` that `keep` accepts, in name order.
pub fn entries(dir: &Path, keep: impl Fn(&Path) -> bool) -> Vec<PathBuf> {
    let mut found: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap_or_else(|e| panic!("{} is readable: {e}", dir.display()))
        .filter_map(|entry| entry.ok().map(|e| e.path()))
        .filter(|path| keep(path))
        .collect();
    found.sort();
    found
}
