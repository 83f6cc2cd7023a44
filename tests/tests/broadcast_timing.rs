//! Broadcast and group addressing, and the manuals' line timing (frame gap floor, inner
//! gap, bytes before the start, reply delay register, start-up silence), against the
//! virtual drive: VF-AS1 (Toshiba ASCII, binary and Modbus RTU) and DV1 (Modbus RTU), with
//! the YD1000 (which states none of these rules) for contrast.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};
use vfd_drives::{dv1, vf_as1, yd1000};
use vfd_runtime::meaning::{decode_meaning, Direction};
use vfd_runtime::prelude::*;
use vfd_runtime::serial::SerialSettings;
use vfd_runtime::transaction::{BroadcastReply, Master};
use vfd_runtime::transport::{memory_pair, Transport};
use vfd_runtime::virtual_drive::{serve, Simulator};
use vfd_runtime::{Broadcast, CommandKind, EncodeError, Request, TransactionErrorKind};
use vfd_tests::outcomes::timed_out;

fn group(text: &str) -> Broadcast {
    text.parse().expect("a group")
}

/// The error that refused a broadcast before anything was sent.
fn refused_broadcast<T: std::fmt::Debug>(result: Result<T, TransactionError>) -> &'static str {
    match result {
        Err(TransactionError {
            kind: TransactionErrorKind::Encode(EncodeError::NoBroadcast { reason, .. }),
            ..
        }) => reason,
        other => panic!("expected a refused broadcast, got {other:?}"),
    }
}

mod vf_as1_broadcasts {
    use super::*;
    use vf_as1::registers::*;

    /// A VF-AS1 at `station`, and a master speaking `protocol` to it.
    fn drive_at(station: u8) -> Simulator {
        let sim = Simulator::new(&vf_as1::DRIVE);
        sim.lock().set_address(station);
        sim
    }

    fn frequency_raw(sim: &Simulator) -> u32 {
        sim.lock().raw("FA01").unwrap()
    }

    #[test]
    fn every_station_acts_and_station_00_answers_with_its_own_number() {
        for protocol in [&vf_as1::protocols::ASCII, &vf_as1::protocols::BINARY] {
            let sim = drive_at(0);
            let mut master = sim.master(protocol);
            let written = master
                .broadcast_write_ram::<FrequencyCommand2wire>(
                    Hertz(60.0),
                    Broadcast::All,
                    BroadcastReply::From(0),
                )
                .unwrap();
            assert_eq!(written, Some(Hertz(60.0)), "{}", protocol.id);
            assert_eq!(frequency_raw(&sim), 6000);
        }
    }

    #[test]
    fn the_broadcast_frame_is_the_manuals_with_the_default_checksum() {
        let protocol = vf_as1::protocols::ASCII.protocol();
        let request = Request::write_ram::<FrequencyCommand2wire>(Hertz(60.0)).unwrap();
        let mut out = [0u8; 32];
        let len = protocol
            .encode_broadcast(&request, &Broadcast::All, &mut out)
            .unwrap();
        // 4.4 prints (**PFA011770)CR; the library adds its default "&" sum.
        assert!(
            out[..len].starts_with(b"(**PFA011770&"),
            "{:?}",
            &out[..len]
        );
        let meaning = decode_meaning(protocol, Direction::Request, &out[..len]).unwrap();
        assert_eq!(meaning.broadcast, Some(Broadcast::All));
        assert_eq!(meaning.address, None);
        let len = protocol
            .encode_broadcast(&request, &group("*9"), &mut out)
            .unwrap();
        assert!(out[..len].starts_with(b"(*9PFA011770&"));
        let binary = vf_as1::protocols::BINARY.protocol();
        let len = binary
            .encode_broadcast(&request, &Broadcast::All, &mut out)
            .unwrap();
        // Station FFh; sum 2F+FF+50+FA+01+17+70 = 300h.
        assert_eq!(
            &out[..len],
            [0x2F, 0xFF, 0x50, 0xFA, 0x01, 0x17, 0x70, 0x00]
        );
    }

    #[test]
    fn a_group_reaches_its_stations_and_only_the_lowest_answers() {
        // *9: stations 09, 19, ..., 99; 09 answers.
        let lowest = drive_at(9);
        let written = lowest
            .master(&vf_as1::protocols::ASCII)
            .broadcast_write_ram::<FrequencyCommand2wire>(
                Hertz(60.0),
                group("*9"),
                BroadcastReply::From(9),
            )
            .unwrap();
        assert_eq!(written, Some(Hertz(60.0)));
        assert_eq!(frequency_raw(&lowest), 6000);

        // Station 19 acts but stays silent: a master told to wait for it times out.
        let member = drive_at(19);
        let mut master = member.master(&vf_as1::protocols::ASCII);
        timed_out(master.broadcast_write_ram::<FrequencyCommand2wire>(
            Hertz(50.0),
            group("*9"),
            BroadcastReply::From(19),
        ));
        assert_eq!(frequency_raw(&member), 5000);
        // Told that no station answers, the master returns once the frame is out.
        let none = master
            .broadcast_write_ram::<FrequencyCommand2wire>(
                Hertz(60.0),
                group("*9"),
                BroadcastReply::None,
            )
            .unwrap();
        assert_eq!(none, None);
        assert_eq!(frequency_raw(&member), 6000);

        // Station 18 is not in the group: it does nothing.
        let outsider = drive_at(18);
        outsider
            .master(&vf_as1::protocols::ASCII)
            .broadcast_write_ram::<FrequencyCommand2wire>(
                Hertz(60.0),
                group("*9"),
                BroadcastReply::None,
            )
            .unwrap();
        assert_eq!(frequency_raw(&outsider), 0);

        // 1*: stations 10-19; 10 answers.
        let tens = drive_at(10);
        let written = tens
            .master(&vf_as1::protocols::ASCII)
            .broadcast_write_ram::<FrequencyCommand2wire>(
                Hertz(60.0),
                group("1*"),
                BroadcastReply::From(10),
            )
            .unwrap();
        assert_eq!(written, Some(Hertz(60.0)));
    }

    #[test]
    fn a_broadcast_read_and_impossible_replies_are_refused_before_anything_is_sent() {
        let sim = drive_at(0);
        let mut master = sim.master(&vf_as1::protocols::ASCII);
        let read = Request::read::<FrequencyCommand2wire>();
        let reason =
            refused_broadcast(master.broadcast(&read, Broadcast::All, BroadcastReply::From(0)));
        assert!(reason.contains("only writes"), "{reason}");
        let write = Request::write_ram::<FrequencyCommand2wire>(Hertz(60.0)).unwrap();
        let reason =
            refused_broadcast(master.broadcast(&write, group("*9"), BroadcastReply::From(8)));
        assert!(reason.contains("not among"), "{reason}");
        // Groups are ASCII only: the binary station byte has no wildcard.
        let mut binary = sim.master(&vf_as1::protocols::BINARY);
        let reason = refused_broadcast(binary.broadcast(&write, group("*9"), BroadcastReply::None));
        assert!(reason.contains("no encoding"), "{reason}");
        // A Modbus broadcast is never answered.
        let mut modbus = sim.master(&vf_as1::protocols::MODBUS);
        let reason =
            refused_broadcast(modbus.broadcast(&write, Broadcast::All, BroadcastReply::From(1)));
        assert!(reason.contains("never answers"), "{reason}");
        assert_eq!(sim.requests(), 0, "nothing went on the line");
    }

    #[test]
    fn the_drive_ignores_the_manuals_broadcast_read() {
        // 4.1.1 prints (*2R0000) answered by station 02; 4.4 says reads are invalid in
        // broadcasts, and the description follows 4.4.
        let sim = drive_at(2);
        let mut link = sim.link(vf_as1::protocols::ASCII.protocol());
        link.send(b"(*2R0000)\r").unwrap();
        let mut buf = [0u8; 32];
        assert_eq!(link.receive(&mut buf, Instant::now()).unwrap(), 0);
        assert_eq!(sim.requests(), 1);
        // The manual's broadcast write is answered by station 09 as printed.
        let sim = drive_at(9);
        sim.lock().set_raw("FH", 8000);
        let mut link = sim.link(vf_as1::protocols::ASCII.protocol());
        link.send(b"(*9PFA011770)\r").unwrap();
        let got = link.receive(&mut buf, Instant::now()).unwrap();
        assert_eq!(&buf[..got], b"(09PFA011770)\r");
    }

    #[test]
    fn a_modbus_broadcast_acts_everywhere_and_gets_no_reply() {
        let sim = Simulator::new(&vf_as1::DRIVE);
        let mut master = sim.master(&vf_as1::protocols::MODBUS);
        let answer = master
            .broadcast_write_ram::<FrequencyCommand2wire>(
                Hertz(60.0),
                Broadcast::All,
                BroadcastReply::None,
            )
            .unwrap();
        assert_eq!(answer, None);
        assert_eq!(frequency_raw(&sim), 6000);
        // The next exchange is an ordinary one.
        assert_eq!(master.read::<FrequencyCommand2wire>().unwrap(), Hertz(60.0));
    }
}

#[test]
fn a_dv1_modbus_broadcast_acts_and_a_read_cannot_be_broadcast() {
    use dv1::registers::FrequencyCommandRam;
    let sim = Simulator::new(&dv1::DRIVE);
    let mut master = sim.master(&dv1::protocols::MODBUS);
    master
        .broadcast_write_ram::<FrequencyCommandRam>(
            Hertz(30.0),
            Broadcast::All,
            BroadcastReply::None,
        )
        .unwrap();
    assert_eq!(sim.lock().raw("frequency_command_ram"), Some(3000));
    let reason = refused_broadcast(master.broadcast(
        &Request::read::<FrequencyCommandRam>(),
        Broadcast::All,
        BroadcastReply::None,
    ));
    assert!(reason.contains("only writes"), "{reason}");
}

#[test]
fn a_drive_without_a_broadcast_rule_refuses_to_send_and_ignores_one() {
    use yd1000::registers::FrequencyCommand;
    let sim = Simulator::new(&yd1000::DRIVE);
    let mut master = sim.master(&yd1000::protocols::ASCII);
    let reason = refused_broadcast(master.broadcast_write_ram::<FrequencyCommand>(
        Hertz(60.0),
        Broadcast::All,
        BroadcastReply::None,
    ));
    assert!(reason.contains("no broadcasts"), "{reason}");
    let mut link = sim.link(yd1000::protocols::ASCII.protocol());
    link.send(b"(**PFA011770)\r").unwrap();
    let mut buf = [0u8; 32];
    assert_eq!(link.receive(&mut buf, Instant::now()).unwrap(), 0);
    assert_eq!(sim.lock().raw("FA01"), Some(0));
}

/// What a master sent (`true`) and received (`false`), in order.
type Log = Arc<Mutex<Vec<(bool, Vec<u8>)>>>;

/// A transport that logs what the master sends and receives, in order.
struct Logged<T> {
    inner: T,
    log: Log,
}

impl<T: Transport> Transport for Logged<T> {
    fn send(&mut self, bytes: &[u8]) -> std::io::Result<()> {
        self.log.lock().unwrap().push((true, bytes.to_vec()));
        self.inner.send(bytes)
    }
    fn receive(&mut self, buf: &mut [u8], deadline: Instant) -> std::io::Result<usize> {
        let got = self.inner.receive(buf, deadline)?;
        if got > 0 {
            self.log.lock().unwrap().push((false, buf[..got].to_vec()));
        }
        Ok(got)
    }
    fn clear_input(&mut self) -> std::io::Result<()> {
        self.inner.clear_input()
    }
    fn last_gap(&self) -> Option<Duration> {
        self.inner.last_gap()
    }
}

/// Serves `sim` in wall time on one end of an in-memory line; returns the other end and a
/// stop flag (set it to end the server).
fn served(
    sim: &Simulator,
    protocol: &'static vfd_runtime::Protocol,
) -> (
    vfd_runtime::transport::MemoryTransport,
    Arc<AtomicBool>,
    std::thread::JoinHandle<()>,
) {
    let (master_end, mut drive_end) = memory_pair();
    let stop = Arc::new(AtomicBool::new(false));
    let (server, flag) = (sim.clone(), stop.clone());
    let settings = sim.lock().drive().serial.default;
    let handle = std::thread::spawn(move || {
        serve(&server, protocol, &mut drive_end, settings, &flag).unwrap();
    });
    (master_end, stop, handle)
}

#[test]
fn the_next_frame_never_runs_into_a_reply_the_caller_did_not_expect() {
    use vf_as1::registers::FrequencyCommand2wire;
    // Station 00 exists but the caller says no station answers: its reply still comes,
    // and the master's next frame waits until it has passed.
    let sim = Simulator::new(&vf_as1::DRIVE);
    sim.lock().set_address(0);
    let protocol = &vf_as1::protocols::ASCII;
    let (line, stop, server) = served(&sim, protocol.protocol());
    let log: Log = Arc::new(Mutex::new(Vec::new()));
    let logged = Logged {
        inner: line,
        log: log.clone(),
    };
    let mut master = Master::new(
        logged,
        protocol,
        vf_as1::SERIAL.default,
        vf_as1::SERIAL.timing,
    )
    .with_address(Some(0));
    master
        .broadcast_write_ram::<FrequencyCommand2wire>(
            Hertz(60.0),
            Broadcast::All,
            BroadcastReply::None,
        )
        .unwrap();
    let read = master.read::<FrequencyCommand2wire>();
    stop.store(true, Ordering::Relaxed);
    server.join().unwrap();
    assert_eq!(read.unwrap(), Hertz(60.0));
    let log = log.lock().unwrap();
    let sends: Vec<usize> = (0..log.len()).filter(|i| log[*i].0).collect();
    assert_eq!(sends.len(), 2, "one frame per send: {log:?}");
    let broadcast_reply = log
        .iter()
        .position(|(sent, bytes)| !sent && bytes.starts_with(b"(00P"))
        .expect("station 00 answered the broadcast");
    assert!(
        broadcast_reply < sends[1],
        "the read went out before the broadcast's reply had passed: {log:?}"
    );
}

#[test]
fn a_frame_with_a_gap_inside_is_dropped_where_the_manual_says_so() {
    // VF-AS1 (3.1, appendix 3): no gap of 1.5 characters (nor 3.5) inside a frame. The
    // YD1000 states no such rule: it waits for the rest until its frame abandon time.
    for (drive, protocol, answered) in [
        (&vf_as1::DRIVE, vf_as1::protocols::ASCII.protocol(), false),
        (&yd1000::DRIVE, yd1000::protocols::ASCII.protocol(), true),
    ] {
        let sim = Simulator::new(drive);
        let (mut line, stop, server) = served(&sim, protocol);
        line.send(b"(RFA").unwrap();
        std::thread::sleep(Duration::from_millis(40));
        line.send(b"01)\r").unwrap();
        let mut buf = [0u8; 32];
        // An answer due is waited for within a bound on a hang; one not due, briefly.
        let wait = if answered {
            Duration::from_secs(5)
        } else {
            Duration::from_millis(400)
        };
        let got = line.receive(&mut buf, Instant::now() + wait).unwrap();
        // A whole frame is answered all the same.
        line.send(b"(RFA01)\r").unwrap();
        let whole = line
            .receive(&mut buf, Instant::now() + Duration::from_secs(2))
            .unwrap();
        stop.store(true, Ordering::Relaxed);
        server.join().unwrap();
        assert_eq!(got > 0, answered, "{}", drive.id);
        assert!(whole > 0, "{}", drive.id);
    }
}

#[test]
fn bytes_before_the_start_reject_the_frame_on_the_vf_as1_only() {
    let mut buf = [0u8; 32];
    let sim = Simulator::new(&vf_as1::DRIVE);
    let mut link = sim.link(vf_as1::protocols::ASCII.protocol());
    link.send(b"\x00(RFA01)\r").unwrap();
    assert_eq!(link.receive(&mut buf, Instant::now()).unwrap(), 0);
    link.send(b"(RFA01)\r").unwrap();
    assert!(link.receive(&mut buf, Instant::now()).unwrap() > 0);
    let mut binary = sim.link(vf_as1::protocols::BINARY.protocol());
    binary.send(&[0x55, 0x2F, 0x52, 0xFA, 0x01, 0x7C]).unwrap();
    assert_eq!(binary.receive(&mut buf, Instant::now()).unwrap(), 0);
    binary.send(&[0x2F, 0x52, 0xFA, 0x01, 0x7C]).unwrap();
    assert!(binary.receive(&mut buf, Instant::now()).unwrap() > 0);

    let sim = Simulator::new(&yd1000::DRIVE);
    let mut link = sim.link(yd1000::protocols::ASCII.protocol());
    link.send(b"\x00(RFA01)\r").unwrap();
    assert!(link.receive(&mut buf, Instant::now()).unwrap() > 0);
}

#[test]
fn the_master_sends_each_frame_whole() {
    // A frame split over two sends could hold a gap the VF-AS1 drops it for.
    let sim = Simulator::new(&vf_as1::DRIVE);
    let log: Log = Arc::new(Mutex::new(Vec::new()));
    let logged = Logged {
        inner: sim.link(vf_as1::protocols::BINARY.protocol()),
        log: log.clone(),
    };
    let mut master = Master::new(
        logged,
        &vf_as1::protocols::BINARY,
        vf_as1::SERIAL.default,
        vf_as1::SERIAL.timing,
    );
    master
        .read::<vf_as1::registers::FrequencyCommand2wire>()
        .unwrap();
    let log = log.lock().unwrap();
    let sends: Vec<&Vec<u8>> = log.iter().filter(|(s, _)| *s).map(|(_, b)| b).collect();
    assert_eq!(sends, [&vec![0x2F, 0x52, 0xFA, 0x01, 0x7C]]);
}

#[test]
fn the_frame_gap_has_a_floor_in_milliseconds() {
    let sim = Simulator::new(&dv1::DRIVE);
    let fast = at_baud(dv1::SERIAL.default, 115_200);
    let master = Master::new(
        sim.link(dv1::protocols::MODBUS.protocol()),
        &dv1::protocols::MODBUS,
        fast,
        dv1::SERIAL.timing,
    );
    // 3.5 characters at 115200 bps are 0.3 ms; the DV1 asks for 10 ms.
    assert_eq!(master.frame_gap(), Duration::from_millis(10));
    assert_eq!(master.silence_limit(), Some(Duration::from_millis(10)));
    let sim = Simulator::new(&vf_as1::DRIVE);
    let at = |baud| {
        Master::new(
            sim.link(vf_as1::protocols::ASCII.protocol()),
            &vf_as1::protocols::ASCII,
            at_baud(vf_as1::SERIAL.default, baud),
            vf_as1::SERIAL.timing,
        )
        .frame_gap()
    };
    // 3.1: about 4 ms at 9600 bps (3.5 x 11 bits), about 2 ms at 19200 and 38400 bps.
    assert_eq!(at(9600).as_micros(), 4010);
    assert_eq!(at(19200).as_micros(), 2005);
    assert_eq!(at(38400), Duration::from_millis(2));
    // The YD1000's protocol file and drive file state no gap.
    let sim = Simulator::new(&yd1000::DRIVE);
    assert_eq!(
        sim.master(&yd1000::protocols::ASCII).frame_gap(),
        Duration::ZERO
    );
}

/// `settings` at another baud rate.
fn at_baud(settings: SerialSettings, baud: u32) -> SerialSettings {
    SerialSettings { baud, ..settings }
}

#[test]
fn the_reply_waits_the_send_wait_register_and_the_master_allows_for_it() {
    use vf_as1::registers::FrequencyCommand2wire;
    let sim = Simulator::new(&vf_as1::DRIVE);
    // F805 = 0.20 s, set on the panel: every reply waits 200 ms.
    sim.lock().set_raw("F805", 20);
    assert_eq!(
        sim.lock().reply_delay(vf_as1::protocols::ASCII.protocol()),
        Duration::from_millis(200)
    );
    // A master that allows only the factory setting (0 s) gives up first.
    let mut unaware = sim.master(&vf_as1::protocols::ASCII);
    assert_eq!(unaware.reply_delay(), Duration::ZERO);
    timed_out(unaware.read::<FrequencyCommand2wire>());
    // Told the wait, it gets the reply.
    let mut told = sim
        .master(&vf_as1::protocols::ASCII)
        .with_reply_delay(Duration::from_millis(200));
    assert_eq!(told.read::<FrequencyCommand2wire>().unwrap(), Hertz(0.0));
    // Or it reads F805 and F825 (allowing their longest wait meanwhile) and keeps the longer.
    let mut reading = sim.master(&vf_as1::protocols::ASCII);
    assert_eq!(
        reading.read_reply_delay().unwrap(),
        Duration::from_millis(200)
    );
    assert!(reading.reply_timeout(8) >= Duration::from_millis(200));
    assert_eq!(reading.read::<FrequencyCommand2wire>().unwrap(), Hertz(0.0));
}

#[test]
fn the_vf_as1_is_silent_for_two_seconds_after_power_on() {
    use vf_as1::registers::FrequencyCommand2wire;
    let sim = Simulator::new(&vf_as1::DRIVE);
    assert_eq!(vf_as1::SERIAL.timing.startup_delay, Duration::from_secs(2));
    sim.power_cycle();
    let mut master = sim.master(&vf_as1::protocols::ASCII);
    sim.advance(Duration::from_millis(1900));
    timed_out(master.read::<FrequencyCommand2wire>());
    sim.advance(Duration::from_millis(100));
    assert_eq!(master.read::<FrequencyCommand2wire>().unwrap(), Hertz(0.0));
}

#[test]
fn the_eaton_wait_digit_asks_the_drive_to_wait_and_the_master_allows_for_it() {
    // *2) of the DV1 manual: the request's wait digit (0-F, x 10 ms) delays the reply.
    let sim = Simulator::new(&dv1::DRIVE);
    sim.lock().set_address(0);
    let protocol = &dv1::protocols::EATON;
    let (line, stop, server) = served(&sim, protocol.protocol());
    let log: Log = Arc::new(Mutex::new(Vec::new()));
    let logged = Logged {
        inner: line,
        log: log.clone(),
    };
    let plain = Master::new(
        memory_pair().0,
        protocol,
        dv1::SERIAL.default,
        dv1::SERIAL.timing,
    );
    let mut master = Master::new(logged, protocol, dv1::SERIAL.default, dv1::SERIAL.timing)
        .with_address(Some(0))
        .with_reply_wait(Duration::from_millis(45));
    // Rounded up to 10 ms steps, and added to the reply timeout.
    assert_eq!(master.reply_wait(), Duration::from_millis(50));
    assert_eq!(
        master.reply_timeout(13),
        plain.reply_timeout(13) + Duration::from_millis(50)
    );
    // The page switch of the manual's 例三 step 1 (HFF, page 1), asking for 50 ms.
    let started = Instant::now();
    // The page register by its wire number (7Fh as a register number is P.127, paged).
    let outcome = master.transact(&Request {
        wire_register: true,
        ..Request::raw(CommandKind::WriteRam, 0xFF, 1)
    });
    let took = started.elapsed();
    stop.store(true, Ordering::Relaxed);
    server.join().unwrap();
    let log = log.lock().unwrap();
    let sent = &log.iter().find(|(sent, _)| *sent).expect("a request").1;
    // 30h+30h+46h+46h+35h+30h+30h+30h+31h = 1E2h: sum "E2".
    assert_eq!(sent.as_slice(), b"\x0500FF50001E2\r");
    // Page 1 exists: the drive acknowledges the switch.
    assert!(outcome.is_ok(), "the drive acknowledges: {outcome:?}");
    assert!(took >= Duration::from_millis(50), "answered after {took:?}");
    // Asking for more than the digit carries is kept to F (150 ms).
    let most = Master::new(
        memory_pair().0,
        protocol,
        dv1::SERIAL.default,
        dv1::SERIAL.timing,
    )
    .with_reply_wait(Duration::from_secs(1));
    assert_eq!(most.reply_wait(), Duration::from_millis(150));
}
