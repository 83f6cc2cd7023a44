//! Where the checks put what they find: diagnostics at a YAML path of the plant file
//! (`buses[0].drives[2].station`), with file:line:column from the positioned reader.

use crate::{Catalogue, SetupError};
use vfd_codegen::yaml::SourceFile;
use vfd_codegen::{Diagnostic, Diagnostics};

/// The plant file being checked and the problems found in it so far.
pub struct Problems<'a> {
    /// The file, read once.
    pub source: &'a SourceFile,
    /// Every problem found, errors and warnings.
    pub found: Diagnostics,
    /// Where the plant's drives are found.
    pub catalogue: &'a Catalogue,
}

impl Problems<'_> {
    /// An error at `path`, with a hint.
    pub fn error(&mut self, path: &str, message: impl Into<String>, hint: impl Into<String>) {
        let diagnostic: Diagnostic = self.source.error(path, message).hint(hint);
        self.found.push(diagnostic);
    }

    /// A warning at `path`: valid, but probably not what was meant.
    pub fn warning(&mut self, path: &str, message: impl Into<String>, hint: impl Into<String>) {
        let diagnostic: Diagnostic = self.source.warning(path, message).hint(hint);
        self.found.push(diagnostic);
    }

    /// A failure of a lookup shared with the other commands, as an error at `path`.
    pub fn failure(&mut self, path: &str, failure: impl Into<SetupError>) {
        let (message, hint) = failure.into().into_parts();
        let mut diagnostic = self.source.error(path, message);
        if let Some(hint) = hint {
            diagnostic = diagnostic.hint(hint);
        }
        self.found.push(diagnostic);
    }

    /// The line of the node at `path`, for "first at line N".
    pub fn line(&self, path: &str) -> usize {
        self.source.position(path).line
    }
}
