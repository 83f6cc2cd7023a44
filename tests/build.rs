//! Generates one golden-frame test per example of every drive in `drives/`
//! (`golden.rs` in OUT_DIR, included by `tests/golden.rs`), and finds which Python peers
//! (pymodbus, minimalmodbus) are installed: a peer test whose package is missing is built
//! `#[ignore]`d with the reason (`cfg(missing_pymodbus)`, `cfg(missing_minimalmodbus)`), so
//! it shows as ignored, never as `ok`. Under CI (`CI` set) nothing is ignored: a missing
//! package fails the test. LinuxCNC's `halrun` likewise (`cfg(missing_halrun)`).

use std::path::PathBuf;
use std::process::Command;

/// Marks the Python peers that cannot be imported (see the module documentation).
fn detect_python_peers() {
    println!("cargo::rustc-check-cfg=cfg(missing_pymodbus)");
    println!("cargo::rustc-check-cfg=cfg(missing_minimalmodbus)");
    println!("cargo:rerun-if-env-changed=CI");
    println!("cargo:rerun-if-env-changed=PATH");
    println!("cargo:rerun-if-env-changed=VIRTUAL_ENV");
    println!("cargo:rerun-if-changed=python/requirements.txt");
    if std::env::var_os("CI").is_some() {
        return;
    }
    for (module, cfg) in [
        ("pymodbus", "missing_pymodbus"),
        ("minimalmodbus", "missing_minimalmodbus"),
    ] {
        let found = Command::new("python3")
            .args(["-c", &format!("import {module}, serial")])
            .output()
            .is_ok_and(|o| o.status.success());
        if !found {
            println!("cargo:rustc-cfg={cfg}");
        }
    }
}

/// Marks LinuxCNC's `halrun` missing (Debian `linuxcnc-uspace`): the tests that run its VFD
/// components are then built `#[ignore]`d with the reason (`cfg(missing_halrun)`); under
/// CI they run, and a missing `halrun` fails them.
fn detect_halrun() {
    println!("cargo::rustc-check-cfg=cfg(missing_halrun)");
    if std::env::var_os("CI").is_some() {
        return;
    }
    let found = Command::new("halrun").arg("-h").output().is_ok();
    if !found {
        println!("cargo:rustc-cfg=missing_halrun");
    }
}

/// Marks mbpoll (libmodbus's command-line master, Debian `mbpoll`) missing likewise
/// (`cfg(missing_mbpoll)`).
fn detect_mbpoll() {
    println!("cargo::rustc-check-cfg=cfg(missing_mbpoll)");
    if std::env::var_os("CI").is_some() {
        return;
    }
    if Command::new("mbpoll").arg("-V").output().is_err() {
        println!("cargo:rustc-cfg=missing_mbpoll");
    }
}

fn main() {
    detect_python_peers();
    detect_halrun();
    detect_mbpoll();
    let manifest = PathBuf::from(
        std::env::var_os("CARGO_MANIFEST_DIR").expect("cargo sets CARGO_MANIFEST_DIR"),
    );
    let out_dir = PathBuf::from(std::env::var_os("OUT_DIR").expect("cargo sets OUT_DIR"));
    let drives_dir = manifest.join("../drives");
    println!("cargo:rerun-if-changed={}", drives_dir.display());
    let builder = match vfd_codegen::Builder::new().drives_in(&drives_dir) {
        Ok(builder) => builder
            .out_dir(&out_dir)
            .golden_tests(true)
            .crate_path("vfd_drives")
            .regenerate_command("cargo build -p vfd-tests")
            .display_root(manifest.join(".."))
            .cargo_metadata(true),
        Err(error) => vfd_codegen::fail_build(&error),
    };
    if let Err(error) = builder.generate() {
        vfd_codegen::fail_build(&error);
    }
}
