//! One truth, two paths: every drive file of the repository, compiled into Rust (the build
//! script's or the proc-macro's statics) and loaded while a program runs
//! (`vfd_codegen::drive_info`, what `vfd --drive ./my_drive.yaml` uses), is the same drive:
//! every register as the CLI shows it, every protocol with its commands, layouts and frame
//! plans, the behaviour model, the ports, formulas and forbidden combinations (compared
//! through their `Debug` form, line by line, with the first difference shown), and every
//! example's and sequence's frames decode alike through both.

use std::fmt::Debug;
use std::path::Path;
use vfd_runtime::{DriveInfo, Protocol};

vfd_macros::include_drive!(
    "fixtures/external-crate/demo_pump.yaml",
    protocols = "../drives/protocols"
);

mod computer_link_fixture {
    vfd_macros::include_drive!(
        "fixtures/computer-link/heron_hl7.yaml",
        protocols = "fixtures/computer-link/protocols"
    );
}

mod error_tables_fixture {
    vfd_macros::include_drive!(
        "fixtures/error-tables/drive.yaml",
        protocols = "../drives/protocols"
    );
}

/// Every drive file with its compiled-in drive.
fn drives() -> Vec<(&'static str, Option<&'static str>, &'static DriveInfo)> {
    let mut all: Vec<(&'static str, Option<&'static str>, &'static DriveInfo)> = vec![
        (
            "fixtures/external-crate/demo_pump.yaml",
            Some("../drives/protocols"),
            &demo_pump::DRIVE,
        ),
        (
            "fixtures/computer-link/heron_hl7.yaml",
            Some("fixtures/computer-link/protocols"),
            &computer_link_fixture::heron_hl7::DRIVE,
        ),
        (
            "fixtures/error-tables/drive.yaml",
            Some("../drives/protocols"),
            &error_tables_fixture::error_tables::DRIVE,
        ),
    ];
    let mut files: Vec<_> = std::fs::read_dir("../drives")
        .expect("drives/ is readable")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == "yaml"))
        .collect();
    files.sort();
    assert!(files.len() >= 4, "the four described drives: {files:?}");
    for file in files {
        let ir = vfd_codegen::compile(&file, None).expect("a described drive compiles");
        let compiled = vfd_drives::drive(&ir.id)
            .unwrap_or_else(|| panic!("{} is not compiled into vfd-drives", ir.id));
        let path: &'static str = Box::leak(file.display().to_string().into_boxed_str());
        all.push((path, None, compiled));
    }
    all
}

/// `value`'s pretty `Debug` form, with compiled plan functions (which only a generated
/// layout has: their addresses differ per build) written as `compiled: <functions>`, and a
/// run-time plan's `compiled: None` the same way, since both run the same steps.
fn shown(value: &impl Debug) -> Vec<String> {
    let text = format!("{value:#?}");
    let mut lines = Vec::new();
    let mut skip_until: Option<String> = None;
    for line in text.lines() {
        if let Some(end) = &skip_until {
            if line == end {
                skip_until = None;
            }
            continue;
        }
        let trimmed = line.trim_start();
        let indent = &line[..line.len() - trimmed.len()];
        if trimmed == "compiled: Some(" {
            skip_until = Some(format!("{indent}),"));
            lines.push(format!("{indent}compiled: <functions>"));
        } else if trimmed == "compiled: None," {
            lines.push(format!("{indent}compiled: <functions>"));
        } else {
            lines.push(line.to_owned());
        }
    }
    lines
}

/// Fails with the first line where `what` differs between the two paths, and its context.
fn assert_same(file: &str, what: &str, compiled: &impl Debug, live: &impl Debug) {
    let (compiled, live) = (shown(compiled), shown(live));
    if compiled == live {
        return;
    }
    let at = compiled
        .iter()
        .zip(&live)
        .position(|(a, b)| a != b)
        .unwrap_or(compiled.len().min(live.len()));
    let from = at.saturating_sub(6);
    let context = |lines: &[String]| lines[from..(at + 3).min(lines.len())].join("\n");
    panic!(
        "{file}: {what} differs between the compiled-in and the run-time path at line {}:\n\
         --- compiled in\n{}\n--- loaded at run time\n{}",
        at + 1,
        context(&compiled),
        context(&live),
    );
}

#[test]
fn every_drive_file_is_the_same_drive_compiled_in_and_loaded_at_run_time() {
    let mut compared = 0;
    for (file, protocols, compiled) in drives() {
        let ir = vfd_codegen::compile(Path::new(file), protocols.map(Path::new))
            .unwrap_or_else(|e| panic!("{file} does not compile:\n{e}"));
        let live = vfd_codegen::drive_info(&ir);
        // Piece by piece first, so a difference names its register or protocol.
        assert_eq!(compiled.registers.len(), live.registers.len(), "{file}");
        for (a, b) in compiled.registers.iter().zip(live.registers) {
            assert_same(file, &format!("register {}", a.code), a, b);
        }
        assert_eq!(compiled.protocols.len(), live.protocols.len(), "{file}");
        for (a, b) in compiled.protocols.iter().zip(live.protocols) {
            assert_same(file, &format!("protocol {}", a.id), a, b);
        }
        assert_same(file, "the whole drive", compiled, live);
        frames_decode_alike(file, &ir, compiled, live);
        compared += 1;
    }
    assert!(compared >= 7, "compared {compared} drive files");
}

/// Every example's and sequence's frames decode to the same outcome through both paths.
fn frames_decode_alike(
    file: &str,
    ir: &vfd_codegen::DriveIr,
    compiled: &DriveInfo,
    live: &DriveInfo,
) {
    let protocol = |drive: &DriveInfo, id: &str| -> &'static Protocol {
        drive
            .protocol(id)
            .unwrap_or_else(|| panic!("{file}: no protocol {id}"))
    };
    let mut frames = 0;
    for example in &ir.examples {
        let (a, b) = (
            protocol(compiled, &example.protocol),
            protocol(live, &example.protocol),
        );
        if let Some(request) = &example.request {
            let what = format!("example {}'s request", example.id);
            assert_same(
                file,
                &what,
                &a.decode_request(&request.bytes),
                &b.decode_request(&request.bytes),
            );
            frames += 1;
        }
        if let Some(reply) = &example.reply {
            let what = format!("example {}'s reply", example.id);
            assert_same(
                file,
                &what,
                &a.decode_reply(None, &reply.bytes),
                &b.decode_reply(None, &reply.bytes),
            );
            frames += 1;
        }
    }
    assert!(
        ir.examples.is_empty() || frames > 0,
        "{file}: no example frame compared"
    );
}
