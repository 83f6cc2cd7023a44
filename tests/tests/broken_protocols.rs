//! Every folder in `tests/fixtures/broken-protocols/` is a small valid drive (`drive.yaml`)
//! that uses a protocol file with deliberate mistakes (`protocols/<name>.yaml`, looked up
//! next to the drive); its `expected.txt` holds the exact messages the generator must print.
//! Run with `UPDATE_EXPECT=1` to rewrite the expectations after a deliberate change.

use std::path::Path;
use vfd_tests::expectations::{check_all, entries, Case};

#[test]
fn every_broken_protocol_file_gets_the_expected_messages() {
    let folders = entries(Path::new("fixtures/broken-protocols"), |path| {
        path.join("drive.yaml").is_file()
    });
    assert!(
        folders.len() >= 11,
        "expected at least 11 broken protocol cases, found {}",
        folders.len()
    );
    let cases: Vec<Case> = folders
        .into_iter()
        .map(|folder| Case {
            drive: folder.join("drive.yaml"),
            expected: folder.join("expected.txt"),
            protocols: None,
        })
        .collect();
    check_all(&cases);
}
