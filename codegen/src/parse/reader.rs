//! Turns a positioned YAML tree ([`super::tree`]) into the model types with serde, and
//! collects every problem instead of stopping at the first.
//!
//! - An unknown key is reported (with "did you mean" when a known key is close, or as a
//!   mis-indentation when the key belongs to a neighbouring mapping) and skipped.
//! - A missing required key, or a value of the wrong type, is reported and replaced by a
//!   placeholder (zero, empty text, the first allowed value) so that reading goes on. The
//!   element holding a placeholder is listed in [`Outcome::incomplete`], so that later
//!   checks can leave out what would only be a consequence of a problem already reported.
//!
//! Which keys are required comes from the JSON Schema of the model type (schemars reads the
//! same serde attributes as the derived `Deserialize`), because serde only says that a key
//! is missing by failing the whole mapping.

use super::tree::{Node, Value};
use crate::diagnostics::Position;
use schemars::JsonSchema;
use serde::de::{self, DeserializeOwned, DeserializeSeed, Visitor};
use std::cell::{OnceCell, RefCell};
use std::collections::HashMap;
use std::fmt;

/// One problem found while reading.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Problem {
    /// YAML path of the node at fault.
    pub path: String,
    /// Where it is.
    pub position: Position,
    /// What is wrong.
    pub message: String,
    /// How to fix it.
    pub hint: Option<String>,
    kind: Kind,
}

/// What a problem is about, for pairing an unknown key with the missing key it explains.
#[derive(Debug, Clone, PartialEq, Eq)]
enum Kind {
    /// A required key absent from the mapping with this node id.
    MissingKey {
        key: String,
        mapping: usize,
    },
    /// A key indented into a child mapping that its enclosing mapping (this id) expects.
    IndentedTooFar {
        key: String,
        parent: usize,
    },
    Other,
}

/// The result of reading a file.
#[derive(Debug)]
pub struct Outcome<T> {
    /// The value, unless a problem left nothing to build it from.
    pub value: Option<T>,
    /// Every problem, in file order.
    pub problems: Vec<Problem>,
    /// Paths of the elements (a sequence item, or else a top-level key) that hold a
    /// placeholder.
    pub incomplete: Vec<String>,
}

/// Reads `tree` as a `T`.
pub fn read<T: DeserializeOwned + JsonSchema>(tree: &Node) -> Outcome<T> {
    let reader = Reader {
        problems: RefCell::default(),
        incomplete: RefCell::default(),
        fields: RefCell::default(),
        schema: OnceCell::new(),
        schema_of: schema_keys::<T>,
    };
    let root = Path::Root;
    let value = T::deserialize(NodeDe {
        node: Some(tree),
        path: &root,
        reader: &reader,
        parent: None,
    })
    .ok();
    let mut problems = reader.problems.into_inner();
    problems.sort_by_key(|p| (p.position.line, p.position.column));
    problems.dedup();
    let mut incomplete = reader.incomplete.into_inner();
    incomplete.sort();
    incomplete.dedup();
    Outcome {
        value,
        problems,
        incomplete,
    }
}

/// What the schema says about one struct type: its required keys, and what each key holds.
#[derive(Debug, Default)]
struct Keys {
    required: Vec<String>,
    described: HashMap<String, String>,
}

/// The keys of every struct type reachable from `T`, by type name.
fn schema_keys<T: JsonSchema>() -> HashMap<String, Keys> {
    let schema = schemars::SchemaGenerator::default().into_root_schema_for::<T>();
    let value = schema.to_value();
    let keys = |schema: &serde_json::Value| Keys {
        required: schema
            .get("required")
            .and_then(serde_json::Value::as_array)
            .map(|keys| {
                keys.iter()
                    .filter_map(|k| k.as_str().map(str::to_owned))
                    .collect()
            })
            .unwrap_or_default(),
        described: schema
            .get("properties")
            .and_then(serde_json::Value::as_object)
            .map(|properties| {
                properties
                    .iter()
                    .filter_map(|(key, property)| {
                        let text = property.get("description")?.as_str()?;
                        Some((key.clone(), text.split("\n\n").next()?.replace('\n', " ")))
                    })
                    .collect()
            })
            .unwrap_or_default(),
    };
    let mut table = HashMap::new();
    table.insert(T::schema_name().into_owned(), keys(&value));
    for definitions in ["$defs", "definitions"] {
        if let Some(map) = value.get(definitions).and_then(|d| d.as_object()) {
            for (name, schema) in map {
                table.insert(name.clone(), keys(schema));
            }
        }
    }
    table
}

struct Reader {
    problems: RefCell<Vec<Problem>>,
    incomplete: RefCell<Vec<String>>,
    /// The keys each mapping read as a struct accepts, by node id.
    fields: RefCell<HashMap<usize, &'static [&'static str]>>,
    schema: OnceCell<HashMap<String, Keys>>,
    schema_of: fn() -> HashMap<String, Keys>,
}

impl Reader {
    fn keys(&self, name: &str) -> Option<&Keys> {
        self.schema.get_or_init(self.schema_of).get(name)
    }

    fn required(&self, name: &str) -> &[String] {
        self.keys(name).map_or(&[], |keys| keys.required.as_slice())
    }

    /// "add the key: <what the schema says it holds>".
    fn missing_hint(&self, name: &str, key: &str) -> String {
        match self.keys(name).and_then(|keys| keys.described.get(key)) {
            Some(what) => format!("add `{key}`: {what}"),
            None => format!("add `{key}`; drives/README.md says what it holds"),
        }
    }

    fn push(&self, problem: Problem) {
        self.problems.borrow_mut().push(problem);
    }

    /// Reports `key`, a second entry of the mapping at `path` (the first is on `first_line`).
    fn duplicate_key(&self, path: &Path<'_>, key: &Node, first_line: usize) {
        let name = key.text().unwrap_or("");
        self.push(Problem {
            path: Path::Key(path, name).to_string(),
            position: key.at,
            message: format!(
                "key `{name}` appears twice in this mapping (first at line {first_line})"
            ),
            hint: Some("keep one of them".to_owned()),
            kind: Kind::Other,
        });
    }
}

/// A YAML path, built on the stack as the reader descends and written out only for a
/// problem.
#[derive(Clone, Copy)]
enum Path<'a> {
    Root,
    Key(&'a Path<'a>, &'a str),
    Index(&'a Path<'a>, usize),
}

impl fmt::Display for Path<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Path::Root => Ok(()),
            Path::Key(Path::Root, key) => f.write_str(key),
            Path::Key(parent, key) => write!(f, "{parent}.{key}"),
            Path::Index(parent, index) => write!(f, "{parent}[{index}]"),
        }
    }
}

impl Path<'_> {
    /// The element a placeholder at this path makes incomplete: the nearest sequence item,
    /// or else the top-level key.
    fn element(&self) -> String {
        let mut path = self;
        let mut top = self;
        loop {
            match path {
                Path::Root => return top.to_string(),
                Path::Index(..) => return path.to_string(),
                Path::Key(parent, _) => {
                    top = path;
                    path = parent;
                }
            }
        }
    }
}

/// An error while reading: either already reported, or a visitor's complaint to report at
/// the node being read.
#[derive(Debug)]
pub struct Error(Complaint);

#[derive(Debug)]
enum Complaint {
    Reported,
    Message(String),
    MissingKey(&'static str),
    UnknownKey(String, &'static [&'static str]),
    UnknownValue(String, &'static [&'static str]),
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match &self.0 {
            Complaint::Reported => f.write_str("reported"),
            Complaint::Message(message) => f.write_str(message),
            Complaint::MissingKey(key) => write!(f, "missing key `{key}`"),
            Complaint::UnknownKey(key, _) => write!(f, "unknown key `{key}`"),
            Complaint::UnknownValue(value, _) => write!(f, "unknown value `{value}`"),
        }
    }
}

impl std::error::Error for Error {}

impl de::Error for Error {
    fn custom<M: fmt::Display>(message: M) -> Self {
        Error(Complaint::Message(message.to_string()))
    }

    fn missing_field(field: &'static str) -> Self {
        Error(Complaint::MissingKey(field))
    }

    fn unknown_field(field: &str, expected: &'static [&'static str]) -> Self {
        Error(Complaint::UnknownKey(field.to_owned(), expected))
    }

    fn unknown_variant(variant: &str, expected: &'static [&'static str]) -> Self {
        Error(Complaint::UnknownValue(variant.to_owned(), expected))
    }
}

const REPORTED: Error = Error(Complaint::Reported);

/// A scalar as YAML 1.2's core schema reads a plain one.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Scalar<'t> {
    Null,
    Bool(bool),
    Int(i128),
    Float(f64),
    Text(&'t str),
}

fn resolve(node: &Node) -> Option<Scalar<'_>> {
    let Value::Scalar { text, plain } = &node.value else {
        return None;
    };
    if !plain {
        return Some(Scalar::Text(text));
    }
    Some(match text.as_str() {
        "" | "~" | "null" | "Null" | "NULL" => Scalar::Null,
        "true" | "True" | "TRUE" => Scalar::Bool(true),
        "false" | "False" | "FALSE" => Scalar::Bool(false),
        ".inf" | ".Inf" | ".INF" | "+.inf" | "+.Inf" | "+.INF" => Scalar::Float(f64::INFINITY),
        "-.inf" | "-.Inf" | "-.INF" => Scalar::Float(f64::NEG_INFINITY),
        ".nan" | ".NaN" | ".NAN" => Scalar::Float(f64::NAN),
        other => integer(other)
            .map(Scalar::Int)
            .or_else(|| float(other).map(Scalar::Float))
            .unwrap_or(Scalar::Text(other)),
    })
}

fn integer(text: &str) -> Option<i128> {
    let (negative, digits) = match text.as_bytes().first()? {
        b'-' => (true, &text[1..]),
        b'+' => (false, &text[1..]),
        _ => (false, text),
    };
    let (radix, digits) = if let Some(hex) = digits.strip_prefix("0x") {
        (16, hex)
    } else if let Some(octal) = digits.strip_prefix("0o") {
        (8, octal)
    } else {
        (10, digits)
    };
    if digits.is_empty() || !digits.chars().all(|c| c.is_digit(radix)) {
        return None;
    }
    let value = i128::from_str_radix(digits, radix).ok()?;
    Some(if negative { -value } else { value })
}

fn float(text: &str) -> Option<f64> {
    let digits = text.trim_start_matches(['-', '+']);
    let numeric = digits.starts_with(|c: char| c.is_ascii_digit() || c == '.')
        && digits.chars().any(|c| c.is_ascii_digit())
        && digits
            .chars()
            .all(|c| c.is_ascii_digit() || matches!(c, '.' | 'e' | 'E' | '-' | '+'));
    numeric.then(|| text.parse().ok()).flatten()
}

/// How a node is named in "found ..." messages.
fn found(node: &Node) -> String {
    match resolve(node) {
        Some(Scalar::Null) => "nothing".to_owned(),
        Some(Scalar::Bool(value)) => format!("`{value}`"),
        Some(Scalar::Int(_) | Scalar::Float(_)) => {
            format!("the number {}", node.text().unwrap_or(""))
        }
        Some(Scalar::Text(text)) => format!("the text `{text}`"),
        None => match node.value {
            Value::Sequence(_) => "a list".to_owned(),
            _ => "a mapping (keys with values)".to_owned(),
        },
    }
}

/// Levenshtein distance between two short names.
pub(crate) fn edit_distance(a: &str, b: &str) -> usize {
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

/// The known name closest to `written`, when at most a third of its letters differ (or it
/// differs only in case, `-` and `_`).
pub fn closest<'k>(written: &str, known: &[&'k str]) -> Option<&'k str> {
    let folded = |s: &str| s.to_lowercase().replace('-', "_");
    if let Some(same) = known.iter().find(|k| folded(k) == folded(written)) {
        return Some(same);
    }
    let (distance, best) = known
        .iter()
        .map(|candidate| (edit_distance(written, candidate), *candidate))
        .min_by_key(|(distance, _)| *distance)?;
    (distance <= (written.chars().count() / 3).max(1)).then_some(best)
}

fn list(names: &[&str]) -> String {
    names
        .iter()
        .map(|name| format!("`{name}`"))
        .collect::<Vec<_>>()
        .join(", ")
}

/// The mapping a value sits in, read as a struct: its node id, the keys it accepts and the
/// entries it has.
type Enclosing<'a> = (usize, &'static [&'static str], &'a [&'a (Node, Node)]);

/// Reads one node (or, with `node: None`, a placeholder for a missing one).
struct NodeDe<'a> {
    node: Option<&'a Node>,
    path: &'a Path<'a>,
    reader: &'a Reader,
    /// The mapping this node is a value of, read as a struct: its id and its keys.
    /// With the keys it has, so that a key it already has is not said to belong there.
    parent: Option<Enclosing<'a>>,
}

impl<'a> NodeDe<'a> {
    fn report(&self, message: String, hint: Option<String>) {
        let Some(node) = self.node else { return };
        self.reader.push(Problem {
            path: self.path.to_string(),
            position: node.at,
            message,
            hint,
            kind: Kind::Other,
        });
    }

    /// Reports a value of the wrong shape and marks its element incomplete.
    fn wrong(&self, expected: &str) {
        if let Some(node) = self.node {
            self.report(
                format!("expected {expected}, found {}", found(node)),
                Some(hint_for_type(expected).to_owned()),
            );
            self.placeholder();
        }
    }

    fn placeholder(&self) {
        self.reader
            .incomplete
            .borrow_mut()
            .push(self.path.element());
    }

    /// Reports a visitor's complaint at this node, once.
    fn locate(&self, error: Error) -> Error {
        let (message, hint) = match error.0 {
            Complaint::Reported => return REPORTED,
            Complaint::Message(message) => {
                let hint = crate::parse::hint_for(&message).map(str::to_owned);
                (message, hint)
            }
            Complaint::MissingKey(key) => (
                format!("missing key `{key}`"),
                Some("add the key; drives/README.md says what it holds".to_owned()),
            ),
            Complaint::UnknownKey(key, known) => (
                format!("unknown key `{key}`"),
                Some(unknown_hint(&key, known, "key")),
            ),
            Complaint::UnknownValue(value, known) => (
                format!("unknown value `{value}`"),
                Some(unknown_hint(&value, known, "value")),
            ),
        };
        self.report(message, hint);
        REPORTED
    }

    fn child<'c>(&'c self, node: Option<&'c Node>, path: &'c Path<'c>) -> NodeDe<'c> {
        NodeDe {
            node,
            path,
            reader: self.reader,
            parent: None,
        }
    }

    fn integer<'de, V: Visitor<'de>>(
        self,
        min: i128,
        max: i128,
        visitor: V,
    ) -> Result<V::Value, Error> {
        let value = match self.node.map(resolve) {
            None => 0,
            Some(Some(Scalar::Int(n))) if (min..=max).contains(&n) => n,
            Some(Some(Scalar::Int(n))) => {
                self.report(
                    format!("{n} is out of range: expected a whole number from {min} to {max}"),
                    None,
                );
                self.placeholder();
                0
            }
            Some(_) => {
                self.wrong(&format!("a whole number from {min} to {max}"));
                0
            }
        };
        let result = if min < 0 {
            visitor.visit_i64(value as i64)
        } else {
            visitor.visit_u64(value as u64)
        };
        result.map_err(|e| self.locate(e))
    }

    fn number<'de, V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, Error> {
        let value = match self.node.map(resolve) {
            None => 0.0,
            Some(Some(Scalar::Int(n))) => n as f64,
            Some(Some(Scalar::Float(x))) => x,
            Some(_) => {
                self.wrong("a number");
                0.0
            }
        };
        visitor.visit_f64(value).map_err(|e| self.locate(e))
    }

    fn text<'de, V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, Error> {
        let text = match self.node {
            None => "",
            Some(node) => match (resolve(node), node.text()) {
                (Some(Scalar::Null), _) => {
                    self.wrong("text");
                    ""
                }
                (Some(_), Some(text)) => text,
                _ => {
                    self.wrong("text");
                    ""
                }
            },
        };
        visitor.visit_str(text).map_err(|e| self.locate(e))
    }

    fn sequence<'de, V: Visitor<'de>>(
        self,
        length: Option<usize>,
        visitor: V,
    ) -> Result<V::Value, Error> {
        let items: &[Node] = match self.node.map(|n| &n.value) {
            Some(Value::Sequence(items)) => match length {
                Some(length) if items.len() != length => {
                    self.report(
                        format!("expected a list of {length} values, found {}", items.len()),
                        None,
                    );
                    self.placeholder();
                    let access = SeqDe {
                        items: &[],
                        placeholders: length,
                        index: 0,
                        path: self.path,
                        reader: self.reader,
                    };
                    return visitor.visit_seq(access).map_err(|e| self.locate(e));
                }
                _ => items,
            },
            None => &[],
            Some(_) => {
                match length {
                    Some(length) => self.wrong(&format!("a list of {length} values")),
                    None => self.wrong("a list"),
                }
                &[]
            }
        };
        let placeholders = if items.is_empty() {
            length.unwrap_or(0)
        } else {
            0
        };
        let access = SeqDe {
            items,
            placeholders,
            index: 0,
            path: self.path,
            reader: self.reader,
        };
        visitor.visit_seq(access).map_err(|e| self.locate(e))
    }

    fn structure<'de, V: Visitor<'de>>(
        self,
        name: &'static str,
        fields: &'static [&'static str],
        visitor: V,
    ) -> Result<V::Value, Error> {
        // "A mapping with these keys, or a scalar" (`model::OR_SCALAR`): a scalar goes to
        // the visitor as itself.
        let name = match name.strip_suffix(super::model::OR_SCALAR) {
            Some(base) => {
                if matches!(self.node.map(|n| &n.value), Some(Value::Scalar { .. })) {
                    return de::Deserializer::deserialize_any(self, visitor);
                }
                base
            }
            None => name,
        };
        let entries: &[(Node, Node)] = match self.node.map(|n| &n.value) {
            Some(Value::Mapping(entries)) => entries,
            None => &[],
            Some(_) => {
                self.wrong("a mapping (keys with values)");
                &[]
            }
        };
        let Some(node) = self.node.filter(|n| matches!(n.value, Value::Mapping(_))) else {
            // A placeholder: every required key gets one too, silently.
            let missing = self.static_names(self.reader.required(name), fields);
            let access = StructDe {
                entries: Vec::new(),
                missing,
                index: 0,
                path: self.path,
                reader: self.reader,
                id: 0,
                fields,
            };
            return visitor.visit_map(access).map_err(|e| self.locate(e));
        };
        self.reader.fields.borrow_mut().insert(node.id, fields);
        let mut kept: Vec<&(Node, Node)> = Vec::with_capacity(entries.len());
        let mut unknown: Vec<&(Node, Node)> = Vec::new();
        for entry in entries {
            let key = entry.0.text().unwrap_or("");
            if !fields.contains(&key) {
                unknown.push(entry);
            } else if let Some(first) = kept.iter().find(|(k, _)| k.text() == Some(key)) {
                self.reader
                    .duplicate_key(self.path, &entry.0, first.0.at.line);
            } else {
                kept.push(entry);
            }
        }
        let present: Vec<&str> = kept.iter().filter_map(|(k, _)| k.text()).collect();
        let required: Vec<String> = self
            .reader
            .required(name)
            .iter()
            .filter(|key| !present.contains(&key.as_str()))
            .cloned()
            .collect();
        let missing = self.static_names(&required, fields);
        let access = StructDe {
            entries: kept,
            missing: missing.clone(),
            index: 0,
            path: self.path,
            reader: self.reader,
            id: node.id,
            fields,
        };
        let result = visitor.visit_map(access).map_err(|e| self.locate(e));
        let mut explained: Vec<&str> = Vec::new();
        for (key, _) in unknown {
            if let Some(covers) = self.unknown_key(key, entries, fields) {
                explained.push(covers);
            }
        }
        for key in missing {
            let moved_here = self.reader.problems.borrow().iter().any(|p| {
                p.kind
                    == Kind::IndentedTooFar {
                        key: key.to_owned(),
                        parent: node.id,
                    }
            });
            if !moved_here && !explained.contains(&key) {
                self.reader.push(Problem {
                    path: self.path.to_string(),
                    position: node.at,
                    message: format!("missing key `{key}`"),
                    hint: Some(self.reader.missing_hint(name, key)),
                    kind: Kind::MissingKey {
                        key: key.to_owned(),
                        mapping: node.id,
                    },
                });
            }
            self.placeholder();
        }
        result
    }

    /// `names` as the `&'static str`s of `fields` (serde wants static keys).
    fn static_names(&self, names: &[String], fields: &'static [&'static str]) -> Vec<&'static str> {
        names
            .iter()
            .filter_map(|name| fields.iter().copied().find(|f| f == name))
            .collect()
    }

    /// Reports an unknown key of `mapping`; returns the missing key it explains, if any.
    fn unknown_key(
        &self,
        key: &Node,
        entries: &[(Node, Node)],
        fields: &'static [&'static str],
    ) -> Option<&'static str> {
        let name = key.text().unwrap_or("");
        let path = Path::Key(self.path, name).to_string();
        let problem = |message: String, hint: String, kind: Kind| Problem {
            path: path.clone(),
            position: key.at,
            message,
            hint: Some(hint),
            kind,
        };
        // Written too far left: a mapping above this key expects it.
        let known = self.reader.fields.borrow();
        let owner = entries.iter().rev().find(|(k, v)| {
            k.at.line < key.at.line && known.get(&v.id).is_some_and(|f| f.contains(&name))
        });
        if let Some((owner_key, owner_value)) = owner {
            let owner_name = owner_key.text().unwrap_or("");
            drop(known);
            self.reader.problems.borrow_mut().retain(|p| {
                p.kind
                    != Kind::MissingKey {
                        key: name.to_owned(),
                        mapping: owner_value.id,
                    }
            });
            self.reader.push(problem(
                format!(
                    "`{name}` is not a key here: it belongs to `{owner_name}` (line {}), and is indented too little",
                    owner_key.at.line
                ),
                format!("indent `{name}` like the other keys under `{owner_name}`"),
                Kind::Other,
            ));
            return None;
        }
        drop(known);
        // Written too far right: the mapping around this one expects it.
        if let Some((parent, parent_fields, parent_entries)) = self.parent {
            let has_it = parent_entries.iter().any(|(k, _)| k.text() == Some(name));
            if parent_fields.contains(&name) && !has_it {
                self.reader.push(problem(
                    format!(
                        "`{name}` is not a key of `{}`: it is indented too far",
                        match self.path {
                            Path::Key(_, own) => own,
                            _ => "this mapping",
                        }
                    ),
                    format!("indent `{name}` like the keys of the mapping around it"),
                    Kind::IndentedTooFar {
                        key: name.to_owned(),
                        parent,
                    },
                ));
                return None;
            }
        }
        let suggestion = closest(name, fields);
        if suggestion.is_some() {
            // A misspelt key: the key meant is effectively missing, so what later checks
            // would say about its absence is a consequence.
            self.placeholder();
        }
        self.reader.push(problem(
            format!("unknown key `{name}`"),
            unknown_hint(name, fields, "key"),
            Kind::Other,
        ));
        suggestion
    }
}

/// "did you mean `x`?", or the list of what is allowed.
fn unknown_hint(written: &str, known: &[&str], what: &str) -> String {
    if written.contains(' ') && what == "key" {
        return "inside `{ ... }` an unquoted comma ends the value: put text containing commas in quotes".to_owned();
    }
    match closest(written, known) {
        Some(best) => format!("did you mean `{best}`?"),
        None if known.is_empty() => format!("no {what} is allowed here"),
        None => format!(
            "the {what}s allowed here are {}; drives/README.md says what each means",
            list(known)
        ),
    }
}

fn hint_for_type(expected: &str) -> &'static str {
    if expected.starts_with("a whole number") || expected == "a number" {
        "numbers may be decimal or 0x-hex; text in quotes is text"
    } else if expected.starts_with("a mapping") {
        "write `key: value` lines indented under the key, or `{ key: value, ... }`"
    } else if expected.starts_with("a list") {
        "write `- item` lines indented under the key, or `[a, b]`"
    } else {
        "check the value against drives/README.md"
    }
}

macro_rules! integers {
    ($($method:ident: $ty:ty),* $(,)?) => {$(
        fn $method<V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, Error> {
            self.integer(<$ty>::MIN as i128, <$ty>::MAX as i128, visitor)
        }
    )*};
}

/// Methods that read any scalar as its text.
macro_rules! texts {
    ($($method:ident),* $(,)?) => {$(
        fn $method<V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, Error> {
            self.text(visitor)
        }
    )*};
}

impl<'de> de::Deserializer<'de> for NodeDe<'_> {
    type Error = Error;

    fn deserialize_any<V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, Error> {
        let Some(node) = self.node else {
            return visitor.visit_u64::<Error>(0).map_err(|_| REPORTED);
        };
        let result = match &node.value {
            Value::Sequence(_) => return self.sequence(None, visitor),
            Value::Mapping(entries) => visitor.visit_map(MapDe {
                entries,
                index: 0,
                path: self.path,
                reader: self.reader,
            }),
            Value::Scalar { .. } => match resolve(node) {
                Some(Scalar::Null) | None => visitor.visit_unit(),
                Some(Scalar::Bool(value)) => visitor.visit_bool(value),
                Some(Scalar::Int(n)) => match (u64::try_from(n), i64::try_from(n)) {
                    (Ok(n), _) => visitor.visit_u64(n),
                    (_, Ok(n)) => visitor.visit_i64(n),
                    _ => visitor.visit_f64(n as f64),
                },
                Some(Scalar::Float(x)) => visitor.visit_f64(x),
                Some(Scalar::Text(text)) => visitor.visit_str(text),
            },
        };
        result.map_err(|e| self.locate(e))
    }

    integers!(
        deserialize_u8: u8, deserialize_u16: u16, deserialize_u32: u32, deserialize_u64: u64,
        deserialize_i8: i8, deserialize_i16: i16, deserialize_i32: i32, deserialize_i64: i64,
    );

    fn deserialize_f32<V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, Error> {
        self.number(visitor)
    }

    fn deserialize_f64<V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, Error> {
        self.number(visitor)
    }

    fn deserialize_bool<V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, Error> {
        let value = match self.node.map(resolve) {
            None => false,
            Some(Some(Scalar::Bool(value))) => value,
            Some(_) => {
                self.wrong("`true` or `false`");
                false
            }
        };
        visitor.visit_bool(value).map_err(|e| self.locate(e))
    }

    texts!(
        deserialize_char,
        deserialize_str,
        deserialize_string,
        deserialize_bytes,
        deserialize_byte_buf,
        deserialize_identifier,
    );

    fn deserialize_option<V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, Error> {
        match self.node.map(resolve) {
            None | Some(Some(Scalar::Null)) => visitor.visit_none().map_err(|e| self.locate(e)),
            Some(_) => visitor.visit_some(self),
        }
    }

    fn deserialize_unit<V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, Error> {
        match self.node.map(resolve) {
            None | Some(Some(Scalar::Null)) => {}
            Some(_) => self.wrong("nothing"),
        }
        visitor.visit_unit().map_err(|e| self.locate(e))
    }

    fn deserialize_unit_struct<V: Visitor<'de>>(
        self,
        _name: &'static str,
        visitor: V,
    ) -> Result<V::Value, Error> {
        self.deserialize_unit(visitor)
    }

    fn deserialize_newtype_struct<V: Visitor<'de>>(
        self,
        _name: &'static str,
        visitor: V,
    ) -> Result<V::Value, Error> {
        visitor.visit_newtype_struct(self)
    }

    fn deserialize_seq<V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, Error> {
        self.sequence(None, visitor)
    }

    fn deserialize_tuple<V: Visitor<'de>>(self, len: usize, visitor: V) -> Result<V::Value, Error> {
        self.sequence(Some(len), visitor)
    }

    fn deserialize_tuple_struct<V: Visitor<'de>>(
        self,
        _name: &'static str,
        len: usize,
        visitor: V,
    ) -> Result<V::Value, Error> {
        self.sequence(Some(len), visitor)
    }

    fn deserialize_map<V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, Error> {
        let entries: &[(Node, Node)] = match self.node.map(|n| &n.value) {
            Some(Value::Mapping(entries)) => entries,
            None => &[],
            Some(_) if matches!(self.node.map(resolve), Some(Some(Scalar::Null))) => &[],
            Some(_) => {
                self.wrong("a mapping (keys with values)");
                &[]
            }
        };
        visitor
            .visit_map(MapDe {
                entries,
                index: 0,
                path: self.path,
                reader: self.reader,
            })
            .map_err(|e| self.locate(e))
    }

    fn deserialize_struct<V: Visitor<'de>>(
        self,
        name: &'static str,
        fields: &'static [&'static str],
        visitor: V,
    ) -> Result<V::Value, Error> {
        self.structure(name, fields, visitor)
    }

    fn deserialize_enum<V: Visitor<'de>>(
        self,
        _name: &'static str,
        variants: &'static [&'static str],
        visitor: V,
    ) -> Result<V::Value, Error> {
        let first = variants.first().copied().unwrap_or("");
        let (variant, content): (&str, Option<&Node>) = match self.node {
            None => (first, None),
            Some(node) => match (&node.value, resolve(node)) {
                (Value::Scalar { text, .. }, Some(scalar)) if scalar != Scalar::Null => {
                    if variants.contains(&text.as_str()) {
                        (text.as_str(), None)
                    } else {
                        self.report(
                            format!("unknown value `{text}`"),
                            Some(unknown_hint(text, variants, "value")),
                        );
                        self.placeholder();
                        (first, None)
                    }
                }
                (Value::Mapping(entries), _) if entries.len() == 1 => {
                    let (key, value) = &entries[0];
                    match key.text().filter(|k| variants.contains(k)) {
                        Some(key) => (key, Some(value)),
                        None => {
                            self.report(
                                format!("unknown value `{}`", key.text().unwrap_or("")),
                                Some(unknown_hint(key.text().unwrap_or(""), variants, "value")),
                            );
                            self.placeholder();
                            (first, None)
                        }
                    }
                }
                _ => {
                    self.wrong(&format!("one of {}", list(variants)));
                    (first, None)
                }
            },
        };
        let path = Path::Key(self.path, variant);
        let access = EnumDe {
            variant,
            content: self.child(content, if content.is_some() { &path } else { self.path }),
        };
        visitor.visit_enum(access).map_err(|e| self.locate(e))
    }

    fn deserialize_ignored_any<V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, Error> {
        visitor.visit_unit()
    }
}

/// A mapping read as a struct: known keys in document order, then placeholders for the
/// required keys that are missing.
struct StructDe<'a> {
    entries: Vec<&'a (Node, Node)>,
    missing: Vec<&'static str>,
    index: usize,
    path: &'a Path<'a>,
    reader: &'a Reader,
    id: usize,
    fields: &'static [&'static str],
}

impl<'de> de::MapAccess<'de> for StructDe<'_> {
    type Error = Error;

    fn next_key_seed<K: DeserializeSeed<'de>>(
        &mut self,
        seed: K,
    ) -> Result<Option<K::Value>, Error> {
        let key = match self.entries.get(self.index) {
            Some((key, _)) => key.text().unwrap_or(""),
            None => match self.missing.get(self.index - self.entries.len()) {
                Some(key) => key,
                None => return Ok(None),
            },
        };
        seed.deserialize(KeyDe(key)).map(Some)
    }

    fn next_value_seed<S: DeserializeSeed<'de>>(&mut self, seed: S) -> Result<S::Value, Error> {
        let index = self.index;
        self.index += 1;
        let (key, node) = match self.entries.get(index) {
            Some((key, value)) => (key.text().unwrap_or(""), Some(value)),
            None => (
                self.missing
                    .get(index - self.entries.len())
                    .copied()
                    .unwrap_or(""),
                None,
            ),
        };
        let path = Path::Key(self.path, key);
        seed.deserialize(NodeDe {
            node,
            path: &path,
            reader: self.reader,
            parent: (self.id != 0).then_some((self.id, self.fields, &self.entries[..])),
        })
    }
}

/// A mapping read as a map (keys of any type).
struct MapDe<'a> {
    entries: &'a [(Node, Node)],
    index: usize,
    path: &'a Path<'a>,
    reader: &'a Reader,
}

impl<'de> de::MapAccess<'de> for MapDe<'_> {
    type Error = Error;

    fn next_key_seed<K: DeserializeSeed<'de>>(
        &mut self,
        seed: K,
    ) -> Result<Option<K::Value>, Error> {
        while let Some((key, _)) = self.entries.get(self.index) {
            let earlier = self.entries[..self.index]
                .iter()
                .find(|(k, _)| k.text() == key.text());
            let Some((first, _)) = earlier else { break };
            self.reader.duplicate_key(self.path, key, first.at.line);
            self.index += 1;
        }
        let Some((key, _)) = self.entries.get(self.index) else {
            return Ok(None);
        };
        let path = Path::Key(self.path, key.text().unwrap_or(""));
        seed.deserialize(NodeDe {
            node: Some(key),
            path: &path,
            reader: self.reader,
            parent: None,
        })
        .map(Some)
    }

    fn next_value_seed<S: DeserializeSeed<'de>>(&mut self, seed: S) -> Result<S::Value, Error> {
        let (key, value) = &self.entries[self.index];
        self.index += 1;
        let path = Path::Key(self.path, key.text().unwrap_or(""));
        seed.deserialize(NodeDe {
            node: Some(value),
            path: &path,
            reader: self.reader,
            parent: None,
        })
    }
}

/// A sequence's items, or placeholders for a list of fixed length.
struct SeqDe<'a> {
    items: &'a [Node],
    placeholders: usize,
    index: usize,
    path: &'a Path<'a>,
    reader: &'a Reader,
}

impl<'de> de::SeqAccess<'de> for SeqDe<'_> {
    type Error = Error;

    fn next_element_seed<S: DeserializeSeed<'de>>(
        &mut self,
        seed: S,
    ) -> Result<Option<S::Value>, Error> {
        let index = self.index;
        if index >= self.items.len().max(self.placeholders) {
            return Ok(None);
        }
        self.index += 1;
        let path = Path::Index(self.path, index);
        seed.deserialize(NodeDe {
            node: self.items.get(index),
            path: &path,
            reader: self.reader,
            parent: None,
        })
        .map(Some)
    }

    fn size_hint(&self) -> Option<usize> {
        Some(self.items.len().max(self.placeholders) - self.index)
    }
}

/// A mapping key, read as text.
struct KeyDe<'k>(&'k str);

impl<'de> de::Deserializer<'de> for KeyDe<'_> {
    type Error = Error;

    fn deserialize_any<V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, Error> {
        visitor.visit_str(self.0)
    }

    serde::forward_to_deserialize_any! {
        bool i8 i16 i32 i64 i128 u8 u16 u32 u64 u128 f32 f64 char str string
        bytes byte_buf option unit unit_struct newtype_struct seq tuple
        tuple_struct map struct enum identifier ignored_any
    }
}

/// An enum's variant and its content.
struct EnumDe<'a> {
    variant: &'a str,
    content: NodeDe<'a>,
}

impl<'de, 'a> de::EnumAccess<'de> for EnumDe<'a> {
    type Error = Error;
    type Variant = NodeDe<'a>;

    fn variant_seed<S: DeserializeSeed<'de>>(
        self,
        seed: S,
    ) -> Result<(S::Value, NodeDe<'a>), Error> {
        let variant = seed.deserialize(KeyDe(self.variant))?;
        Ok((variant, self.content))
    }
}

impl<'de> de::VariantAccess<'de> for NodeDe<'_> {
    type Error = Error;

    fn unit_variant(self) -> Result<(), Error> {
        Ok(())
    }

    fn newtype_variant_seed<S: DeserializeSeed<'de>>(self, seed: S) -> Result<S::Value, Error> {
        seed.deserialize(self)
    }

    fn tuple_variant<V: Visitor<'de>>(self, len: usize, visitor: V) -> Result<V::Value, Error> {
        self.sequence(Some(len), visitor)
    }

    fn struct_variant<V: Visitor<'de>>(
        self,
        fields: &'static [&'static str],
        visitor: V,
    ) -> Result<V::Value, Error> {
        self.structure("", fields, visitor)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::parse::tree;
    use serde::Deserialize;

    #[derive(Debug, Deserialize, JsonSchema, PartialEq)]
    #[serde(deny_unknown_fields)]
    struct Range {
        min: f64,
        max: f64,
    }

    #[derive(Debug, Deserialize, JsonSchema, PartialEq)]
    #[serde(deny_unknown_fields, rename_all = "kebab-case")]
    enum Access {
        ReadOnly,
        ReadWrite,
    }

    #[derive(Debug, Deserialize, JsonSchema, PartialEq)]
    #[serde(deny_unknown_fields)]
    struct Item {
        address: u16,
        name: String,
        range: Option<Range>,
        access: Option<Access>,
        #[serde(default)]
        tags: Vec<String>,
    }

    #[derive(Debug, Deserialize, JsonSchema, PartialEq)]
    #[serde(deny_unknown_fields)]
    struct File {
        items: Vec<Item>,
        pair: Option<[u16; 2]>,
    }

    fn read_text(text: &str) -> Outcome<File> {
        read(&tree::read(text).unwrap())
    }

    fn messages(outcome: &Outcome<File>) -> Vec<String> {
        outcome
            .problems
            .iter()
            .map(|p| {
                format!(
                    "{}:{} {} | {} | {}",
                    p.position.line,
                    p.position.column,
                    p.path,
                    p.message,
                    p.hint.as_deref().unwrap_or("")
                )
            })
            .collect()
    }

    #[test]
    fn a_valid_file_reads_plainly() {
        let outcome = read_text(
            "items:\n  - { address: 0x10, name: a, range: { min: 0, max: 1.5 }, access: read-only }\npair: [1, 2]\n",
        );
        assert!(outcome.problems.is_empty(), "{:?}", outcome.problems);
        let file = outcome.value.unwrap();
        assert_eq!(file.items[0].address, 16);
        assert_eq!(file.items[0].range, Some(Range { min: 0.0, max: 1.5 }));
        assert_eq!(file.items[0].access, Some(Access::ReadOnly));
        assert_eq!(file.pair, Some([1, 2]));
    }

    #[test]
    fn every_problem_is_reported_in_one_read() {
        let outcome = read_text(concat!(
            "items:\n",
            "  - { address: twelve, name: a }\n",
            "  - { adress: 3, name: b }\n",
            "  - { address: 4, name: c, access: readonly }\n",
            "  - { address: 70000, name: d, colour: red }\n",
            "pair: [1]\n",
        ));
        assert_eq!(
            messages(&outcome),
            [
                "2:16 items[0].address | expected a whole number from 0 to 65535, found the text `twelve` | numbers may be decimal or 0x-hex; text in quotes is text",
                "3:7 items[1].adress | unknown key `adress` | did you mean `address`?",
                "4:36 items[2].access | unknown value `readonly` | did you mean `read-only`?",
                "5:16 items[3].address | 70000 is out of range: expected a whole number from 0 to 65535 | ",
                "5:32 items[3].colour | unknown key `colour` | the keys allowed here are `address`, `name`, `range`, `access`, `tags`; drives/README.md says what each means",
                "6:1 pair | expected a list of 2 values, found 1 | ",
            ]
        );
        assert!(
            outcome.value.is_some(),
            "placeholders keep the file readable"
        );
        assert_eq!(
            outcome.incomplete,
            ["items[0]", "items[1]", "items[2]", "items[3]", "pair"]
        );
    }

    #[test]
    fn missing_keys_are_all_reported() {
        let outcome = read_text("items:\n  - { tags: [] }\n");
        assert_eq!(
            messages(&outcome),
            [
                "2:7 items[0] | missing key `address` | add `address`; drives/README.md says what it holds",
                "2:7 items[0] | missing key `name` | add `name`; drives/README.md says what it holds",
            ]
        );
    }

    #[test]
    fn a_key_indented_too_little_is_reported_where_it_is() {
        let outcome = read_text(concat!(
            "items:\n",
            "  - address: 1\n",
            "    name: a\n",
            "    range:\n",
            "      min: 0\n",
            "    max: 10\n",
        ));
        assert_eq!(
            messages(&outcome),
            ["6:5 items[0].max | `max` is not a key here: it belongs to `range` (line 4), and is indented too little | indent `max` like the other keys under `range`"]
        );
    }

    #[test]
    fn a_key_indented_too_far_is_reported_where_it_is() {
        let outcome = read_text(concat!(
            "items:\n",
            "  - address: 1\n",
            "    range:\n",
            "      min: 0\n",
            "      max: 10\n",
            "      name: a\n",
        ));
        assert_eq!(
            messages(&outcome),
            ["6:7 items[0].range.name | `name` is not a key of `range`: it is indented too far | indent `name` like the keys of the mapping around it"]
        );
    }

    #[test]
    fn a_key_the_enclosing_mapping_already_has_is_just_unknown() {
        let outcome = read_text(concat!(
            "items:\n",
            "  - address: 1\n",
            "    name: a\n",
            "    range:\n",
            "      min: 0\n",
            "      max: 10\n",
            "      name: b\n",
        ));
        assert_eq!(
            messages(&outcome),
            ["7:7 items[0].range.name | unknown key `name` | the keys allowed here are `min`, `max`; drives/README.md says what each means"]
        );
    }

    #[test]
    fn a_duplicate_key_is_reported() {
        let outcome = read_text("items:\n  - { address: 1, name: a, name: b }\n");
        assert_eq!(
            messages(&outcome),
            ["2:28 items[0].name | key `name` appears twice in this mapping (first at line 2) | keep one of them"]
        );
    }

    #[test]
    fn plain_scalars_follow_the_core_schema() {
        let node = |text: &str| tree::read(text).unwrap();
        assert_eq!(resolve(&node("0x1F")), Some(Scalar::Int(31)));
        assert_eq!(resolve(&node("-12")), Some(Scalar::Int(-12)));
        assert_eq!(resolve(&node("0o17")), Some(Scalar::Int(15)));
        assert_eq!(resolve(&node("1.5e3")), Some(Scalar::Float(1500.0)));
        assert_eq!(resolve(&node("'12'")), Some(Scalar::Text("12")));
        assert_eq!(resolve(&node("~")), Some(Scalar::Null));
        assert_eq!(resolve(&node("inf")), Some(Scalar::Text("inf")));
        assert_eq!(resolve(&node("FH")), Some(Scalar::Text("FH")));
        assert_eq!(resolve(&node("1e")), Some(Scalar::Text("1e")));
    }

    #[test]
    fn close_names_are_suggested() {
        assert_eq!(closest("fromat", &["literal", "format"]), Some("format"));
        assert_eq!(
            closest("readonly", &["read-only", "read-write"]),
            Some("read-only")
        );
        assert_eq!(closest("register", &["parameter", "coil"]), None);
    }
}
