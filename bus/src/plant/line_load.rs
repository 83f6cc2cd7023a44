//! Whether a bus's line can carry what its poll lists ask. Each poll group is read as the
//! bus worker reads it (consecutive registers in one block read where the protocol has one,
//! `vfd_runtime::read_runs`), each exchange's frames as the runtime prepares them
//! (`vfd_runtime::transaction::script`: a protocol's steps, the page switch a paged register
//! needs, the request) with the shortest reply each can have, at the line's baud rate and
//! character format, with the protocol's silence after every frame and the drive's reply
//! delay. A group's round times its rounds per second, summed over every group of the bus,
//! is a lower bound of the line time the polls take each second (the drives' processing
//! time is not counted): above one second the bus cannot keep the rates asked, and the
//! check warns.

use super::model::Station;
use super::problems::Problems;
use std::time::Duration;
use vfd_runtime::read_runs::{block_words, read_runs};
use vfd_runtime::serial::SerialSettings;
use vfd_runtime::transaction::{script, Exchange, ExchangeKind, Prepared, Station as Address};
use vfd_runtime::{CommandKind, DataType, Protocol, RegisterInfo, Request};

/// What a bus's polls ask of its line each second.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Load {
    /// Registers read per second.
    pub reads: f64,
    /// Line time per second they take, at least (1.0: the whole line).
    pub busy: f64,
}

/// The load `stations`' polls put on a line with `settings` and at least `min_gap` of
/// silence between frames.
pub fn load(stations: &[Station], settings: &SerialSettings, min_gap: Option<Duration>) -> Load {
    let mut total = Load {
        reads: 0.0,
        busy: 0.0,
    };
    for station in stations {
        let line = Timing {
            settings,
            gap: frame_gap(station.protocol, settings, min_gap),
            delay: station
                .protocol
                .timing
                .reply_delay
                .as_ref()
                .map_or(Duration::ZERO, |delay| delay.default),
        };
        let mut groups: Vec<(Duration, Vec<&'static RegisterInfo>)> = Vec::new();
        for poll in &station.polls {
            let register = station
                .port
                .map_or(poll.register, |p| p.register(poll.register));
            match groups.iter_mut().find(|(every, _)| *every == poll.every) {
                Some((_, registers)) => registers.push(register),
                None => groups.push((poll.every, vec![register])),
            }
        }
        let mut page = None;
        for (every, registers) in &groups {
            // The first round selects the pages it needs; the second, timed, is one of the
            // rounds that follow.
            round(station, registers, &mut page, &line);
            let time = round(station, registers, &mut page, &line);
            let per_second = 1.0 / every.as_secs_f64();
            total.reads += registers.len() as f64 * per_second;
            total.busy += time.as_secs_f64() * per_second;
        }
    }
    total
}

/// Warns at `path` (the bus `name`) when its polls need more line time than there is.
pub fn check(
    path: &str,
    name: &str,
    stations: &[Station],
    settings: &SerialSettings,
    min_gap: Option<Duration>,
    problems: &mut Problems<'_>,
) {
    let load = load(stations, settings, min_gap);
    if load.busy <= 1.0 {
        return;
    }
    let parity = settings
        .parity
        .as_str()
        .chars()
        .next()
        .unwrap_or('n')
        .to_ascii_uppercase();
    problems.warning(
        path,
        format!(
            "bus `{name}` asks for {:.1} reads/s, which take at least {:.2} s of line time each second at {} baud {}{parity}{}: more than the line carries",
            load.reads, load.busy, settings.baud, settings.data_bits, settings.stop_bits
        ),
        format!(
            "poll less often (a longer `every`) or fewer registers, or use a faster baud rate (every drive set to it); as it is, each group is read about {:.0}% as often as asked",
            100.0 / load.busy
        ),
    );
}

/// The line's timing for one station's exchanges.
struct Timing<'a> {
    settings: &'a SerialSettings,
    /// The silence kept after every frame.
    gap: Duration,
    /// The drive's wait before each reply.
    delay: Duration,
}

/// The silence a master keeps between frames on this line: the protocol's (in characters,
/// at least its floor in time), or the bus's `gap_ms` where longer; as
/// `vfd_runtime::transaction::Master::frame_gap` has it.
fn frame_gap(
    protocol: &Protocol,
    settings: &SerialSettings,
    min_gap: Option<Duration>,
) -> Duration {
    settings
        .char_time()
        .mul_f32(protocol.frame_gap_chars)
        .max(protocol.timing.frame_gap_min)
        .max(min_gap.unwrap_or(Duration::ZERO))
}

/// The line time of one round of `registers` on `station`, whose page is `page` before it
/// and after it.
fn round(
    station: &Station,
    registers: &[&'static RegisterInfo],
    page: &mut Option<u16>,
    line: &Timing<'_>,
) -> Duration {
    let protocol = station.protocol;
    let address = Address {
        address: station.address,
        reply_wait: 0,
    };
    let mut time = Duration::ZERO;
    for run in read_runs(protocol, registers) {
        let exchange = if run.len() > 1 {
            let words: usize = run.iter().map(|i| block_words(registers[*i])).sum();
            Exchange::new(
                Request::raw(CommandKind::Read, registers[run[0]].address, 0),
                ExchangeKind::BlockRead {
                    words: u16::try_from(words).unwrap_or(u16::MAX),
                },
            )
        } else {
            let info = registers[run[0]];
            let kind = if info.data_type == DataType::Text {
                CommandKind::ReadText
            } else {
                CommandKind::Read
            };
            Exchange::single(Request::for_register(kind, info, 0))
        };
        // A read the protocol cannot carry sends nothing.
        let Ok(frames) = script(protocol, &exchange, &address, *page) else {
            continue;
        };
        for step in frames.steps.iter().flatten() {
            time += exchange_time(step, line);
        }
        if let Some((switch, number)) = &frames.page {
            time += exchange_time(switch, line);
            *page = Some(*number);
        }
        time += exchange_time(&frames.main, line);
    }
    time
}

/// One prepared frame on the line, its shortest reply and its follow-up, each followed by
/// the gap.
fn exchange_time(frame: &Prepared, line: &Timing<'_>) -> Duration {
    let on_line = |bytes: usize| line.settings.wire_time(bytes) + line.gap;
    let mut time = on_line(frame.bytes().len());
    if frame.answered() {
        time += line.delay + on_line(frame.shortest_own_reply());
        if let Some(follow_up) = frame.follow_up() {
            time += on_line(follow_up.sound.as_slice().len());
        }
    }
    time
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::plant::model::Poll;

    fn station(drive: &str, protocol: &str, codes: &[&str], every: Duration) -> Station {
        let catalogue = crate::Catalogue::new();
        let drive = catalogue.drive(drive).unwrap_or_else(|f| panic!("{f}"));
        let protocol =
            crate::lookup::protocol(drive, Some(protocol)).unwrap_or_else(|f| panic!("{f}"));
        Station {
            name: "d".into(),
            drive,
            drive_name: drive.id.into(),
            protocol,
            address: Some(1),
            port: None,
            polls: codes
                .iter()
                .map(|code| Poll {
                    register: catalogue
                        .register_for(drive, code, false)
                        .unwrap_or_else(|f| panic!("{f}")),
                    every,
                })
                .collect(),
            writes: vec![],
        }
    }

    #[test]
    fn a_modbus_block_read_costs_its_frames_and_gaps() {
        // DV1 Modbus RTU, 1001h-1003h in one read: request 8 bytes, reply 5 + 6 data bytes,
        // at 9600 baud 8N1 (1.042 ms a character), 10 ms of silence after each frame.
        let settings = SerialSettings {
            baud: 9600,
            data_bits: 8,
            parity: vfd_runtime::serial::Parity::None,
            stop_bits: 1,
        };
        let dv1 = station(
            "dv1",
            "modbus",
            &["H7A", "H6D-HED", "H6F"],
            Duration::from_secs(1),
        );
        let once = load(std::slice::from_ref(&dv1), &settings, None);
        let expected = settings.wire_time(8 + 11) + Duration::from_millis(20);
        assert!(
            (once.busy - expected.as_secs_f64()).abs() < 1e-6,
            "{once:?} vs {expected:?}"
        );
        assert_eq!(once.reads, 3.0);
        // Ten times a second is ten rounds; a longer `gap_ms` lengthens each.
        let fast = station(
            "dv1",
            "modbus",
            &["H7A", "H6D-HED", "H6F"],
            Duration::from_millis(100),
        );
        let slow = load(
            std::slice::from_ref(&fast),
            &settings,
            Some(Duration::from_millis(50)),
        );
        let expected = (settings.wire_time(19) + Duration::from_millis(100)) * 10;
        assert!(
            (slow.busy - expected.as_secs_f64()).abs() < 1e-6,
            "{slow:?} vs {expected:?}"
        );
    }

    #[test]
    fn registers_apart_are_read_one_by_one() {
        let settings = vfd_runtime::serial::SerialSettings {
            baud: 9600,
            data_bits: 8,
            parity: vfd_runtime::serial::Parity::Even,
            stop_bits: 1,
        };
        let every = Duration::from_secs(1);
        let together = station("dv1", "modbus", &["H7A", "H6D-HED"], every);
        let apart = station("dv1", "modbus", &["H7A", "H6F"], every);
        let one = load(std::slice::from_ref(&together), &settings, None).busy;
        let two = load(std::slice::from_ref(&apart), &settings, None).busy;
        assert!(
            two > one * 1.5,
            "{one} s for a block, {two} s for two reads"
        );
    }
}
