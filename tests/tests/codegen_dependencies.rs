//! The generator compiles no transports: every build script that runs `vfd-codegen` would
//! otherwise build a serial-port and pseudo-terminal stack it never uses.

use std::process::Command;

#[test]
fn the_generator_depends_on_no_transport_crate() {
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".to_owned());
    let output = Command::new(cargo)
        .args([
            "tree",
            "--offline",
            "--locked",
            "-p",
            "vfd-codegen",
            "-e",
            "normal",
            "--prefix",
            "none",
        ])
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .expect("cargo runs");
    let tree = String::from_utf8_lossy(&output.stdout);
    assert!(
        output.status.success(),
        "cargo tree failed: {}",
        String::from_utf8_lossy(&output.stderr)
    );
    assert!(
        tree.contains("vfd-runtime"),
        "the tree lists the runtime:\n{tree}"
    );
    for transport in ["nix ", "serialport "] {
        assert!(
            !tree.lines().any(|line| line.starts_with(transport)),
            "vfd-codegen pulls in `{}`:\n{tree}",
            transport.trim()
        );
    }
}
