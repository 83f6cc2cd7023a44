//! `Protocol::default_address`: no station where a protocol's frames may leave it out, the
//! lowest station (at least 1) where they must carry one. `read_runs` groups a backup's
//! registers into block reads only where the protocol has one. `Protocol::can_read`: a
//! register the description numbers for other protocols only cannot be read over this one.

use vfd_drives::{dv1, fc51, yd1000};
use vfd_runtime::read_runs::read_runs;
use vfd_runtime::RegisterInfo;

#[test]
fn a_station_only_where_frames_need_one() {
    // The YD1000's Toshiba-style frames may leave the station out.
    assert_eq!(yd1000::protocols::ASCII.default_address(), None);
    assert_eq!(yd1000::protocols::BINARY.default_address(), None);
    // Modbus and FC telegrams always carry one; 0 is the broadcast, so 1.
    assert_eq!(fc51::protocols::MODBUS.default_address(), Some(1));
    assert_eq!(fc51::protocols::FC.default_address(), Some(1));
    assert_eq!(dv1::protocols::MODBUS.default_address(), Some(1));
}

#[test]
fn runs_of_consecutive_addresses_only_where_a_block_read_exists() {
    let registers: &[&RegisterInfo] = dv1::DRIVE.registers;
    let every = |runs: &[Vec<usize>]| {
        let mut all: Vec<usize> = runs.iter().flatten().copied().collect();
        all.sort_unstable();
        all
    };
    let all: Vec<usize> = (0..registers.len()).collect();
    let modbus = read_runs(&dv1::protocols::MODBUS, registers);
    assert_eq!(every(&modbus), all, "every register exactly once");
    assert!(
        modbus.len() < registers.len(),
        "some registers share a read"
    );
    let max = usize::from(dv1::protocols::MODBUS.max_words_per_read);
    assert!(modbus.iter().all(|run| run.len() <= max));
    let eaton = read_runs(&dv1::protocols::EATON, registers);
    assert_eq!(eaton.len(), registers.len(), "no block read: one each");
    assert_eq!(every(&eaton), all);
}

#[test]
fn a_register_numbered_for_other_protocols_only_cannot_be_read_over_this_one() {
    let monitor = dv1::DRIVE
        .registers
        .iter()
        .find(|r| r.address == 0x1014)
        .expect("DV1 1014h, a Modbus-only monitor");
    assert!(dv1::protocols::MODBUS.can_read(monitor));
    assert!(!dv1::protocols::EATON.can_read(monitor));
    // A paged parameter reads over both.
    let parameter = dv1::DRIVE
        .registers
        .iter()
        .find(|r| r.code == "02-15")
        .expect("DV1 02-15");
    assert!(dv1::protocols::MODBUS.can_read(parameter));
    assert!(dv1::protocols::EATON.can_read(parameter));
}
