//! The files of each crate use each other without circles, folder by folder (see
//! `vfd_tests::module_graph` for what counts as a use); and the check itself fails on a
//! small source tree with a circle inside a folder or across folders. The library the tool
//! runs on (`vfd-bus`) depends on nothing of the tool's, and no source file is over 800
//! lines.

use std::path::{Path, PathBuf};
use vfd_tests::module_graph::{assert_no_module_cycle, ModuleGraph};

fn crate_src(folder: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("..")
        .join(folder)
        .join("src")
}

#[test]
fn runtime_files_form_no_circle() {
    assert_no_module_cycle(&crate_src("runtime"));
}

#[test]
fn codegen_files_form_no_circle() {
    assert_no_module_cycle(&crate_src("codegen"));
}

#[test]
fn bus_files_form_no_circle() {
    assert_no_module_cycle(&crate_src("bus"));
}

#[test]
fn cli_files_form_no_circle() {
    assert_no_module_cycle(&crate_src("cli"));
}

#[test]
fn the_other_crates_form_no_circle() {
    for folder in ["codegen/macros", "drives", "tests", "bench"] {
        assert_no_module_cycle(&crate_src(folder));
    }
}

/// Every `.rs` file under `folder`, recursively, in path order.
fn rust_files(folder: &Path) -> Vec<PathBuf> {
    let mut files = Vec::new();
    let mut folders = vec![folder.to_path_buf()];
    while let Some(dir) = folders.pop() {
        for entry in std::fs::read_dir(&dir).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                folders.push(path);
            } else if path.extension().is_some_and(|e| e == "rs") {
                files.push(path);
            }
        }
    }
    files.sort();
    files
}

/// The library knows nothing of the tool: its manifest does not depend on `vfd-cli`, and
/// no source file of it names the tool's crate or its human error (`Failure`, which lives
/// at the CLI's edge, cli/src/failure.rs).
#[test]
fn the_library_does_not_depend_on_the_cli() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let manifest = std::fs::read_to_string(root.join("bus").join("Cargo.toml")).unwrap();
    assert!(
        !manifest.contains("vfd-cli"),
        "bus/Cargo.toml depends on the CLI"
    );
    for file in rust_files(&crate_src("bus")) {
        let text = std::fs::read_to_string(&file).unwrap();
        for word in ["vfd_cli", "Failure"] {
            assert!(
                !text.contains(word),
                "{} names `{word}`: the library must not use the CLI",
                file.display()
            );
        }
    }
}

/// The longest a source file may be: a file holds one idea.
const MAX_LINES: usize = 800;

/// No source file of these crates, nor of the workspace's integration tests
/// (`tests/tests/`), is over [`MAX_LINES`] lines.
#[test]
fn no_file_is_over_800_lines() {
    let mut files = Vec::new();
    for folder in [
        "bus",
        "cli",
        "drives",
        "codegen",
        "codegen/macros",
        "bench",
        "runtime",
        "tests",
    ] {
        files.extend(rust_files(&crate_src(folder)));
    }
    files.extend(rust_files(
        &Path::new(env!("CARGO_MANIFEST_DIR")).join("tests"),
    ));
    let mut long = Vec::new();
    for file in files {
        let lines = std::fs::read_to_string(&file).unwrap().lines().count();
        if lines > MAX_LINES {
            long.push(format!("{} ({lines} lines)", file.display()));
        }
    }
    assert!(
        long.is_empty(),
        "files over {MAX_LINES} lines (split them, one idea a file):\n{}",
        long.join("\n")
    );
}

/// A source tree written under the system's temporary folder, removed when dropped.
struct Tree(PathBuf);

impl Tree {
    fn new(name: &str, files: &[(&str, &str)]) -> Tree {
        let root =
            std::env::temp_dir().join(format!("vfd-module-graph-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&root);
        for (path, text) in files {
            let path = root.join(path);
            std::fs::create_dir_all(path.parent().expect("a file in a folder")).unwrap();
            std::fs::write(path, text).unwrap();
        }
        Tree(root)
    }

    /// The message `assert_no_module_cycle` panics with, if it does.
    fn failure(&self) -> Option<String> {
        let root = self.0.clone();
        let result = std::panic::catch_unwind(move || assert_no_module_cycle(&root));
        result.err().map(|payload| {
            payload
                .downcast_ref::<String>()
                .cloned()
                .unwrap_or_default()
        })
    }
}

impl Drop for Tree {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

#[test]
fn a_circle_between_two_files_of_a_folder_fails_naming_them() {
    let tree = Tree::new(
        "inside",
        &[
            ("lib.rs", "mod drive;\npub use drive::Drive;\n"),
            (
                "drive/mod.rs",
                "mod pages;\nmod respond;\npub use respond::Outcome;\npub struct Drive;\n",
            ),
            (
                "drive/pages.rs",
                "use super::{Drive, Outcome};\npub enum Paged { Done(Outcome) }\n",
            ),
            (
                "drive/respond.rs",
                "pub enum Outcome {}\nimpl super::Drive { fn f(&self) { let _ = super::pages::Paged::Done; } }\n",
            ),
        ],
    );
    let failure = tree.failure().expect("pages and respond use each other");
    assert!(
        failure.contains("drive/pages.rs -> drive/respond.rs -> drive/pages.rs"),
        "{failure}"
    );
}

#[test]
fn a_circle_across_folders_fails_naming_the_files_that_make_it() {
    let tree = Tree::new(
        "across",
        &[
            ("lib.rs", "mod bus;\nmod sim;\n"),
            ("bus/mod.rs", "mod session;\n"),
            (
                "bus/session.rs",
                "use crate::sim::text::frame_text;\npub fn g() {}\n",
            ),
            ("sim/mod.rs", "pub mod text;\npub mod line;\n"),
            ("sim/text.rs", "pub fn frame_text() { super::line::h(); }\n"),
            ("sim/line.rs", "pub fn h() {}\n"),
        ],
    );
    // bus uses sim, sim does not use bus: no circle yet.
    assert_eq!(tree.failure(), None);
    // A folder counts as one: sim/line.rs using bus makes a circle of the two folders.
    std::fs::write(
        tree.0.join("sim/line.rs"),
        "pub fn h() { crate::bus::session::g(); }\n",
    )
    .unwrap();
    let failure = tree.failure().expect("bus -> sim -> bus");
    assert!(
        failure.contains(
            "bus/ -> sim/ -> bus/ (bus/session.rs uses sim/text.rs; sim/line.rs uses bus/session.rs)"
        ),
        "{failure}"
    );
}

#[test]
fn a_tree_without_circles_passes() {
    let tree = Tree::new(
        "clean",
        &[
            ("main.rs", "mod out;\nmod protocols;\npub struct Failure;\nfn main() { protocols::lower(); }\n"),
            ("out.rs", "macro_rules! say { () => { $crate::out::line() }; }\npub(crate) use say;\npub fn line() {}\n"),
            (
                "protocols/mod.rs",
                "mod commands;\nmod lowered_command;\npub struct Input;\npub fn lower() { commands::lower_commands(); }\n",
            ),
            (
                "protocols/commands.rs",
                "use super::lowered_command::LoweredCommand;\nuse super::Input;\nuse crate::{out::say, Failure};\npub fn lower_commands() { say!(); }\n#[cfg(test)]\nmod tests { use super::*; }\n",
            ),
            ("protocols/lowered_command.rs", "pub struct LoweredCommand;\n// crate::protocols::commands\n"),
        ],
    );
    assert_eq!(tree.failure(), None);
    let graph = ModuleGraph::of_folder(&tree.0).unwrap();
    assert_eq!(
        graph.edges["protocols/commands.rs"]
            .iter()
            .map(String::as_str)
            .collect::<Vec<_>>(),
        [
            "main.rs",
            "out.rs",
            "protocols/lowered_command.rs",
            "protocols/mod.rs"
        ]
    );
}
