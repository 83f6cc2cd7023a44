//! Every file in `tests/fixtures/broken/` is a drive description with deliberate mistakes;
//! its `.expected` file holds the exact messages the generator must print for it.
//! Run with `UPDATE_EXPECT=1` to rewrite the expectations after a deliberate change.

use std::path::{Path, PathBuf};

fn fixtures() -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = std::fs::read_dir("fixtures/broken")
        .expect("tests/fixtures/broken exists")
        .filter_map(|entry| entry.ok().map(|e| e.path()))
        .filter(|path| path.extension().is_some_and(|ext| ext == "yaml"))
        .collect();
    files.sort();
    files
}

#[test]
fn every_broken_drive_file_gets_the_expected_messages() {
    let files = fixtures();
    assert!(
        files.len() >= 10,
        "expected at least 10 broken fixtures, found {}",
        files.len()
    );
    let update = std::env::var_os("UPDATE_EXPECT").is_some();
    let mut failures = Vec::new();
    for file in files {
        let protocols = Path::new("../drives/protocols");
        let outcome = vfd_codegen::compile(&file, Some(protocols));
        let actual = match outcome {
            Ok(_) => format!(
                "{} unexpectedly validated without problems\n",
                file.display()
            ),
            Err(diagnostics) => format!("{diagnostics}\n"),
        };
        let expected_path = file.with_extension("expected");
        if update {
            std::fs::write(&expected_path, &actual).expect("write expectation");
            continue;
        }
        let expected = std::fs::read_to_string(&expected_path).unwrap_or_default();
        if expected != actual {
            failures.push(format!(
                "--- {} (expected)\n{expected}\n+++ actual\n{actual}",
                expected_path.display()
            ));
        }
    }
    assert!(
        failures.is_empty(),
        "messages changed (rerun with UPDATE_EXPECT=1 if intended):\n{}",
        failures.join("\n")
    );
}

#[test]
fn broken_files_generate_nothing() {
    let out = std::env::temp_dir().join(format!("vfd-broken-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&out);
    let result = vfd_codegen::Builder::new()
        .drive("../drives/yd1000.yaml")
        .drive("fixtures/broken/duplicate_address.yaml")
        .protocols_dir("../drives/protocols")
        .out_dir(&out)
        .docs_dir(out.join("docs"))
        .generate();
    assert!(
        matches!(result, Err(vfd_codegen::Error::Invalid(_))),
        "an invalid drive must fail the whole run"
    );
    assert!(
        !out.exists(),
        "nothing may be written when a description is invalid"
    );
}
