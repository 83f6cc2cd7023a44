//! Layouts: each `layouts:` entry resolved into a runtime [`FrameLayout`], then checked as a
//! whole (variable-size fields that something sizes, frames that fit `max_frame_len`, the
//! parts `default_optional_parts` names, Rust names that stay distinct).

use super::lowered_command::LoweredCommand;
use super::names_of;
use super::parts::{lower_part, PartContext};
use crate::diagnostics::Diagnostics;
use crate::naming::const_name;
use crate::parse::model::{OptionalModel, PartModel, PartRefModel, ProtocolFile};
use crate::parse::SourceFile;
use std::borrow::Cow;
use std::collections::{BTreeMap, BTreeSet};
use vfd_runtime::layout::MAX_PARTS;
use vfd_runtime::{Counts, FrameLayout, LengthSpec, Part, SizedBy};

/// The layouts of one protocol file that lowered without problems.
pub(super) struct Layouts<'a> {
    file: &'a ProtocolFile,
    source: &'a SourceFile,
    built: Vec<FrameLayout>,
}

impl Layouts<'_> {
    /// The layout called `name`, reporting at `path` when the file does not define it. A
    /// layout that is defined but had problems gives `None` silently: they are reported.
    pub fn find(&self, name: &str, path: &str, out: &mut Diagnostics) -> Option<FrameLayout> {
        let found = self.built.iter().find(|layout| layout.name == name);
        if found.is_none() && !self.file.layouts.contains_key(name) {
            out.push(
                self.source
                    .error(path, format!("layout `{name}` is not defined"))
                    .hint(format!(
                        "define it under `layouts:`; defined: {}",
                        names_of(self.file.layouts.keys())
                    )),
            );
        }
        found.cloned()
    }

    /// The layouts that lowered, in name order.
    pub fn iter(&self) -> impl Iterator<Item = &FrameLayout> {
        self.built.iter()
    }
}

/// Lowers every layout of the file; those with problems are reported and left out.
pub(super) fn lower_layouts<'a>(
    file: &'a ProtocolFile,
    source: &'a SourceFile,
    out: &mut Diagnostics,
) -> Layouts<'a> {
    let built = file
        .layouts
        .iter()
        .filter_map(|(name, entries)| lower_layout(name, entries, file, source, out))
        .collect();
    Layouts {
        file,
        source,
        built,
    }
}

/// Lowers one layout: every entry resolved and lowered into a part, then the sizes checked.
fn lower_layout(
    name: &str,
    entries: &[PartRefModel],
    file: &ProtocolFile,
    source: &SourceFile,
    out: &mut Diagnostics,
) -> Option<FrameLayout> {
    let before = out.items.len();
    if entries.len() > MAX_PARTS {
        out.push(
            source
                .error(
                    &format!("layouts.{name}"),
                    format!(
                        "layout `{name}` has {} parts; the runtime supports {MAX_PARTS}",
                        entries.len()
                    ),
                )
                .hint("merge fields or split the frame"),
        );
    }
    let names: Vec<String> = entries
        .iter()
        .enumerate()
        .map(|(index, entry)| entry_name(entry, index))
        .collect();
    let mut parts = Vec::new();
    for (index, entry) in entries.iter().enumerate() {
        let Some((model, path)) = resolve_entry(name, index, entry, file, source, out) else {
            continue;
        };
        let context = PartContext {
            layout: name,
            index,
            names: &names,
            path: &path,
            source,
        };
        let part_name = match entry {
            PartRefModel::Named(key) => model.name.as_ref().unwrap_or(key),
            PartRefModel::Inline(_) => &names[index],
        };
        if let Some(part) = lower_part(part_name, model, &context, out) {
            parts.push(part);
        }
    }
    if out.items.len() > before {
        return None;
    }
    let layout = FrameLayout {
        name: Cow::Owned(name.to_owned()),
        parts: Cow::Owned(parts),
        encoding: file.protocol.encoding,
        plan: None,
    }
    .planned();
    check_sizes(&layout, source, out).then_some(layout)
}

/// The part an entry stands for and the YAML path its keys are reported under: the shared
/// part under `parts:` for a name, the entry itself for an inline part.
fn resolve_entry<'f>(
    layout: &str,
    index: usize,
    entry: &'f PartRefModel,
    file: &'f ProtocolFile,
    source: &SourceFile,
    out: &mut Diagnostics,
) -> Option<(&'f PartModel, String)> {
    let entry_path = format!("layouts.{layout}[{index}]");
    match entry {
        PartRefModel::Inline(model) => Some((model, entry_path)),
        PartRefModel::Named(key) => match file.parts.get(key) {
            Some(model) => Some((model, format!("parts.{key}"))),
            None => {
                out.push(
                    source
                        .error(&entry_path, format!("part `{key}` is not defined"))
                        .hint(format!(
                            "define it under `parts:`; defined: {}",
                            names_of(file.parts.keys())
                        )),
                );
                None
            }
        },
    }
}

/// The name other entries of a layout use for this one (`covers_from`, `counts`): a shared
/// part's key, or an inline part's `name`, role or kind.
pub(super) fn entry_name(entry: &PartRefModel, index: usize) -> String {
    match entry {
        PartRefModel::Named(name) => name.clone(),
        PartRefModel::Inline(model) => model
            .name
            .clone()
            .or_else(|| model.field.map(|role| role.as_str().to_owned()))
            .or_else(|| model.checksum.as_ref().map(|_| "checksum".to_owned()))
            .or_else(|| model.length.as_ref().map(|_| "length".to_owned()))
            .unwrap_or_else(|| format!("part{index}")),
    }
}

/// Every variable-size field can be sized when decoding; reports the first that cannot.
fn check_sizes(layout: &FrameLayout, source: &SourceFile, out: &mut Diagnostics) -> bool {
    for (index, part) in layout.parts.iter().enumerate() {
        let Part::Field(field) = part else { continue };
        let path = format!("layouts.{}[{index}]", layout.name);
        let problem = match field.sized_by {
            SizedBy::Format => None,
            SizedBy::Rest if !rest_is_sized(&layout.parts, index) => Some((
                format!("`{}` takes the rest of the frame, but no earlier length covers the frame to its end, or a later part has no fixed size", field.name),
                "put a length counting `from` the next part `through` the last part before it, and only fixed-size parts after it",
            )),
            SizedBy::Length if !length_covers(&layout.parts, index) => Some((
                format!("`{}` is sized by a length, but no earlier length covers exactly it", field.name),
                "add a length part with counts: { from: this, through: this } before it",
            )),
            SizedBy::Rest | SizedBy::Length => None,
        };
        if let Some((message, hint)) = problem {
            out.push(source.error(&path, message).hint(hint));
            return false;
        }
    }
    true
}

/// A `size: rest` field at `index`: an earlier length counts up to the last part, and every
/// part after the field has a fixed size.
fn rest_is_sized(parts: &[Part], index: usize) -> bool {
    let framed = parts[..index].iter().any(|part| {
        matches!(part, Part::Length(LengthSpec { counts: Counts::Parts { through, .. }, .. })
            if usize::from(*through) + 1 == parts.len())
    });
    framed && parts[index + 1..].iter().all(|p| p.fixed_size().is_some())
}

/// A `size: length` field at `index`: an earlier length counts exactly it.
fn length_covers(parts: &[Part], index: usize) -> bool {
    parts[..index].iter().any(|part| {
        matches!(part, Part::Length(LengthSpec { counts: Counts::Parts { from, through }, .. })
            if usize::from(*from) == index && from == through)
    })
}

/// No two layouts become the same Rust name: the generated code declares a static per layout,
/// `<PROTOCOL>_<LAYOUT>` with the layout's name through [`const_name`] (`read-request` and
/// `read_request` both become `..._READ_REQUEST`). Reported at the one written later.
pub(super) fn check_rust_names(
    protocol_id: &str,
    file: &ProtocolFile,
    source: &SourceFile,
    out: &mut Diagnostics,
) {
    let mut by_rust_name: BTreeMap<String, Vec<&String>> = BTreeMap::new();
    for name in file.layouts.keys() {
        by_rust_name.entry(const_name(name)).or_default().push(name);
    }
    for (rust, mut names) in by_rust_name {
        let position = |name: &&String| {
            let at = source.position(&format!("layouts.{name}"));
            (at.line, at.column)
        };
        names.sort_by_key(position);
        let Some((first, later)) = names.split_first() else {
            continue;
        };
        let rust = format!("{}_{rust}", const_name(protocol_id));
        for name in later {
            out.push(
                source
                    .error(
                        &format!("layouts.{name}"),
                        format!("layout `{name}` becomes the Rust static `{rust}`, like layout `{first}`"),
                    )
                    .hint("layouts are named in Rust in upper case with `-` as `_`; rename one of the two"),
            );
        }
    }
}

/// Every layout a command uses fits in `max_frame_len` when its size is fixed.
pub(super) fn check_frame_sizes(
    commands: &[LoweredCommand],
    file: &ProtocolFile,
    source: &SourceFile,
    out: &mut Diagnostics,
) {
    let max = file.protocol.max_frame_len;
    let mut seen = BTreeSet::new();
    let layouts = commands
        .iter()
        .flat_map(|command| [&command.spec.request, &command.spec.reply]);
    for layout in layouts {
        if !seen.insert(layout.name.clone()) {
            continue;
        }
        let fixed: Option<usize> = layout.parts.iter().map(Part::fixed_size).sum();
        if let Some(size) = fixed.filter(|size| *size > usize::from(max)) {
            out.push(
                source
                    .error(
                        "protocol.max_frame_len",
                        format!(
                            "layout `{}` is {size} bytes, longer than max_frame_len {max}",
                            layout.name
                        ),
                    )
                    .hint("raise max_frame_len: it sizes buffers and reply timeouts"),
            );
        }
    }
}

/// `default_optional_parts` names parts of the layouts, and only optional ones. Judged by
/// the names the layouts list, so that a part that failed to lower is not reported a second
/// time as missing.
pub(super) fn check_default_optional_parts(
    file: &ProtocolFile,
    source: &SourceFile,
    out: &mut Diagnostics,
) {
    for (index, name) in file.protocol.default_optional_parts.iter().enumerate() {
        let path = format!("protocol.default_optional_parts[{index}]");
        if !is_listed(file, name) {
            out.push(
                source
                    .error(&path, format!("no layout has a part named `{name}`"))
                    .hint("name an optional part of the layouts (e.g. sum, end)"),
            );
        } else if is_always_sent(file, name) {
            out.push(
                source
                    .error(
                        &path,
                        format!("part `{name}` is not optional; it is always sent"),
                    )
                    .hint("list only parts marked `optional: true`"),
            );
        }
    }
}

/// Whether some layout has a part called `name`.
fn is_listed(file: &ProtocolFile, name: &str) -> bool {
    file.layouts.values().any(|entries| {
        entries
            .iter()
            .enumerate()
            .any(|(index, entry)| match entry {
                PartRefModel::Named(key) => {
                    key == name || file.parts.get(key).and_then(|p| p.name.as_deref()) == Some(name)
                }
                PartRefModel::Inline(_) => entry_name(entry, index) == name,
            })
    })
}

/// Whether a layout lists the shared part `name` and it is a part other than a field that
/// is not marked optional.
fn is_always_sent(file: &ProtocolFile, name: &str) -> bool {
    file.layouts.values().flatten().any(|entry| match entry {
        PartRefModel::Named(key) => {
            key == name
                && file.parts.get(key).is_some_and(|part| {
                    matches!(part.optional, None | Some(OptionalModel::Flag(false)))
                        && part.field.is_none()
                })
        }
        PartRefModel::Inline(_) => false,
    })
}

#[cfg(test)]
mod tests {
    use super::super::test_support::{at, lowered, problems, protocol_with, PROTOCOL};
    use super::*;

    #[test]
    fn inline_parts_are_named_by_name_role_or_kind() {
        let yaml = "- { field: data, name: pwe }\n- { field: data }\n- { checksum: xor8 }\n- { length: u8 }\n- { literal: \"(\" }";
        let tree = crate::parse::tree::read(yaml).unwrap();
        let entries: Vec<PartRefModel> = crate::parse::reader::read(&tree).value.unwrap();
        let names: Vec<String> = entries
            .iter()
            .enumerate()
            .map(|(index, entry)| entry_name(entry, index))
            .collect();
        assert_eq!(names, ["pwe", "data", "checksum", "length", "part4"]);
    }

    #[test]
    fn undefined_parts_and_layouts_are_reported_where_they_are_named() {
        let yaml = protocol_with(&[
            (
                "register, sum, cr]\n  write",
                "register, chksum, cr]\n  write",
            ),
            ("request: write_request", "request: write_reqest"),
            ("error_reply: error_reply\n", "error_reply: nak\n"),
        ]);
        assert_eq!(
            problems(&yaml),
            [
                format!(
                    "{} layouts.read_request[4]: part `chksum` is not defined",
                    at(&yaml, "chksum")
                ),
                format!(
                    "{} commands[1].request: layout `write_reqest` is not defined",
                    at(&yaml, "write_reqest")
                ),
                format!(
                    "{} error_reply: layout `nak` is not defined",
                    at(&yaml, "nak")
                ),
            ]
        );
    }

    #[test]
    fn a_layout_with_a_bad_part_is_not_reported_again_as_undefined() {
        let yaml = protocol_with(&[(
            "format: hex, width: 4 }, sum, cr]\n  reply",
            "format: hex, width: 40 }, sum, cr]\n  reply",
        )]);
        assert_eq!(
            problems(&yaml),
            [format!(
                "{} layouts.write_request[4].width: `width: 40` is out of range for hex",
                at(&yaml, "40")
            )]
        );
    }

    #[test]
    fn too_many_parts_are_reported_at_the_layout() {
        let many = vec!["cr"; MAX_PARTS + 1].join(", ");
        let yaml = protocol_with(&[(
            "register, sum, cr]\n  write",
            &format!("register, sum, {many}]\n  write"),
        )]);
        assert_eq!(
            problems(&yaml),
            [format!("{} layouts.read_request: layout `read_request` has 22 parts; the runtime supports 16", at(&yaml, "read_request:"))]
        );
    }

    #[test]
    fn variable_fields_need_something_that_sizes_them() {
        let yaml = protocol_with(&[
            ("text: true", "text: false"),
            (
                "{ field: data, format: hex, width: 4 }, sum, cr]\n  reply",
                "{ field: data, format: bytes, size: length }, sum, cr]\n  reply",
            ),
            (
                "{ field: data, format: hex, width: 4 }, sum, cr]\n  error",
                "{ field: data, format: uint_be, size: rest }, sum, cr]\n  error",
            ),
        ]);
        assert_eq!(
            problems(&yaml),
            [
                format!("{} layouts.write_request[4]: `data` is sized by a length, but no earlier length covers exactly it", at(&yaml, "field: data, format: bytes")),
                format!("{} layouts.reply[4]: `data` takes the rest of the frame, but no earlier length covers the frame to its end, or a later part has no fixed size", at(&yaml, "field: data, format: uint_be")),
            ]
        );
    }

    #[test]
    fn fixed_frames_must_fit_max_frame_len() {
        // Variable parts (the optional address and checksum) leave the other layouts unsized.
        let yaml = protocol_with(&[
            ("max_frame_len: 17", "max_frame_len: 9"),
            (
                "  reply:",
                "  fixed: [start, register, register, cr]\n  reply:",
            ),
            (
                "commands:\n",
                "commands:\n  - { kind: process, request: fixed, reply: fixed }\n",
            ),
        ]);
        assert_eq!(
            problems(&yaml),
            [format!("{} protocol.max_frame_len: layout `fixed` is 10 bytes, longer than max_frame_len 9", at(&yaml, "9"))]
        );
    }

    #[test]
    fn default_optional_parts_must_be_optional_parts_of_the_layouts() {
        let yaml = protocol_with(&[(
            "default_optional_parts: [sum]",
            "default_optional_parts: [sum, cr, end]",
        )]);
        assert_eq!(
            problems(&yaml),
            [
                format!("{} protocol.default_optional_parts[1]: part `cr` is not optional; it is always sent", at(&yaml, "cr, end")),
                format!("{} protocol.default_optional_parts[2]: no layout has a part named `end`", at(&yaml, "end]")),
            ]
        );
    }

    #[test]
    fn layouts_that_become_the_same_rust_name_are_reported_at_the_later_one() {
        let copy = PROTOCOL
            .lines()
            .find(|line| line.starts_with("  read_request:"))
            .unwrap()
            .replace("read_request", "read-request");
        // `read-request` sorts first, but is written last.
        let yaml = protocol_with(&[("  reply:", &format!("{copy}\n  reply:"))]);
        assert_eq!(
            problems(&yaml),
            [format!("{} layouts.read-request: layout `read-request` becomes the Rust static `ASCII_READ_REQUEST`, like layout `read_request`", at(&yaml, "read-request:"))]
        );
        lowered(&protocol_with(&[(
            "  reply:",
            &format!(
                "{}\n  reply:",
                copy.replace("read-request", "read-request-2")
            ),
        )]));
    }
}
