//! Writes the seed corpora: every example frame of every described drive (as printed and as
//! corrected) into `corpus/<protocol file>_request/` and `_reply/` (requests also, behind a
//! selector byte, into `corpus/virtual_drive/`; and behind a protocol and a command byte, into
//! `corpus/plan_agreement/`), every drive file and broken-description
//! fixture into `corpus/description/`, and `set` message payloads into
//! `corpus/set_value/`. Run from `fuzz/`: `cargo run --example seed_corpus`.

use std::fs;
use std::path::Path;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let drives = root.join("../drives");
    let corpus = root.join("corpus");
    let mut written = 0;
    let description = corpus.join("description");
    fs::create_dir_all(&description)?;
    let fixtures = root.join("../tests/fixtures/broken");
    for dir in [&drives, &fixtures] {
        for entry in fs::read_dir(dir)? {
            let path = entry?.path();
            if path.extension().is_some_and(|e| e == "yaml") {
                fs::copy(&path, description.join(path.file_name().unwrap_or_default()))?;
                written += 1;
            }
        }
    }
    for entry in fs::read_dir(&drives)? {
        let path = entry?.path();
        if path.extension().is_none_or(|e| e != "yaml") {
            continue;
        }
        let drive = vfd_codegen::compile(&path, None).map_err(|e| e.to_string())?;
        for example in &drive.examples {
            let Some(protocol) = drive.protocols.iter().find(|p| p.id == example.protocol) else {
                continue;
            };
            let file_name = protocol.uses.replace('-', "_");
            for (side, frame) in [("request", &example.request), ("reply", &example.reply)] {
                let Some(frame) = frame else { continue };
                let dir = corpus.join(format!("{file_name}_{side}"));
                fs::create_dir_all(&dir)?;
                fs::write(dir.join(format!("{}_{}", drive.id, example.id)), &frame.bytes)?;
                written += 1;
                if side == "request" {
                    // The virtual drive's target: a selector byte (drive, protocol), then
                    // the request; every selector of two drives and two protocols.
                    let dir = corpus.join("virtual_drive");
                    fs::create_dir_all(&dir)?;
                    for selector in [0x00u8, 0x01, 0x10, 0x11] {
                        let mut seed = vec![selector];
                        seed.extend_from_slice(&frame.bytes);
                        fs::write(
                            dir.join(format!("{}_{}_{selector:02x}", drive.id, example.id)),
                            seed,
                        )?;
                        written += 1;
                    }
                }
                // The plan-agreement target: a selector byte (the protocol, in the order
                // of `vfd_drives::ALL_DRIVES` and their variants), a command byte, then the
                // frame; one seed per command of the protocol.
                let dir = corpus.join("plan_agreement");
                fs::create_dir_all(&dir)?;
                let all = vfd_drives::ALL_DRIVES.iter().flat_map(|d| {
                    d.protocols
                        .iter()
                        .flat_map(|p| p.all_variants())
                        .map(move |p| (d.id, p))
                });
                for (selector, (_, protocol)) in all
                    .enumerate()
                    .filter(|(_, (id, p))| *id == drive.id && p.id == example.protocol)
                {
                    for pick in 0..protocol.commands.len() {
                        let mut seed = vec![selector as u8, pick as u8];
                        seed.extend_from_slice(&frame.bytes);
                        let name = format!("{}_{}_{side}_{selector}_{pick}", drive.id, example.id);
                        fs::write(dir.join(name), seed)?;
                        written += 1;
                    }
                }
                if let Some(printed) = &frame.printed {
                    fs::write(
                        dir.join(format!("{}_{}_printed", drive.id, example.id)),
                        &printed.bytes,
                    )?;
                    written += 1;
                }
            }
        }
    }
    // The set-message reader of `vfd serve --mqtt`: values as text and as JSON, and a few
    // that are refused.
    let dir = corpus.join("set_value");
    fs::create_dir_all(&dir)?;
    let seeds: [&[u8]; 10] = [
        b"50",
        b"50 Hz",
        b"command_enabled,frequency_enabled,run",
        b"\"50 Hz\"",
        br#"{"value": 42.5}"#,
        br#"{"value": "50 Hz"}"#,
        br#"{"value": [[1]]}"#,
        br#"{"value": 1e999999}"#,
        b"\xff\xfe",
        b"",
    ];
    for (n, seed) in seeds.iter().enumerate() {
        fs::write(dir.join(format!("seed_{n}")), seed)?;
        written += 1;
    }
    println!("{written} seeds written under {}", corpus.display());
    Ok(())
}
