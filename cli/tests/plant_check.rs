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

/// `vfd serve --check PLANT`, its standard output (and, with `stderr_too`, its standard
/// error) a pipe whose reader has gone before it writes, as after `| head -1`: the pipe's
/// reader is closed at once, and the check starts 0.3 s later (through `sh`, which hands
/// on its exit status). Its exit status and standard error (empty with `stderr_too`).
#[cfg(unix)]
fn check_into_closed_pipe(plant: &str, stderr_too: bool) -> (Option<i32>, String) {
    let script = if stderr_too {
        "sleep 0.3; exec \"$0\" serve --check \"$1\" 2>&1"
    } else {
        "sleep 0.3; exec \"$0\" serve --check \"$1\""
    };
    let errors = std::env::temp_dir().join(format!(
        "vfd-check-pipe-{}-{stderr_too}.txt",
        std::process::id()
    ));
    let mut child = Command::new("sh")
        .args(["-c", script, env!("CARGO_BIN_EXE_vfd"), plant])
        .current_dir(concat!(env!("CARGO_MANIFEST_DIR"), "/.."))
        .stdout(std::process::Stdio::piped())
        .stderr(std::fs::File::create(&errors).expect("a file for standard error"))
        .spawn()
        .expect("sh runs");
    drop(child.stdout.take());
    let status = child.wait().expect("it ends");
    let stderr = std::fs::read_to_string(&errors).unwrap_or_default();
    let _ = std::fs::remove_file(&errors);
    (status.code(), stderr)
}

#[cfg(unix)]
#[test]
fn the_exit_status_is_the_checks_when_the_reader_stops_early() {
    let broken = format!("{FIXTURES}/registers.yaml");
    let (code, stderr) = check_into_closed_pipe(&broken, false);
    assert_eq!(code, Some(1), "{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert!(stderr.contains("registers.yaml has 6 problems"), "{stderr}");
    // Standard error closed as well (`2>&1 | head -1`): still 1, not a panic (101).
    assert_eq!(check_into_closed_pipe(&broken, true).0, Some(1));
    let (code, stderr) = check_into_closed_pipe("plants/example.yaml", true);
    assert_eq!(code, Some(0), "{stderr}");
}
