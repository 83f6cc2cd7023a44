//! Reads of several consecutive registers in one request (`max_words_per_read`), against
//! the virtual drive of every described drive whose protocol allows them: each value read
//! in a block equals the value the same register gives alone; a count beyond the limit is
//! refused before anything is sent; a block over a number with no register is refused by
//! the drive with the protocol's code, unless the drive answers partial blocks
//! (`partial_blocks`), where it reads as 0.

use vfd_runtime::virtual_drive::Simulator;
use vfd_runtime::{
    CommandKind, DataType, DriveInfo, EncodeError, Protocol, RegisterInfo, Request, Space,
    TransactionErrorKind,
};

use vfd_tests::masters::untyped as master;

/// Word and double-word parameters, by wire address, with their wire address.
fn wired(protocol: &Protocol, drive: &DriveInfo) -> Vec<(u16, &'static RegisterInfo)> {
    let command = protocol.block_read_command(Space::Parameter).unwrap();
    let mut wired: Vec<(u16, &'static RegisterInfo)> = drive
        .registers
        .iter()
        .copied()
        .filter(|r| {
            r.space == Space::Parameter
                && r.array_len == 0
                && matches!(r.data_type, DataType::Word | DataType::DoubleWord)
        })
        .filter_map(|r| command.address_map.to_wire(r.address).map(|w| (w, r)))
        .collect();
    wired.sort_by_key(|(wire, _)| *wire);
    wired
}

/// Runs of registers at consecutive wire addresses, at most `max` words each.
fn runs(wired: &[(u16, &'static RegisterInfo)], max: usize) -> Vec<Vec<&'static RegisterInfo>> {
    let mut runs: Vec<Vec<&'static RegisterInfo>> = Vec::new();
    let mut next = None;
    let mut words = 0;
    for (wire, info) in wired {
        let width = usize::from(info.data_type.size() / 2);
        if next == Some(*wire) && words + width <= max {
            runs.last_mut().unwrap().push(*info);
            words += width;
        } else {
            runs.push(vec![*info]);
            words = width;
        }
        next = wire.checked_add(width as u16);
    }
    runs
}

#[test]
fn a_block_read_returns_what_single_reads_return() {
    let mut checked_blocks = 0;
    for drive in vfd_drives::ALL_DRIVES {
        for protocol in drive.protocols.iter().copied() {
            if protocol.block_read_command(Space::Parameter).is_none() {
                continue;
            }
            let sim = Simulator::new(drive);
            // Distinct values, each within its register's range.
            for (i, (_, info)) in wired(protocol, drive).iter().enumerate() {
                let low = info.raw_min.max(0) as u32;
                let high = (info.raw_max.max(0) as u32).max(low);
                let raw = (low + 1 + i as u32).min(high);
                sim.lock().set_raw(info.id, raw);
            }
            let mut master = master(&sim, drive, protocol);
            let max = usize::from(protocol.max_words_per_read);
            for run in runs(&wired(protocol, drive), max) {
                if run.len() < 2 {
                    continue;
                }
                let widths: Vec<usize> = run
                    .iter()
                    .map(|r| usize::from(r.data_type.size() / 2))
                    .collect();
                let mut words = vec![0u16; widths.iter().sum()];
                master
                    .read_words(run[0].address, &mut words)
                    .unwrap_or_else(|e| panic!("{} {}: {e}", drive.id, protocol.id));
                let mut at = 0;
                for (info, width) in run.iter().zip(&widths) {
                    let in_block = master.join_words(&words[at..at + width]);
                    at += width;
                    let alone = master
                        .transact(&Request::for_register(CommandKind::Read, info, 0))
                        .unwrap()
                        .data
                        .unwrap();
                    assert_eq!(
                        in_block, alone,
                        "{} {} {}: block and single read differ",
                        drive.id, protocol.id, info.code
                    );
                }
                checked_blocks += 1;
            }
        }
    }
    assert!(
        checked_blocks > 0,
        "some described drive reads blocks of registers"
    );
}

#[test]
fn counts_beyond_the_limit_and_gaps_are_refused() {
    for drive in vfd_drives::ALL_DRIVES {
        for protocol in drive.protocols.iter().copied() {
            let sim = Simulator::new(drive);
            let mut master = master(&sim, drive, protocol);
            let first = drive
                .registers
                .iter()
                .find(|r| r.space == Space::Parameter && r.data_type == DataType::Word)
                .unwrap();
            let limit = if protocol.block_read_command(Space::Parameter).is_some() {
                usize::from(protocol.max_words_per_read)
            } else {
                1
            };
            let mut words = vec![0u16; limit + 1];
            let error = master.read_words(first.address, &mut words).unwrap_err();
            assert!(
                matches!(
                    error.kind,
                    TransactionErrorKind::Encode(EncodeError::TooManyWords { .. })
                ),
                "{} {}: {error}",
                drive.id,
                protocol.id
            );
            assert!(
                error.to_string().contains(&format!("at most {limit}")),
                "{error}"
            );
            // A block that runs past the last register: the drive refuses it.
            if limit > 1 {
                let wired = wired(protocol, drive);
                let (_, last) = wired.last().unwrap();
                let mut two = [0u16; 2];
                let beyond = master.read_words(last.address, &mut two);
                if last.data_type == DataType::Word && protocol.partial_blocks {
                    // A drive that answers a block as long as one of its registers exists
                    // (DV1, l. 473): the missing register reads as 0.
                    beyond.unwrap_or_else(|e| panic!("{} {}: {e}", drive.id, protocol.id));
                    assert_eq!(two[1], 0, "{} {}", drive.id, protocol.id);
                } else if last.data_type == DataType::Word {
                    // An error reply where the description gives one, else silence.
                    let error = beyond.unwrap_err();
                    assert!(
                        matches!(
                            error.kind,
                            TransactionErrorKind::Rejected { .. }
                                | TransactionErrorKind::Timeout { .. }
                        ),
                        "{} {}: {error}",
                        drive.id,
                        protocol.id
                    );
                }
            }
        }
    }
}
