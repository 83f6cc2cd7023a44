//! Every folder in `tests/fixtures/broken-protocols/` is a small valid drive (`drive.yaml`)
//! that uses a protocol file with deliberate mistakes (`protocols/<name>.yaml`, looked up
//! next to the drive); its `expected.txt` holds the exact messages the generator must print.
//! Run with `UPDATE_EXPECT=1` to rewrite the expectations after a deliberate change.

use std::path::PathBuf;

fn cases() -> Vec<PathBuf> {
    let mut cases: Vec<PathBuf> = std::fs::read_dir("fixtures/broken-protocols")
        .expect("tests/fixtures/broken-protocols exists")
        .filter_map(|entry| entry.ok().map(|e| e.path()))
        .filter(|path| path.join("drive.yaml").is_file())
        .collect();
    cases.sort();
    cases
}

#[test]
fn every_broken_protocol_file_gets_the_expected_messages() {
    let cases = cases();
    assert!(
        cases.len() >= 11,
        "expected at least 11 broken protocol cases, found {}",
        cases.len()
    );
    let update = std::env::var_os("UPDATE_EXPECT").is_some();
    let mut failures = Vec::new();
    for case in cases {
        let drive = case.join("drive.yaml");
        let outcome = vfd_codegen::compile(&drive, None);
        let actual = match outcome {
            Ok(_) => format!(
                "{} unexpectedly validated without problems\n",
                drive.display()
            ),
            Err(diagnostics) => format!("{diagnostics}\n"),
        };
        let expected_path = case.join("expected.txt");
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
