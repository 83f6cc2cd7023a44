//! The graph of references between the files of a crate, to keep it free of circles: a
//! file may use the files below it, never one that (through others) uses it. Checked
//! folder by folder (see [`circle`]), so a circle between two files of one folder fails as
//! well as one between top-level modules.
//!
//! What counts as a use of another file (see [`references`]): every path, in a `use` item
//! (grouped ones too: `use crate::{a::X, b}`, globs: `use super::*`) or in code
//! (`crate::codec::encode(..)`, `$crate::out::print_line` in macros, a type in a signature),
//! that starts with `crate::`, `super::`, `self::` or with a module declared where it stands
//! (`commands::lower(..)` in `protocols/mod.rs`). The path is followed through the crate's
//! modules to the file that holds the item; a name that a `use` item brought into a module
//! (`pub use outcome::Outcome` in `virtual_drive/mod.rs`, `pub use protocol::Protocol` in
//! `lib.rs`) leads on to where that item comes from, so `super::Outcome` uses `outcome.rs`.
//! Test modules count (they are part of their file); comments and string literals do not;
//! nor do method calls (`self.reply(..)` names no path: the methods of one type may be
//! spread over the files of its folder), nor names a glob import brought in;
//! paths to other crates (`std::`, `vfd_runtime::`) do not; a module declaration
//! (`mod pages;`) is not a use. A folder's face (its `mod.rs`, `name.rs` beside `name/`,
//! the crate root `lib.rs` or `main.rs` for `src/`) declares its files, re-exports from them
//! and may call them: its references down into its own folder are not counted, while the
//! files' references up to it (`super::Input`) are. Files under `src/bin/` are separate
//! crates and are skipped.

pub mod circle;
pub mod references;
pub mod source;

pub use circle::Cycle;
pub use source::strip_comments_and_literals;

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// File-to-file references of one crate.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct ModuleGraph {
    /// For each file (path relative to `src`, with `/`), the other files it refers to.
    pub edges: BTreeMap<String, BTreeSet<String>>,
}

impl ModuleGraph {
    /// Reads every `.rs` file under `src` (a crate's source folder).
    pub fn of_folder(src: &Path) -> std::io::Result<ModuleGraph> {
        let mut files = Vec::new();
        collect_rust_files(src, src, &mut files)?;
        let mut sources = Vec::new();
        for relative in files {
            let text = std::fs::read_to_string(src.join(&relative))?;
            sources.push((relative, text));
        }
        Ok(ModuleGraph::of_sources(
            sources
                .iter()
                .map(|(path, text)| (path.as_path(), text.as_str())),
        ))
    }

    /// Builds the graph from `(path relative to src, source text)` pairs.
    pub fn of_sources<'a>(files: impl IntoIterator<Item = (&'a Path, &'a str)>) -> ModuleGraph {
        let files: Vec<(String, String)> = files
            .into_iter()
            .filter(|(path, _)| !path.starts_with("bin"))
            .map(|(path, text)| {
                let parts: Vec<String> = path
                    .components()
                    .map(|c| c.as_os_str().to_string_lossy().into_owned())
                    .collect();
                (parts.join("/"), text.to_owned())
            })
            .collect();
        ModuleGraph {
            edges: references::file_references(&files),
        }
    }

    /// Every circle, at most one per tangle, folder by folder (the crate's top first).
    pub fn cycles(&self) -> Vec<Cycle> {
        circle::cycles(&self.edges)
    }

    /// The first circle, if there is one.
    pub fn cycle(&self) -> Option<Cycle> {
        self.cycles().into_iter().next()
    }
}

/// Panics naming every circle when the crate whose sources are in `src` has one.
#[track_caller]
pub fn assert_no_module_cycle(src: &Path) {
    assert_no_module_cycle_but(src, &[]);
}

/// As [`assert_no_module_cycle`], but tolerating the circles listed in `known` (as
/// [`Cycle`] displays them): circles in files being rewritten elsewhere, to be fixed there.
/// Panics as well when a known circle is gone, so that the list only shrinks.
#[track_caller]
pub fn assert_no_module_cycle_but(src: &Path, known: &[&str]) {
    let graph = ModuleGraph::of_folder(src)
        .unwrap_or_else(|error| panic!("cannot read {}: {error}", src.display()));
    assert!(
        !graph.edges.is_empty(),
        "no modules found under {}",
        src.display()
    );
    let found: Vec<String> = graph.cycles().iter().map(Cycle::to_string).collect();
    let new: Vec<String> = found
        .iter()
        .filter(|cycle| !known.contains(&cycle.as_str()))
        .map(|cycle| format!("  {cycle}"))
        .collect();
    if !new.is_empty() {
        panic!(
            "files of {} use each other in a circle (put what they share in a file of its \
             own, or move a function to where it belongs):\n{}",
            src.display(),
            new.join("\n")
        );
    }
    let gone: Vec<&str> = known
        .iter()
        .copied()
        .filter(|cycle| !found.iter().any(|f| f == cycle))
        .collect();
    assert!(
        gone.is_empty(),
        "these known circles of {} are gone: remove them from the list: {gone:?}",
        src.display()
    );
}

fn collect_rust_files(root: &Path, dir: &Path, out: &mut Vec<PathBuf>) -> std::io::Result<()> {
    let mut entries = std::fs::read_dir(dir)?.collect::<Result<Vec<_>, _>>()?;
    entries.sort_by_key(|entry| entry.path());
    for entry in entries {
        let path = entry.path();
        if entry.file_type()?.is_dir() {
            collect_rust_files(root, &path, out)?;
        } else if path.extension().is_some_and(|ext| ext == "rs") {
            out.push(
                path.strip_prefix(root)
                    .expect("under the root")
                    .to_path_buf(),
            );
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn graph(files: &[(&str, &str)]) -> ModuleGraph {
        ModuleGraph::of_sources(files.iter().map(|(path, text)| (Path::new(*path), *text)))
    }

    fn targets<'g>(graph: &'g ModuleGraph, file: &str) -> Vec<&'g str> {
        graph.edges[file].iter().map(String::as_str).collect()
    }

    #[test]
    fn finds_a_circle_through_grouped_uses_inline_paths_and_root_reexports() {
        let graph = graph(&[
            (
                "lib.rs",
                "pub mod a; pub mod b; pub mod c;\npub use c::{Thing, other::More};",
            ),
            (
                "a.rs",
                "use crate::{b::{X, Y}, self_check};\nfn f() { crate::a::g(); }",
            ),
            ("b/mod.rs", "mod inner;"),
            ("b/inner.rs", "fn f() -> crate::Thing { todo!() }"),
            ("c.rs", "fn f() { let _ = crate::a::Z; }"),
        ]);
        assert_eq!(
            targets(&graph, "a.rs"),
            ["b/mod.rs", "lib.rs"],
            "a self reference is no edge; an item the root does not re-export is the root's"
        );
        assert_eq!(targets(&graph, "b/inner.rs"), ["c.rs"]);
        let cycle = graph.cycle().expect("a -> b -> c -> a");
        assert_eq!(cycle.members, ["a.rs", "b/", "c.rs"]);
        assert_eq!(
            cycle.to_string(),
            "a.rs -> b/ -> c.rs -> a.rs (a.rs uses b/mod.rs; b/inner.rs uses c.rs; c.rs uses a.rs)"
        );
    }

    #[test]
    fn comments_strings_and_char_literals_are_not_code() {
        let graph = graph(&[
            ("a.rs", "// crate::b\n/* crate::b /* nested */ crate::b */ const S: &str = \"crate::b\"; const R: &str = r#\"crate::b \"# ; const C: char = '\"'; const Q: char = '\\''; fn f<'x>() { crate::c::g() }"),
            ("b.rs", "use crate::a::S;"),
            ("c.rs", ""),
        ]);
        assert_eq!(targets(&graph, "a.rs"), ["c.rs"]);
        assert_eq!(graph.cycle(), None);
    }

    #[test]
    fn names_every_file_of_a_tangle() {
        let graph = graph(&[
            ("a.rs", "use crate::b::X;"),
            ("b.rs", "use crate::{a::Y, c::Z};"),
            ("c.rs", "use crate::a::W;"),
        ]);
        let cycle = graph.cycle().expect("a circle");
        assert_eq!(cycle.members, ["a.rs", "b.rs"]);
        assert_eq!(cycle.tangled, ["a.rs", "b.rs", "c.rs"]);
        assert_eq!(
            cycle.to_string(),
            "a.rs -> b.rs -> a.rs (tangled together: a.rs, b.rs, c.rs)"
        );
    }

    #[test]
    fn finds_a_circle_between_two_files_of_one_folder() {
        let graph = graph(&[
            ("lib.rs", "mod drive;"),
            (
                "drive/mod.rs",
                "mod pages; mod respond; pub use respond::Outcome;",
            ),
            ("drive/pages.rs", "use super::Outcome;"),
            (
                "drive/respond.rs",
                "pub enum Outcome {} fn f() { super::pages::Paged::Plain; }",
            ),
        ]);
        assert_eq!(
            targets(&graph, "drive/pages.rs"),
            ["drive/respond.rs"],
            "a name the face re-exports leads to the file it comes from"
        );
        let cycle = graph.cycle().expect("pages <-> respond");
        assert_eq!(
            cycle.to_string(),
            "drive/pages.rs -> drive/respond.rs -> drive/pages.rs"
        );
    }

    #[test]
    fn a_face_calling_its_files_and_its_files_using_the_face_is_no_circle() {
        let graph = graph(&[
            ("lib.rs", "mod protocols; pub use protocols::lower;"),
            (
                "protocols/mod.rs",
                "mod commands; mod test_support; pub struct Input; \
                 pub fn lower() { commands::lower_commands(); }",
            ),
            (
                "protocols/commands.rs",
                "use super::Input; pub fn lower_commands() {} \
                 #[cfg(test)] mod tests { use super::*; use super::super::test_support::at; }",
            ),
            (
                "protocols/test_support.rs",
                "use super::lower; pub fn at() {}",
            ),
        ]);
        assert_eq!(
            targets(&graph, "protocols/commands.rs"),
            ["protocols/mod.rs", "protocols/test_support.rs"],
            "`super` in an inline test module is the file itself, `super::super` its folder"
        );
        assert_eq!(
            targets(&graph, "protocols/mod.rs"),
            ["protocols/commands.rs"]
        );
        assert_eq!(graph.cycle(), None);
    }

    #[test]
    fn a_circle_across_folders_is_found_at_the_level_where_it_closes() {
        let graph = graph(&[
            ("lib.rs", "mod a; mod b;"),
            ("a/mod.rs", "mod x; mod z;"),
            ("a/x.rs", "fn f() { crate::b::y::g(); }"),
            ("a/z.rs", "use super::x::X;"),
            ("b/mod.rs", "pub mod y;"),
            ("b/y.rs", "use crate::a::z::Z;"),
        ]);
        let cycles = graph.cycles();
        assert_eq!(cycles.len(), 1, "{cycles:?}");
        assert_eq!(
            cycles[0].to_string(),
            "a/ -> b/ -> a/ (a/x.rs uses b/y.rs; b/y.rs uses a/z.rs)"
        );
    }

    #[test]
    fn relative_paths_from_a_face_and_macros_count() {
        let graph = graph(&[
            ("main.rs", "mod out; mod sim; pub struct Failure;"),
            (
                "out.rs",
                "macro_rules! say { () => { $crate::out::print_line() }; } pub(crate) use say;",
            ),
            (
                "sim.rs",
                "use crate::{out::say, Failure}; fn f() -> Result<(), Failure> { say!(); Ok(()) }",
            ),
        ]);
        assert_eq!(targets(&graph, "sim.rs"), ["main.rs", "out.rs"]);
        assert!(targets(&graph, "out.rs").is_empty());
        assert_eq!(graph.cycle(), None);
    }
}
