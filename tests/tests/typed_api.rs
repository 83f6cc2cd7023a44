//! The generated YD1000 API used the way a newcomer would: typed registers, units,
//! ranges, bit fields, code tables and error codes.

use vfd_drives::yd1000::{self, bits, codes, protocols, registers, ErrorCode};
use vfd_runtime::prelude::*;
use vfd_runtime::units::{Hertz, Seconds};
use vfd_runtime::{Register, RegisterValue, Space, ValueError};

fn encode(
    protocol: &vfd_runtime::Protocol,
    request: &vfd_runtime::Request,
    address: Option<u8>,
) -> Vec<u8> {
    let mut frame = [0u8; 32];
    let len = protocol
        .encode_request(request, address, &mut frame)
        .expect("encodes");
    frame[..len].to_vec()
}

#[test]
fn set_60_hz_in_ram_builds_the_manual_frame() {
    let request = registers::FrequencyCommand::write_ram(Hertz(60.0)).unwrap();
    assert_eq!(
        encode(&protocols::BINARY, &request, None),
        [0x2F, 0x50, 0xFA, 0x01, 0x17, 0x70, 0x01]
    );
}

#[test]
fn ascii_requests_carry_a_checksum_and_the_station_number_by_default() {
    let request = registers::FrequencyCommand::write_ram(Hertz(60.0)).unwrap();
    assert_eq!(
        encode(&protocols::ASCII, &request, None),
        b"(PFA011770&55)\r"
    );
    assert_eq!(
        encode(
            &protocols::ASCII,
            &registers::OutputFrequencyNow::read(),
            Some(5)
        ),
        b"(05RFD00&EF)\r"
    );
    let frame = encode(&protocols::ASCII, &request, None);
    let sum: u32 = frame[..frame.iter().position(|b| *b == b'&').unwrap() + 1]
        .iter()
        .map(|b| u32::from(*b))
        .sum();
    assert_eq!(&frame[11..13], format!("{:02X}", sum & 0xFF).as_bytes());
}

#[test]
fn persistent_writes_use_w_and_ram_writes_use_p() {
    let persistent = registers::DecelerationTime2::write_persistent(Seconds(30.0)).unwrap();
    let ram = registers::DecelerationTime2::write_ram(Seconds(30.0)).unwrap();
    assert_eq!(
        encode(&protocols::BINARY, &persistent, None),
        [0x2F, 0x57, 0x05, 0x01, 0x01, 0x2C, 0xB9]
    );
    assert_eq!(
        encode(&protocols::BINARY, &ram, None),
        [0x2F, 0x50, 0x05, 0x01, 0x01, 0x2C, 0xB2]
    );
}

#[test]
fn a_value_outside_the_range_is_refused_before_any_byte_is_built() {
    let error = registers::FrequencyCommand::write_ram(Hertz(400.0)).unwrap_err();
    assert!(
        matches!(error, ValueError::OutOfRange { max, .. } if max == 320.0),
        "{error:?}"
    );
    let message = error.to_string();
    for needle in ["FA01", "通信频率指令", "400 Hz", "320", "FH"] {
        assert!(message.contains(needle), "`{message}` should name {needle}");
    }
    assert!(
        registers::AccelerationTime1::write_ram(Seconds(0.0)).is_err(),
        "Acc starts at 0.1 s"
    );
    assert!(matches!(
        registers::FrequencyCommand::write_ram(Hertz(f64::NAN)),
        Err(ValueError::NotFinite { .. })
    ));
}

#[test]
fn register_metadata_comes_from_the_yaml() {
    let info = <registers::MaximumFrequency as Register>::INFO;
    assert_eq!(
        (info.address, info.code, info.name_zh),
        (0x0011, "FH", "最高频率")
    );
    assert!(!info.writable_while_running);
    assert!(<registers::FrequencyCommand as Register>::INFO.ram_only);
    assert_eq!(
        yd1000::DRIVE.register("fh").map(|r| r.address),
        Some(0x0011)
    );
    assert_eq!(
        yd1000::DRIVE
            .register_at(Space::Parameter, 0xFE01)
            .map(|r| r.code),
        Some("FE01")
    );
    assert_eq!(
        yd1000::DRIVE.register("UL").and_then(|r| r.max_bound),
        Some("FH")
    );
    assert_eq!(registers::ALL.len(), 64);
}

#[test]
fn command_word_builders_and_status_word_accessors() {
    let command = bits::CommandWord::new()
        .with_command_enabled(true)
        .with_frequency_enabled(true)
        .with_run(true);
    assert_eq!(command.bits(), 0xC400);
    assert_eq!(
        command.to_string(),
        "command_enabled | frequency_enabled | run"
    );
    assert!(!command.with_run(false).run());
    let status = bits::StatusWord(0x0440);
    assert!(status.running() && status.acc_dec_2() && !status.reverse());
    assert!(bits::StatusWord(0x9000).has_reserved_bits());
    let request = registers::CommandWord::write_ram(command).unwrap();
    assert_eq!(
        encode(&protocols::BINARY, &request, None),
        [0x2F, 0x50, 0xFA, 0x00, 0xC4, 0x00, 0x3D]
    );
}

#[test]
fn code_tables_are_enums() {
    assert_eq!(
        codes::BaudRate::from_code(3),
        Some(codes::BaudRate::Bps9600)
    );
    assert_eq!(codes::Parity::Even.name_zh(), "偶校验");
    let info = <registers::BaudRate as Register>::INFO;
    let error = codes::BaudRate::from_raw(7, info).unwrap_err();
    assert!(error.to_string().contains("baud_rate"), "{error}");
    let request = registers::Parity::write_persistent(codes::Parity::Odd).unwrap();
    assert_eq!(request.data, 2);
}

#[test]
fn error_codes_carry_the_manual_meaning() {
    let code = ErrorCode::from_code(1).unwrap();
    assert_eq!(code, ErrorCode::DataError);
    assert_eq!(
        code.info().map(|info| info.name_zh.as_ref()),
        Some("数据错误")
    );
    assert_eq!(ErrorCode::from_code(9), None);
}

#[test]
fn station_numbers_outside_the_drive_range_are_refused() {
    let mut frame = [0u8; 32];
    let error = protocols::BINARY
        .encode_request(&registers::Status::read(), Some(64), &mut frame)
        .unwrap_err();
    assert!(error.to_string().contains("64"), "{error}");
}

/// The requests every register gets from the runtime's traits, used generically.
fn requests_through_the_traits<R: vfd_runtime::Persistable>(
    ram: R::Value,
    persistent: R::Value,
) -> [vfd_runtime::DriveRequest<R::Drive>; 3] {
    [
        R::read(),
        R::write_ram(ram).unwrap(),
        R::write_persistent(persistent).unwrap(),
    ]
}

#[test]
fn the_runtime_traits_build_the_same_requests_as_the_generated_functions() {
    use vfd_runtime::prelude::*;
    type Dec2 = registers::DecelerationTime2;
    assert_eq!(
        requests_through_the_traits::<Dec2>(Seconds(30.0), Seconds(30.0)),
        [
            Dec2::read(),
            Dec2::write_ram(Seconds(30.0)).unwrap(),
            Dec2::write_persistent(Seconds(30.0)).unwrap(),
        ]
    );
    // Fully qualified, the trait's function is the one called.
    assert_eq!(
        <Dec2 as Writable>::write_ram(Seconds(30.0)).unwrap(),
        Dec2::write_ram(Seconds(30.0)).unwrap()
    );
    let fc51_preset = <vfd_drives::fc51::registers::PresetReference as Register>::read_at(3);
    assert_eq!(
        fc51_preset.unwrap(),
        vfd_drives::fc51::registers::PresetReference::read_at(3).unwrap()
    );
}
