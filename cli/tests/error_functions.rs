//! An error reply decodes only with a function the drive has, marked as an error: the FC 51
//! has no Modbus function 08, so 88h is no reply of it (its manual lists 81h, 83h, 85h,
//! 86h, 8Fh and 90h), while the DV1, which has 08, sends 88h. A drive that answers a
//! function it lacks (`unsupported_function`) sends that function + 80h too, with its code.

mod common;

use common::text;
use std::process::{Command, Output};

fn decode(drive: &str, frame: &str) -> Output {
    Command::new(env!("CARGO_BIN_EXE_vfd"))
        .args(["decode", "-d", drive, "-p", "modbus", "--reply", frame])
        .output()
        .expect("vfd runs")
}

#[test]
fn the_fc51_sends_no_88h_and_the_dv1_does() {
    // 01 88 12: function 08 refused with error 18 (CRC 0DC6h).
    let fc51 = decode("fc51", "01 88 12 C6 0D");
    assert!(!fc51.status.success(), "{}", text(&fc51));
    assert!(text(&fc51).contains("holds 0x0088"), "{}", text(&fc51));
    let dv1 = decode("dv1", "01 88 12 C6 0D");
    assert!(dv1.status.success(), "{}", text(&dv1));
    // 01 83 40: the FC 51's 03 refused with error 64 (invalid data address).
    let read = decode("fc51", "01 83 40 40 C0");
    assert!(read.status.success(), "{}", text(&read));
    assert!(text(&read).contains("64"), "{}", text(&read));
}

#[test]
fn the_dv1_and_the_vf_as1_reply_to_a_function_they_lack_decodes() {
    // 01 81 01: function 01 refused with exception 01, as the virtual drive sends it.
    for drive in ["dv1", "vf-as1"] {
        let lacking = decode(drive, "01 81 01 81 90");
        assert!(lacking.status.success(), "{drive}: {}", text(&lacking));
        assert!(
            text(&lacking).contains("81h (error reply)"),
            "{}",
            text(&lacking)
        );
    }
    // The same function with another code is no reply of theirs.
    let other = decode("dv1", "01 81 02 C1 91");
    assert!(!other.status.success(), "{}", text(&other));
}
