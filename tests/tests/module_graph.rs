//! The files of each crate use each other without circles, folder by folder (see
//! `vfd_tests::module_graph` for what counts as a use); and the check itself fails on a
//! small source tree with a circle inside a folder or across folders.

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
fn cli_files_form_no_circle() {
    assert_no_module_cycle(&crate_src("cli"));
}

#[test]
fn the_other_crates_form_no_circle() {
    for folder in ["codegen/macros", "drives", "tests", "bench"] {
        assert_no_module_cycle(&crate_src(folder));
    }
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
