//! Problems that do not concern the wire, and the drive without the parts that have them.
//!
//! `vfd check` reports every problem, and nothing is generated from a description with
//! errors. A tool at a real bus needs less: the protocols' framing and checksums, the
//! register table, the code tables and error codes, and the frames and values the manual's
//! examples give as evidence of them. A problem only in a part that documents the drive or
//! rehearses it on the virtual drive does not change a byte on the wire: an example's
//! `not_simulated`, `settings`, `no_reply`, id or words (or an example with no frame at
//! all), the behaviour model (only the virtual drive uses it), the manual's errata and
//! safety warnings, a sequence's id or words. When every error lies in such parts,
//! [`usable`] builds the drive without them; the tool reports the problems and goes on
//! (`Compiled::usable`).

use crate::diagnostics::Diagnostics;
use crate::ir::DriveIr;
use crate::validate::Context;

/// A part of a drive file that does not concern the wire.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
enum OffTheWire {
    /// `examples[i]`.
    Example(usize),
    /// `sequences[i]`.
    Sequence(usize),
    /// `manual_errata[i]`.
    Erratum(usize),
    /// `warnings[i]`.
    Warning(usize),
    /// `behaviour`.
    Behaviour,
}

/// Keys of an example that are neither its frames nor their values.
const EXAMPLE_KEYS: [&str; 7] = [
    "not_simulated",
    "settings",
    "no_reply",
    "id",
    "description",
    "description_zh",
    "source",
];

/// Keys of a sequence that are not its steps, call or result.
const SEQUENCE_KEYS: [&str; 4] = ["id", "description", "description_zh", "source"];

/// The part off the wire that the problem at `path` (a YAML path of the drive file) lies
/// in; `None` when the problem concerns the wire.
fn part_of(path: &str) -> Option<OffTheWire> {
    if path == "behaviour" || path.starts_with("behaviour.") {
        return Some(OffTheWire::Behaviour);
    }
    if let Some((index, rest)) = indexed(path, "examples") {
        let key = rest.strip_prefix('.').map(first_key);
        return match key {
            None if rest.is_empty() => Some(OffTheWire::Example(index)),
            Some(key) if EXAMPLE_KEYS.contains(&key) => Some(OffTheWire::Example(index)),
            _ => None,
        };
    }
    if let Some((index, rest)) = indexed(path, "sequences") {
        let key = rest.strip_prefix('.').map(first_key)?;
        return SEQUENCE_KEYS
            .contains(&key)
            .then_some(OffTheWire::Sequence(index));
    }
    if let Some((index, _)) = indexed(path, "manual_errata") {
        return Some(OffTheWire::Erratum(index));
    }
    if let Some((index, _)) = indexed(path, "warnings") {
        return Some(OffTheWire::Warning(index));
    }
    None
}

/// `examples[3].settings.F999` with `key` `examples`: `(3, ".settings.F999")`.
fn indexed<'p>(path: &'p str, key: &str) -> Option<(usize, &'p str)> {
    let rest = path.strip_prefix(key)?.strip_prefix('[')?;
    let (number, rest) = rest.split_once(']')?;
    Some((number.parse().ok()?, rest))
}

/// `settings` of `settings.F999`, `settings[0]` or `settings`.
fn first_key(rest: &str) -> &str {
    rest.split(['.', '[']).next().unwrap_or(rest)
}

/// Whether every error in `errors` lies in a part of the drive file that does not concern
/// the wire (a problem in a protocol file always does).
pub(crate) fn none_concern_the_wire(context: &Context, errors: &Diagnostics) -> bool {
    parts(context, errors).is_some()
}

/// The parts off the wire `errors` lie in, or `None` when one concerns the wire.
fn parts(context: &Context, errors: &Diagnostics) -> Option<Vec<OffTheWire>> {
    let mut parts = Vec::new();
    for error in errors.items.iter().filter(|d| !d.is_warning()) {
        if error.file != context.source.path {
            return None;
        }
        parts.push(part_of(&error.path)?);
    }
    parts.sort();
    parts.dedup();
    Some(parts)
}

/// The drive of `context` without the parts off the wire that `errors` lie in, when every
/// error lies in one and the drive has no other problem without them; `None` otherwise.
pub(crate) fn usable(context: &Context, errors: &Diagnostics) -> Option<DriveIr> {
    let parts = parts(context, errors)?;
    let mut model = context.model.clone();
    // Highest index first, so that the lower ones stay where they are.
    for part in parts.iter().rev() {
        match *part {
            OffTheWire::Example(index) if index < model.examples.len() => {
                model.examples.remove(index);
            }
            OffTheWire::Sequence(index) if index < model.sequences.len() => {
                model.sequences.remove(index);
            }
            OffTheWire::Erratum(index) if index < model.manual_errata.len() => {
                model.manual_errata.remove(index);
            }
            OffTheWire::Warning(index) if index < model.warnings.len() => {
                model.warnings.remove(index);
            }
            OffTheWire::Behaviour => model.behaviour = None,
            _ => return None,
        }
    }
    let frames = crate::frames::decode_examples(&model, &context.protocols);
    let without = Context {
        source: context.source.clone(),
        model,
        protocols: context.protocols.clone(),
        frames,
    };
    let mut problems = Diagnostics::default();
    crate::validate::check(&without, &mut problems);
    if problems.has_errors() {
        return None;
    }
    Some(crate::ir::lower(&without))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::validate::testing::{valid_with, FILE};
    use std::path::Path;

    fn compiled(yaml: &str) -> crate::Compiled {
        let protocols = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../drives/protocols"));
        crate::compile_source(
            crate::parse::SourceFile::from_text(Path::new(FILE), yaml.to_owned()),
            Some(protocols),
            &[],
        )
    }

    #[test]
    fn a_drive_whose_problems_are_off_the_wire_is_usable_without_those_parts() {
        // A `not_simulated` the virtual drive contradicts (a rehearsal error).
        let wrong_claim = valid_with(&[(
            "    value: 80.0\n",
            "    value: 80.0\n    not_simulated: \"Believed unreachable.\"\n",
        )]);
        let result = compiled(&wrong_claim);
        assert!(result.drive.is_err());
        let usable = result
            .usable
            .expect("usable: the problem is the example's claim");
        assert_eq!(
            usable.examples.len(),
            1,
            "the rehearsal's problem keeps the example"
        );
        // A setting naming no register: the example is left out.
        let bad_setting = valid_with(&[(
            "    value: 80.0\n",
            "    value: 80.0\n    settings: { F999: 1 }\n",
        )]);
        let result = compiled(&bad_setting);
        assert!(result.drive.is_err());
        let usable = result
            .usable
            .expect("usable: the problem is an example's setting");
        assert!(usable.examples.is_empty());
        assert_eq!(usable.registers.len(), 5);
    }

    #[test]
    fn a_problem_on_the_wire_leaves_nothing_usable() {
        for edit in [
            // A default outside its range (the register table).
            ("default: 10.0, source", "default: 9999.0, source"),
            // An example frame whose value contradicts the register's scale.
            ("    value: 80.0\n", "    value: 70.0\n"),
        ] {
            let result = compiled(&valid_with(&[edit]));
            assert!(result.drive.is_err(), "{edit:?}");
            assert!(result.usable.is_none(), "{edit:?}");
        }
    }

    #[test]
    fn only_parts_that_document_or_rehearse_are_off_the_wire() {
        assert_eq!(
            part_of("examples[3].not_simulated"),
            Some(OffTheWire::Example(3))
        );
        assert_eq!(
            part_of("examples[0].settings.F999"),
            Some(OffTheWire::Example(0))
        );
        assert_eq!(part_of("examples[2]"), Some(OffTheWire::Example(2)));
        assert_eq!(
            part_of("behaviour.command.run"),
            Some(OffTheWire::Behaviour)
        );
        assert_eq!(part_of("sequences[1].id"), Some(OffTheWire::Sequence(1)));
        assert_eq!(
            part_of("manual_errata[0].printed"),
            Some(OffTheWire::Erratum(0))
        );
        // The frames, their values and everything else are the wire's.
        for path in [
            "examples[0].reply",
            "examples[0].request.expect.data",
            "examples[1].value",
            "sequences[0].steps[2]",
            "registers[4].default",
            "value_examples[0].raw",
            "protocols[0].broadcast",
            "behaviourx",
        ] {
            assert_eq!(part_of(path), None, "{path}");
        }
    }
}
