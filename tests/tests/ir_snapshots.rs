//! The generator's IR of every described drive, held as a snapshot in `tests/snapshots/ir/`
//! (`cargo run -p vfd-cli -- generate --dump-ir DRIVE` prints the same). A change to the IR
//! shows up here as a reviewable diff; `UPDATE_EXPECT=1` rewrites the snapshots.

use std::path::PathBuf;
use vfd_tests::expectations::outdated_files;

#[test]
fn the_ir_of_each_drive_matches_its_snapshot() {
    let generated = vfd_codegen::Builder::new()
        .drives_in("../drives")
        .expect("drives/ is readable")
        .display_root("..")
        .generate_in_memory()
        .unwrap_or_else(|error| panic!("the drive files do not generate:\n{error}"));
    let snapshots: Vec<(PathBuf, String)> = generated
        .drives
        .iter()
        .map(|drive| {
            (
                PathBuf::from(format!("snapshots/ir/{}.yaml", drive.ir.id)),
                drive.ir.to_yaml(),
            )
        })
        .collect();
    let stale: Vec<String> = outdated_files(&snapshots)
        .iter()
        .map(|file| file.first_difference())
        .collect();
    assert!(
        stale.is_empty(),
        "the IR changed:\n{}\nReview the change, then rerun with UPDATE_EXPECT=1 to accept it.",
        stale.join("\n")
    );
}
