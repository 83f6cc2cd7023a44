//! Which files of a crate each file refers to: every path in a `use` item or in code
//! (`crate::`, `super::`, `self::`, or starting with a module declared where it stands),
//! resolved through the crate's modules and its `use` items to the file that holds the item.

use super::source::{strip_comments_and_literals, tokens, Token};
use std::collections::{BTreeMap, BTreeSet};

/// A path as written, with the module it is written in.
#[derive(Debug, Clone)]
struct Written {
    /// The module the path stands in (file modules, then inline `mod name { }` ones).
    module: Vec<String>,
    /// Its segments (`crate`, `super`, `self` included; a glob ends in `*`).
    segments: Vec<String>,
}

/// What one file says: the paths it writes, the inline modules it opens, and the names its
/// `use` items bring into each of its modules.
#[derive(Debug, Default)]
struct Scanned {
    paths: Vec<Written>,
    inline_modules: Vec<Vec<String>>,
    /// `(module, name)` to the path the name stands for.
    imports: Vec<((Vec<String>, String), Written)>,
}

/// The crate's modules and names, to resolve paths against.
struct Crate {
    /// Module path to the file that holds it (inline modules: the file they are written in).
    modules: BTreeMap<Vec<String>, String>,
    /// `(module, name)` to the path a `use` item makes the name stand for.
    imports: BTreeMap<(Vec<String>, String), Written>,
}

/// The module a file is: `lib.rs` and `main.rs` are the crate root, `a/mod.rs` and `a.rs`
/// are `a`, `a/b.rs` is `a::b`.
pub fn module_of_file(file: &str) -> Vec<String> {
    let mut parts: Vec<String> = file.split('/').map(str::to_owned).collect();
    let last = parts.pop().unwrap_or_default();
    let stem = last.strip_suffix(".rs").unwrap_or(&last);
    let is_root = parts.is_empty() && (stem == "lib" || stem == "main");
    if stem != "mod" && !is_root {
        parts.push(stem.to_owned());
    }
    parts
}

/// For each file (path relative to `src`, with `/`), the other files it refers to.
pub fn file_references(files: &[(String, String)]) -> BTreeMap<String, BTreeSet<String>> {
    let mut krate = Crate {
        modules: BTreeMap::new(),
        imports: BTreeMap::new(),
    };
    for (file, _) in files {
        krate.modules.insert(module_of_file(file), file.clone());
    }
    let mut scanned = Vec::new();
    for (file, text) in files {
        let found = scan(&module_of_file(file), &strip_comments_and_literals(text));
        for inline in &found.inline_modules {
            krate
                .modules
                .entry(inline.clone())
                .or_insert_with(|| file.clone());
        }
        scanned.push((file, found));
    }
    for (_, found) in &mut scanned {
        for (key, target) in std::mem::take(&mut found.imports) {
            krate.imports.entry(key).or_insert(target);
        }
    }
    let mut references = BTreeMap::new();
    for (file, found) in &scanned {
        let targets: &mut BTreeSet<String> = references.entry((*file).clone()).or_default();
        for path in &found.paths {
            let Some(module) = krate.resolve(&path.module, &path.segments, 0) else {
                continue;
            };
            let Some(target) = krate.file_of(&module) else {
                continue;
            };
            if target != *file {
                targets.insert(target.to_owned());
            }
        }
    }
    references
}

impl Crate {
    /// The module where the item `segments` names (seen from `module`) is defined, following
    /// `use` items; `None` for paths outside the crate (`std::`, other crates, local names).
    fn resolve(&self, module: &[String], segments: &[String], depth: usize) -> Option<Vec<String>> {
        let first = segments.first()?;
        let (mut at, rest) = match first.as_str() {
            "crate" => (Vec::new(), &segments[1..]),
            "self" => (module.to_vec(), &segments[1..]),
            "super" => {
                let mut at = module.to_vec();
                let ups = segments.iter().take_while(|s| *s == "super").count();
                for _ in 0..ups {
                    at.pop()?;
                }
                (at, &segments[ups..])
            }
            name => {
                let mut child = module.to_vec();
                child.push(name.to_owned());
                if self.modules.contains_key(&child) {
                    (module.to_vec(), segments)
                } else {
                    // A name a `use` item brought in: its own `use` is the reference.
                    return None;
                }
            }
        };
        for segment in rest {
            if segment == "*" || segment == "self" {
                break;
            }
            let mut child = at.clone();
            child.push(segment.clone());
            if self.modules.contains_key(&child) {
                at = child;
                continue;
            }
            if depth < 16 {
                if let Some(target) = self.imports.get(&(at.clone(), segment.clone())) {
                    // Re-exported or imported here: the item lives where that path leads
                    // (nowhere in this crate when it leads outside).
                    // (`pub(crate) use say;` of a local macro: the item is right here).
                    if let [local] = target.segments.as_slice() {
                        if !self
                            .modules
                            .contains_key(&[target.module.clone(), vec![local.clone()]].concat())
                        {
                            return Some(target.module.clone());
                        }
                    }
                    return self.resolve(&target.module, &target.segments, depth + 1);
                }
            }
            return Some(at);
        }
        Some(at)
    }

    /// The file that holds `module` (the file of its longest known prefix).
    fn file_of(&self, module: &[String]) -> Option<&str> {
        (0..=module.len())
            .rev()
            .find_map(|len| self.modules.get(&module[..len]))
            .map(String::as_str)
    }
}

/// Reads the paths, inline modules and imports of one file's stripped code.
fn scan(file_module: &[String], code: &str) -> Scanned {
    let tokens = tokens(code);
    let mut found = Scanned::default();
    // One entry per open brace: the inline module it opens, if it does.
    let mut braces: Vec<Option<String>> = Vec::new();
    let mut i = 0;
    while i < tokens.len() {
        let module: Vec<String> = file_module
            .iter()
            .cloned()
            .chain(braces.iter().flatten().cloned())
            .collect();
        match &tokens[i] {
            Token::Ident(word) if word == "mod" => {
                if let (Some(Token::Ident(name)), Some(Token::Punct('{'))) =
                    (tokens.get(i + 1), tokens.get(i + 2))
                {
                    let mut inline = module.clone();
                    inline.push(name.clone());
                    found.inline_modules.push(inline);
                    braces.push(Some(name.clone()));
                    i += 3;
                    continue;
                }
                i += 1;
            }
            Token::Ident(word) if word == "use" => {
                i = use_tree(&tokens, i + 1, &[], &module, &mut found);
                while i < tokens.len() && tokens[i] != Token::Punct(';') {
                    i += 1;
                }
            }
            Token::Ident(_) if i == 0 || tokens[i - 1] != Token::PathSep => {
                let (segments, end) = path_segments(&tokens, i);
                if segments.len() > 1 {
                    found.paths.push(Written { module, segments });
                }
                i = end.max(i + 1);
            }
            Token::Punct('{') => {
                braces.push(None);
                i += 1;
            }
            Token::Punct('}') => {
                braces.pop();
                i += 1;
            }
            _ => i += 1,
        }
    }
    found
}

/// `a::b::c` starting at `start`: its segments and the index after it.
fn path_segments(tokens: &[Token], start: usize) -> (Vec<String>, usize) {
    let mut segments = Vec::new();
    let mut i = start;
    while let Some(Token::Ident(name)) = tokens.get(i) {
        segments.push(name.clone());
        if tokens.get(i + 1) == Some(&Token::PathSep)
            && matches!(tokens.get(i + 2), Some(Token::Ident(_)))
        {
            i += 2;
        } else {
            i += 1;
            break;
        }
    }
    (segments, i)
}

/// Reads one use tree (`a::b`, `a::{b, c::d as e}`, `a::*`) after `prefix`, recording each
/// leaf as a path and as an import of its name; returns the index after the tree.
fn use_tree(
    tokens: &[Token],
    start: usize,
    prefix: &[String],
    module: &[String],
    found: &mut Scanned,
) -> usize {
    let mut i = start;
    if tokens.get(i) == Some(&Token::PathSep) {
        i += 1;
    }
    let (segments, end) = path_segments(tokens, i);
    i = end;
    let mut full: Vec<String> = prefix.iter().cloned().chain(segments).collect();
    let record = |full: Vec<String>, name: Option<String>, found: &mut Scanned| {
        let written = Written {
            module: module.to_vec(),
            segments: full,
        };
        if let Some(name) = name.filter(|n| n != "_") {
            found
                .imports
                .push(((module.to_vec(), name), written.clone()));
        }
        found.paths.push(written);
    };
    if tokens.get(i) == Some(&Token::PathSep) || tokens.get(i) == Some(&Token::Punct('{')) {
        if tokens.get(i) == Some(&Token::PathSep) {
            i += 1;
        }
        match tokens.get(i) {
            Some(Token::Punct('{')) => {
                i += 1;
                while i < tokens.len() && tokens[i] != Token::Punct('}') {
                    if tokens[i] == Token::Punct(',') {
                        i += 1;
                        continue;
                    }
                    let before = i;
                    i = use_tree(tokens, i, &full, module, found);
                    if i == before {
                        i += 1;
                    }
                }
                return i + 1;
            }
            Some(Token::Punct('*')) => {
                full.push("*".to_owned());
                record(full, None, found);
                return i + 1;
            }
            _ => {}
        }
    }
    if full.is_empty() {
        return i;
    }
    let mut name = full.last().cloned();
    if full.last().is_some_and(|last| last == "self") {
        full.pop();
        name = full.last().cloned();
    }
    if tokens.get(i).is_some_and(|t| t.is("as")) {
        if let Some(Token::Ident(alias)) = tokens.get(i + 1) {
            name = Some(alias.clone());
        }
        i += 2;
    }
    record(full, name, found);
    i
}
