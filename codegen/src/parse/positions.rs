//! Maps YAML paths (`registers[3].address`) to line and column, so that problems found
//! after deserialisation can still point at the right place in the file.

use std::collections::HashMap;
use std::sync::OnceLock;
use yaml_rust2::parser::{Event, MarkedEventReceiver, Parser};
use yaml_rust2::scanner::Marker;

pub use crate::diagnostics::Position;

/// Positions of every node of one YAML document, by path.
///
/// The index is built on the first [`PositionIndex::find`]: only a description with a
/// problem needs positions, and for a valid one indexing would cost as much as reading
/// the YAML again.
#[derive(Debug, Clone, Default)]
pub struct PositionIndex {
    text: String,
    values: OnceLock<HashMap<String, Position>>,
}

impl PositionIndex {
    /// An index of `text`, built when first used. Syntax errors leave the index partial;
    /// serde reports them.
    pub fn build(text: &str) -> PositionIndex {
        PositionIndex {
            text: text.to_owned(),
            values: OnceLock::new(),
        }
    }

    fn values(&self) -> &HashMap<String, Position> {
        self.values.get_or_init(|| {
            let mut builder = IndexBuilder::default();
            let mut parser = Parser::new_from_str(&self.text);
            let _ = parser.load(&mut builder, false);
            builder.values
        })
    }

    /// The position of the node at `path`, or of its nearest indexed ancestor.
    pub fn find(&self, path: &str) -> Position {
        let values = self.values();
        let mut path = path.to_owned();
        loop {
            if let Some(position) = values.get(&path) {
                return *position;
            }
            match path.rfind(['.', '[']) {
                Some(cut) => path.truncate(cut),
                None => {
                    return values
                        .get("")
                        .copied()
                        .unwrap_or(Position { line: 1, column: 1 })
                }
            }
        }
    }
}

enum Frame {
    /// `key` is the pending key and its position; `at_marker` says the mapping's own
    /// position came from the parser's marker (which points past the first key of a
    /// block mapping), so the first key's position should replace it.
    Mapping {
        path: String,
        key: Option<(String, Position)>,
        at_marker: bool,
    },
    Sequence {
        path: String,
        index: usize,
    },
}

#[derive(Default)]
struct IndexBuilder {
    stack: Vec<Frame>,
    values: HashMap<String, Position>,
}

impl IndexBuilder {
    /// Path of the node now starting and the position of its key (for mapping values),
    /// or `None` when the node is itself a mapping key.
    fn next_path(&mut self) -> Option<(String, Option<Position>)> {
        match self.stack.last_mut() {
            None => Some((String::new(), None)),
            Some(Frame::Mapping { path, key, .. }) => {
                key.take().map(|(key, at)| (join(path, &key), Some(at)))
            }
            Some(Frame::Sequence { path, index }) => {
                let here = format!("{path}[{index}]");
                *index += 1;
                Some((here, None))
            }
        }
    }
}

fn join(path: &str, key: &str) -> String {
    if path.is_empty() {
        key.to_owned()
    } else {
        format!("{path}.{key}")
    }
}

impl MarkedEventReceiver for IndexBuilder {
    fn on_event(&mut self, event: Event, mark: Marker) {
        let position = Position {
            line: mark.line(),
            column: mark.col() + 1,
        };
        match event {
            Event::Scalar(value, ..) => match self.next_path() {
                Some((path, _)) => {
                    self.values.insert(path, position);
                }
                None => {
                    if let Some(Frame::Mapping {
                        path,
                        key,
                        at_marker,
                    }) = self.stack.last_mut()
                    {
                        if *at_marker {
                            self.values.insert(path.clone(), position);
                            *at_marker = false;
                        }
                        self.values
                            .insert(format!("{}#key", join(path, &value)), position);
                        *key = Some((value, position));
                    }
                }
            },
            Event::MappingStart(..) | Event::SequenceStart(..) => {
                let (path, key_position) = self.next_path().unwrap_or_default();
                // A collection is best shown at its key (`reply:`), else where it starts.
                self.values
                    .insert(path.clone(), key_position.unwrap_or(position));
                if matches!(event, Event::MappingStart(..)) {
                    self.stack.push(Frame::Mapping {
                        path,
                        key: None,
                        at_marker: key_position.is_none(),
                    });
                } else {
                    self.stack.push(Frame::Sequence { path, index: 0 });
                }
            }
            Event::MappingEnd | Event::SequenceEnd => {
                self.stack.pop();
            }
            Event::Alias(..) => {
                if let Some((path, _)) = self.next_path() {
                    self.values.insert(path, position);
                }
            }
            _ => {}
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_nested_values_in_block_and_flow_style() {
        let index = PositionIndex::build("a:\n  b: 1\nlist:\n  - { x: 2, y: 3 }\n  - z: 4\n");
        assert_eq!(index.find("a.b"), Position { line: 2, column: 6 });
        assert_eq!(
            index.find("list[0].y"),
            Position {
                line: 4,
                column: 16
            }
        );
        assert_eq!(index.find("list[1].z"), Position { line: 5, column: 8 });
    }

    #[test]
    fn falls_back_to_the_nearest_ancestor() {
        let index = PositionIndex::build("a:\n  b: 1\n");
        assert_eq!(index.find("a.missing"), Position { line: 1, column: 1 });
    }

    #[test]
    fn block_mappings_in_sequences_start_at_their_first_key() {
        let index = PositionIndex::build("items:\n  - id: x\n    reply:\n      ascii: y\n");
        assert_eq!(index.find("items[0]"), Position { line: 2, column: 5 });
        assert_eq!(
            index.find("items[0].reply"),
            Position { line: 3, column: 5 }
        );
    }
}
