//! The JSON Schemas in `drives/schema/` (for editors) and the key tables in
//! `drives/README.md` must equal what `vfd_codegen` derives from the reader's serde types
//! now, every description file must name its schema on its first line and pass it, and the
//! schema must refuse what the reader refuses. `cargo run -p vfd-cli -- generate` refreshes
//! the generated files, and so does this test under `UPDATE_EXPECT=1`.

use serde_json::Value;
use std::path::{Path, PathBuf};
use vfd_tests::expectations::{entries, outdated_files};

const REFRESH: &str = "cargo run -p vfd-cli -- generate";

#[test]
fn committed_schemas_and_key_tables_are_current() {
    let drives = PathBuf::from("../drives");
    let mut files: Vec<(PathBuf, String)> = vfd_codegen::schemas()
        .files()
        .iter()
        .map(|(path, text)| (drives.join(path), (*text).to_owned()))
        .collect();
    let readme = std::fs::read_to_string(drives.join("README.md")).expect("drives/README.md");
    let readme =
        vfd_codegen::with_key_tables(&readme).expect("drives/README.md has the key-table markers");
    files.push((drives.join("README.md"), readme));
    let problems: Vec<String> = outdated_files(&files)
        .iter()
        .map(|file| format!("stale: {}", file.first_difference()))
        .collect();
    assert!(
        problems.is_empty(),
        "the schemas or the README's key tables differ from what the model gives now:\n{}\nRefresh them with `{REFRESH}` (or rerun this test with UPDATE_EXPECT=1) and commit the result.",
        problems.join("\n")
    );
}

fn yaml_files(dir: &str) -> Vec<PathBuf> {
    entries(Path::new(dir), |path| {
        path.extension().is_some_and(|ext| ext == "yaml")
    })
}

/// Every description file that must pass a schema, with the schema file it must name.
fn described_files() -> Vec<(PathBuf, &'static str)> {
    let mut files: Vec<(PathBuf, &str)> = yaml_files("../drives")
        .into_iter()
        .map(|path| (path, vfd_codegen::DRIVE_SCHEMA_PATH))
        .collect();
    files.extend(
        yaml_files("../drives/protocols")
            .into_iter()
            .map(|path| (path, vfd_codegen::PROTOCOL_SCHEMA_PATH)),
    );
    files.push((
        PathBuf::from("fixtures/external-crate/demo_pump.yaml"),
        vfd_codegen::DRIVE_SCHEMA_PATH,
    ));
    files
}

fn validator(schema_path: &str) -> jsonschema::Validator {
    let schemas = vfd_codegen::schemas();
    let text = if schema_path == vfd_codegen::DRIVE_SCHEMA_PATH {
        schemas.drive
    } else {
        schemas.protocol
    };
    let schema: Value = serde_json::from_str(&text).expect("the schema is JSON");
    jsonschema::validator_for(&schema).expect("the schema is a valid JSON Schema")
}

fn as_json(path: &Path) -> Value {
    let text = std::fs::read_to_string(path).expect("readable");
    let yaml: yaml_serde::Value = yaml_serde::from_str(&text).expect("YAML");
    serde_json::to_value(yaml).expect("YAML that JSON can hold")
}

fn schema_errors(path: &Path, schema_path: &str) -> Vec<String> {
    let instance = as_json(path);
    validator(schema_path)
        .iter_errors(&instance)
        .map(|error| format!("{}: {error}", error.instance_path()))
        .collect()
}

#[test]
fn every_description_file_names_its_schema_on_the_first_line() {
    for (path, schema) in described_files() {
        let text = std::fs::read_to_string(&path).expect("readable");
        let first = text.lines().next().unwrap_or_default();
        let named = first
            .strip_prefix("# yaml-language-server: $schema=")
            .unwrap_or_else(|| {
                panic!(
                    "{} must start with `# yaml-language-server: $schema=<path to {schema}>`",
                    path.display()
                )
            });
        let resolved = path.parent().expect("a folder").join(named);
        let expected = Path::new("../drives").join(schema);
        assert_eq!(
            std::fs::canonicalize(&resolved).ok(),
            std::fs::canonicalize(&expected).ok(),
            "{}: the first line names {named}, which is not drives/{schema}",
            path.display()
        );
    }
}

#[test]
fn every_description_file_passes_its_schema() {
    let mut problems = Vec::new();
    for (path, schema) in described_files() {
        for error in schema_errors(&path, schema) {
            problems.push(format!("{}: {error}", path.display()));
        }
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

/// The broken fixtures are not held to the schema, but those the reader refuses for a key
/// or a value (rather than for what they mean) the schema refuses too.
#[test]
fn the_schema_refuses_what_the_reader_refuses() {
    for (fixture, expected) in [
        ("unknown_key", "defualt"),
        ("unknown_enum_value", "readonly"),
    ] {
        let path = PathBuf::from(format!("fixtures/broken/{fixture}.yaml"));
        let errors = schema_errors(&path, vfd_codegen::DRIVE_SCHEMA_PATH);
        assert!(
            errors.iter().any(|e| e.contains(expected)),
            "{fixture}.yaml: the schema should refuse `{expected}`, found: {errors:?}"
        );
    }
}
