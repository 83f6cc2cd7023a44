//! Circles, folder by folder: inside each folder of a crate, its files and subfolders (a
//! subfolder counting as one, everything in it together) must not refer to each other in
//! a circle. A folder's face (`mod.rs`, `name.rs` beside `name/`, the crate root for `src/`)
//! refers down into its folder without that counting.

use std::collections::{BTreeMap, BTreeSet, VecDeque};
use std::fmt;

/// A circle of files or folders inside one folder: each refers to the next, the last to
/// the first.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Cycle {
    /// The files (`virtual_drive/pages.rs`) and folders (`parse/`) in order, starting with
    /// the alphabetically first.
    pub members: Vec<String>,
    /// For each step, a file reference that makes it (`from`, `to`): the step from
    /// `members[i]` to the next.
    pub because: Vec<(String, String)>,
    /// Every member of the tangle this circle is part of (its strongly connected
    /// component), sorted.
    pub tangled: Vec<String>,
}

impl fmt::Display for Cycle {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} -> {}", self.members.join(" -> "), self.members[0])?;
        if self.members.iter().any(|m| m.ends_with('/')) {
            let steps: Vec<String> = self
                .because
                .iter()
                .map(|(from, to)| format!("{from} uses {to}"))
                .collect();
            write!(f, " ({})", steps.join("; "))?;
        }
        if self.tangled.len() > self.members.len() {
            write!(f, " (tangled together: {})", self.tangled.join(", "))?;
        }
        Ok(())
    }
}

/// The circles of a crate whose files (paths relative to `src`) refer to each other as
/// `references` says: at most one per tangle, folder by folder (the crate's top first).
pub fn cycles(references: &BTreeMap<String, BTreeSet<String>>) -> Vec<Cycle> {
    let files: BTreeSet<&str> = references
        .iter()
        .flat_map(|(from, to)| std::iter::once(from).chain(to))
        .map(String::as_str)
        .collect();
    let mut folders: BTreeSet<String> = BTreeSet::from([String::new()]);
    for file in &files {
        let mut folder = String::new();
        let parts: Vec<&str> = file.split('/').collect();
        for part in &parts[..parts.len() - 1] {
            folder.push_str(part);
            folder.push('/');
            folders.insert(folder.clone());
        }
    }
    let mut found = Vec::new();
    for folder in &folders {
        let face = face_of(folder, &files);
        let member = |file: &str| member_of(folder, face.as_deref(), &folders, file);
        let mut units = Units::default();
        for (from, targets) in references {
            let Some(from_unit) = member(from) else {
                continue;
            };
            units.edges.entry(from_unit.clone()).or_default();
            for to in targets {
                let Some(to_unit) = member(to) else { continue };
                let downward = face.as_deref() == Some(from.as_str()) && from_unit != to_unit;
                if from_unit == to_unit || downward {
                    continue;
                }
                units
                    .because
                    .entry((from_unit.clone(), to_unit.clone()))
                    .or_insert_with(|| (from.clone(), to.clone()));
                units
                    .edges
                    .entry(from_unit.clone())
                    .or_default()
                    .insert(to_unit);
            }
        }
        found.extend(units.cycles());
    }
    found
}

/// The face of `folder`: its `mod.rs`, else `name.rs` beside it, else (the crate's top)
/// `lib.rs` or `main.rs`.
fn face_of(folder: &str, files: &BTreeSet<&str>) -> Option<String> {
    let candidates = if folder.is_empty() {
        vec!["lib.rs".to_owned(), "main.rs".to_owned()]
    } else {
        vec![
            format!("{folder}mod.rs"),
            format!("{}.rs", folder.trim_end_matches('/')),
        ]
    };
    candidates.into_iter().find(|c| files.contains(c.as_str()))
}

/// What `file` counts as inside `folder`: itself (a file of the folder, or its face), or
/// the subfolder it is in (`parse/`, also for `parse.rs` beside `parse/`); `None` when it is
/// outside.
fn member_of(
    folder: &str,
    face: Option<&str>,
    folders: &BTreeSet<String>,
    file: &str,
) -> Option<String> {
    if face == Some(file) {
        return Some(file.to_owned());
    }
    let rest = file.strip_prefix(folder)?;
    if let Some((sub, _)) = rest.split_once('/') {
        return Some(format!("{folder}{sub}/"));
    }
    let beside = format!("{folder}{}/", rest.strip_suffix(".rs").unwrap_or(rest));
    Some(if folders.contains(&beside) {
        beside
    } else {
        file.to_owned()
    })
}

/// The members of one folder and their references.
#[derive(Default)]
struct Units {
    edges: BTreeMap<String, BTreeSet<String>>,
    because: BTreeMap<(String, String), (String, String)>,
}

impl Units {
    /// One circle per tangle, each the shortest way back to its alphabetically first member.
    fn cycles(&self) -> Vec<Cycle> {
        let mut cycles = Vec::new();
        for tangled in self.tangled_components() {
            let members: BTreeSet<&str> = tangled.iter().map(String::as_str).collect();
            let start = tangled[0].as_str();
            let mut previous: BTreeMap<&str, &str> = BTreeMap::new();
            let mut queue = VecDeque::from([start]);
            'search: while let Some(node) = queue.pop_front() {
                for next in self.targets(node).filter(|n| members.contains(n)) {
                    if next == start {
                        let mut path = vec![node.to_owned()];
                        let mut at = node;
                        while at != start {
                            at = previous[at];
                            path.push(at.to_owned());
                        }
                        path.reverse();
                        let because = (0..path.len())
                            .map(|i| {
                                let key = (path[i].clone(), path[(i + 1) % path.len()].clone());
                                self.because[&key].clone()
                            })
                            .collect();
                        cycles.push(Cycle {
                            members: path,
                            because,
                            tangled: tangled.clone(),
                        });
                        break 'search;
                    }
                    if !previous.contains_key(next) && next != start {
                        previous.insert(next, node);
                        queue.push_back(next);
                    }
                }
            }
        }
        cycles
    }

    fn targets<'a>(&'a self, unit: &str) -> impl Iterator<Item = &'a str> {
        self.edges
            .get(unit)
            .into_iter()
            .flatten()
            .map(String::as_str)
    }

    /// Strongly connected components of two or more members (Tarjan), each sorted, in
    /// order of their first member.
    fn tangled_components(&self) -> Vec<Vec<String>> {
        struct State<'g> {
            units: &'g Units,
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
            let units = state.units;
            for next in units.targets(node) {
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
            units: self,
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
