//! Problems found in a description, each with file, line, column, YAML path and a hint,
//! rendered the way compilers render errors.

use std::fmt;
use std::path::{Path, PathBuf};

/// A 1-based line and column.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Position {
    /// Line, from 1.
    pub line: usize,
    /// Column, from 1.
    pub column: usize,
}

/// How serious a diagnostic is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Severity {
    /// The description is wrong: nothing is generated from it.
    #[default]
    Error,
    /// The description is valid but says something that does not do what it seems to
    /// (a setting that changes nothing, an example the virtual drive refuses): generation
    /// goes on; `vfd check --deny-warnings` fails on it.
    Warning,
}

impl Severity {
    /// `error` or `warning`, as printed.
    pub fn as_str(self) -> &'static str {
        match self {
            Severity::Error => "error",
            Severity::Warning => "warning",
        }
    }
}

/// One problem in a drive or protocol file.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Diagnostic {
    /// An error, or a warning.
    pub severity: Severity,
    /// The file, as given to the generator.
    pub file: PathBuf,
    /// Where in the file.
    pub position: Position,
    /// YAML path of the offending node (`registers[12].range.max`).
    pub path: String,
    /// What is wrong.
    pub message: String,
    /// How to fix it.
    pub hint: Option<String>,
    /// The offending source line, when the file could be read.
    pub source_line: Option<String>,
}

impl Diagnostic {
    /// A diagnostic without a source line (filled in by [`Diagnostics::attach_sources`]).
    pub fn new(
        file: &Path,
        position: Position,
        path: impl Into<String>,
        message: impl Into<String>,
    ) -> Self {
        Diagnostic {
            severity: Severity::Error,
            file: file.to_owned(),
            position,
            path: path.into(),
            message: message.into(),
            hint: None,
            source_line: None,
        }
    }

    /// Adds a hint.
    pub fn hint(mut self, hint: impl Into<String>) -> Self {
        self.hint = Some(hint.into());
        self
    }

    /// Makes it a warning.
    pub fn warning(mut self) -> Self {
        self.severity = Severity::Warning;
        self
    }

    /// Whether it is a warning.
    pub fn is_warning(&self) -> bool {
        self.severity == Severity::Warning
    }

    /// `file:line:column`.
    pub fn location(&self) -> String {
        format!(
            "{}:{}:{}",
            self.file.display(),
            self.position.line,
            self.position.column
        )
    }
}

impl fmt::Display for Diagnostic {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(f, "{}: {}", self.severity.as_str(), self.message)?;
        writeln!(f, "  --> {}", self.location())?;
        if let Some(line) = &self.source_line {
            let number = self.position.line.to_string();
            let pad = " ".repeat(number.len());
            let (shown, caret_at) = excerpt(line, self.position.column);
            writeln!(f, "{pad} |")?;
            writeln!(f, "{number} | {shown}")?;
            writeln!(f, "{pad} | {}^", " ".repeat(caret_at))?;
        }
        if !self.path.is_empty() {
            writeln!(f, "  = at: {}", self.path)?;
        }
        if let Some(hint) = &self.hint {
            writeln!(f, "  = hint: {hint}")?;
        }
        Ok(())
    }
}

/// Cuts long lines (flow-style YAML rows) to a window around the column, returning the
/// text and the caret's offset in characters.
fn excerpt(line: &str, column: usize) -> (String, usize) {
    let chars: Vec<char> = line.chars().collect();
    let column = column.saturating_sub(1).min(chars.len());
    let start = column.saturating_sub(40);
    let end = (column + 60).min(chars.len());
    let mut shown: String = chars[start..end].iter().collect();
    let mut caret = column - start;
    if start > 0 {
        shown.insert_str(0, "...");
        caret += 3;
    }
    if end < chars.len() {
        shown.push_str("...");
    }
    (shown, caret)
}

/// All problems found in one run, in file and line order.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Diagnostics {
    /// The problems.
    pub items: Vec<Diagnostic>,
}

impl Diagnostics {
    /// Adds one.
    pub fn push(&mut self, diagnostic: Diagnostic) {
        self.items.push(diagnostic);
    }

    /// Whether there are none.
    pub fn is_empty(&self) -> bool {
        self.items.is_empty()
    }

    /// Whether any is an error.
    pub fn has_errors(&self) -> bool {
        self.items.iter().any(|item| !item.is_warning())
    }

    /// Moves the warnings out, leaving the errors.
    pub fn take_warnings(&mut self) -> Diagnostics {
        let (warnings, errors) = std::mem::take(&mut self.items)
            .into_iter()
            .partition(Diagnostic::is_warning);
        self.items = errors;
        Diagnostics { items: warnings }
    }

    /// Leaves out the problems found after the first `keep` that are at, under, or refer
    /// to an element holding a placeholder for a value already reported as wrong
    /// (`incomplete`: file and YAML path): they are consequences, not further mistakes.
    pub fn leave_out_consequences(&mut self, keep: usize, incomplete: &[(PathBuf, String)]) {
        if incomplete.is_empty() {
            return;
        }
        let mut index = 0;
        self.items.retain(|item| {
            index += 1;
            index <= keep
                || !incomplete.iter().any(|(file, element)| {
                    (*file == item.file && within(&item.path, element))
                        || mentions(&item.message, element)
                })
        });
    }

    /// Fills in source lines from the files read, and sorts by file and position.
    pub fn attach_sources<'t>(&mut self, text_of: impl Fn(&Path) -> Option<&'t str>) {
        for item in &mut self.items {
            if let Some(text) = text_of(&item.file) {
                item.source_line = text
                    .lines()
                    .nth(item.position.line.saturating_sub(1))
                    .map(str::to_owned);
            }
        }
        self.items.sort_by(|a, b| {
            (&a.file, a.position.line, a.position.column).cmp(&(
                &b.file,
                b.position.line,
                b.position.column,
            ))
        });
        self.items.dedup();
    }
}

/// Whether `path` is `element` or lies under it.
fn within(path: &str, element: &str) -> bool {
    path.strip_prefix(element)
        .is_some_and(|rest| rest.is_empty() || rest.starts_with(['.', '[']))
}

/// Whether `message` names the element's path (`first at registers[3]`).
fn mentions(message: &str, element: &str) -> bool {
    message.match_indices(element).any(|(at, _)| {
        let before = message[..at].chars().next_back();
        let after = message[at + element.len()..].chars().next();
        !before.is_some_and(|c| c.is_alphanumeric() || c == '_' || c == '.')
            && !after.is_some_and(|c| c.is_alphanumeric() || c == '_' || c == '.' || c == '[')
    })
}

impl fmt::Display for Diagnostics {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for item in &self.items {
            writeln!(f, "{item}")?;
        }
        let plural = |n: usize| if n == 1 { "" } else { "s" };
        let warnings = self.items.iter().filter(|item| item.is_warning()).count();
        let errors = self.items.len() - warnings;
        match (errors, warnings) {
            (errors, 0) => write!(f, "{errors} problem{} found", plural(errors)),
            (0, warnings) => write!(f, "{warnings} warning{}", plural(warnings)),
            (errors, warnings) => write!(
                f,
                "{errors} problem{} and {warnings} warning{} found",
                plural(errors),
                plural(warnings)
            ),
        }
    }
}

impl std::error::Error for Diagnostics {}
