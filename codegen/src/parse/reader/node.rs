//! The node deserializer: one node (or a placeholder for a missing one), and how it
//! reports a problem at that node.

use super::error::{Complaint, Error, REPORTED};
use super::hints::{hint_for_type, unknown_hint};
use super::path::Path;
use super::scalar::found;
use super::state::Reader;
use super::{Kind, Problem};
use crate::parse::tree::Node;

/// The mapping a value sits in, read as a struct: its node id, the keys it accepts and the
/// entries it has.
pub(super) type Enclosing<'a> = (usize, &'static [&'static str], &'a [&'a (Node, Node)]);

/// Reads one node (or, with `node: None`, a placeholder for a missing one).
pub(super) struct NodeDe<'a> {
    pub(super) node: Option<&'a Node>,
    pub(super) path: &'a Path<'a>,
    pub(super) reader: &'a Reader,
    /// The mapping this node is a value of, read as a struct: its id and its keys.
    /// With the keys it has, so that a key it already has is not said to belong there.
    pub(super) parent: Option<Enclosing<'a>>,
}

impl<'a> NodeDe<'a> {
    pub(super) fn report(&self, message: String, hint: Option<String>) {
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
    pub(super) fn wrong(&self, expected: &str) {
        if let Some(node) = self.node {
            self.report(
                format!("expected {expected}, found {}", found(node)),
                Some(hint_for_type(expected).to_owned()),
            );
            self.placeholder();
        }
    }

    pub(super) fn placeholder(&self) {
        self.reader
            .incomplete
            .borrow_mut()
            .push(self.path.element());
    }

    /// Reports a visitor's complaint at this node, once.
    pub(super) fn locate(&self, error: Error) -> Error {
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

    pub(super) fn child<'c>(&'c self, node: Option<&'c Node>, path: &'c Path<'c>) -> NodeDe<'c> {
        NodeDe {
            node,
            path,
            reader: self.reader,
            parent: None,
        }
    }
}
