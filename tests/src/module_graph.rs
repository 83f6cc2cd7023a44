//! The graph of `crate::` references between a crate's modules, to keep it free of
//! circles: a module may use the modules below it, never one that (through others) uses it.
//!
//! A module is a top-level module of the crate: `src/codec.rs`, or everything under
//! `src/parse/` (`parse/mod.rs`, `parse/yaml.rs`, ...). An edge `a -> b` is any
//! `crate::b` path in `a`'s files, in `use` items (grouped ones too: `use crate::{b::X, c}`)
//! or inline (`crate::b::f()`, `$crate::b` in macros), test modules included; comments and
//! string literals do not count. A path to an item the crate root re-exports
//! (`crate::Protocol`, from `pub use protocol::{..., Protocol}` in `lib.rs`) counts as an
//! edge to the module it comes from. The crate root itself (`lib.rs`, `main.rs`) is not a
//! node: it declares and re-exports everything. `super::` paths are not followed, and files
//! under `src/bin/` are separate crates and are skipped.

use std::collections::{BTreeMap, BTreeSet};
use std::fmt;
use std::path::{Path, PathBuf};

/// Module-to-module edges of one crate.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct ModuleGraph {
    /// For each module, the modules it references (never itself).
    pub edges: BTreeMap<String, BTreeSet<String>>,
}

/// A circle of modules: each uses the next, and the last uses the first.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Cycle {
    /// The modules in order, starting with the alphabetically first.
    pub modules: Vec<String>,
    /// Every module that is part of some circle with these (their strongly connected
    /// component), sorted.
    pub tangled: Vec<String>,
}

impl fmt::Display for Cycle {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let mut path = self.modules.join(" -> ");
        path.push_str(" -> ");
        path.push_str(&self.modules[0]);
        write!(f, "{path}")?;
        if self.tangled.len() > self.modules.len() {
            write!(f, " (tangled together: {})", self.tangled.join(", "))?;
        }
        Ok(())
    }
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
        let files: Vec<(Option<String>, String)> = files
            .into_iter()
            .filter(|(path, _)| !path.starts_with("bin"))
            .map(|(path, text)| (module_of(path), strip_comments_and_literals(text)))
            .collect();
        let modules: BTreeSet<String> = files.iter().filter_map(|(m, _)| m.clone()).collect();
        let mut reexported = BTreeMap::new();
        for (_, code) in files.iter().filter(|(module, _)| module.is_none()) {
            root_reexports(code, &modules, &mut reexported);
        }
        let mut graph = ModuleGraph::default();
        for (module, code) in &files {
            let Some(module) = module else { continue };
            let targets = graph.edges.entry(module.clone()).or_default();
            for name in crate_path_heads(code) {
                let target = if modules.contains(&name) {
                    Some(&name)
                } else {
                    reexported.get(&name)
                };
                if let Some(target) = target.filter(|t| *t != module) {
                    targets.insert(target.clone());
                }
            }
        }
        graph
    }

    /// A circle in the graph, if there is one: the first found, starting from the
    /// alphabetically first module that is part of one.
    pub fn cycle(&self) -> Option<Cycle> {
        let components = self.tangled_components();
        let tangled = components.into_iter().next()?;
        let members: BTreeSet<&str> = tangled.iter().map(String::as_str).collect();
        // Shortest way back to the start through the component (breadth first).
        let start = tangled[0].as_str();
        let mut previous: BTreeMap<&str, &str> = BTreeMap::new();
        let mut queue = std::collections::VecDeque::from([start]);
        while let Some(node) = queue.pop_front() {
            for next in self.targets(node).filter(|n| members.contains(n)) {
                if next == start {
                    let mut modules = vec![node.to_owned()];
                    let mut at = node;
                    while at != start {
                        at = previous[at];
                        modules.push(at.to_owned());
                    }
                    modules.reverse();
                    return Some(Cycle { modules, tangled });
                }
                if !previous.contains_key(next) && next != start {
                    previous.insert(next, node);
                    queue.push_back(next);
                }
            }
        }
        unreachable!("a strongly connected component of two or more modules has a cycle")
    }

    fn targets<'a>(&'a self, module: &str) -> impl Iterator<Item = &'a str> {
        self.edges
            .get(module)
            .into_iter()
            .flatten()
            .map(String::as_str)
    }

    /// Strongly connected components of two or more modules (Tarjan), each sorted,
    /// in order of their first module.
    fn tangled_components(&self) -> Vec<Vec<String>> {
        struct State<'g> {
            graph: &'g ModuleGraph,
            next_index: usize,
            index: BTreeMap<&'g str, usize>,
            low: BTreeMap<&'g str, usize>,
            stack: Vec<&'g str>,
            on_stack: BTreeSet<&'g str>,
            components: Vec<Vec<String>>,
        }
        fn visit<'g>(state: &mut State<'g>, node: &'g str) {
            state.index.insert(node, state.next_index);
            state.low.insert(node, state.next_index);
            state.next_index += 1;
            state.stack.push(node);
            state.on_stack.insert(node);
            let graph = state.graph;
            for next in graph.targets(node) {
                if !state.index.contains_key(next) {
                    visit(state, next);
                    let low = state.low[node].min(state.low[next]);
                    state.low.insert(node, low);
                } else if state.on_stack.contains(next) {
                    let low = state.low[node].min(state.index[next]);
                    state.low.insert(node, low);
                }
            }
            if state.low[node] == state.index[node] {
                let mut component = Vec::new();
                loop {
                    let member = state.stack.pop().expect("node is on the stack");
                    state.on_stack.remove(member);
                    component.push(member.to_owned());
                    if member == node {
                        break;
                    }
                }
                if component.len() > 1 {
                    component.sort();
                    state.components.push(component);
                }
            }
        }
        let mut state = State {
            graph: self,
            next_index: 0,
            index: BTreeMap::new(),
            low: BTreeMap::new(),
            stack: Vec::new(),
            on_stack: BTreeSet::new(),
            components: Vec::new(),
        };
        for node in self.edges.keys() {
            if !state.index.contains_key(node.as_str()) {
                visit(&mut state, node);
            }
        }
        let mut components = state.components;
        components.sort();
        components
    }
}

/// Panics naming a circle when the crate whose sources are in `src` has one.
#[track_caller]
pub fn assert_no_module_cycle(src: &Path) {
    let graph = ModuleGraph::of_folder(src)
        .unwrap_or_else(|error| panic!("cannot read {}: {error}", src.display()));
    assert!(
        !graph.edges.is_empty(),
        "no modules found under {}",
        src.display()
    );
    if let Some(cycle) = graph.cycle() {
        let edges: Vec<String> = graph
            .edges
            .iter()
            .map(|(from, to)| {
                let to: Vec<&str> = to.iter().map(String::as_str).collect();
                format!("  {from} -> {}", to.join(", "))
            })
            .collect();
        panic!(
            "the modules of {} use each other in a circle: {cycle}\nall edges:\n{}",
            src.display(),
            edges.join("\n")
        );
    }
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

/// `codec.rs` -> `codec`, `parse/yaml.rs` -> `parse`; `None` for the crate root.
fn module_of(relative: &Path) -> Option<String> {
    let mut components = relative.components();
    let first = components.next()?.as_os_str().to_str()?;
    if components.next().is_some() {
        return Some(first.to_owned());
    }
    let stem = first.strip_suffix(".rs")?;
    (stem != "lib" && stem != "main").then(|| stem.to_owned())
}

/// Names the crate root's `pub use module::...` items bring to the root, mapped to their module.
fn root_reexports(code: &str, modules: &BTreeSet<String>, out: &mut BTreeMap<String, String>) {
    let mut rest = code;
    while let Some(at) = find_word(rest, "use") {
        let statement_end = rest[at..].find(';').map_or(rest.len(), |end| at + end);
        let statement = &rest[at + 3..statement_end];
        rest = &rest[statement_end.min(rest.len())..];
        let path = statement.trim_start();
        let path = path
            .strip_prefix("crate")
            .map_or(path, |p| p.trim_start().strip_prefix("::").unwrap_or(p));
        let Some(module) = identifiers(path).next() else {
            continue;
        };
        if !modules.contains(module) {
            continue;
        }
        // `pub use protocol::{Protocol, Request as Req}`: every identifier after the module
        // may name an item the root now has (aliases included; extra names are harmless).
        for name in identifiers(path).skip(1) {
            out.entry(name.to_owned())
                .or_insert_with(|| module.to_owned());
        }
    }
}

/// The first segment of every `crate::` path: `crate::a::X` gives `a`, and
/// `crate::{a::X, b}` gives `a` and `b`.
fn crate_path_heads(code: &str) -> Vec<String> {
    let mut heads = Vec::new();
    let mut rest = code;
    while let Some(at) = find_word(rest, "crate") {
        rest = &rest[at + "crate".len()..];
        let Some(after) = rest.trim_start().strip_prefix("::") else {
            continue;
        };
        let after = after.trim_start();
        if let Some(group) = after.strip_prefix('{') {
            // Top-level items of the group: the identifier starting each.
            let mut depth = 0usize;
            let mut expect_head = true;
            for (offset, ch) in group.char_indices() {
                match ch {
                    '{' => depth += 1,
                    '}' if depth == 0 => break,
                    '}' => depth -= 1,
                    ',' if depth == 0 => expect_head = true,
                    c if expect_head && depth == 0 && is_ident_start(c) => {
                        expect_head = false;
                        if let Some(name) = identifiers(&group[offset..]).next() {
                            heads.push(name.to_owned());
                        }
                    }
                    _ => {}
                }
            }
        } else if let Some(name) = identifiers(after).next() {
            if after.starts_with(name) {
                heads.push(name.to_owned());
            }
        }
    }
    heads
}

fn is_ident_start(c: char) -> bool {
    c.is_alphabetic() || c == '_'
}

fn is_ident_char(c: char) -> bool {
    c.is_alphanumeric() || c == '_'
}

/// Offset of the next occurrence of `word` as a whole word.
fn find_word(text: &str, word: &str) -> Option<usize> {
    let mut from = 0;
    while let Some(found) = text[from..].find(word) {
        let at = from + found;
        let before = text[..at].chars().next_back();
        let after = text[at + word.len()..].chars().next();
        if !before.is_some_and(is_ident_char) && !after.is_some_and(is_ident_char) {
            return Some(at);
        }
        from = at + word.len();
    }
    None
}

/// The identifiers in `text`, in order (keywords included).
fn identifiers(text: &str) -> impl Iterator<Item = &str> {
    text.split(|c: char| !is_ident_char(c))
        .filter(|word| word.chars().next().is_some_and(is_ident_start))
}

/// The source with comments, string literals and character literals blanked out (each
/// replaced by a space), so that paths inside them are not taken for code.
pub fn strip_comments_and_literals(source: &str) -> String {
    let chars: Vec<char> = source.chars().collect();
    let mut out = String::with_capacity(source.len());
    let mut i = 0;
    while i < chars.len() {
        let c = chars[i];
        let next = chars.get(i + 1).copied();
        if c == '/' && next == Some('/') {
            while i < chars.len() && chars[i] != '\n' {
                i += 1;
            }
            out.push(' ');
        } else if c == '/' && next == Some('*') {
            let mut depth = 0usize;
            while i < chars.len() {
                if chars[i] == '/' && chars.get(i + 1) == Some(&'*') {
                    depth += 1;
                    i += 2;
                } else if chars[i] == '*' && chars.get(i + 1) == Some(&'/') {
                    depth -= 1;
                    i += 2;
                    if depth == 0 {
                        break;
                    }
                } else {
                    i += 1;
                }
            }
            out.push(' ');
        } else if let Some(end) = raw_string_end(&chars, i) {
            i = end;
            out.push(' ');
        } else if c == '"' {
            i += 1;
            while i < chars.len() && chars[i] != '"' {
                i += if chars[i] == '\\' { 2 } else { 1 };
            }
            i += 1;
            out.push(' ');
        } else if c == '\'' {
            // A character literal ('x', '\n', '\u{1F600}') or a lifetime ('a, 'static).
            if next == Some('\\') {
                // Skip the quote, the backslash and the escaped character.
                i += 3;
                while i < chars.len() && chars[i] != '\'' {
                    i += 1;
                }
                i += 1;
                out.push(' ');
            } else if chars.get(i + 2) == Some(&'\'') {
                i += 3;
                out.push(' ');
            } else {
                out.push(c);
                i += 1;
            }
        } else {
            out.push(c);
            i += 1;
        }
    }
    out
}

/// When `chars[start..]` opens a raw string (`r"`, `r#"`, `br#"`), the index after its end.
fn raw_string_end(chars: &[char], start: usize) -> Option<usize> {
    if start > 0 && is_ident_char(chars[start - 1]) {
        return None;
    }
    let mut i = start;
    if chars.get(i) == Some(&'b') {
        i += 1;
    }
    if chars.get(i) != Some(&'r') {
        return None;
    }
    i += 1;
    let mut hashes = 0;
    while chars.get(i) == Some(&'#') {
        hashes += 1;
        i += 1;
    }
    if chars.get(i) != Some(&'"') {
        return None;
    }
    i += 1;
    while i < chars.len() {
        if chars[i] == '"' && (1..=hashes).all(|k| chars.get(i + k) == Some(&'#')) {
            return Some(i + 1 + hashes);
        }
        i += 1;
    }
    Some(chars.len())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn graph(files: &[(&str, &str)]) -> ModuleGraph {
        ModuleGraph::of_sources(files.iter().map(|(path, text)| (Path::new(*path), *text)))
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
            ("c.rs", "fn f() { let _ = crate::a::X; }"),
        ]);
        assert_eq!(
            graph.edges["a"].iter().collect::<Vec<_>>(),
            ["b"],
            "self references and unknown names are no edges"
        );
        assert_eq!(graph.edges["b"].iter().collect::<Vec<_>>(), ["c"]);
        let cycle = graph.cycle().expect("a -> b -> c -> a");
        assert_eq!(cycle.modules, ["a", "b", "c"]);
        assert_eq!(cycle.to_string(), "a -> b -> c -> a");
    }

    #[test]
    fn comments_strings_and_char_literals_are_not_code() {
        let graph = graph(&[
            ("a.rs", "// crate::b\n/* crate::b /* nested */ crate::b */ const S: &str = \"crate::b\"; const R: &str = r#\"crate::b \"# ; const C: char = '\"'; const Q: char = '\\''; fn f<'x>() { crate::c::g() }"),
            ("b.rs", "use crate::a::S;"),
            ("c.rs", ""),
        ]);
        assert_eq!(graph.edges["a"].iter().collect::<Vec<_>>(), ["c"]);
        assert_eq!(graph.cycle(), None);
    }

    #[test]
    fn names_every_module_of_a_tangle() {
        let graph = graph(&[
            ("a.rs", "use crate::b::X;"),
            ("b.rs", "use crate::{a::Y, c::Z};"),
            ("c.rs", "use crate::a::W;"),
        ]);
        let cycle = graph.cycle().expect("a circle");
        assert_eq!(cycle.modules, ["a", "b"]);
        assert_eq!(cycle.tangled, ["a", "b", "c"]);
        assert_eq!(cycle.to_string(), "a -> b -> a (tangled together: a, b, c)");
    }
}
