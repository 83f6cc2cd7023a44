//! A backup file written by `vfd backup` before the YAML crate changed (serde_yaml 0.9,
//! `fixtures/yd1000-backup-serde_yaml-0.9.yaml`, taken from the factory-state virtual drive)
//! still restores: read, checked and found equal to the drive, nothing to write.

mod common;

use common::{text, Sim};

#[test]
fn a_backup_written_with_serde_yaml_still_restores() {
    let file = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fixtures/yd1000-backup-serde_yaml-0.9.yaml");
    let sim = Sim::start("yd1000", "ascii");
    let dry = sim.vfd(
        "yd1000",
        "ascii",
        &["restore", "--from", file.to_str().unwrap(), "--dry-run"],
    );
    assert!(dry.status.success(), "{}", text(&dry));
    assert!(text(&dry).contains("dry run: 0 to write"), "{}", text(&dry));

    // A changed value on the drive is found and would be written back.
    let changed = sim.vfd("yd1000", "ascii", &["write", "FH", "70"]);
    assert!(changed.status.success(), "{}", text(&changed));
    let dry = sim.vfd(
        "yd1000",
        "ascii",
        &["restore", "--from", file.to_str().unwrap(), "--dry-run"],
    );
    assert!(dry.status.success(), "{}", text(&dry));
    assert!(
        text(&dry).contains("FH") && text(&dry).contains("dry run: 1 to write"),
        "{}",
        text(&dry)
    );
}
