//! Expectation files for diagnostics: compile a description, compare the rendered messages
//! with a committed file, or rewrite the file when `UPDATE_EXPECT` is set.

use std::path::{Path, PathBuf};

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

/// Checks every case against its expectation file (or rewrites them all under
/// `UPDATE_EXPECT=1`) and reports every difference at once.
#[track_caller]
pub fn check_all(cases: &[Case]) {
    let update = std::env::var_os("UPDATE_EXPECT").is_some();
    let mut failures = Vec::new();
    for case in cases {
        let actual = render(case);
        if update {
            std::fs::write(&case.expected, &actual).expect("write expectation");
            continue;
        }
        let expected = std::fs::read_to_string(&case.expected).unwrap_or_default();
        if expected != actual {
            failures.push(format!(
                "--- {} (expected)\n{expected}\n+++ actual\n{actual}",
                case.expected.display()
            ));
        }
    }
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
