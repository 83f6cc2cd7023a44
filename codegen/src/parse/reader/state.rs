//! What one reading collects and knows: the problems found, the elements left incomplete,
//! the keys each mapping read as a struct accepts, and each struct type's keys as the
//! schema gives them.

use super::path::Path;
use super::{Kind, Problem};
use crate::parse::tree::Node;
use schemars::JsonSchema;
use std::cell::{OnceCell, RefCell};
use std::collections::HashMap;

/// What the schema says about one struct type: its required keys, and what each key holds.
#[derive(Debug, Default)]
pub(super) struct Keys {
    required: Vec<String>,
    described: HashMap<String, String>,
}

/// The keys of every struct type reachable from `T`, by type name.
pub(super) fn schema_keys<T: JsonSchema>() -> HashMap<String, Keys> {
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

pub(super) struct Reader {
    pub(super) problems: RefCell<Vec<Problem>>,
    pub(super) incomplete: RefCell<Vec<String>>,
    /// The keys each mapping read as a struct accepts, by node id.
    pub(super) fields: RefCell<HashMap<usize, &'static [&'static str]>>,
    pub(super) schema: OnceCell<HashMap<String, Keys>>,
    pub(super) schema_of: fn() -> HashMap<String, Keys>,
}

impl Reader {
    fn keys(&self, name: &str) -> Option<&Keys> {
        self.schema.get_or_init(self.schema_of).get(name)
    }

    pub(super) fn required(&self, name: &str) -> &[String] {
        self.keys(name).map_or(&[], |keys| keys.required.as_slice())
    }

    /// "add the key: <what the schema says it holds>".
    pub(super) fn missing_hint(&self, name: &str, key: &str) -> String {
        match self.keys(name).and_then(|keys| keys.described.get(key)) {
            Some(what) => format!("add `{key}`: {what}"),
            None => format!("add `{key}`; drives/README.md says what it holds"),
        }
    }

    pub(super) fn push(&self, problem: Problem) {
        self.problems.borrow_mut().push(problem);
    }

    /// Reports `key`, a second entry of the mapping at `path` (the first is on `first_line`).
    pub(super) fn duplicate_key(&self, path: &Path<'_>, key: &Node, first_line: usize) {
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
