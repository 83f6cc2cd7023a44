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
//!
//! The reading's state is in `state.rs`, the node deserializer in `node.rs` (reporting),
//! `deserializer.rs` (values) and `structs.rs` (mappings read as structs), the other serde
//! access types in `access.rs`.

mod access;
mod deserializer;
mod error;
mod hints;
mod node;
mod path;
mod scalar;
mod state;
mod structs;
#[cfg(test)]
mod tests;

pub use hints::closest;

use super::tree::Node;
use crate::diagnostics::Position;
use node::NodeDe;
use path::Path;
use schemars::JsonSchema;
use serde::de::DeserializeOwned;
use state::{schema_keys, Reader};
use std::cell::{OnceCell, RefCell};

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
