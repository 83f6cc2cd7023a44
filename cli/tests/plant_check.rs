//! `vfd serve --check PLANT`: every file in `cli/tests/fixtures/plants/` is a plant file
//! with deliberate mistakes (one kind of check each); its `.expected` file holds exactly
//! what `vfd serve --check` prints for it. The annotated example is accepted. Run with
//! `UPDATE_EXPECT=1` to rewrite the expectations after a deliberate change.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn vfd(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_vfd"))
        .args(args)
        .current_dir(concat!(env!("CARGO_MANIFEST_DIR"), "/.."))
        .output()
        .expect("vfd runs")
}

fn stdout(output: &Output) -> String {
    String::from_utf8_lossy(&output.stdout).into_owned()
}

const FIXTURES: &str = "cli/tests/fixtures/plants";

fn fixtures() -> Vec<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("..")
        .join(FIXTURES);
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .expect("the fixtures folder")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == "yaml"))
        .collect();
    files.sort();
    files
}

#[test]
fn every_broken_plant_file_gets_the_expected_messages() {
    let files = fixtures();
    assert!(files.len() >= 14, "found {} fixtures", files.len());
    let update = std::env::var_os("UPDATE_EXPECT").is_some();
    let mut stale = Vec::new();
    for file in files {
        let name = file.file_name().unwrap().to_string_lossy().into_owned();
        let relative = format!("{FIXTURES}/{name}");
        let output = vfd(&["serve", "--check", &relative]);
        let printed = stdout(&output);
        let warned_only = name.starts_with("warnings");
        assert_eq!(
            output.status.success(),
            warned_only,
            "{relative}: exit status {:?}\n{printed}",
            output.status
        );
        if !warned_only {
            let stderr = String::from_utf8_lossy(&output.stderr);
            assert!(
                stderr.contains(&format!("vfd: {relative} has ")),
                "{stderr}"
            );
        }
        let expected = file.with_extension("expected");
        let committed = std::fs::read_to_string(&expected).unwrap_or_default();
        if committed != printed {
            if update {
                std::fs::write(&expected, &printed).unwrap();
            } else {
                stale.push(format!(
                    "{}:\n--- committed\n{committed}\n--- now\n{printed}",
                    expected.display()
                ));
            }
        }
    }
    assert!(
        stale.is_empty(),
        "run with UPDATE_EXPECT=1 after a deliberate change\n{}",
        stale.join("\n")
    );
}

#[test]
fn the_annotated_example_is_accepted() {
    let output = vfd(&["serve", "--check", "plants/example.yaml"]);
    let text = stdout(&output);
    assert!(output.status.success(), "{text}");
    assert!(
        text.starts_with("plants/example.yaml: ok (2 buses, 4 drives, "),
        "{text}"
    );
    assert!(text.contains("tcp://"), "{text}");
    assert!(text.contains("(persistent)"), "{text}");
    assert!(!text.contains("warning"), "{text}");
}

#[test]
fn a_missing_plant_file_is_one_error_and_exit_status_1() {
    let output = vfd(&["serve", "--check", "plants/no-such-plant.yaml"]);
    assert_eq!(output.status.code(), Some(1));
    let text = stdout(&output);
    assert!(text.contains("cannot read the file"), "{text}");
    assert!(text.contains("plants/no-such-plant.yaml:1:1"), "{text}");
}
