//! Every file in `tests/fixtures/broken/` is a drive description with deliberate mistakes;
//! its `.expected` file holds the exact messages the generator must print for it.
//! Run with `UPDATE_EXPECT=1` to rewrite the expectations after a deliberate change.

use std::path::Path;
use vfd_tests::expectations::{check_all, entries, Case};

#[test]
fn every_broken_drive_file_gets_the_expected_messages() {
    let files = entries(Path::new("fixtures/broken"), |path| {
        path.extension().is_some_and(|ext| ext == "yaml")
    });
    assert!(
        files.len() >= 10,
        "expected at least 10 broken fixtures, found {}",
        files.len()
    );
    let cases: Vec<Case> = files
        .into_iter()
        .map(|drive| Case {
            expected: drive.with_extension("expected"),
            drive,
            protocols: Some("../drives/protocols".into()),
        })
        .collect();
    check_all(&cases);
}

/// `fixtures/broken/link/`: broken drives on the made-up computer link of
/// `fixtures/computer-link/` (its protocol file has byte-wide commands, which no shipped
/// protocol has).
#[test]
fn every_broken_computer_link_drive_gets_the_expected_messages() {
    let cases: Vec<Case> = entries(Path::new("fixtures/broken/link"), |path| {
        path.extension().is_some_and(|ext| ext == "yaml")
    })
    .into_iter()
    .map(|drive| Case {
        expected: drive.with_extension("expected"),
        drive,
        protocols: Some("fixtures/computer-link/protocols".into()),
    })
    .collect();
    assert!(!cases.is_empty(), "fixtures/broken/link has fixtures");
    check_all(&cases);
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
