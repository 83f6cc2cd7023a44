//! `vfd ... | head`: a reader that stops early must not make the tool panic.

use std::io::Read;
use std::process::{Command, Stdio};

#[test]
fn a_closed_pipe_ends_the_tool_quietly() {
    for args in [
        &["registers", "yd1000"][..],
        &["generate", "--dump-ir", "yd1000"][..],
        &["info", "yd1000"][..],
        &["info", "fc51"][..],
        &["completions", "bash"][..],
        &["demo", "--seconds", "1"][..],
    ] {
        let mut child = Command::new(env!("CARGO_BIN_EXE_vfd"))
            .args(args)
            .current_dir(concat!(env!("CARGO_MANIFEST_DIR"), "/.."))
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .expect("vfd starts");
        // Read one byte, then close the pipe while the tool still has lines to write.
        let mut stdout = child.stdout.take().expect("piped");
        let mut first = [0u8; 1];
        stdout.read_exact(&mut first).expect("some output");
        drop(stdout);
        let output = child.wait_with_output().expect("vfd ends");
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert!(
            output.status.success(),
            "{args:?}: {:?}\n{stderr}",
            output.status
        );
        assert!(!stderr.contains("panicked"), "{args:?}: {stderr}");
    }
}

#[test]
fn dump_ir_without_a_drive_is_an_error_not_a_generation() {
    let output = Command::new(env!("CARGO_BIN_EXE_vfd"))
        .args(["generate", "--dump-ir"])
        .current_dir(concat!(env!("CARGO_MANIFEST_DIR"), "/.."))
        .output()
        .expect("vfd runs");
    assert!(!output.status.success());
    assert!(String::from_utf8_lossy(&output.stderr).contains("--dump-ir needs a drive id"));
    assert!(output.stdout.is_empty(), "nothing generated");
}
