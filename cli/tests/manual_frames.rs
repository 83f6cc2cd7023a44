//! `vfd decode` on every example frame of every described manual: each request and reply
//! the drive files carry (as corrected where the manual misprints it) decodes, as a request
//! or a reply, with a good checksum, for its drive and protocol; and every printed frame
//! recorded as an erratum is refused with a non-zero exit, except those wrong only in their
//! exchange (valid on their own), which decode.

use std::path::Path;
use std::process::Command;

fn hex(bytes: &[u8]) -> String {
    bytes
        .iter()
        .map(|b| format!("{b:02X}"))
        .collect::<Vec<_>>()
        .join(" ")
}

fn decode(drive: &str, protocol: &str, side: &str, bytes: &[u8]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_vfd"))
        .args(["decode", "--drive", drive, "--protocol", protocol, side])
        .arg(hex(bytes))
        .output()
        .expect("vfd runs")
}

#[test]
fn every_example_frame_of_every_manual_decodes() {
    let drives = Path::new(env!("CARGO_MANIFEST_DIR")).join("../drives");
    let mut decoded = 0;
    let mut refused = 0;
    let mut valid_alone = 0;
    let mut names: Vec<_> = std::fs::read_dir(&drives)
        .expect("drives/")
        .filter_map(|entry| entry.ok().map(|e| e.path()))
        .filter(|path| path.extension().is_some_and(|e| e == "yaml"))
        .collect();
    names.sort();
    for path in names {
        let drive = vfd_codegen::compile(&path, None).expect("a valid description");
        for example in &drive.examples {
            if let Some(ignored) = &example.ignored_request {
                let output = decode(&drive.id, &example.protocol, "--request", &ignored.bytes);
                assert!(
                    !output.status.success(),
                    "{} {}: the drive ignores {}, yet it decodes",
                    drive.id,
                    example.id,
                    hex(&ignored.bytes)
                );
                refused += 1;
            }
            for (side, frame) in [("--request", &example.request), ("--reply", &example.reply)] {
                let Some(frame) = frame else { continue };
                let output = decode(&drive.id, &example.protocol, side, &frame.bytes);
                let stdout = String::from_utf8_lossy(&output.stdout);
                assert!(
                    output.status.success(),
                    "{} {} {side}: {}\n{stdout}{}",
                    drive.id,
                    example.id,
                    hex(&frame.bytes),
                    String::from_utf8_lossy(&output.stderr)
                );
                assert!(
                    stdout.contains("checksum ok") || stdout.contains("no checksum"),
                    "{} {}: {stdout}",
                    drive.id,
                    example.id
                );
                decoded += 1;
                if let Some(printed) = &frame.printed {
                    let output = decode(&drive.id, &example.protocol, side, &printed.bytes);
                    if printed.rejected_as.decode_kind().is_none() {
                        // Wrong only in its exchange: valid on its own, so it decodes
                        // (the golden tests check the exchange).
                        assert!(
                            output.status.success(),
                            "{} {}: the printed frame {} is valid on its own, yet refused",
                            drive.id,
                            example.id,
                            hex(&printed.bytes)
                        );
                        valid_alone += 1;
                        continue;
                    }
                    assert!(
                        !output.status.success(),
                        "{} {}: the printed frame {} is an erratum, yet it decodes",
                        drive.id,
                        example.id,
                        hex(&printed.bytes)
                    );
                    refused += 1;
                }
            }
        }
    }
    eprintln!(
        "{decoded} example frames decoded, {refused} printed errata refused, \
         {valid_alone} wrong only in their exchange"
    );
    assert!(decoded > 100, "only {decoded} frames");
}

#[test]
fn broadcast_frames_decode_with_their_stations_and_what_the_drive_makes_of_them() {
    let text = |output: std::process::Output| String::from_utf8_lossy(&output.stdout).into_owned();
    let group = text(decode("vf-as1", "ascii", "--request", b"(*9PFA011770)\r"));
    assert!(group.contains("every station matching *9"), "{group}");
    assert!(group.contains("*9 (broadcast)"), "{group}");
    let read = text(decode("vf-as1", "ascii", "--request", b"(*2R0000)\r"));
    assert!(read.contains("a broadcast read"), "{read}");
    let yd1000 = text(decode("yd1000", "ascii", "--request", b"(**PFA011770)\r"));
    assert!(yd1000.contains("yd1000 takes no broadcasts"), "{yd1000}");
    let binary = text(decode(
        "vf-as1",
        "binary",
        "--request",
        &[0x2F, 0xFF, 0x50, 0xFA, 0x01, 0x17, 0x70, 0x00],
    ));
    assert!(binary.contains("broadcast: every station"), "{binary}");
    // A reply comes from one station: open digits are refused there.
    let reply = Command::new(env!("CARGO_BIN_EXE_vfd"))
        .args([
            "decode",
            "--drive",
            "vf-as1",
            "--protocol",
            "ascii",
            "--reply",
            "(**PFA011770)\\r",
        ])
        .output()
        .expect("vfd runs");
    assert!(!reply.status.success());
}
