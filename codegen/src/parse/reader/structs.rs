//! A mapping read as a struct: unknown keys reported (misspelt, or indented too little or
//! too far) and skipped, duplicate keys reported, missing required keys reported and given
//! placeholders.

use super::access::KeyDe;
use super::error::Error;
use super::hints::{closest, unknown_hint};
use super::node::NodeDe;
use super::path::Path;
use super::state::Reader;
use super::{Kind, Problem};
use crate::parse::tree::{Node, Value};
use serde::de::{self, DeserializeSeed, Visitor};

impl<'a> NodeDe<'a> {
    pub(super) fn structure<'de, V: Visitor<'de>>(
        self,
        name: &'static str,
        fields: &'static [&'static str],
        visitor: V,
    ) -> Result<V::Value, Error> {
        // "A mapping with these keys, or a scalar" (`model::OR_SCALAR`): a scalar goes to
        // the visitor as itself.
        let name = match name.strip_suffix(crate::parse::model::OR_SCALAR) {
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
