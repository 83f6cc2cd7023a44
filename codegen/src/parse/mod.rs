//! Stage 1: reads YAML files into the [`crate::parse::model`] types, turning syntax and type
//! errors into diagnostics with file, line, column and YAML path.

use crate::diagnostics::{Diagnostic, Position};
pub mod model;
pub mod reader;
pub mod tree;

use schemars::JsonSchema;
use serde::de::DeserializeOwned;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use tree::{Node, SyntaxError};

/// A file's text, read once into a tree of positioned nodes.
#[derive(Debug, Clone)]
pub struct SourceFile {
    /// The path as given.
    pub path: PathBuf,
    /// The text.
    pub text: String,
    /// The document, or its syntax error.
    tree: Arc<Result<Node, SyntaxError>>,
}

/// A file read into a model type.
#[derive(Debug)]
pub struct Read<T> {
    /// The value, unless a problem left nothing to build it from.
    pub value: Option<T>,
    /// Every problem found, in file order.
    pub problems: Vec<Diagnostic>,
    /// Paths of the elements that hold a placeholder for a value in error: later checks
    /// leave out what would only be a consequence of a problem already reported.
    pub incomplete: Vec<String>,
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
        let tree = Arc::new(tree::read(&text));
        SourceFile {
            path: path.to_owned(),
            text,
            tree,
        }
    }

    /// The document, unless it has a syntax error.
    pub fn tree(&self) -> Option<&Node> {
        self.tree.as_ref().as_ref().ok()
    }

    /// The position of the node at `path` (`registers[3].range.max`), or of its nearest
    /// ancestor in the file.
    pub fn position(&self, path: &str) -> Position {
        self.tree().map_or(Position { line: 1, column: 1 }, |tree| {
            tree.position_of(path)
        })
    }

    /// A diagnostic at the node `path` of this file.
    pub fn error(&self, path: &str, message: impl Into<String>) -> Diagnostic {
        Diagnostic::new(&self.path, self.position(path), path, message)
    }

    /// A warning at the node `path`: valid, but not doing what it seems to.
    pub fn warning(&self, path: &str, message: impl Into<String>) -> Diagnostic {
        self.error(path, message).warning()
    }

    /// Reads the whole file as `T`, reporting every problem rather than the first.
    pub fn read_model<T: DeserializeOwned + JsonSchema>(&self) -> Read<T> {
        let tree = match self.tree.as_ref() {
            Ok(tree) => tree,
            Err(syntax) => {
                return Read {
                    value: None,
                    problems: vec![Diagnostic::new(
                        &self.path,
                        syntax.position,
                        "",
                        format!("YAML syntax: {}", syntax.message),
                    )
                    .hint("check brackets, quotes and indentation at the lines named; a `{` or `[` may be unclosed")],
                    incomplete: Vec::new(),
                }
            }
        };
        let outcome = reader::read::<T>(tree);
        let problems = outcome
            .problems
            .into_iter()
            .map(|problem| {
                let diagnostic =
                    Diagnostic::new(&self.path, problem.position, problem.path, problem.message);
                match problem.hint {
                    Some(hint) => diagnostic.hint(hint),
                    None => diagnostic,
                }
            })
            .collect();
        Read {
            value: outcome.value,
            problems,
            incomplete: outcome.incomplete,
        }
    }
}

/// A hint for a complaint from one of the model's hand-written readers.
pub(crate) fn hint_for(message: &str) -> Option<&'static str> {
    if message.contains("untagged enum BoundModel") {
        Some("a range bound is a number in the register's unit, or the code of another register (\"FH\")")
    } else if message.contains("untagged enum") {
        Some("check the value's type against drives/README.md")
    } else if message.starts_with("invalid value") {
        Some("write one of the values listed, spelled exactly so; drives/README.md says what each means")
    } else if message.starts_with("invalid type") {
        Some("check the value's type against drives/README.md (numbers may be decimal or 0x-hex)")
    } else {
        None
    }
}
