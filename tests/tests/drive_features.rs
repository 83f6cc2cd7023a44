//! One drive, one compile: `vfd-drives` has a cargo feature per drive file, all on by
//! default, and a crate outside the workspace that turns on one (`fixtures/one-drive/`)
//! compiles that drive alone.

use std::path::Path;
use vfd_tests::out_of_tree::{cargo_test, Passed};

/// The drive files `drives/<id>.yaml`, by id.
fn drive_ids() -> Vec<String> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../drives");
    let mut ids: Vec<String> = std::fs::read_dir(&dir)
        .expect("drives/ lists")
        .filter_map(|entry| entry.ok().map(|e| e.path()))
        .filter_map(|path| {
            let name = path.file_name()?.to_str()?;
            name.strip_suffix(".yaml").map(str::to_owned)
        })
        .collect();
    ids.sort();
    ids
}

/// The `[features]` table of `drives/Cargo.toml`: each feature and what it turns on.
fn features() -> Vec<(String, String)> {
    let text =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("../drives/Cargo.toml"))
            .expect("drives/Cargo.toml reads");
    let mut in_features = false;
    let mut found = Vec::new();
    for line in text.lines() {
        let line = line.trim();
        if line.starts_with('[') {
            in_features = line == "[features]";
            continue;
        }
        if !in_features || line.is_empty() || line.starts_with('#') {
            continue;
        }
        let (name, value) = line
            .split_once('=')
            .expect("feature lines are `name = [...]`");
        found.push((name.trim().to_owned(), value.trim().to_owned()));
    }
    found
}

#[test]
fn every_drive_file_has_a_feature_on_by_default() {
    let features = features();
    let default = &features
        .iter()
        .find(|(name, _)| name == "default")
        .expect("a default feature")
        .1;
    for id in drive_ids() {
        assert!(
            features.iter().any(|(name, on)| *name == id && on == "[]"),
            "drives/{id}.yaml has no feature `{id} = []` in drives/Cargo.toml"
        );
        assert!(
            default.contains(&format!("\"{id}\"")),
            "the feature `{id}` is not in vfd-drives' default features: {default}"
        );
    }
    let ids = drive_ids();
    for (name, _) in &features {
        assert!(
            name == "default" || ids.contains(name),
            "the feature `{name}` of drives/Cargo.toml names no drive file"
        );
    }
}

#[test]
fn every_drive_file_is_compiled_by_default() {
    let compiled: Vec<&str> = vfd_drives::ALL_DRIVES.iter().map(|d| d.id).collect();
    assert_eq!(compiled.len(), drive_ids().len(), "compiled: {compiled:?}");
}

#[test]
fn a_crate_that_turns_on_one_drive_compiles_one() {
    let Passed { stdout, stderr } = cargo_test(
        Path::new(env!("CARGO_MANIFEST_DIR")),
        Path::new(env!("CARGO_TARGET_TMPDIR")),
        "one-drive",
    );
    for test in [
        "test tests::only_the_chosen_drive_is_compiled ... ok",
        "test tests::the_chosen_drive_works ... ok",
    ] {
        assert!(
            stdout.contains(test),
            "missing `{test}` in the outside crate:\n{stdout}\n{stderr}"
        );
    }
}
