//! A protocol file built on another (`based_on:`): the base's parts, layouts, commands,
//! error reply and error codes, with the changes the file states (parts put before and
//! after every layout, parts replaced), merged into one [`ProtocolFile`] before lowering.
//! Problems the lowering finds in what came from the base are moved back to the base
//! file's positions ([`Inherited::relocate`]).

use crate::diagnostics::{Diagnostic, Diagnostics};
use crate::parse::model::{PartRefModel, ProtocolFile};
use crate::parse::tree::{segments, Segment};
use crate::parse::SourceFile;
use std::collections::{BTreeMap, BTreeSet};
use std::path::PathBuf;

/// What a merged protocol file took from its base, to place diagnostics in the right file.
#[derive(Debug, Clone)]
pub(crate) struct Inherited {
    /// The base file.
    pub source: SourceFile,
    /// Parts put before every inherited layout.
    pub prepend: usize,
    /// The inherited layouts and their length in the base.
    pub layouts: BTreeMap<String, usize>,
    /// The parts defined by the base only.
    pub parts: BTreeSet<String>,
    /// Whether the commands, error reply and error codes came from the base.
    pub commands: bool,
    /// See `commands`.
    pub error_reply: bool,
    /// See `commands`.
    pub error_codes: bool,
}

/// A protocol file after `based_on` was applied.
pub(crate) struct Merged {
    /// The whole protocol, base and changes.
    pub file: ProtocolFile,
    /// What came from the base, when there is one.
    pub inherited: Option<Inherited>,
}

/// Applies the file's `based_on` (reading the base from `shelf`), or checks that a file
/// without one lists its own layouts and commands. Problems go to `out`; files read are
/// added to `sources`, elements holding placeholders to `incomplete`. `None` when the
/// protocol cannot be built.
pub(crate) fn merge(
    source: &SourceFile,
    mut file: ProtocolFile,
    shelf: &super::Shelf,
    out: &mut Diagnostics,
    sources: &mut Vec<SourceFile>,
    incomplete: &mut Vec<(PathBuf, String)>,
) -> Option<Merged> {
    let Some(based_on) = file.based_on.clone() else {
        let mut complete = true;
        for (key, empty) in [
            ("layouts", file.layouts.is_empty()),
            ("commands", file.commands.is_empty()),
        ] {
            if empty {
                complete = false;
                out.push(
                    source
                        .error(key, format!("the protocol file has no `{key}`"))
                        .hint(format!(
                            "list its {key}, or take another protocol file's with `based_on:`"
                        )),
                );
            }
        }
        return complete.then_some(Merged {
            file,
            inherited: None,
        });
    };
    let base_id = &based_on.protocol;
    if *base_id == file.protocol.id {
        out.push(
            source
                .error(
                    "based_on.protocol",
                    "a protocol file cannot be based on itself",
                )
                .hint("name the protocol file whose layouts this one changes"),
        );
        return None;
    }
    let base_source = match shelf.read(base_id) {
        Ok(base_source) => base_source,
        Err(path) => {
            out.push(
                source
                    .error(
                        "based_on.protocol",
                        format!(
                            "no protocol file `{base_id}` to be based on ({} does not exist)",
                            path.display()
                        ),
                    )
                    .hint(format!(
                        "a base is looked up in {}; available: {}",
                        shelf.describe(),
                        shelf.available()
                    )),
            );
            return None;
        }
    };
    if !sources.iter().any(|s| s.path == base_source.path) {
        sources.push(base_source.clone());
    }
    let read = base_source.read_model::<ProtocolFile>();
    let before = out.items.len();
    read.problems
        .into_iter()
        .for_each(|problem| out.push(problem));
    incomplete.extend(
        read.incomplete
            .into_iter()
            .map(|path| (base_source.path.clone(), path)),
    );
    let base = read.value?;
    if out.items.len() > before {
        return None;
    }
    if let Some(further) = &base.based_on {
        out.push(
            source
                .error(
                    "based_on.protocol",
                    format!(
                        "`{base_id}` is itself based on `{}`; a base must list its own layouts",
                        further.protocol
                    ),
                )
                .hint(format!("base this file on `{}` directly", further.protocol)),
        );
        return None;
    }
    let mut problems = false;
    // Every part the changes name must exist in this file or the base.
    let defined = |name: &str| file.parts.contains_key(name) || base.parts.contains_key(name);
    let named = based_on
        .prepend
        .iter()
        .enumerate()
        .map(|(i, name)| (format!("based_on.prepend[{i}]"), name))
        .chain(
            based_on
                .append
                .iter()
                .enumerate()
                .map(|(i, name)| (format!("based_on.append[{i}]"), name)),
        )
        .chain(
            based_on
                .replace
                .iter()
                .map(|(old, new)| (format!("based_on.replace.{old}"), new)),
        );
    for (path, name) in named {
        if !defined(name) {
            problems = true;
            out.push(
                source
                    .error(&path, format!("part `{name}` is not defined"))
                    .hint(format!(
                        "define it under this file's `parts:`; defined here and in `{base_id}`: {}",
                        names_of(
                            file.parts
                                .keys()
                                .chain(base.parts.keys())
                                .collect::<BTreeSet<_>>()
                                .into_iter()
                        )
                    )),
            );
        }
    }
    // A replaced part must be one the base's layouts name.
    let used: BTreeSet<&String> = base
        .layouts
        .values()
        .flatten()
        .filter_map(|entry| match entry {
            PartRefModel::Named(name) => Some(name),
            PartRefModel::Inline(_) => None,
        })
        .collect();
    for old in based_on.replace.keys() {
        if !used.contains(old) {
            problems = true;
            out.push(
                source
                    .error(
                        &format!("based_on.replace.{old}"),
                        format!("the layouts of `{base_id}` name no part `{old}` to replace"),
                    )
                    .hint(format!(
                        "parts the layouts of `{base_id}` name: {}",
                        names_of(used.iter().copied())
                    )),
            );
        }
    }
    if problems {
        return None;
    }
    let mut inherited = Inherited {
        source: base_source,
        prepend: based_on.prepend.len(),
        layouts: BTreeMap::new(),
        parts: BTreeSet::new(),
        commands: file.commands.is_empty(),
        error_reply: file.error_reply.is_none(),
        error_codes: file.error_codes.is_none(),
    };
    for (name, part) in base.parts {
        if let std::collections::btree_map::Entry::Vacant(slot) = file.parts.entry(name) {
            inherited.parts.insert(slot.key().clone());
            slot.insert(part);
        }
    }
    for (name, entries) in base.layouts {
        if file.layouts.contains_key(&name) {
            continue;
        }
        inherited.layouts.insert(name.clone(), entries.len());
        let changed = based_on
            .prepend
            .iter()
            .map(|part| PartRefModel::Named(part.clone()))
            .chain(entries.into_iter().map(|entry| match entry {
                PartRefModel::Named(part) => {
                    PartRefModel::Named(based_on.replace.get(&part).cloned().unwrap_or(part))
                }
                inline => inline,
            }))
            .chain(
                based_on
                    .append
                    .iter()
                    .map(|part| PartRefModel::Named(part.clone())),
            )
            .collect();
        file.layouts.insert(name, changed);
    }
    if inherited.commands {
        file.commands = base.commands;
    }
    if inherited.error_reply {
        file.error_reply = base.error_reply;
    }
    if inherited.error_codes {
        file.error_codes = base.error_codes;
    }
    Some(Merged {
        file,
        inherited: Some(inherited),
    })
}

impl Inherited {
    /// Moves a problem found in the merged file (reported at the derived file's path) to
    /// where the element it is about is written: the base file, or the derived file's
    /// `based_on` entry for a part it puts into every layout.
    pub(crate) fn relocate(&self, derived: &SourceFile, item: &mut Diagnostic) {
        if item.file != derived.path {
            return;
        }
        let Some(target) = self.target(&item.path) else {
            return;
        };
        let (source, path) = match target {
            Target::Base(path) => (&self.source, path),
            Target::Derived(path) => (derived, path),
        };
        item.file = source.path.clone();
        item.position = source.position(&path);
        item.path = path;
    }

    /// Where the element at `path` of the merged file is written.
    fn target(&self, path: &str) -> Option<Target> {
        let steps: Vec<Segment<'_>> = segments(path).collect();
        let rest = |from: usize| render(&steps[from..]);
        match steps.as_slice() {
            [Segment::Key("layouts"), Segment::Key(name), tail @ ..] => {
                let length = *self.layouts.get(*name)?;
                match tail {
                    [Segment::Index(i), ..] if *i < self.prepend => {
                        Some(Target::Derived(format!("based_on.prepend[{i}]{}", rest(3))))
                    }
                    [Segment::Index(i), ..] if *i >= self.prepend + length => {
                        Some(Target::Derived(format!(
                            "based_on.append[{}]{}",
                            i - self.prepend - length,
                            rest(3)
                        )))
                    }
                    [Segment::Index(i), ..] => Some(Target::Base(format!(
                        "layouts.{name}[{}]{}",
                        i - self.prepend,
                        rest(3)
                    ))),
                    _ => Some(Target::Base(path.to_owned())),
                }
            }
            [Segment::Key("parts"), Segment::Key(name), ..] => self
                .parts
                .contains(*name)
                .then(|| Target::Base(path.to_owned())),
            [Segment::Key("commands"), ..] if self.commands => Some(Target::Base(path.to_owned())),
            [Segment::Key("error_reply"), ..] if self.error_reply => {
                Some(Target::Base(path.to_owned()))
            }
            [Segment::Key("error_codes"), ..] if self.error_codes => {
                Some(Target::Base(path.to_owned()))
            }
            _ => None,
        }
    }
}

/// Where a merged element is written.
enum Target {
    /// At this path of the base file.
    Base(String),
    /// At this path of the derived file.
    Derived(String),
}

/// `a, b, c`: names for a hint.
fn names_of<'a>(names: impl Iterator<Item = &'a String>) -> String {
    names.map(String::as_str).collect::<Vec<_>>().join(", ")
}

/// Path steps written back as text (`.key[2]`), for appending to a prefix.
fn render(steps: &[Segment<'_>]) -> String {
    steps
        .iter()
        .map(|step| match step {
            Segment::Key(key) => format!(".{key}"),
            Segment::Index(i) => format!("[{i}]"),
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    fn inherited() -> Inherited {
        Inherited {
            source: SourceFile::from_text(Path::new("base.yaml"), "a: 1\n".to_owned()),
            prepend: 1,
            layouts: BTreeMap::from([("reply".to_owned(), 3)]),
            parts: BTreeSet::from(["crc".to_owned()]),
            commands: true,
            error_reply: false,
            error_codes: false,
        }
    }

    fn target(path: &str) -> Option<(bool, String)> {
        inherited().target(path).map(|t| match t {
            Target::Base(p) => (true, p),
            Target::Derived(p) => (false, p),
        })
    }

    #[test]
    fn an_inherited_layout_entry_is_placed_in_the_base_or_the_based_on_entry() {
        assert_eq!(
            target("layouts.reply[0]"),
            Some((false, "based_on.prepend[0]".to_owned()))
        );
        assert_eq!(
            target("layouts.reply[2].format"),
            Some((true, "layouts.reply[1].format".to_owned()))
        );
        assert_eq!(
            target("layouts.reply[4]"),
            Some((false, "based_on.append[0]".to_owned()))
        );
        assert_eq!(
            target("layouts.reply"),
            Some((true, "layouts.reply".to_owned()))
        );
        assert_eq!(target("layouts.own[0]"), None);
    }

    #[test]
    fn parts_and_sections_follow_where_they_came_from() {
        assert_eq!(
            target("parts.crc.format"),
            Some((true, "parts.crc.format".to_owned()))
        );
        assert_eq!(target("parts.lrc"), None);
        assert_eq!(
            target("commands[2].reply"),
            Some((true, "commands[2].reply".to_owned()))
        );
        assert_eq!(target("error_reply"), None);
        assert_eq!(target("protocol.id"), None);
    }
}
