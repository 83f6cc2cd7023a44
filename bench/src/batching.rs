//! Backup batching: a full backup of a described drive over one of its protocols, read from
//! the virtual drive through a recording transport, once with consecutive registers batched
//! into block reads where the protocol allows them (as `vfd backup` does) and once with one
//! read per register, counting requests and bytes and the wire time they take.
//!
//! The selection of registers and their grouping into blocks follow `vfd backup`
//! (`cli/src/commands/backup.rs`; both group blocks with `vfd_runtime::read_runs`): readable parameters that
//! are neither write-only, RAM-only nor arrays; runs of consecutive wire addresses of word
//! and double-word parameters, at most the protocol's `max_words_per_read` words each, read
//! with [`Master::read_words`]; a run the drive refuses is read register by register.

use std::time::Duration;
use vfd_runtime::read_runs::{block_words, read_runs};
use vfd_runtime::serial::SerialSettings;
use vfd_runtime::transaction::Master;
use vfd_runtime::transport::{Direction, Recording, Transport};
use vfd_runtime::virtual_drive::Simulator;
use vfd_runtime::{
    Access, CommandKind, DataType, DriveInfo, Protocol, RegisterInfo, Request, Space,
};

/// What one backup put on the line.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Traffic {
    /// Request frames sent (each one transaction; pre-steps such as page switches count).
    pub requests: usize,
    /// Bytes sent by the master.
    pub sent: usize,
    /// Bytes received from the drive.
    pub received: usize,
}

impl Traffic {
    /// Time the traffic takes on a line with `settings` and `gap` of silence before every
    /// frame (request and reply): characters plus two gaps a transaction. The drive's own
    /// processing time is not counted.
    pub fn wire_time(&self, settings: &SerialSettings, gap: Duration) -> Duration {
        settings.wire_time(self.sent + self.received)
            + gap * u32::try_from(self.requests * 2).unwrap_or(u32::MAX)
    }
}

/// One drive's backup over one protocol, batched and one read per register.
#[derive(Debug, Clone)]
pub struct BackupComparison {
    /// Drive id.
    pub drive: &'static str,
    /// Protocol id (within the drive).
    pub protocol: String,
    /// Registers in the backup.
    pub registers: usize,
    /// Registers read (both ways read the same ones and got the same values).
    pub read: usize,
    /// Whether the protocol has a block read (Modbus 03 with more than one word).
    pub blocks: bool,
    /// The backup as `vfd backup` reads it: consecutive registers batched.
    pub batched: Traffic,
    /// One read per register.
    pub single: Traffic,
    /// The line: the drive's factory character format at the baud rate asked for.
    pub settings: SerialSettings,
    /// The silence kept before every frame: the protocol's gap at that line.
    pub gap: Duration,
}

/// Whether `info` belongs in a backup over `protocol`, as `vfd backup` decides: a readable
/// parameter that is not a command (neither write-only nor RAM-only) nor an array.
pub fn backed_up(protocol: &Protocol, info: &RegisterInfo) -> bool {
    info.space == Space::Parameter
        && info.access != Access::WriteOnly
        && !info.ram_only
        && info.array_len == 0
        && protocol.can_read(info)
}

/// Reads one register alone: its raw value (`Some(None)` for text), `None` if refused.
fn read_one<T: Transport>(
    master: &mut Master<T>,
    info: &'static RegisterInfo,
) -> Option<Option<u32>> {
    let kind = if info.data_type == DataType::Text {
        CommandKind::ReadText
    } else {
        CommandKind::Read
    };
    let answer = master
        .transact(&Request::for_register(kind, info, 0))
        .ok()?;
    Some(if kind == CommandKind::ReadText {
        None
    } else {
        answer.data
    })
}

/// Backs up `drive` over `protocol` from a fresh virtual drive: the raw values read (`None`
/// for a register that could not be read, `Some(None)` for text) and the traffic.
pub fn backup(
    drive: &'static DriveInfo,
    protocol: &'static Protocol,
    batched: bool,
) -> (Vec<Option<Option<u32>>>, Traffic) {
    let registers: Vec<&'static RegisterInfo> = drive
        .registers
        .iter()
        .copied()
        .filter(|info| backed_up(protocol, info))
        .collect();
    let sim = Simulator::new(drive);
    let address = protocol.default_address();
    sim.lock()
        .set_address(address.unwrap_or(protocol.address_range.0.max(1)));
    // The in-process link answers at once; a fast line keeps the master's frame gaps short
    // (the wire time is computed from the bytes afterwards).
    let fast = SerialSettings {
        baud: 1_000_000,
        ..drive.serial.default
    };
    let mut master = Master::for_protocol(
        Recording::new(sim.link(protocol)),
        protocol,
        fast,
        drive.serial.timing,
    )
    .with_address(address);
    let mut values = vec![None; registers.len()];
    let runs = if batched {
        // `vfd backup` hands the registers over 128 at a time.
        let mut runs = Vec::new();
        for (chunk_index, chunk) in registers.chunks(128).enumerate() {
            runs.extend(
                read_runs(protocol, chunk)
                    .into_iter()
                    .map(|run| run.into_iter().map(|i| i + chunk_index * 128).collect()),
            );
        }
        runs
    } else {
        (0..registers.len())
            .map(|i| vec![i])
            .collect::<Vec<Vec<usize>>>()
    };
    for run in runs {
        if run.len() > 1 {
            let widths: Vec<usize> = run.iter().map(|i| block_words(registers[*i])).collect();
            let mut words = vec![0u16; widths.iter().sum()];
            if master
                .read_words(registers[run[0]].address, &mut words)
                .is_ok()
            {
                let mut at = 0;
                for (index, width) in run.iter().zip(widths) {
                    values[*index] = Some(Some(master.join_words(&words[at..at + width])));
                    at += width;
                }
                continue;
            }
        }
        for index in run {
            values[index] = read_one(&mut master, registers[index]);
        }
    }
    let mut traffic = Traffic::default();
    for (direction, bytes) in master.transport().log() {
        match direction {
            Direction::Sent => {
                traffic.requests += 1;
                traffic.sent += bytes.len();
            }
            Direction::Received => traffic.received += bytes.len(),
        }
    }
    (values, traffic)
}

/// Backs up `drive` over `protocol` both ways, with the wire time at `baud` in the drive's
/// factory character format. `Err` when the two backups read different values.
pub fn compare(
    drive: &'static DriveInfo,
    protocol: &'static Protocol,
    baud: u32,
) -> Result<BackupComparison, String> {
    let (batched_values, batched) = backup(drive, protocol, true);
    let (single_values, single) = backup(drive, protocol, false);
    if batched_values != single_values {
        return Err(format!(
            "{} over {}: the batched backup read other values than one read per register",
            drive.id, protocol.id
        ));
    }
    let settings = SerialSettings {
        baud,
        ..drive.serial.default
    };
    let gap = settings
        .char_time()
        .mul_f32(protocol.frame_gap_chars)
        .max(protocol.timing.frame_gap_min);
    Ok(BackupComparison {
        drive: drive.id,
        protocol: protocol.id.to_string(),
        registers: single_values.len(),
        read: single_values.iter().filter(|v| v.is_some()).count(),
        blocks: protocol.block_read_command(Space::Parameter).is_some(),
        batched,
        single,
        settings,
        gap,
    })
}
