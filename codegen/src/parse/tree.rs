//! A YAML document read once, with `yaml-rust2`, into a tree of nodes that keep their
//! positions: the reader ([`super::reader`]) turns it into the model types, and messages
//! found later point into it.

use crate::diagnostics::Position;
use std::collections::HashMap;
use yaml_rust2::parser::{Event, MarkedEventReceiver, Parser};
use yaml_rust2::scanner::{Marker, TScalarStyle};

/// One node of the document.
#[derive(Debug, Clone, PartialEq)]
pub struct Node {
    /// What the node holds.
    pub value: Value,
    /// Where messages about the node point: a scalar's first character; a collection's key
    /// when it is a mapping's value (`reply:`), else its first entry.
    pub at: Position,
    /// Number of the node in document order, unique within its tree.
    pub id: usize,
}

/// The content of a [`Node`].
#[derive(Debug, Clone, PartialEq)]
pub enum Value {
    /// A scalar as written, and whether it was written plain (unquoted): only plain scalars
    /// are numbers, booleans or null.
    Scalar {
        /// The text as written (without quotes).
        text: String,
        /// Written plain (unquoted).
        plain: bool,
    },
    /// A sequence.
    Sequence(Vec<Node>),
    /// A mapping, in document order; keys are scalars (a complex key is kept as its text).
    Mapping(Vec<(Node, Node)>),
}

/// A YAML syntax error.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SyntaxError {
    /// Where the fix goes: the opening `{` or `[` when one is left unclosed, else where the
    /// parser noticed the problem.
    pub position: Position,
    /// What the parser says, with where it noticed it when that differs from `position`.
    pub message: String,
}

impl Node {
    /// The node at a YAML path (`registers[3].range.max`, `registers[3].range#key` for a
    /// key), if the document has it.
    pub fn find(&self, path: &str) -> Option<&Node> {
        let (path, key) = match path.strip_suffix("#key") {
            Some(stripped) => (stripped, true),
            None => (path, false),
        };
        let mut node = self;
        let mut segments = segments(path).peekable();
        while let Some(segment) = segments.next() {
            let last = segments.peek().is_none();
            node = match (segment, &node.value) {
                (Segment::Key(name), Value::Mapping(entries)) => {
                    let (k, v) = entries.iter().find(|(k, _)| k.text() == Some(name))?;
                    if last && key {
                        return Some(k);
                    }
                    v
                }
                (Segment::Index(index), Value::Sequence(items)) => items.get(index)?,
                _ => return None,
            };
        }
        Some(node)
    }

    /// The position of the node at `path`, or of its nearest ancestor in the document.
    pub fn position_of(&self, path: &str) -> Position {
        let mut path = path.to_owned();
        loop {
            if let Some(node) = self.find(&path) {
                return node.at;
            }
            match path.rfind(['.', '[', '#']) {
                Some(cut) => path.truncate(cut),
                None => return self.at,
            }
        }
    }

    /// The text of a scalar.
    pub fn text(&self) -> Option<&str> {
        match &self.value {
            Value::Scalar { text, .. } => Some(text),
            _ => None,
        }
    }
}

/// One step of a YAML path.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Segment<'p> {
    /// A mapping key.
    Key(&'p str),
    /// A sequence index.
    Index(usize),
}

/// The steps of `registers[3].range.max`.
pub fn segments(path: &str) -> impl Iterator<Item = Segment<'_>> {
    path.split('.')
        .filter(|part| !part.is_empty())
        .flat_map(|part| {
            let (key, indices) = match part.find('[') {
                Some(open) => part.split_at(open),
                None => (part, ""),
            };
            let key = (!key.is_empty()).then_some(Segment::Key(key));
            let indices = indices
                .split(['[', ']'])
                .filter(|index| !index.is_empty())
                .map(|index| Segment::Index(index.parse().unwrap_or(usize::MAX)));
            key.into_iter().chain(indices)
        })
}

/// Reads the first document of `text`. An empty document is a null scalar.
pub fn read(text: &str) -> Result<Node, SyntaxError> {
    let mut builder = TreeBuilder::default();
    let mut parser = Parser::new_from_str(text);
    if let Err(error) = parser.load(&mut builder, false) {
        let noticed = position(error.marker());
        let message = error.info().to_owned();
        // An unclosed `{` or `[` is noticed lines later: the fix goes where it opened.
        let opened = unclosed_bracket(text, noticed);
        return Err(match opened {
            Some((at, opener)) if at.line != noticed.line => SyntaxError {
                position: at,
                message: format!(
                    "{message} (noticed at line {} column {}); the `{opener}` opened here is not closed",
                    noticed.line, noticed.column,
                ),
            },
            _ => SyntaxError {
                position: noticed,
                message,
            },
        });
    }
    Ok(builder.root.unwrap_or(Node {
        value: Value::Scalar {
            text: String::new(),
            plain: true,
        },
        at: Position { line: 1, column: 1 },
        id: 0,
    }))
}

/// The last `{` or `[` still open at `upto`, outside quotes and comments.
fn unclosed_bracket(text: &str, upto: Position) -> Option<(Position, char)> {
    let mut open: Vec<(Position, char)> = Vec::new();
    for (index, line) in text.lines().enumerate().take(upto.line) {
        let number = index + 1;
        let mut quote: Option<char> = None;
        let mut previous = ' ';
        let mut chars = line.chars().enumerate().peekable();
        while let Some((column, c)) = chars.next() {
            if number == upto.line && column + 1 >= upto.column {
                break;
            }
            match (quote, c) {
                (Some('\''), '\'') if chars.peek().map(|(_, n)| *n) == Some('\'') => {
                    chars.next();
                }
                (Some('"'), '\\') => {
                    chars.next();
                }
                (Some(q), c) if c == q => quote = None,
                (Some(_), _) => {}
                (None, '\'' | '"') => quote = Some(c),
                (None, '#') if previous.is_whitespace() => break,
                (None, '{' | '[') => open.push((
                    Position {
                        line: number,
                        column: column + 1,
                    },
                    c,
                )),
                (None, '}' | ']') => {
                    open.pop();
                }
                _ => {}
            }
            previous = c;
        }
    }
    open.pop()
}

fn position(marker: &Marker) -> Position {
    Position {
        line: marker.line(),
        column: marker.col() + 1,
    }
}

/// A collection being read.
struct Open {
    node: Node,
    /// For a mapping: the key read, waiting for its value.
    key: Option<Node>,
    /// The position came from the parser's marker, which for a block mapping points past
    /// its first key: the first key's position replaces it.
    at_marker: bool,
    anchor: usize,
}

#[derive(Default)]
struct TreeBuilder {
    stack: Vec<Open>,
    root: Option<Node>,
    anchors: HashMap<usize, Node>,
    next_id: usize,
}

impl TreeBuilder {
    fn id(&mut self) -> usize {
        self.next_id += 1;
        self.next_id
    }

    /// Whether the next node completes a mapping entry's key.
    fn expects_key(&self) -> bool {
        matches!(self.stack.last(), Some(open) if matches!(open.node.value, Value::Mapping(_)) && open.key.is_none())
    }

    /// The key the next value belongs to, if it is a mapping value.
    fn pending_key_position(&self) -> Option<Position> {
        self.stack
            .last()
            .and_then(|open| open.key.as_ref())
            .map(|key| key.at)
    }

    fn finish(&mut self, node: Node, anchor: usize) {
        if anchor != 0 {
            self.anchors.insert(anchor, node.clone());
        }
        let Some(open) = self.stack.last_mut() else {
            if self.root.is_none() {
                self.root = Some(node);
            }
            return;
        };
        match &mut open.node.value {
            Value::Sequence(items) => items.push(node),
            Value::Mapping(entries) => match open.key.take() {
                Some(key) => entries.push((key, node)),
                None => {
                    if open.at_marker {
                        open.node.at = node.at;
                        open.at_marker = false;
                    }
                    // A complex key is kept as its text form; the reader reports it.
                    let key = match node.value {
                        Value::Scalar { .. } => node,
                        _ => Node {
                            value: Value::Scalar {
                                text: String::from("<complex key>"),
                                plain: false,
                            },
                            ..node
                        },
                    };
                    open.key = Some(key);
                }
            },
            Value::Scalar { .. } => {}
        }
    }
}

impl MarkedEventReceiver for TreeBuilder {
    fn on_event(&mut self, event: Event, mark: Marker) {
        let at = position(&mark);
        match event {
            Event::Scalar(text, style, anchor, _) => {
                let id = self.id();
                let node = Node {
                    value: Value::Scalar {
                        text,
                        plain: style == TScalarStyle::Plain,
                    },
                    at,
                    id,
                };
                self.finish(node, anchor);
            }
            Event::SequenceStart(anchor, _) | Event::MappingStart(anchor, _) => {
                let key_at = if self.expects_key() {
                    None
                } else {
                    self.pending_key_position()
                };
                let value = if matches!(event, Event::SequenceStart(..)) {
                    Value::Sequence(Vec::new())
                } else {
                    Value::Mapping(Vec::new())
                };
                let is_mapping = matches!(value, Value::Mapping(_));
                let id = self.id();
                self.stack.push(Open {
                    node: Node {
                        value,
                        at: key_at.unwrap_or(at),
                        id,
                    },
                    key: None,
                    at_marker: key_at.is_none() && is_mapping,
                    anchor,
                });
            }
            Event::SequenceEnd | Event::MappingEnd => {
                if let Some(open) = self.stack.pop() {
                    self.finish(open.node, open.anchor);
                }
            }
            Event::Alias(anchor) => {
                let node = self.anchors.get(&anchor).cloned().unwrap_or(Node {
                    value: Value::Scalar {
                        text: String::new(),
                        plain: true,
                    },
                    at,
                    id: 0,
                });
                let id = self.id();
                self.finish(Node { at, id, ..node }, 0);
            }
            _ => {}
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn at(line: usize, column: usize) -> Position {
        Position { line, column }
    }

    #[test]
    fn finds_nested_values_in_block_and_flow_style() {
        let tree = read("a:\n  b: 1\nlist:\n  - { x: 2, y: 3 }\n  - z: 4\n").unwrap();
        assert_eq!(tree.position_of("a.b"), at(2, 6));
        assert_eq!(tree.position_of("list[0].y"), at(4, 16));
        assert_eq!(tree.position_of("list[1].z"), at(5, 8));
        assert_eq!(tree.position_of("list[1].z#key"), at(5, 5));
        assert_eq!(tree.find("list[1].z").and_then(Node::text), Some("4"));
    }

    #[test]
    fn falls_back_to_the_nearest_ancestor() {
        let tree = read("a:\n  b: 1\n").unwrap();
        assert_eq!(tree.position_of("a.missing"), at(1, 1));
        assert_eq!(tree.position_of("a.b.c[2]"), at(2, 6));
    }

    #[test]
    fn collections_point_at_their_key_or_first_entry() {
        let tree = read("items:\n  - id: x\n    reply:\n      ascii: y\n").unwrap();
        assert_eq!(tree.position_of("items[0]"), at(2, 5));
        assert_eq!(tree.position_of("items[0].reply"), at(3, 5));
        assert_eq!(tree.position_of("items"), at(1, 1));
    }

    #[test]
    fn scalars_remember_whether_they_were_quoted() {
        let tree = read("a: 1\nb: '1'\nc:\n").unwrap();
        assert_eq!(
            tree.find("a").unwrap().value,
            Value::Scalar {
                text: "1".into(),
                plain: true
            }
        );
        assert!(matches!(
            tree.find("b").unwrap().value,
            Value::Scalar { plain: false, .. }
        ));
        assert_eq!(tree.find("c").and_then(Node::text), Some(""));
    }

    #[test]
    fn aliases_copy_their_anchor() {
        let tree = read("a: &x { k: 1 }\nb: *x\n").unwrap();
        assert_eq!(tree.find("b.k").and_then(Node::text), Some("1"));
    }

    #[test]
    fn an_unclosed_brace_is_reported_where_it_opens() {
        let error = read("list:\n  - { a: 1, b: 2\n  - { a: 3 }\nnext: 4\n").unwrap_err();
        assert_eq!(error.position, at(2, 5), "{error:?}");
        assert!(error.message.contains("noticed at line"), "{error:?}");
    }

    #[test]
    fn a_bad_indentation_is_reported_at_its_line() {
        let error = read("a:\n  b: 1\n   c: 2\n").unwrap_err();
        assert_eq!(error.position.line, 3, "{error:?}");
    }

    #[test]
    fn paths_split_into_keys_and_indices() {
        let steps: Vec<Segment> = segments("a[2].b[0][1]").collect();
        assert_eq!(
            steps,
            [
                Segment::Key("a"),
                Segment::Index(2),
                Segment::Key("b"),
                Segment::Index(0),
                Segment::Index(1)
            ]
        );
    }
}
