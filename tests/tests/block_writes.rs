//! Writes of several consecutive registers in one request (`max_words_per_write`, Modbus
//! 10h), with `Master::write_words`, against the virtual drive of every described drive
//! whose protocol allows them: each register written in a block reads back alone as
//! written; more words than the limit are refused before anything is sent; a block over
//! a number with no register is refused whole, or, on a drive that answers partial blocks
//! (`partial_blocks`, the DV1), carried out for the registers it has.

use vfd_runtime::virtual_drive::Simulator;
use vfd_runtime::{
    CommandKind, DataType, DriveInfo, EncodeError, Protocol, RegisterInfo, Request, Space,
    TransactionErrorKind,
};

use vfd_tests::masters::untyped as master;

/// Readable and writable one-word parameters by wire address, without behaviour (no command word) and
/// in no forbidden combination.
fn writable(protocol: &Protocol, drive: &DriveInfo) -> Vec<(u16, &'static RegisterInfo)> {
    let command = protocol.block_write_command(Space::Parameter).unwrap();
    let behaviour_registers: Vec<&str> = drive
        .behaviour
        .iter()
        .flat_map(|b| [b.command.register, b.frequency.command])
        .collect();
    let mut wired: Vec<(u16, &'static RegisterInfo)> = drive
        .registers
        .iter()
        .copied()
        .filter(|r| {
            r.space == Space::Parameter
                && r.array_len == 0
                && r.data_type == DataType::Word
                && r.access == vfd_runtime::Access::ReadWrite
                && !r.no_reply
                && !behaviour_registers.contains(&r.id)
                // A new station number moves the drive away from the master.
                && drive.station_register != Some(r.id)
                // Values chosen one by one could make a combination the manual forbids.
                && drive.combinations_of(r).next().is_none()
        })
        .filter_map(|r| command.address_map.to_wire(r.address).map(|w| (w, r)))
        .collect();
    wired.sort_by_key(|(wire, _)| *wire);
    wired
}

/// A value within the register's raw range, other than its present one.
fn value_for(info: &RegisterInfo, present: u32) -> u16 {
    let low = info.raw_min.max(0) as u32;
    let high = (info.raw_max.max(0) as u32).clamp(low, 0xFFFF);
    let value = if present < high { present + 1 } else { low };
    value as u16
}

#[test]
fn a_block_write_writes_each_register_as_a_single_write_would() {
    let mut checked = 0;
    for drive in vfd_drives::ALL_DRIVES {
        for protocol in drive.protocols.iter().copied() {
            if protocol.block_write_command(Space::Parameter).is_none() {
                continue;
            }
            let sim = Simulator::new(drive);
            let mut master = master(&sim, drive, protocol);
            let wired = writable(protocol, drive);
            // The longest run of consecutive writable registers within the limit.
            let max = usize::from(protocol.max_words_per_write);
            let mut best: Vec<(u16, &'static RegisterInfo)> = Vec::new();
            let mut run: Vec<(u16, &'static RegisterInfo)> = Vec::new();
            for (wire, info) in &wired {
                if run.last().is_some_and(|(w, _)| w + 1 == *wire) && run.len() < max {
                    run.push((*wire, info));
                } else {
                    run = vec![(*wire, info)];
                }
                if run.len() > best.len() {
                    best = run.clone();
                }
            }
            if best.len() < 2 {
                continue;
            }
            let values: Vec<u16> = best
                .iter()
                .map(|(_, info)| {
                    let present = sim.lock().raw(info.id).unwrap_or(0);
                    value_for(info, present)
                })
                .collect();
            master
                .write_words(best[0].1.address, &values)
                .unwrap_or_else(|e| panic!("{} {}: {e}", drive.id, protocol.id));
            for ((_, info), value) in best.iter().zip(&values) {
                let alone = master
                    .transact(&Request::for_register(CommandKind::Read, info, 0))
                    .unwrap()
                    .data
                    .unwrap();
                assert_eq!(
                    alone,
                    u32::from(*value),
                    "{} {} {}: written in a block of {}",
                    drive.id,
                    protocol.id,
                    info.code,
                    best.len()
                );
            }
            checked += 1;
        }
    }
    assert!(
        checked > 0,
        "some described drive writes blocks of registers"
    );
}

#[test]
fn more_words_than_the_limit_are_refused_before_sending() {
    for drive in vfd_drives::ALL_DRIVES {
        for protocol in drive.protocols.iter().copied() {
            let limit = if protocol.block_write_command(Space::Parameter).is_some() {
                usize::from(protocol.max_words_per_write)
            } else {
                1
            };
            let sim = Simulator::new(drive);
            let mut master = master(&sim, drive, protocol);
            let error = master.write_words(0x0030, &vec![0; limit + 1]).unwrap_err();
            assert!(
                matches!(
                    error.kind,
                    TransactionErrorKind::Encode(EncodeError::TooManyWordsToWrite { .. })
                ),
                "{} {}: {error}",
                drive.id,
                protocol.id
            );
            assert!(
                error.to_string().contains(&format!("1 to {limit}")),
                "{error}"
            );
            assert!(master.last_reply().is_empty(), "nothing was exchanged");
            assert_eq!(sim.requests(), 0, "nothing was sent");
        }
    }
}

/// The DV1 (5.8.1): 10h takes 1 to 12 registers (l. 439-440), and a block is not refused
/// while at least one of its addresses can be written (l. 473): 0030h-0035h are 07-03 ..
/// 07-09, 0036h-003Bh hold no parameter.
#[test]
fn the_dv1_writes_twelve_registers_and_skips_the_reserved_ones() {
    use vfd_drives::dv1;
    for protocol in [
        dv1::protocols::MODBUS.protocol(),
        dv1::protocols::MODBUS_ASCII.protocol(),
    ] {
        assert_eq!(protocol.max_words_per_write, 12, "{}", protocol.id);
        let sim = Simulator::new(&dv1::DRIVE);
        let mut master = master(&sim, &dv1::DRIVE, protocol);
        // Two stop bits first (07-04 = 1, 07-05 = 0): the block below sets one stop bit and
        // odd parity together, which the manual allows (note 4, l. 102) though odd parity
        // with the two stop bits held before would not be.
        master.write_words(0x0031, &[1]).unwrap();
        let twelve = [0, 0, 1, 2, 3, 50, 0x11, 0x12, 0x13, 0x14, 0x15, 0x16];
        master
            .write_words(0x0030, &twelve)
            .unwrap_or_else(|e| panic!("{}: {e}", protocol.id));
        let mut back = [0xFFFFu16; 12];
        master.read_words(0x0030, &mut back).unwrap();
        assert_eq!(back[..6], twelve[..6], "{}", protocol.id);
        assert_eq!(
            back[6..],
            [0; 6],
            "{}: reserved addresses read as 0",
            protocol.id
        );
        // Only reserved addresses: nothing can be written, exception 02.
        let error = master.write_words(0x0036, &[1, 2, 3]).unwrap_err();
        assert!(
            matches!(
                error.kind,
                TransactionErrorKind::Rejected { code: 0x02, .. }
            ),
            "{}: {error}",
            protocol.id
        );
        // A value out of range in a block with others that can be written: those are.
        master.write_words(0x0030, &[1, 9]).unwrap();
        let mut two = [0u16; 2];
        master.read_words(0x0030, &mut two).unwrap();
        assert_eq!(
            two,
            [1, 0],
            "{}: 07-04 keeps 0 (9 is out of its range)",
            protocol.id
        );
    }
}
