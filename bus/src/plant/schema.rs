//! The JSON Schema of plant files, derived from [`super::file`] as the drive files'
//! schema is from theirs; `vfd generate` writes it to [`PATH`] (editors complete and check
//! keys with `# yaml-language-server: $schema=plant.schema.json` on a file's first line).

use super::file::PlantFile;
use schemars::generate::SchemaSettings;

/// Where the schema is kept, relative to the repository root.
pub const PATH: &str = "plants/plant.schema.json";

/// The schema (draft 7) as pretty-printed JSON, ending in a newline.
pub fn text() -> String {
    let schema = SchemaSettings::draft07()
        .into_generator()
        .into_root_schema_for::<PlantFile>();
    let mut value = schema.to_value();
    if let Some(object) = value.as_object_mut() {
        object.insert(
            "title".to_owned(),
            serde_json::Value::from("A plant file for `vfd serve` (docs/plant.md)"),
        );
    }
    let mut text = serde_json::to_string_pretty(&value).unwrap_or_default();
    text.push('\n');
    text
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_committed_schema_is_up_to_date() {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("..")
            .join(PATH);
        let committed = std::fs::read_to_string(&path).unwrap_or_default();
        assert!(
            committed == text(),
            "{} is stale: run `cargo run -p vfd-cli -- generate`",
            path.display()
        );
    }

    #[test]
    fn every_key_is_described() {
        let value: serde_json::Value = serde_json::from_str(&text()).unwrap();
        let definitions = value["definitions"].as_object().unwrap();
        for (name, definition) in definitions {
            for (key, property) in definition["properties"].as_object().into_iter().flatten() {
                assert!(
                    property.get("description").is_some(),
                    "{name}.{key} has no description"
                );
            }
        }
        assert!(definitions.contains_key("BusFile"));
    }
}
