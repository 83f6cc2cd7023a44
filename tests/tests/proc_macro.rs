//! The proc-macro front end yields the same API as the build script.

use vfd_runtime::prelude::*;

vfd_macros::include_drive!("../drives/yd1000.yaml");

#[test]
fn the_macro_expands_to_the_drive_module() {
    let request =
        yd1000::registers::FrequencyCommand::write_ram(vfd_runtime::units::Hertz(60.0)).unwrap();
    let mut frame = [0u8; 16];
    let len = yd1000::protocols::BINARY
        .encode_request(&request, None, &mut frame)
        .unwrap();
    assert_eq!(&frame[..len], [0x2F, 0x50, 0xFA, 0x01, 0x17, 0x70, 0x01]);
    assert_eq!(
        yd1000::registers::ALL.len(),
        vfd_drives::yd1000::registers::ALL.len()
    );
}

/// An explicit protocol folder (here the default one, named from another place).
mod explicit_protocols {
    vfd_macros::include_drive!(
        "../drives/fc51.yaml",
        protocols = "../drives/../drives/protocols"
    );
}

#[test]
fn the_macro_takes_a_protocol_folder() {
    assert_eq!(
        explicit_protocols::fc51::registers::ALL.len(),
        vfd_drives::fc51::registers::ALL.len()
    );
}
