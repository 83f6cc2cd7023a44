//! What the fault matrix and the soak share: the faults the virtual drive can commit, the
//! outcome a master owes for each, the drives, protocols and registers exercised (picked
//! from the descriptions, so no drive is named here), a virtual drive served over a
//! pseudo-terminal, and the master's end of a line that counts the frames sent.

use crate::slack::Slack;
use std::io;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, Mutex, PoisonError};
use std::thread::{self, JoinHandle};
use std::time::{Duration, Instant};
use vfd_runtime::transaction::ReplyField;
use vfd_runtime::transport::Transport;
use vfd_runtime::transport::{PseudoTerminal, PtyTransport};
use vfd_runtime::virtual_drive::{serve, Fault, Simulator};
use vfd_runtime::{
    Access, CommandKind, DataType, DriveInfo, Protocol, RegisterInfo, Request, Space, TakesEffect,
    TransactionError, TransactionErrorKind,
};

/// Every fault the virtual drive can commit, with a short name for tables.
pub fn faults() -> Vec<(&'static str, Fault)> {
    vec![
        ("drop reply", Fault::DropReply),
        ("corrupt checksum", Fault::CorruptChecksum),
        ("delay", Fault::Delay),
        (
            "garbage before",
            Fault::GarbageBefore(vec![0x00, 0xFF, 0x55, 0xAA, 0x13]),
        ),
        ("wrong station", Fault::WrongStation),
        ("echo request", Fault::EchoRequest),
        ("split bytes", Fault::SplitBytes(2)),
        ("noise", Fault::Noise),
        ("answer broadcast", Fault::AnswerBroadcast),
    ]
}

/// What an exchange came to, as the tests compare it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Kind {
    /// Success (the caller checks the value).
    Value,
    /// [`TransactionErrorKind::Timeout`].
    Timeout,
    /// [`TransactionErrorKind::Decode`].
    Decode,
    /// [`TransactionErrorKind::Mismatch`], with the part that differs.
    Mismatch(ReplyField),
    /// [`TransactionErrorKind::Rejected`], with the drive's code.
    Rejected(u16),
    /// [`TransactionErrorKind::Io`].
    Io,
    /// [`TransactionErrorKind::Encode`].
    Encode,
    /// [`TransactionErrorKind::Value`], or a value that is not the drive's.
    BadValue,
}

impl Kind {
    /// The kind of `result`.
    pub fn of<T>(result: &Result<T, TransactionError>) -> Kind {
        match result {
            Ok(_) => Kind::Value,
            Err(error) => match &error.kind {
                TransactionErrorKind::Timeout { .. } => Kind::Timeout,
                TransactionErrorKind::Decode(_) => Kind::Decode,
                TransactionErrorKind::Mismatch { field, .. } => Kind::Mismatch(*field),
                TransactionErrorKind::Rejected { code, .. } => Kind::Rejected(*code),
                TransactionErrorKind::Io(_) => Kind::Io,
                TransactionErrorKind::Encode(_) => Kind::Encode,
                TransactionErrorKind::Value(_) => Kind::BadValue,
            },
        }
    }

    /// A short name for tables: `value`, `timeout`, `mismatch(address)`.
    pub fn label(self) -> String {
        match self {
            Kind::Value => "value".into(),
            Kind::Timeout => "timeout".into(),
            Kind::Decode => "decode".into(),
            Kind::Mismatch(field) => format!("mismatch({})", field.as_str()),
            Kind::Rejected(code) => format!("rejected({code})"),
            Kind::Io => "io".into(),
            Kind::Encode => "encode".into(),
            Kind::BadValue => "bad value".into(),
        }
    }
}

/// The outcome a master without retries owes its caller when `fault` hits the reply to a
/// request of one frame: the typed error the fault explains, or the value where the master
/// reads through the fault.
/// What a write owes under `fault` over `protocol`: as [`expected`], except that a
/// corrupted checksum cannot touch a write reply without one (the Eaton ACK), so the write
/// succeeds.
pub fn expected_for_write(fault: &Fault, protocol: &vfd_runtime::Protocol) -> Kind {
    let unsummed = protocol
        .commands
        .iter()
        .filter(|c| c.kind.is_write())
        .any(|c| {
            !c.reply
                .parts
                .iter()
                .any(|p| matches!(p, vfd_runtime::Part::Checksum(_)))
        });
    match fault {
        Fault::CorruptChecksum if unsummed => Kind::Value,
        _ => expected(fault),
    }
}

/// What an exchange owes under `fault` ([`Kind::Value`]: the value despite it).
pub fn expected(fault: &Fault) -> Kind {
    match fault {
        Fault::DropReply | Fault::Delay | Fault::Noise => Kind::Timeout,
        Fault::CorruptChecksum => Kind::Decode,
        Fault::WrongStation => Kind::Mismatch(ReplyField::Address),
        Fault::GarbageBefore(_)
        | Fault::EchoRequest
        | Fault::SplitBytes(_)
        | Fault::AnswerBroadcast => Kind::Value,
    }
}

/// One protocol of one drive, and the registers the tests read and write.
#[derive(Debug, Clone, Copy)]
pub struct Subject {
    /// The drive.
    pub drive: &'static DriveInfo,
    /// One of its protocols.
    pub protocol: &'static Protocol,
    /// A register read.
    pub read: &'static RegisterInfo,
    /// Another register read (the first one when the drive has one only).
    pub other: &'static RegisterInfo,
    /// A register written.
    pub write: &'static RegisterInfo,
    /// How it is written: a RAM write, or a persistent one where the protocol writes
    /// parameters only so (the Huanyang HY's 02).
    pub write_kind: CommandKind,
}

impl Subject {
    /// `drive protocol`, e.g. for a table; `drive protocol (variant)` for a protocol in
    /// another variant than its first.
    pub fn name(&self) -> String {
        match &self.protocol.variants {
            Some(variants) if variants.current != 0 => format!(
                "{} {} ({})",
                self.drive.id,
                self.protocol.id,
                self.protocol.variant_id().unwrap_or_default()
            ),
            _ => format!("{} {}", self.drive.id, self.protocol.id),
        }
    }

    /// A virtual drive in its factory state, set to speak the subject's protocol variant
    /// (its selecting register set so; unchanged for a protocol without variants).
    pub fn simulator(&self) -> Simulator {
        let sim = Simulator::new(self.drive);
        sim.lock().select_variant(self.protocol);
        sim
    }

    /// The `n`th raw value (from 0) the tests write: inside the register's range, never
    /// its default.
    pub fn value(&self, n: u32) -> u32 {
        // From raw_min + 1 to raw_min + span - 1, the default left out.
        let low = self.write.raw_min as u32 + 1;
        let span = (self.write.raw_max - self.write.raw_min).clamp(3, 1 << 20) as u32;
        let mut raw = low + n % (span - 2);
        if self.write.default_raw.is_some_and(|d| d >= low && raw >= d) {
            raw += 1;
        }
        raw
    }
}

/// Ids of the registers a drive's behaviour model reads or drives.
fn behaviour_registers(drive: &DriveInfo) -> Vec<&'static str> {
    let Some(b) = drive.behaviour else {
        return Vec::new();
    };
    let mut ids = vec![b.command.register, b.frequency.command];
    for amount in [
        b.frequency.acceleration,
        b.frequency.deceleration,
        b.frequency.span,
    ] {
        if let vfd_runtime::behaviour::Amount::Register(id) = amount {
            ids.push(id);
        }
    }
    ids.extend(b.frequency.output);
    ids.extend(b.frequency.reference);
    ids.extend(b.status.registers);
    ids.extend(b.trip.code);
    ids.extend(b.trip.history.iter().map(|slot| slot.register));
    for written in [b.command.reset_by_write, b.trip.clear_by_write]
        .into_iter()
        .flatten()
    {
        ids.push(written.register);
    }
    if let Some(current) = &b.current {
        ids.extend(current.registers);
    }
    if let Some(p) = &b.process {
        ids.extend([p.control, p.reference, p.status, p.output]);
    }
    ids
}

/// Plain read-write parameters of `drive` that `protocol` reads and writes: no array, no
/// bound named after another register or used as one, not used by the behaviour model,
/// taking effect at once, with room for a few values.
fn candidates(drive: &DriveInfo, protocol: &Protocol) -> Vec<&'static RegisterInfo> {
    let used = behaviour_registers(drive);
    let bounds: Vec<&str> = drive
        .registers
        .iter()
        .flat_map(|r| [r.min_bound, r.max_bound])
        .flatten()
        .collect();
    let mut buffer = [0u8; 512];
    drive
        .registers
        .iter()
        .copied()
        .filter(|r| {
            r.space == Space::Parameter
                && r.access == Access::ReadWrite
                && matches!(r.data_type, DataType::Word | DataType::DoubleWord)
                && r.array_len == 0
                && r.min_bound.is_none()
                && r.max_bound.is_none()
                && !r.panel_only
                && !r.signed
                && r.takes_effect == TakesEffect::Immediately
                && r.raw_min >= 0
                && r.raw_max - r.raw_min >= 8
                && !used.contains(&r.id)
                && !bounds.iter().any(|b| *b == r.id || *b == r.code)
        })
        // A paged register takes a page switch first, whose count depends on what came
        // before: the matrix is about single exchanges (pages: tests/tests/pages.rs).
        .filter(|r| protocol.page_of(r.address).is_none())
        .filter(|r| {
            let request = Request::for_register(CommandKind::Read, r, r.raw_min as u32);
            protocol
                .encode_request(&request, Some(1), &mut buffer)
                .is_ok()
                && write_kind(protocol, r).is_some()
        })
        .collect()
}

/// How `protocol` writes `register`: a RAM write where it has one, else a persistent one.
fn write_kind(protocol: &Protocol, register: &'static RegisterInfo) -> Option<CommandKind> {
    let mut buffer = [0u8; 512];
    [CommandKind::WriteRam, CommandKind::WritePersistent]
        .into_iter()
        .find(|kind| {
            let request = Request::for_register(*kind, register, register.raw_min as u32);
            protocol
                .encode_request(&request, Some(1), &mut buffer)
                .is_ok()
        })
}

/// Every protocol of every described drive, with the registers to exercise. A protocol
/// without such a register is left out and named in the second list.
pub fn subjects() -> (Vec<Subject>, Vec<String>) {
    let mut subjects = Vec::new();
    let mut left_out = Vec::new();
    for drive in vfd_drives::ALL_DRIVES {
        // Every variant of a protocol is a subject (the DV1's Eaton protocol in CR LF too).
        for protocol in drive.protocols.iter().flat_map(|p| p.all_variants()) {
            // A protocol described without a read (the DV1's Eaton reads are not yet in its
            // protocol file) has nothing to read back: it is not a subject.
            if !protocol
                .commands
                .iter()
                .any(|c| c.kind == vfd_runtime::CommandKind::Read)
            {
                eprintln!(
                    "{} {}: no read command described, not exercised",
                    drive.id, protocol.id
                );
                continue;
            }
            let found = candidates(drive, protocol);
            let (Some(first), Some(last)) = (found.first(), found.last()) else {
                left_out.push(format!("{} {}", drive.id, protocol.id));
                continue;
            };
            subjects.push(Subject {
                drive,
                protocol,
                read: first,
                other: found[found.len().min(2) - 1],
                write: last,
                write_kind: write_kind(protocol, last).expect("a candidate is writable"),
            });
        }
    }
    (subjects, left_out)
}

/// A virtual drive answering over a pseudo-terminal with the `serve` loop, at the drive's
/// default serial settings. Stop it with [`Served::stop`] before closing the master's end.
pub struct Served {
    stop: Arc<AtomicBool>,
    server: JoinHandle<io::Result<()>>,
}

impl Served {
    /// Serves `sim` in `protocol`; returns the master's end of the line.
    pub fn start(
        sim: &Simulator,
        protocol: &'static Protocol,
    ) -> io::Result<(PtyTransport, Served)> {
        let (line, drive_end) = PseudoTerminal::open()?.into_transports()?;
        Ok((line, Served::serve(sim, protocol, drive_end)))
    }

    /// Like [`Served::start`], with both ends allowing `slack` for a loaded machine (see
    /// [`crate::slack`]).
    pub fn start_with_slack(
        sim: &Simulator,
        protocol: &'static Protocol,
        slack: Duration,
    ) -> io::Result<(Slack<PtyTransport>, Served)> {
        let (line, drive_end) = PseudoTerminal::open()?.into_transports()?;
        let served = Served::serve(sim, protocol, Slack::new(drive_end, slack));
        Ok((Slack::new(line, slack), served))
    }

    fn serve<T: Transport + Send + 'static>(
        sim: &Simulator,
        protocol: &'static Protocol,
        mut drive_end: T,
    ) -> Served {
        let stop = Arc::new(AtomicBool::new(false));
        let settings = sim.lock().drive().serial.default;
        let server = {
            let (sim, stop) = (sim.clone(), Arc::clone(&stop));
            thread::spawn(move || serve(&sim, protocol, &mut drive_end, settings, &stop))
        };
        Served { stop, server }
    }

    /// Stops the serve loop and returns how it ended (an error message if it failed).
    pub fn stop(self) -> Result<(), String> {
        self.stop.store(true, Ordering::Relaxed);
        match self.server.join() {
            Ok(Ok(())) => Ok(()),
            Ok(Err(error)) => Err(format!("the serve loop failed: {error}")),
            Err(_) => Err("the serve loop panicked".into()),
        }
    }
}

/// The master's end of a line, shared with the test: it counts the frames the master sends
/// (one per `send`) and lets the test drain the line between exchanges. A follow-up that
/// acknowledges a reply is not counted: it asks the drive for nothing (the drive counts
/// requests, and a follow-up asking for a reply again, the same way).
pub struct CountingLine<T> {
    inner: Arc<Mutex<T>>,
    sent: Arc<AtomicU64>,
    protocol: &'static Protocol,
}

/// The test's handle on a [`CountingLine`].
pub struct LineHandle<T> {
    inner: Arc<Mutex<T>>,
    sent: Arc<AtomicU64>,
}

impl<T> Clone for LineHandle<T> {
    fn clone(&self) -> Self {
        LineHandle {
            inner: Arc::clone(&self.inner),
            sent: Arc::clone(&self.sent),
        }
    }
}

impl<T: Transport> CountingLine<T> {
    /// Wraps `transport`, a line in `protocol`; the handle counts and drains.
    pub fn new(transport: T, protocol: &'static Protocol) -> (CountingLine<T>, LineHandle<T>) {
        let inner = Arc::new(Mutex::new(transport));
        let sent = Arc::new(AtomicU64::new(0));
        let handle = LineHandle {
            inner: Arc::clone(&inner),
            sent: Arc::clone(&sent),
        };
        (
            CountingLine {
                inner,
                sent,
                protocol,
            },
            handle,
        )
    }

    fn with<R>(&self, work: impl FnOnce(&mut T) -> R) -> R {
        work(&mut self.inner.lock().unwrap_or_else(PoisonError::into_inner))
    }
}

impl<T: Transport> Transport for CountingLine<T> {
    fn send(&mut self, bytes: &[u8]) -> io::Result<()> {
        let acknowledges = self
            .protocol
            .commands
            .iter()
            .filter_map(|c| c.follow_up.as_ref())
            .any(|f| matches!(f.recognise(bytes), Some((true, _, len)) if len == bytes.len()));
        if !acknowledges {
            self.sent.fetch_add(1, Ordering::Relaxed);
        }
        self.with(|t| t.send(bytes))
    }
    fn receive(&mut self, buf: &mut [u8], deadline: Instant) -> io::Result<usize> {
        self.with(|t| t.receive(buf, deadline))
    }
    fn clear_input(&mut self) -> io::Result<()> {
        self.with(|t| t.clear_input())
    }
    fn last_gap(&self) -> Option<Duration> {
        self.with(|t| t.last_gap())
    }
    fn allowance(&self) -> Duration {
        self.with(|t| t.allowance())
    }
}

impl<T: Transport> LineHandle<T> {
    /// Frames the master has sent so far.
    pub fn sent(&self) -> u64 {
        self.sent.load(Ordering::Relaxed)
    }

    /// Waits until `sim` has received every frame the master sent (a serve loop may still
    /// be busy with a late reply); false when it has not within `limit`.
    pub fn caught_up(&self, sim: &Simulator, limit: Duration) -> bool {
        let deadline = Instant::now() + limit;
        while sim.requests() < self.sent() {
            if Instant::now() >= deadline {
                return false;
            }
            thread::sleep(Duration::from_millis(1));
        }
        true
    }

    /// Drops what arrives until the line has been silent for `quiet`; false when it is
    /// not silent within `limit`.
    pub fn drain_until_quiet(&self, quiet: Duration, limit: Duration) -> bool {
        let deadline = Instant::now() + limit;
        let mut buf = [0u8; 256];
        let mut line = self.inner.lock().unwrap_or_else(PoisonError::into_inner);
        while Instant::now() < deadline {
            match line.receive(&mut buf, Instant::now() + quiet) {
                Ok(0) => return true,
                Ok(_) => {}
                Err(_) => return false,
            }
        }
        false
    }
}
