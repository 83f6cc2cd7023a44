//! The master does not wake up for every byte of a reply that crosses the line a byte at a
//! time: while the reply is incomplete it waits until nearly all the bytes the shortest
//! reply still needs can have arrived. A line here delivers the virtual drive's reply at the
//! character rate of the drive's default format, and the test counts how often the master
//! asked it for bytes.
//!
//! No timed assertion: a slow machine can only make the master find more bytes at each
//! look, never fewer, so the counts asserted are upper bounds that load cannot break.

use std::collections::VecDeque;
use std::io;
use std::time::{Duration, Instant};
use vfd_runtime::transaction::Master;
use vfd_runtime::transport::Transport;
use vfd_runtime::virtual_drive::{SimLink, Simulator};
use vfd_runtime::{Access, CommandKind, DataType, DriveInfo, Protocol, Request, Space};

/// A line that delivers the reply a byte per character time after the request has crossed
/// it, and counts the reads that returned bytes.
struct PacedReply {
    drive: SimLink,
    char_time: Duration,
    reply: VecDeque<u8>,
    /// When the reply's first byte has crossed the line.
    first_due: Instant,
    delivered: u32,
    reads: u32,
}

impl Transport for PacedReply {
    fn send(&mut self, bytes: &[u8]) -> io::Result<()> {
        self.drive.send(bytes)?;
        let mut buf = [0u8; 512];
        loop {
            let got = self.drive.receive(&mut buf, Instant::now())?;
            if got == 0 {
                break;
            }
            self.reply.extend(&buf[..got]);
        }
        let request_time = self.char_time * u32::try_from(bytes.len()).unwrap();
        self.first_due = Instant::now() + request_time + self.char_time;
        self.delivered = 0;
        Ok(())
    }

    fn receive(&mut self, buf: &mut [u8], deadline: Instant) -> io::Result<usize> {
        if self.reply.is_empty() {
            std::thread::sleep(deadline.saturating_duration_since(Instant::now()));
            return Ok(0);
        }
        // The next byte's due time; wait for it (or the deadline).
        let next_due = self.first_due + self.char_time * self.delivered;
        let now = Instant::now();
        if now < next_due {
            std::thread::sleep(next_due.min(deadline) - now);
            if deadline < next_due {
                return Ok(0);
            }
        }
        let elapsed = Instant::now().saturating_duration_since(self.first_due);
        let due = (elapsed.as_nanos() / self.char_time.as_nanos()) as usize + 1;
        let count = (due - self.delivered as usize)
            .min(self.reply.len())
            .min(buf.len());
        for (slot, byte) in buf.iter_mut().zip(self.reply.drain(..count)) {
            *slot = byte;
        }
        self.delivered += count as u32;
        self.reads += 1;
        Ok(count)
    }
}

/// A read of the first plain word register `protocol` reads, and the reply's length.
fn a_read(drive: &'static DriveInfo, protocol: &'static Protocol) -> (Request, usize) {
    drive
        .registers
        .iter()
        .copied()
        .filter(|r| {
            r.space == Space::Parameter
                && r.access != Access::WriteOnly
                && r.data_type == DataType::Word
                && r.array_len == 0
        })
        .find_map(|info| {
            let request = Request::for_register(CommandKind::Read, info, 0);
            let sim = Simulator::new(drive);
            let address = sim.lock().address();
            let mut master = Master::for_protocol(
                sim.link(protocol),
                protocol,
                drive.serial.default,
                drive.serial.timing,
            )
            .with_address(Some(address));
            master
                .transact(&request)
                .ok()
                .map(|_| (request, master.last_reply().len()))
        })
        .expect("a readable word register")
}

/// Reads over a paced reply; returns the reads that returned bytes and the reply length.
fn reads_for(drive: &'static DriveInfo, protocol_id: &str) -> (u32, usize) {
    let protocol = *drive
        .protocols
        .iter()
        .find(|p| p.id == protocol_id)
        .expect("the protocol");
    let (request, reply_len) = a_read(drive, protocol);
    let sim = Simulator::new(drive);
    let address = sim.lock().address();
    let line = PacedReply {
        drive: sim.link(protocol),
        char_time: drive.serial.default.char_time(),
        reply: VecDeque::new(),
        first_due: Instant::now(),
        delivered: 0,
        reads: 0,
    };
    let mut master =
        Master::for_protocol(line, protocol, drive.serial.default, drive.serial.timing)
            .with_address(Some(address))
            .with_local_echo(Some(false));
    master.transact(&request).expect("the read succeeds");
    (master.transport().reads, reply_len)
}

#[test]
fn a_fixed_length_reply_is_read_in_a_few_looks_not_one_per_byte() {
    let drive = vfd_drives::drive("fc51").expect("the FC 51");
    let (reads, reply_len) = reads_for(drive, "fc");
    assert_eq!(reply_len, 16, "an FC telegram");
    // The first byte, then the rest once nearly all of it can have come (and perhaps the
    // last byte on its own): not one look per byte.
    assert!(reads <= 3, "{reads} reads for a {reply_len}-byte reply");
}

#[test]
fn a_reply_longer_than_the_shortest_error_reply_is_read_in_fewer_looks_than_bytes() {
    let drive = vfd_drives::drive("fc51").expect("the FC 51");
    let (reads, reply_len) = reads_for(drive, "modbus");
    assert_eq!(reply_len, 7, "a Modbus read of one register");
    // A Modbus exception is 5 bytes: after the first byte the master waits for all but
    // the last of the 4 the shortest answer still needs. Once the function code shows no
    // exception bit only the 7-byte reply can come, so it waits for all but the last of
    // the rest, then reads the last (1 + 1 + 1 + 1 looks at most, where the paced line
    // alone would take 7, and 5 without ruling the exception out).
    assert!(reads <= 4, "{reads} reads for a {reply_len}-byte reply");
}
