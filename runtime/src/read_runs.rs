//! Grouping registers into block reads: runs of consecutive wire addresses a protocol's
//! block read (Modbus 03 of several registers) carries in one request, as `vfd backup`
//! and the batching benchmark read a whole drive.

use crate::{DataType, Protocol, RegisterInfo, Space};

/// Words `info` takes in a block read (a double word two, anything smaller one).
pub fn block_words(info: &RegisterInfo) -> usize {
    usize::from(info.data_type.size().max(2) / 2)
}

/// Indexes of `registers` in runs of consecutive wire addresses, each at most as many
/// words as one read of `protocol` carries (`max_words_per_read`). Registers a block
/// cannot hold (not a word or double-word parameter, an array, no wire address for the
/// block command) stand alone, and every register is alone where `protocol` has no block
/// read. Runs are in wire-address order; every index appears exactly once.
pub fn read_runs(protocol: &Protocol, registers: &[&RegisterInfo]) -> Vec<Vec<usize>> {
    let Some(command) = protocol.block_read_command(Space::Parameter) else {
        return (0..registers.len()).map(|i| vec![i]).collect();
    };
    let max = usize::from(protocol.max_words_per_read);
    let mut placed: Vec<(usize, Option<u16>)> = registers
        .iter()
        .enumerate()
        .map(|(i, info)| {
            let blockable = info.space == Space::Parameter
                && info.array_len == 0
                && matches!(info.data_type, DataType::Word | DataType::DoubleWord);
            let wire = blockable
                .then(|| protocol.to_wire(command, info.address))
                .flatten();
            (i, wire)
        })
        .collect();
    placed.sort_by_key(|(i, wire)| (wire.is_none(), *wire, *i));
    let mut runs: Vec<Vec<usize>> = Vec::new();
    // The wire address that continues the last run, and the words it holds so far.
    let mut next: Option<(u16, usize)> = None;
    for (i, wire) in placed {
        let words = block_words(registers[i]);
        match (wire, next, runs.last_mut()) {
            (Some(at), Some((expected, used)), Some(run))
                if at == expected && used + words <= max =>
            {
                run.push(i);
                next = at
                    .checked_add(words as u16)
                    .map(|after| (after, used + words));
            }
            (Some(at), _, _) => {
                runs.push(vec![i]);
                next = at.checked_add(words as u16).map(|after| (after, words));
            }
            (None, _, _) => {
                runs.push(vec![i]);
                next = None;
            }
        }
    }
    runs
}
