//! `vfd decode` and `vfd encode` agree on a drive's station range (the description's
//! `addressing`): a YD1000 frame naming station 64 (range 0-63, manual l. 118, 149) is
//! refused by both, in either direction and either protocol; station 63 is accepted.

mod common;

use common::text;
use std::process::{Command, Output};

fn vfd(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_vfd"))
        .args(args)
        .output()
        .expect("vfd runs")
}

#[test]
fn a_yd1000_reply_from_station_64_is_refused_as_the_encoder_refuses_it() {
    let decoded = vfd(&[
        "decode",
        "-d",
        "yd1000",
        "-p",
        "ascii",
        "--reply",
        "(64R0501012C)\\r",
    ]);
    assert!(!decoded.status.success(), "{}", text(&decoded));
    assert!(
        text(&decoded).contains(
            "station 64 in `address` at byte 1 is outside the drive's station range 0..=63"
        ),
        "{}",
        text(&decoded)
    );
    let encoded = vfd(&[
        "encode",
        "yd1000",
        "ascii",
        "read",
        "F501",
        "--address",
        "64",
    ]);
    assert!(!encoded.status.success(), "{}", text(&encoded));
    assert!(
        text(&encoded).contains("outside 0..=63"),
        "{}",
        text(&encoded)
    );

    // The same frame from station 63 (sum adjusted) decodes.
    let ok = vfd(&[
        "decode",
        "-d",
        "yd1000",
        "-p",
        "ascii",
        "--reply",
        "(63R0501012B)\\r",
    ]);
    assert!(ok.status.success(), "{}", text(&ok));
    assert!(text(&ok).contains("station:  63"), "{}", text(&ok));
}

#[test]
fn a_yd1000_request_to_station_64_is_refused_in_both_protocols() {
    let ascii = vfd(&[
        "decode",
        "-d",
        "yd1000",
        "-p",
        "ascii",
        "--request",
        "(64RFA01)\\r",
    ]);
    assert!(!ascii.status.success(), "{}", text(&ascii));
    assert!(text(&ascii).contains("station 64"), "{}", text(&ascii));
    // Binary: station byte 40h, sum 2F + 40 + 52 + FA + 01 = BCh.
    let binary = vfd(&[
        "decode",
        "-d",
        "yd1000",
        "-p",
        "binary",
        "--request",
        "2F 40 52 FA 01 BC",
    ]);
    assert!(!binary.status.success(), "{}", text(&binary));
    let encoded = vfd(&[
        "encode",
        "yd1000",
        "binary",
        "read",
        "FA01",
        "--address",
        "63",
    ]);
    assert!(
        text(&encoded).contains("2F 3F 52 FA 01 BB"),
        "{}",
        text(&encoded)
    );
    let back = vfd(&[
        "decode",
        "-d",
        "yd1000",
        "-p",
        "binary",
        "--request",
        "2F 3F 52 FA 01 BB",
    ]);
    assert!(back.status.success(), "{}", text(&back));
}

#[test]
fn a_modbus_broadcast_is_no_station_out_of_range() {
    // Station 0 is Modbus's broadcast, outside the FC 51's stations 1-247 but decoded as
    // the broadcast it is.
    let broadcast = vfd(&[
        "decode",
        "-d",
        "fc51",
        "-p",
        "modbus",
        "--request",
        "00 06 03 F1 00 01 18 6C",
    ]);
    assert!(broadcast.status.success(), "{}", text(&broadcast));
    assert!(
        text(&broadcast).contains("every station"),
        "{}",
        text(&broadcast)
    );
    // Station 248 is no station of the FC 51: 03 reply of one word, CRC recomputed.
    let frame = with_crc(&[248, 0x03, 0x02, 0x00, 0x01]);
    let refused = vfd(&["decode", "-d", "fc51", "-p", "modbus", "--reply", &frame]);
    assert!(!refused.status.success(), "{}", text(&refused));
    assert!(
        text(&refused).contains("station 248") && text(&refused).contains("1..=247"),
        "{}",
        text(&refused)
    );
}

/// `bytes` with their Modbus CRC-16 (low byte first), as hex.
fn with_crc(bytes: &[u8]) -> String {
    let mut crc: u16 = 0xFFFF;
    for byte in bytes {
        crc ^= u16::from(*byte);
        for _ in 0..8 {
            crc = if crc & 1 == 1 {
                crc >> 1 ^ 0xA001
            } else {
                crc >> 1
            };
        }
    }
    bytes
        .iter()
        .copied()
        .chain(crc.to_le_bytes())
        .map(|b| format!("{b:02X}"))
        .collect::<Vec<_>>()
        .join(" ")
}
