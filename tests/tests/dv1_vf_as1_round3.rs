//! Round-3 audit of the DV1 and VF-AS1 descriptions, sections (a)-(c): the `unknown`
//! while-running flag, the FExx copies read as live between trips, and the errata and notes
//! the audit asked for, as the generated pages show them.

use std::time::Duration;
use vfd_drives::vf_as1;
use vfd_runtime::prelude::*;
use vfd_runtime::virtual_drive::Simulator;
use vfd_runtime::DriveProtocol;
use vfd_tests::outcomes::refused;

const VF_AS1_PROTOCOLS: [&DriveProtocol<vf_as1::Drive>; 3] = [
    &vf_as1::protocols::ASCII,
    &vf_as1::protocols::BINARY,
    &vf_as1::protocols::MODBUS,
];

/// C400h: command and frequency priority, forward run (4.5).
fn run_forward() -> vf_as1::bits::CommandWord1 {
    vf_as1::bits::CommandWord1::new()
        .with_command_priority(true)
        .with_frequency_priority(true)
        .with_run(true)
}

fn running_drive(
    protocol: &'static DriveProtocol<vf_as1::Drive>,
) -> (
    Simulator,
    Master<vfd_runtime::virtual_drive::SimLink, vf_as1::Drive>,
) {
    use vf_as1::registers::*;
    let sim = Simulator::new(&vf_as1::DRIVE);
    let mut master = sim.master(protocol);
    master
        .write_ram::<AccelerationTime1>(Seconds(10.0))
        .unwrap();
    master
        .write_ram::<FrequencyCommand2wire>(Hertz(60.0))
        .unwrap();
    master
        .write_ram::<CommandWord12wire>(run_forward())
        .unwrap();
    sim.advance(Duration::from_secs(10));
    assert!(master.read::<Status1>().unwrap().running());
    (sim, master)
}

#[test]
fn registers_without_a_while_running_column_are_unknown_not_false() {
    use vf_as1::registers::*;
    // Section 7's table, FA09, FMOD and F420: 30 registers, none stated either way.
    let unknown: Vec<&str> = vf_as1::DRIVE
        .registers
        .iter()
        .filter(|r| r.while_running_unknown)
        .map(|r| r.code)
        .collect();
    assert_eq!(unknown.len(), 30, "{unknown:?}");
    for code in ["F800", "F805", "F856", "F880", "FA09", "FMOD", "F420"] {
        assert!(unknown.contains(&code), "{code}");
    }
    let f803 = CommunicationTimeout::INFO;
    assert!(f803.while_running_unknown && !f803.writable_while_running);
    // Stated registers keep their flags: FH is refused while running (4.1.1), ACC is not.
    assert!(!MaximumFrequency::INFO.while_running_unknown);
    assert!(AccelerationTime1::INFO.writable_while_running);
}

#[test]
fn the_virtual_drive_accepts_an_unknown_write_while_running_and_refuses_a_known_one() {
    use vf_as1::registers::*;
    for protocol in VF_AS1_PROTOCOLS {
        let (_sim, mut master) = running_drive(protocol);
        // F803 has no while-running column: the write is attempted and accepted.
        master
            .write_ram::<CommunicationTimeout>(Seconds(5.0))
            .unwrap_or_else(|e| panic!("{}: {e}", protocol.id));
        assert_eq!(
            master.read::<CommunicationTimeout>().unwrap().value,
            Seconds(5.0)
        );
        // FH cannot be changed while running (4.1.1): 0000 (Toshiba), 04 (Modbus).
        let code = refused(master.write_ram::<MaximumFrequency>(Hertz(70.0)));
        let expected = if protocol.id == "modbus" {
            0x04
        } else {
            0x0000
        };
        assert_eq!(code, expected, "{}", protocol.id);
    }
}

#[test]
fn fe_copies_follow_the_live_values_between_trips_and_hold_them_while_tripped() {
    use vf_as1::registers::*;
    for protocol in VF_AS1_PROTOCOLS {
        let (sim, mut master) = running_drive(protocol);
        // 4.6 example 1 reads FE00 as the output frequency while the drive runs.
        assert_eq!(master.read::<OutputFrequencyAtTrip>().unwrap(), Hertz(60.0));
        assert_eq!(
            master.read::<OutputCurrentAtTrip>().unwrap(),
            master.read::<OutputCurrent>().unwrap()
        );
        // ... and during a stop it falls with FD00 (80 -> 79.95 -> 0 Hz in the manual).
        master
            .write_ram::<DecelerationTime1>(Seconds(10.0))
            .unwrap();
        master
            .write_ram::<CommandWord12wire>(run_forward().with_run(false))
            .unwrap();
        sim.advance(Duration::from_secs(4));
        assert_eq!(master.read::<OutputFrequencyAtTrip>().unwrap(), Hertz(28.0));
        master
            .write_ram::<CommandWord12wire>(run_forward())
            .unwrap();
        sim.advance(Duration::from_secs(10));
        sim.inject_trip(0x0018);
        assert_eq!(master.read::<OutputFrequency>().unwrap().value, Hertz(0.0));
        sim.advance(Duration::from_secs(3));
        assert_eq!(
            master.read::<OutputFrequencyAtTrip>().unwrap().value,
            Hertz(60.0),
            "{}: held while tripped",
            protocol.id
        );
    }
}

fn page(name: &str) -> String {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../generated-docs/").to_owned() + name;
    let page = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path}: {e}"));
    // Paragraphs and list items on one line each, as the assertions read them.
    vfd_codegen::unwrap_markdown(&page)
}

#[test]
fn the_vf_as1_page_marks_the_unknown_flags_and_shows_the_new_errata() {
    let page = page("vf-as1.md");
    let f800 = page
        .lines()
        .find(|l| l.starts_with("| `0800` | F800 |"))
        .expect("F800 row");
    assert!(f800.contains("| unknown (not in the manual) |"), "{f800}");
    for text in [
        "(F803) (F804) (F808)",
        "设定为 5（2 线制 RS485 通信输入）或 6",
        "参考附录 5",
        "ERR4 and E-21",
        "appendix 3's 0.1 s is a general time-out period",
        "the description reads 06 as writing RAM and EEPROM",
        "80 -> 79.95 -> 0 Hz",
    ] {
        assert!(page.contains(text), "the page lacks {text:?}");
    }
    // The F826 half of the MOUBUS erratum is gone (a synonym, not a misprint).
    assert!(!page.contains("5: 主变频器 (发送扭矩指令) / 1: MODBUS-RTU"));
    assert!(!page.contains("are not modelled (vf-as1.NEEDS.md item 9) and read 0"));
}

#[test]
fn the_dv1_page_shows_the_new_errata_and_no_stale_pointers() {
    let page = page("dv1.md");
    for text in [
        "生成多项式 101000000000001",
        "07-11 (P.34)",
        "P参数模式： H0000~H0141",
        "例三 ends with step 4",
        "assumed for Modbus",
        "the example modbus_ascii_read_02_15",
    ] {
        assert!(page.contains(text), "the page lacks {text:?}");
    }
    for stale in [
        "ASCII twin is in dv1.NEEDS.md",
        "Modbus ASCII cannot be described yet",
        "in both protocols (*6)",
    ] {
        assert!(!page.contains(stale), "the page still says {stale:?}");
    }
}
