//! Stage 1: reads YAML files into the [`crate::parse::model`] types, turning syntax and type
//! errors into diagnostics with file, line, column and YAML path.

use crate::diagnostics::Diagnostic;
pub mod model;
pub mod positions;

use positions::{Position, PositionIndex};
use serde::de::DeserializeOwned;
use std::path::{Path, PathBuf};

/// A file's text and the positions of its nodes.
#[derive(Debug, Clone)]
pub struct SourceFile {
    /// The path as given.
    pub path: PathBuf,
    /// The text.
    pub text: String,
    /// Path-to-position index.
    pub index: PositionIndex,
}

impl SourceFile {
    /// Reads a file.
    pub fn read(path: &Path) -> Result<SourceFile, Diagnostic> {
        let text = std::fs::read_to_string(path).map_err(|error| {
            Diagnostic::new(
                path,
                Position { line: 1, column: 1 },
                "",
                format!("cannot read the file: {error}"),
            )
            .hint(
                "check the path; a relative path starts at the current folder (a build script's is its crate's folder)",
            )
        })?;
        Ok(SourceFile::from_text(path, text))
    }

    /// Wraps text already in memory (used by tests and the proc-macro).
    pub fn from_text(path: &Path, text: String) -> SourceFile {
        let index = PositionIndex::build(&text);
        SourceFile {
            path: path.to_owned(),
            text,
            index,
        }
    }

    /// A diagnostic at the node `path` of this file.
    pub fn error(&self, path: &str, message: impl Into<String>) -> Diagnostic {
        Diagnostic::new(&self.path, self.index.find(path), path, message)
    }

    /// Deserialises the whole file as `T`.
    ///
    /// A valid file is read once, plainly. Tracking the YAML path of every node (which a
    /// message needs) costs about a third more, so only a file that fails is read again
    /// with `serde_path_to_error`, which fails the same way and says where.
    pub fn deserialize<T: DeserializeOwned>(&self) -> Result<T, Diagnostic> {
        if let Ok(value) = serde_yaml::from_str(&self.text) {
            return Ok(value);
        }
        let deserializer = serde_yaml::Deserializer::from_str(&self.text);
        serde_path_to_error::deserialize(deserializer).map_err(|error| {
            let path = match error.path().to_string() {
                dot if dot == "." => String::new(),
                path => path,
            };
            let inner = error.inner();
            let indexed = self.index.find(&path);
            let position = match inner.location() {
                // serde_yaml sometimes reports an error before the node it belongs to
                // (hand-written deserialisers): the node's own position is better then.
                Some(location) if location.line() >= indexed.line => Position {
                    line: location.line(),
                    column: location.column(),
                },
                _ => indexed,
            };
            let path = path.trim_end_matches(".?").trim_end_matches('?').to_owned();
            let mut message = inner.to_string();
            // serde_yaml repeats the path and the position; the diagnostic shows both.
            // serde_yaml prefixes the path (or its parent) that `= at:` shows anyway.
            if let Some((prefix, rest)) = message.split_once(": ") {
                if !prefix.contains(' ') && path.starts_with(prefix) {
                    message = rest.to_owned();
                }
            }
            message = strip_first_position(&message);
            // For an unclosed `{`/`[`, the place it was opened is where the fix goes.
            let (position, message) = match opened_at(&message) {
                Some(opened) => (
                    opened,
                    message.replacen(
                        ", while parsing",
                        &format!(
                            " (noticed at line {} column {}), while parsing",
                            position.line, position.column
                        ),
                        1,
                    ),
                ),
                None => (position, message),
            };
            let hint = match (did_you_mean(&message), hint_for(&message)) {
                (Some(suggestion), Some(hint)) => Some(format!("{suggestion} Otherwise, {hint}")),
                (Some(suggestion), None) => Some(suggestion),
                (None, hint) => hint.map(str::to_owned),
            };
            let mut diagnostic = Diagnostic::new(&self.path, position, path, message);
            if let Some(hint) = hint {
                diagnostic = diagnostic.hint(hint);
            }
            diagnostic
        })
    }
}

/// The position in "while parsing a flow mapping at line 51 column 5", if present.
fn opened_at(message: &str) -> Option<Position> {
    let context = &message[message.find("while parsing")?..];
    let rest = &context[context.find(" at line ")? + " at line ".len()..];
    let (line, rest) = rest.split_once(" column ")?;
    let column: String = rest.chars().take_while(char::is_ascii_digit).collect();
    Some(Position {
        line: line.trim().parse().ok()?,
        column: column.parse().ok()?,
    })
}

/// Removes the first " at line N column M" (the diagnostic's own position) and keeps any
/// later context such as "while parsing a flow mapping at line 51 column 5".
fn strip_first_position(message: &str) -> String {
    let Some(start) = message.find(" at line ") else {
        return message.to_owned();
    };
    let after = &message[start + " at line ".len()..];
    let end = after
        .find(" column ")
        .map(|c| {
            let digits = after[c + " column ".len()..]
                .chars()
                .take_while(char::is_ascii_digit)
                .count();
            c + " column ".len() + digits
        })
        .unwrap_or(0);
    format!("{}{}", &message[..start], &after[end..])
}

/// "did you mean `format`?" for serde's "unknown field `fromat`, expected one of `format`,
/// ..." and "unknown variant `u16bee`, expected one of ...", when one known name is close
/// to the one written (at most a third of its letters differ).
fn did_you_mean(message: &str) -> Option<String> {
    let rest = message
        .strip_prefix("unknown field `")
        .or_else(|| message.strip_prefix("unknown variant `"))?;
    let (written, known) = rest.split_once('`')?;
    let best = known
        .split('`')
        .skip(1)
        .step_by(2)
        .map(|candidate| (edit_distance(written, candidate), candidate))
        .min_by_key(|(distance, _)| *distance)?;
    let limit = (written.chars().count() / 3).max(1);
    (best.0 <= limit).then(|| format!("did you mean `{}`?", best.1))
}

/// Levenshtein distance between two short names.
fn edit_distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut previous: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut current = vec![i + 1];
        for (j, cb) in b.iter().enumerate() {
            let substitution = previous[j] + usize::from(ca != *cb);
            current.push(substitution.min(previous[j + 1] + 1).min(current[j] + 1));
        }
        previous = current;
    }
    previous[b.len()]
}

fn hint_for(message: &str) -> Option<&'static str> {
    if message.contains("while parsing")
        || message.contains("did not find expected")
        || message.contains("mapping values are not allowed")
    {
        Some("YAML syntax: check brackets, quotes and indentation at the lines named; a `{` or `[` may be unclosed")
    } else if message.contains("unknown field `")
        && message
            .split('`')
            .nth(1)
            .is_some_and(|field| field.contains(' '))
    {
        Some("inside `{ ... }` an unquoted comma ends the value: put text containing commas in quotes")
    } else if message.contains("unknown field") {
        Some("remove the key or fix its spelling; drives/README.md lists every key")
    } else if message.contains("missing field") {
        Some("add the key; drives/README.md says what it holds")
    } else if message.contains("untagged enum BoundModel") {
        Some("a range bound is a number in the register's unit, or the code of another register (\"FH\")")
    } else if message.starts_with("unknown variant `")
        || message.starts_with("invalid value: string")
    {
        Some("write one of the values listed, spelled exactly so; drives/README.md says what each means")
    } else if message.contains("invalid type") {
        Some("check the value's type against drives/README.md (numbers may be decimal or 0x-hex)")
    } else {
        None
    }
}

#[cfg(test)]
mod tests {
    use super::did_you_mean;

    #[test]
    fn a_close_known_name_is_suggested() {
        assert_eq!(
            did_you_mean(
                "unknown field `fromat`, expected one of `literal`, `field`, `format`, `width`"
            ),
            Some("did you mean `format`?".to_owned())
        );
        assert_eq!(
            did_you_mean("unknown variant `readonly`, expected one of `read-only`, `read-write`, `write-only`"),
            Some("did you mean `read-only`?".to_owned())
        );
        assert_eq!(
            did_you_mean("unknown variant `register`, expected `parameter` or `coil`"),
            None,
            "nothing close"
        );
        assert_eq!(did_you_mean("missing field `id`"), None);
    }
}
