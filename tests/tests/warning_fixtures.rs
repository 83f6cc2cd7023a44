//! Every file in `tests/fixtures/warnings/` is a valid drive description with deliberate
//! warnings (valid, but not doing what it seems to); its `.expected` file holds the exact
//! warnings `vfd check` must print for it, and the description must still compile.
//! Run with `UPDATE_EXPECT=1` to rewrite the expectations after a deliberate change.

use std::path::Path;
use vfd_tests::expectations::{check_all_rendered, entries, render_warnings, Case};

fn cases() -> Vec<Case> {
    entries(Path::new("fixtures/warnings"), |path| {
        path.extension().is_some_and(|ext| ext == "yaml")
    })
    .into_iter()
    .map(|drive| Case {
        expected: drive.with_extension("expected"),
        drive,
        protocols: Some("../drives/protocols".into()),
    })
    .collect()
}

#[test]
fn every_warnings_fixture_gets_the_expected_warnings() {
    let cases = cases();
    assert!(
        cases.len() >= 3,
        "expected a fixture per warning, found {}",
        cases.len()
    );
    check_all_rendered(&cases, render_warnings);
}

#[test]
fn warnings_do_not_stop_generation() {
    for case in cases() {
        let compiled = vfd_codegen::compile_with_warnings(&case.drive, case.protocols.as_deref());
        assert!(
            compiled.drive.is_ok(),
            "{} is valid apart from its warnings:\n{}",
            case.drive.display(),
            compiled.drive.unwrap_err()
        );
        assert!(
            !compiled.warnings.is_empty()
                && compiled
                    .warnings
                    .items
                    .iter()
                    .all(|w| w.is_warning() && w.hint.is_some()),
            "{} has warnings, each with a hint",
            case.drive.display()
        );
    }
}

#[test]
fn the_described_drives_have_no_warnings() {
    let drives = entries(Path::new("../drives"), |path| {
        path.extension().is_some_and(|ext| ext == "yaml")
    });
    assert!(drives.len() >= 4, "found {} drives", drives.len());
    for drive in drives {
        let compiled = vfd_codegen::compile_with_warnings(&drive, None);
        assert!(compiled.drive.is_ok(), "{} is valid", drive.display());
        assert!(
            compiled.warnings.is_empty(),
            "{} has warnings:\n{}",
            drive.display(),
            compiled.warnings
        );
    }
}
