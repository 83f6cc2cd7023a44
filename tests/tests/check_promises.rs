//! `vfd check` promises what the golden tests then do. `vfd check` runs every golden check
//! itself (`vfd_runtime::golden`, the functions the generated tests call); these tests hold
//! the other half: for every drive file in the repository (`drives/*.yaml`,
//! `tests/fixtures/external-crate/*.yaml`), a file `compile` accepts has every example and
//! sequence golden-tested by a suite that runs (`tests/golden.rs` for `drives/`,
//! `tests/external_crate.rs` for the outside crate), so "ok" implies those tests passed.
//! `fixtures/broken/sequence_replay.yaml` shows a file whose golden test would fail being
//! refused (and `example_not_simulated.yaml` one saying its virtual drive cannot answer as
//! printed where it does).

use std::path::{Path, PathBuf};
use vfd_codegen::{DriveIr, OutputNames};

/// The golden tests compiled into `tests/golden.rs`, generated from `drives/` by build.rs:
/// `golden.rs` includes one `<file stem>_golden.rs` per drive.
fn drives_golden(path: &Path) -> String {
    let out = Path::new(env!("OUT_DIR"));
    let index = std::fs::read_to_string(out.join("golden.rs")).unwrap();
    let stem = path.file_stem().unwrap().to_string_lossy();
    let file = format!("/{stem}_golden.rs");
    assert!(
        index.contains(&file),
        "tests/golden.rs includes the golden tests of {}",
        path.display()
    );
    std::fs::read_to_string(out.join(&file[1..])).unwrap()
}

fn yaml_files(dir: &str) -> Vec<PathBuf> {
    vfd_tests::expectations::entries(Path::new(dir), |path| {
        path.extension().is_some_and(|ext| ext == "yaml")
    })
}

/// The test functions a drive's golden file must hold: one per example and sequence.
fn expected_tests(ir: &DriveIr) -> Vec<String> {
    ir.examples
        .iter()
        .map(|e| format!("fn example_{}()", e.id))
        .chain(
            ir.sequences
                .iter()
                .map(|s| format!("fn sequence_{}()", s.id)),
        )
        .collect()
}

#[test]
fn every_described_drive_that_checks_ok_has_every_example_golden_tested() {
    let drives = yaml_files("../drives");
    assert!(drives.len() >= 4, "found {} drives", drives.len());
    let mut with_examples = 0;
    for path in drives {
        let ir = match vfd_codegen::compile(&path, None) {
            Ok(ir) => ir,
            // Refused: the promise is about files `vfd check` accepts.
            Err(_) => continue,
        };
        let tests = expected_tests(&ir);
        // A drive whose manual's frames could not be read has none (its manual_note says so).
        if !tests.is_empty() {
            with_examples += 1;
        }
        let golden = drives_golden(&path);
        for test in tests {
            assert!(
                golden.contains(&test),
                "{} checks ok, but `{test}` is not among the golden tests tests/golden.rs runs",
                path.display()
            );
        }
    }
    // Not vacuous: the seeds and most drives print frames.
    assert!(with_examples >= 4, "{with_examples} drives with examples");
}

#[test]
fn every_outside_drive_that_checks_ok_is_golden_tested_by_the_outside_crate() {
    let build = std::fs::read_to_string("fixtures/external-crate/build.rs").unwrap();
    for path in yaml_files("fixtures/external-crate") {
        let Ok(ir) = vfd_codegen::compile(&path, Some(Path::new("../drives/protocols"))) else {
            continue;
        };
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        assert!(
            build.contains(&format!(".drive(\"{name}\")")),
            "{name} checks ok, but the outside crate's build.rs does not generate its golden tests"
        );
        let golden = vfd_codegen::golden_tests_file(&ir, &OutputNames::default()).unwrap();
        for test in expected_tests(&ir) {
            assert!(golden.contains(&test), "{name}: `{test}` is generated");
        }
    }
}

#[test]
fn a_drive_whose_golden_test_would_fail_is_refused_at_the_example() {
    let file = "fixtures/broken/sequence_replay.yaml";
    let refused = vfd_codegen::compile(Path::new(file), Some(Path::new("../drives/protocols")))
        .expect_err(file);
    let shown = refused.to_string();
    assert!(shown.contains("its golden test would fail"), "{shown}");
    assert!(
        shown.contains("the call reads 60 (raw 1770h), not 50"),
        "{shown}"
    );
    assert!(
        refused.items.iter().all(|d| d.position.line > 1),
        "each points into the file: {shown}"
    );
}
