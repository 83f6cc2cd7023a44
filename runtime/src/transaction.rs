//! Request/reply exchanges: run any steps a request needs first, encode, send, collect the
//! reply within a timeout derived from the baud rate, check it answers the request, and
//! map error replies to typed errors.
//!
//! Finding the reply in what the line delivers is generic: stale input is dropped before a
//! request goes out, the master's own request coming back (an echoing half-duplex adapter)
//! is skipped, noise and frames that answer something else are passed over, a silence
//! longer than a frame allows starts a new frame (where the transport can tell), and of
//! overlapping frames the one starting last wins. Every wait ends at the reply deadline.
//!
//! A request that gets no reply (a command with `reply: none`, or a write of a register
//! with `no_reply: true`) is done once its frame is on the line: the master waits the
//! frame's wire time and the frame gap, looks for nothing and never repeats it.

use crate::error::{hex, DecodeError, EncodeError, ValueError};
use crate::info::ErrorCodeInfo;
use crate::kinds::{CommandKind, DataType, Space};
use crate::layout::Role;
use crate::protocol::{
    CommandSpec, Difference, DriveProtocol, Expectation, PreStep, Protocol, Reply, Search,
};
use crate::register::{Persistable, Register, RegisterValue, Request, Writable};
use crate::serial::{DriveTiming, SerialSettings};
use crate::transport::Transport;
use std::fmt;
use std::marker::PhantomData;
use std::time::{Duration, Instant};

mod broadcast;
pub use broadcast::BroadcastReply;
mod persistence;

/// Largest frame the master buffers; longer noise is dropped from the front.
pub const MAX_FRAME: usize = 256;

/// What a successful exchange returned.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Answer {
    /// Data read, or the value the drive reports written; `None` when the reply carries no
    /// data (the protocol echoes nothing).
    pub data: Option<u32>,
    /// The drive said it is tripped (lower-case command letter in the reply).
    pub tripped: bool,
    /// Process words the reply carried (status word, output value).
    pub process: Option<[u16; 2]>,
    /// Offset and length of text in the reply, for text reads.
    pub text: Option<(usize, usize)>,
    /// Offset and length in the reply of the registers a block read returned
    /// ([`Master::read_words`]), or of the words a block transfer read
    /// ([`Master::block_transfer`]).
    pub block: Option<(usize, usize)>,
    /// The write status a block transfer's reply carries ([`Role::WriteStatus`]).
    pub write_status: Option<u32>,
    /// The decimal places the reply states for its value ([`Role::Decimals`], the Eaton
    /// unit digit); `None` when it states none. A read of a described register is checked
    /// against it (see [`crate::info::RegisterInfo::scaled_for_decimals`]): a reply whose
    /// decimals no scale of the register has fails with [`ValueError::WrongDecimals`].
    pub decimals: Option<u8>,
}

/// What a block transfer ([`Master::block_transfer`]) returned.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct BlockTransfer {
    /// The words read, in order, each with the register its position selects (`None`: the
    /// position selects nothing and the drive sends 0).
    pub reads: Vec<(Option<u16>, u16)>,
    /// The registers the written words went to, in order (`None`: not selected).
    pub writes: Vec<Option<u16>>,
    /// The reply's write status: bit `n` set means word `n` was not written.
    pub write_status: u32,
    /// The reply said the drive is tripped.
    pub tripped: bool,
}

impl BlockTransfer {
    /// Whether word `position` (0: the first) was not written.
    pub fn write_failed(&self, position: usize) -> bool {
        position < 32 && self.write_status & (1 << position) != 0
    }

    /// The typed value of register `R`, when a read position selected it (`None`
    /// otherwise).
    pub fn value<R: Register>(&self) -> Option<Result<R::Value, ValueError>> {
        if R::INFO.space != Space::Parameter {
            return None;
        }
        self.reads
            .iter()
            .find(|(register, _)| *register == Some(R::INFO.address))
            .map(|(_, word)| R::Value::from_raw(u32::from(*word), R::INFO))
    }

    /// Whether the word written to register `R` was written: `None` when no write position
    /// selected `R`.
    pub fn written<R: Register>(&self) -> Option<bool> {
        self.writes
            .iter()
            .position(|register| *register == Some(R::INFO.address))
            .map(|position| !self.write_failed(position))
    }
}

/// The word a block transfer writes for `value` of register `R`: its raw value, checked
/// against the register's range as a typed write is (the frame carries 16-bit words).
pub fn block_word<R: Writable>(value: &R::Value) -> Result<u16, ValueError> {
    value.to_raw(R::INFO).map(|raw| raw as u16)
}

/// A value read from a drive, with what the reply said about the drive: a tripped drive
/// still answers reads (its monitors hold the values at the trip), so the value comes back
/// and [`Reading::tripped`] says so, without an extra request.
///
/// It dereferences to the value and compares with it (`reading == Hertz(60.0)`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Reading<V> {
    /// The typed value.
    pub value: V,
    /// The reply said the drive is tripped (in the Toshiba-style protocols, a lower-case
    /// command letter). Protocols whose replies carry no such sign report `false`; the FC
    /// drives report a trip in the status word instead.
    pub tripped: bool,
}

impl<V> Reading<V> {
    /// The value, without the drive state.
    pub fn into_value(self) -> V {
        self.value
    }
}

impl<V> std::ops::Deref for Reading<V> {
    type Target = V;
    fn deref(&self) -> &V {
        &self.value
    }
}

impl<V: PartialEq> PartialEq<V> for Reading<V> {
    fn eq(&self, other: &V) -> bool {
        self.value == *other
    }
}

impl<V: fmt::Display> fmt::Display for Reading<V> {
    /// The value, followed by `(drive tripped)` when the reply said so.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        self.value.fmt(f)?;
        if self.tripped {
            f.write_str(" (drive tripped)")?;
        }
        Ok(())
    }
}

/// Drive parameter of a [`Master`] built on an untyped [`Protocol`]
/// ([`Master::for_protocol`]): it sends raw requests ([`Master::transact`]) for tools that
/// work with any drive, and no typed register requests.
#[derive(Debug, Clone, Copy)]
pub enum AnyDrive {}

/// A bus master speaking one protocol to one station of drive `D`.
///
/// Typed reads and writes take only registers of `D` (`R: Register<Drive = D>`), so a
/// register of another drive does not compile. Buffers are fixed arrays, so a transaction
/// makes no heap allocation unless it fails.
pub struct Master<T: Transport, D: 'static = AnyDrive> {
    transport: T,
    protocol: &'static Protocol,
    drive: PhantomData<fn() -> D>,
    settings: SerialSettings,
    timing: DriveTiming,
    address: Option<u8>,
    request: [u8; MAX_FRAME],
    reply: [u8; MAX_FRAME],
    reply_len: usize,
    last_activity: Option<Instant>,
    retries: u8,
    echo: Option<bool>,
    echo_fixed: bool,
    /// Registers the request under way reads in one block (0: an ordinary request).
    block_words: u16,
    /// The words a block transfer under way writes, and the words it asks back.
    block_transfer: Option<(crate::codec::Words, u8)>,
    /// The registers a block write under way carries ([`Master::write_words`]).
    block_write: Option<crate::codec::Words>,
    /// Added to the drive's processing time in every reply timeout: the adapter's and the
    /// host's latency, which no manual can know.
    host_latency: Duration,
    /// After a timeout: until when a late reply may still arrive (the next exchange waits
    /// for it and drops it, so it cannot be taken for the next reply).
    late_reply_until: Option<Instant>,
    /// The drive's wait before replying as the caller stated or read it
    /// ([`Master::with_reply_delay`], [`Master::read_reply_delay`]); `None`: the
    /// description's factory setting.
    reply_delay: Option<Duration>,
    /// The wait the master asks the drive to make before each reply, in requests whose
    /// layout carries one ([`Role::ReplyWait`], in tens of milliseconds).
    reply_wait: u8,
    /// What the master knows about the drive's persistence selector, if it has one
    /// ([`crate::protocol::PersistenceSelector`]).
    selector: persistence::SelectorState,
    /// The stations the request under way is broadcast to (see [`Master::broadcast`]).
    broadcast_to: Option<crate::broadcast::Broadcast>,
    /// The port the master talks to, for drives with several: requests for a register
    /// that exists once per port go to this port's copy.
    port: Option<crate::drive::Port>,
    /// The page each station is known to be on, on a protocol with pages
    /// ([`Protocol::paging`]): set when a page switch is acknowledged, dropped after any
    /// failed exchange with the station, a write that resets it, or a broadcast.
    pages: Vec<(u8, u16)>,
}

impl<T: Transport> Master<T, AnyDrive> {
    /// A master for an untyped `protocol` (from a [`crate::DriveInfo`], for tools that work
    /// with any drive): it runs raw requests with [`Master::transact`].
    pub fn for_protocol(
        transport: T,
        protocol: &'static Protocol,
        settings: SerialSettings,
        timing: DriveTiming,
    ) -> Self {
        Master::build(transport, protocol, settings, timing)
    }
}

impl<T: Transport, D: 'static> Master<T, D> {
    /// A master for drive `D`'s `protocol` over `transport`, with the line `settings` and
    /// the drive's `timing` (all from the generated drive module).
    pub fn new(
        transport: T,
        protocol: &'static DriveProtocol<D>,
        settings: SerialSettings,
        timing: DriveTiming,
    ) -> Self {
        Master::build(transport, protocol.protocol(), settings, timing)
    }

    fn build(
        transport: T,
        protocol: &'static Protocol,
        settings: SerialSettings,
        timing: DriveTiming,
    ) -> Self {
        Master {
            transport,
            protocol,
            drive: PhantomData,
            settings,
            timing,
            address: None,
            request: [0; MAX_FRAME],
            reply: [0; MAX_FRAME],
            reply_len: 0,
            last_activity: None,
            retries: 0,
            echo: None,
            echo_fixed: false,
            block_words: 0,
            block_transfer: None,
            block_write: None,
            host_latency: crate::serial::HOST_LATENCY,
            late_reply_until: None,
            reply_delay: None,
            reply_wait: 0,
            selector: persistence::SelectorState::default(),
            broadcast_to: None,
            port: None,
            pages: Vec::new(),
        }
    }

    /// The transport it talks through.
    pub fn transport(&self) -> &T {
        &self.transport
    }

    /// The transport it talks through, to inspect or adjust between exchanges.
    pub fn transport_mut(&mut self) -> &mut T {
        &mut self.transport
    }

    /// The page the master knows station `address` to be on (`None`: unknown, so the next
    /// paged access selects its page first). See [`Protocol::paging`].
    pub fn known_page(&self, address: Option<u8>) -> Option<u16> {
        let station = address.unwrap_or(0);
        self.pages
            .iter()
            .find(|(s, _)| *s == station)
            .map(|(_, page)| *page)
    }

    /// Forgets the pages of every station: call it after reconnecting to a line whose
    /// drives may have been reset or switched by another master (a new master starts
    /// knowing none).
    pub fn forget_pages(&mut self) {
        self.pages.clear();
    }

    fn remember_page(&mut self, page: Option<u16>) {
        let station = self.address.unwrap_or(0);
        self.pages.retain(|(s, _)| *s != station);
        if let Some(page) = page {
            self.pages.push((station, page));
        }
    }

    /// Talks in the protocol's variant `id` (`cr_lf`: every frame ends in CR LF), the one
    /// the drive is set to ([`Protocol::variant`]): requests are sent in it and replies
    /// are expected in it. An unknown variant is refused, naming the protocol's variants.
    pub fn with_variant(mut self, id: &str) -> Result<Self, EncodeError> {
        self.protocol = self.protocol.variant_or_error(id)?;
        Ok(self)
    }

    /// The id of the protocol variant the master talks in (`None`: the protocol has none).
    pub fn variant(&self) -> Option<&'static str> {
        self.protocol.variant_id()
    }

    /// Talks to the drive's port `port` (of a drive with several serial ports): a request
    /// for a register that exists once per port goes to this port's copy, as the
    /// description's `ports.registers` pairs them (one port's command word becomes the
    /// other's). `None`: registers are sent as given.
    pub fn with_port(mut self, port: Option<crate::drive::Port>) -> Self {
        self.port = port;
        self
    }

    /// The latency added to the drive's processing time in every reply timeout, for the
    /// adapter and the host (USB serial adapters buffer for up to 16 ms; a loaded machine
    /// schedules late). Default: [`crate::serial::HOST_LATENCY`].
    pub fn with_host_latency(mut self, latency: Duration) -> Self {
        self.host_latency = latency;
        self
    }

    /// Addresses requests to station `address` (`None`: send no address, which the
    /// Toshiba-style protocols accept when one drive is on the line).
    pub fn with_address(mut self, address: Option<u8>) -> Self {
        self.address = address;
        // Another station's persistence selector is not known.
        self.selector.value = None;
        self
    }

    /// Repeats a request whose exchange failed (no reply in time, a garbled reply, a reply
    /// to something else) up to `retries` more times, **for requests that only read**
    /// ([`CommandKind::Read`], [`CommandKind::ReadText`]: register and text reads, including
    /// the read after an index step). Writes, process-data exchanges and the steps before a
    /// request (index and RAM/EEPROM selection) are never repeated: a write whose reply was
    /// lost may have been carried out. A refusal by the drive, a value or request that
    /// cannot be sent and transport failures are not retried either. A read then takes at
    /// most `retries + 1` reply timeouts. Default: 0.
    pub fn with_retries(mut self, retries: u8) -> Self {
        self.retries = retries;
        self
    }

    /// States whether the line returns every request to the master (a half-duplex adapter
    /// that echoes what it sends): `Some(true)` skips that copy before the reply,
    /// `Some(false)` never looks for one. `None` (the default) detects it: the bytes
    /// identical to the request at the start of what comes back are skipped when a reply
    /// follows them or when they cannot be a reply; the first replies teach the master
    /// which kind of line it is on. Until then, a reply that is byte for byte the request
    /// (Modbus RTU answers writes of one register or coil so) is taken only at the reply
    /// deadline, when no second copy came. Once the line has shown an echo, a lone copy is
    /// taken for the echo of a request the drive did not answer (a timeout rather than a
    /// false success) until a reply that differs from its request, such as a read's, shows
    /// that the line no longer echoes.
    pub fn with_local_echo(mut self, echo: Option<bool>) -> Self {
        self.echo = echo;
        self.echo_fixed = echo.is_some();
        self
    }

    /// The bytes of the last reply taken as the answer (empty before the first). A text
    /// read's [`Answer::text`] is an offset and length within it, so tools that work with
    /// any drive read text this way.
    pub fn last_reply(&self) -> &[u8] {
        &self.reply[..self.reply_len.min(MAX_FRAME)]
    }

    /// The transport, e.g. to close it.
    pub fn into_transport(self) -> T {
        self.transport
    }

    /// The reply timeout for a request of `request_len` bytes: both frames' wire time, the
    /// drive's processing time, its wait before replying ([`Master::reply_delay`]) and the
    /// host latency.
    pub fn reply_timeout(&self, request_len: usize) -> Duration {
        self.timing.reply_timeout(
            &self.settings,
            request_len,
            usize::from(self.protocol.max_frame_len),
        ) + self.reply_delay()
            + self.reply_wait()
            + self.host_latency
    }

    /// Asks the drive to wait `wait` before each reply, in protocols whose requests carry
    /// a wait ([`Role::ReplyWait`], in tens of milliseconds: the Eaton protocol's wait-time
    /// digit, 0-150 ms; some RS-485 converters need the line turned round slowly). It is
    /// rounded up to 10 ms and kept within what the field can carry; the reply timeout
    /// grows by it. Protocols without such a field ignore it.
    pub fn with_reply_wait(mut self, wait: Duration) -> Self {
        let tens = wait.as_millis().div_ceil(10);
        let most = self
            .protocol
            .commands
            .iter()
            .filter_map(|c| c.request.field(Role::ReplyWait))
            .map(|field| field.format.max_value(field.width))
            .max()
            .unwrap_or(0);
        self.reply_wait = tens.min(u128::from(most)).min(255) as u8;
        self
    }

    /// The wait each reply is asked for ([`Master::with_reply_wait`]), where the protocol's
    /// requests carry one.
    pub fn reply_wait(&self) -> Duration {
        Duration::from_millis(10 * u64::from(self.reply_wait))
    }

    /// States the drive's wait before every reply, where registers of the drive set one
    /// (the protocol's [`crate::serial::ReplyDelay`]: VF-AS1 F805 / F825): it is added to
    /// every reply timeout. Without it the master takes the description's factory setting.
    pub fn with_reply_delay(mut self, delay: Duration) -> Self {
        self.reply_delay = Some(delay);
        self
    }

    /// The drive's wait before replying that the master allows for: the value stated or
    /// read, else the factory setting of the protocol's reply-delay registers (zero when
    /// the protocol has none).
    pub fn reply_delay(&self) -> Duration {
        self.reply_delay.unwrap_or_else(|| {
            self.protocol
                .timing
                .reply_delay
                .as_ref()
                .map_or(Duration::ZERO, |delay| delay.default)
        })
    }

    /// Reads the protocol's reply-delay registers (allowing the longest wait they can set
    /// while reading them) and from then on allows for the longest value read. Returns it;
    /// zero, without an exchange, when the protocol has no such register.
    pub fn read_reply_delay(&mut self) -> Result<Duration, TransactionError> {
        let Some(delay) = self.protocol.timing.reply_delay.clone() else {
            return Ok(Duration::ZERO);
        };
        let before = self.reply_delay;
        self.reply_delay = Some(delay.max);
        let mut longest = Duration::ZERO;
        for register in delay.registers.iter() {
            let request = Request::raw(CommandKind::Read, *register, 0);
            match self.transact(&request) {
                Ok(answer) => longest = longest.max(delay.of_raw(answer.data.unwrap_or(0))),
                Err(error) => {
                    self.reply_delay = before;
                    return Err(error);
                }
            }
        }
        self.reply_delay = Some(longest);
        Ok(longest)
    }

    /// How long after a timeout a late reply may still arrive: the longest frame's wire
    /// time and the host latency.
    fn late_reply_window(&self) -> Duration {
        self.settings
            .wire_time(usize::from(self.protocol.max_frame_len))
            + self.frame_gap()
            + self.host_latency
    }

    /// The silence kept between frames: the protocol's gap in character times (Modbus
    /// RTU: 3.5), or the drive's floor in milliseconds where that is longer (DV1 Modbus
    /// RTU: 10 ms; VF-AS1: 2 ms).
    pub fn frame_gap(&self) -> Duration {
        self.settings
            .char_time()
            .mul_f32(self.protocol.frame_gap_chars)
            .max(self.protocol.timing.frame_gap_min)
    }

    /// The longest silence a frame may hold, from the protocol's timing (the frame gap): a
    /// longer one inside a reply starts a new frame. `None` when the protocol states no
    /// gap.
    pub fn silence_limit(&self) -> Option<Duration> {
        let gap = self.frame_gap();
        (!gap.is_zero()).then_some(gap)
    }

    /// Reads register `R`: its typed value, and whether the reply said the drive is tripped.
    pub fn read<R: Register<Drive = D>>(&mut self) -> Result<Reading<R::Value>, TransactionError> {
        let request = Request::read::<R>();
        let answer = self.transact(&request)?;
        Self::value_read::<R>(&request, answer)
    }

    /// Reads register `R` with the command whose code is `code` (a letter as a number,
    /// `u32::from(b'G')`), where the protocol has several read commands (the Toshiba
    /// binary G besides R). Fails before sending when the drive's protocol has no such
    /// read ([`EncodeError::NoSuchCommand`]).
    pub fn read_using<R: Register<Drive = D>>(
        &mut self,
        code: u32,
    ) -> Result<Reading<R::Value>, TransactionError> {
        let request = Request::read::<R>().using(code);
        let answer = self.transact(&request)?;
        Self::value_read::<R>(&request, answer)
    }

    /// Sends `value` for register `R` with the command `code` whose data is a percentage of
    /// register `F`'s value ([`crate::protocol::PercentOf`]; the Toshiba drive-to-drive S
    /// command: frequency in 0.01 % of the maximum frequency FH), `reference` being the
    /// sender's value of `F` (100 %). The percentage is truncated as the manuals do; no
    /// other range is checked (the drive checks none). A command that gets no reply
    /// returns once the frame is on the line. Returns the raw word sent.
    pub fn write_percent_of<R: Writable<Drive = D>, F: Register<Drive = D>>(
        &mut self,
        code: u32,
        value: R::Value,
        reference: F::Value,
    ) -> Result<u32, TransactionError> {
        let protocol = self.protocol;
        let command = protocol
            .commands
            .iter()
            .find(|c| c.answers_to(code) && c.percent_of.is_some());
        let Some((command, percent_of)) =
            command.and_then(|c| c.percent_of.as_ref().map(|p| (c, p)))
        else {
            let request = Request::for_register(CommandKind::WriteRam, R::INFO, 0).using(code);
            return Err(TransactionError::new(
                Some(&request),
                TransactionErrorKind::Encode(EncodeError::NoSuchCommand {
                    protocol: protocol.id.clone(),
                    code,
                    kind: CommandKind::WriteRam,
                }),
            ));
        };
        let request = Request::for_register(command.kind, R::INFO, 0).using(code);
        if percent_of.register != F::INFO.code && percent_of.register != F::INFO.id {
            return Err(TransactionError::new(
                Some(&request),
                TransactionErrorKind::Encode(EncodeError::NotPercentOf {
                    protocol: protocol.id.clone(),
                    code,
                    register: F::INFO.code,
                }),
            ));
        }
        let value = engineering(value.to_raw(R::INFO)?, R::INFO);
        let reference = engineering(reference.to_raw(F::INFO)?, F::INFO);
        let raw = percent_of
            .to_raw(value, reference)
            .ok_or(ValueError::NotAPercentage {
                register: R::INFO,
                value,
                reference,
            })?;
        self.transact(&Request {
            data: raw,
            ..request
        })?;
        Ok(raw)
    }

    /// Reads element `index` of the array register `R`. Refuses indexes beyond the array.
    pub fn read_at<R: Register<Drive = D>>(
        &mut self,
        index: u16,
    ) -> Result<Reading<R::Value>, TransactionError> {
        let request = Request::read::<R>().at_index(index)?;
        let answer = self.transact(&request)?;
        Self::value_read::<R>(&request, answer)
    }

    /// The typed value a read reply carries; a reply without data does not answer a read.
    fn value_read<R: Register>(
        request: &Request,
        answer: Answer,
    ) -> Result<Reading<R::Value>, TransactionError> {
        let data = answer.data.ok_or_else(|| {
            TransactionError::new(
                Some(request),
                TransactionErrorKind::Mismatch {
                    field: ReplyField::Data,
                    expected: 1,
                    found: 0,
                },
            )
        })?;
        // A reply stating its decimals (checked against the register's scales) picks the
        // scale of a register whose scale another register chooses.
        let info = match answer.decimals {
            Some(decimals) => for_decimals(R::INFO, decimals)?,
            None => R::INFO,
        };
        Ok(Reading {
            value: R::Value::from_raw(data, info)?,
            tripped: answer.tripped,
        })
    }

    /// Reads the text register `R` (text parameters such as an ordering number).
    pub fn read_text<R: Register<Drive = D>>(&mut self) -> Result<String, TransactionError> {
        let answer = self.transact(&Request::read::<R>())?;
        let (start, len) = answer.text.unwrap_or((0, 0));
        Ok(String::from_utf8_lossy(&self.reply[start..start + len]).into_owned())
    }

    /// Writes `value` to register `R` in RAM only. Returns the value the drive reports
    /// written (its echo), or `None` when the protocol's reply carries no data. On a drive
    /// whose own register chooses where parameter writes go (DV1 07-11), the master sets it
    /// to RAM only first (see [`Master::persistence_selector`]).
    pub fn write_ram<R: Writable<Drive = D>>(
        &mut self,
        value: R::Value,
    ) -> Result<Option<R::Value>, TransactionError> {
        let answer = self.transact(&Request::write_ram::<R>(value)?)?;
        self.written::<R>(answer)
    }

    /// Writes `value` to element `index` of the array register `R` in RAM only. Returns
    /// the value the drive reports written, if its reply carries one.
    pub fn write_ram_at<R: Writable<Drive = D>>(
        &mut self,
        index: u16,
        value: R::Value,
    ) -> Result<Option<R::Value>, TransactionError> {
        let answer = self.transact(&Request::write_ram::<R>(value)?.at_index(index)?)?;
        self.written::<R>(answer)
    }

    /// Writes `value` to register `R` in RAM and EEPROM (persistent; EEPROM wears out).
    /// Returns the value the drive reports written, if its reply carries one. On a drive
    /// whose own register chooses where parameter writes go (DV1 07-11), the master sets it
    /// to RAM and EEPROM around the write and back (see [`Master::persistence_selector`]).
    pub fn write_persistent<R: Persistable<Drive = D>>(
        &mut self,
        value: R::Value,
    ) -> Result<Option<R::Value>, TransactionError> {
        let answer = self.transact(&Request::write_persistent::<R>(value)?)?;
        self.written::<R>(answer)
    }

    /// Writes `value` to element `index` of the array register `R` in RAM and EEPROM
    /// (persistent; EEPROM wears out). Returns the value the drive reports written, if its
    /// reply carries one.
    pub fn write_persistent_at<R: Persistable<Drive = D>>(
        &mut self,
        index: u16,
        value: R::Value,
    ) -> Result<Option<R::Value>, TransactionError> {
        let request = Request::write_persistent::<R>(value)?.at_index(index)?;
        let answer = self.transact(&request)?;
        self.written::<R>(answer)
    }

    fn written<R: Register>(&self, answer: Answer) -> Result<Option<R::Value>, TransactionError> {
        Ok(answer
            .data
            .map(|data| R::Value::from_raw(data, R::INFO))
            .transpose()?)
    }

    /// Sends process words (control word, reference) and returns those the drive answers
    /// with (status word, output value).
    pub fn exchange_process(
        &mut self,
        control: u16,
        reference: u16,
    ) -> Result<[u16; 2], TransactionError> {
        let request = Request::process(control, reference);
        let answer = self.transact(&request)?;
        answer.process.ok_or_else(|| {
            TransactionError::new(
                Some(&request),
                TransactionErrorKind::Mismatch {
                    field: ReplyField::ProcessWords,
                    expected: 2,
                    found: 0,
                },
            )
        })
    }

    /// A diagnostic echo (Modbus 08, sub-function 0000h): sends `data` and returns what the
    /// drive sends back, which must be the same (a reply carrying other data answers another
    /// request). Refused before anything is sent when the protocol has no echo command.
    pub fn echo(&mut self, data: u16) -> Result<u16, TransactionError> {
        let mut request = Request::raw(CommandKind::Echo, 0, u32::from(data));
        request.wire_register = true;
        request.command = self
            .protocol
            .commands
            .iter()
            .find(|c| c.kind == CommandKind::Echo)
            .map(|c| c.code);
        let answer = self.transact(&request)?;
        Ok(answer.data.map_or(data, |d| d as u16))
    }

    /// Reads `words.len()` consecutive 16-bit registers of the parameter space, from
    /// register `start` (its number before the protocol's address map), in one exchange
    /// where the protocol's read command counts its data (Modbus 03: its quantity), at most
    /// [`Protocol::max_words_per_read`] of them. Each word is taken in the byte order of
    /// the reply's data field; a double-word register fills two (see
    /// [`Master::join_words`]). A protocol that reads one register at a time refuses more
    /// than one, before anything is sent. Returns what the reply said besides.
    pub fn read_words(
        &mut self,
        start: u16,
        words: &mut [u16],
    ) -> Result<Answer, TransactionError> {
        let request = Request::raw(CommandKind::Read, start, 0);
        let protocol = self.protocol;
        let max = if protocol.block_read_command(Space::Parameter).is_some() {
            protocol.max_words_per_read
        } else {
            1
        };
        if words.is_empty() || words.len() > usize::from(max) {
            return Err(TransactionError::new(
                Some(&request),
                TransactionErrorKind::Encode(EncodeError::TooManyWords {
                    protocol: protocol.id.clone(),
                    words: words.len(),
                    max,
                }),
            ));
        }
        if words.len() == 1 {
            let answer = self.transact(&request)?;
            words[0] = answer.data.map(|d| d as u16).ok_or_else(|| {
                TransactionError::new(
                    Some(&request),
                    TransactionErrorKind::Mismatch {
                        field: ReplyField::Data,
                        expected: 1,
                        found: 0,
                    },
                )
            })?;
            return Ok(answer);
        }
        self.block_words = words.len() as u16;
        let outcome = self.exchange_block(&request);
        self.block_words = 0;
        let answer = outcome?;
        let little_endian = self.block_little_endian();
        // Two words fit a number: the data field's bytes again, in its byte order.
        let number = match answer.data {
            Some(data) if little_endian => data.to_le_bytes(),
            Some(data) => data.to_be_bytes(),
            None => [0; 4],
        };
        let bytes = match (answer.block, answer.data) {
            (Some((offset, len)), _) => self.reply.get(offset..offset + len).unwrap_or(&[]),
            (None, Some(_)) => {
                if little_endian {
                    &number[..4]
                } else {
                    &number[4usize.saturating_sub(words.len() * 2)..]
                }
            }
            (None, None) => &[],
        };
        // Blocks written as hex digits (Modbus ASCII): two digits per byte.
        let mut digits = [0u8; 2 * 125];
        let hex = protocol
            .block_read_command(Space::Parameter)
            .is_some_and(|c| c.reply.encoding == crate::layout::Encoding::HexPairs);
        let bytes = if hex && answer.block.is_some() {
            let n = crate::codec::hex_digits_to_bytes(bytes, &mut digits);
            &digits[..n]
        } else {
            bytes
        };
        for (word, pair) in words.iter_mut().zip(bytes.chunks_exact(2)) {
            let pair = [pair[0], pair[1]];
            *word = if little_endian {
                u16::from_le_bytes(pair)
            } else {
                u16::from_be_bytes(pair)
            };
        }
        Ok(answer)
    }

    /// Writes `words` to consecutive 16-bit registers of the parameter space, from register
    /// `start` (its number before the protocol's address map), in one exchange where the
    /// protocol has a write command whose data field is sized by a length part (Modbus 10h:
    /// its quantity and byte count), at most [`Protocol::max_words_per_write`] of them
    /// (the DV1: 12). Each word goes in the byte order of the request's data field; a
    /// double-word register takes two (Modbus: the high word first). One word is written
    /// with the protocol's ordinary RAM write. Too many words, none, or more than one on a
    /// protocol that writes one register at a time, is refused before anything is sent.
    /// Not repeated on failure (it writes). Returns what the reply said besides.
    pub fn write_words(&mut self, start: u16, words: &[u16]) -> Result<Answer, TransactionError> {
        let mut request = Request::raw(CommandKind::WriteRam, start, 0);
        let protocol = self.protocol;
        let command = protocol.block_write_command(Space::Parameter);
        let max = if command.is_some() {
            protocol.max_words_per_write
        } else {
            1
        };
        let too_many = |request: &Request| {
            TransactionError::new(
                Some(request),
                TransactionErrorKind::Encode(EncodeError::TooManyWordsToWrite {
                    protocol: protocol.id.clone(),
                    words: words.len(),
                    max,
                }),
            )
        };
        if words.is_empty() || words.len() > usize::from(max) {
            return Err(too_many(&request));
        }
        if let [only] = *words {
            request.data = u32::from(only);
            return self.transact(&request);
        }
        let Some(command) = command else {
            return Err(too_many(&request));
        };
        request.command = Some(command.code);
        if let [first, second] = *words {
            // Two words are a number, as a double-word register's write carries them.
            request.data_type = DataType::DoubleWord;
            request.data = if self.block_write_little_endian(command) {
                u32::from(first) | (u32::from(second) << 16)
            } else {
                (u32::from(first) << 16) | u32::from(second)
            };
        }
        let list = crate::codec::Words::from_slice(words).ok_or_else(|| too_many(&request))?;
        self.block_write = Some(list);
        let outcome = self.exchange_block(&request);
        self.block_write = None;
        outcome
    }

    /// Whether a block write's data field is least significant byte first.
    fn block_write_little_endian(&self, command: &CommandSpec) -> bool {
        command
            .request
            .field(Role::Data)
            .is_some_and(|field| field.format == crate::layout::Format::UintLe)
    }

    /// The value of a register `words.len()` words wide (1 or 2) that [`Master::read_words`]
    /// returned, as a read of that register alone gives it (Modbus: the high word first).
    pub fn join_words(&self, words: &[u16]) -> u32 {
        let little_endian = self.block_little_endian();
        match *words {
            [only] => u32::from(only),
            [first, second] if little_endian => u32::from(first) | (u32::from(second) << 16),
            [first, second] => (u32::from(first) << 16) | u32::from(second),
            _ => 0,
        }
    }

    /// Runs one block transfer ([`CommandKind::Block`]): writes `writes` to the registers
    /// `selection` names for writing (word `n` to position `n`) and asks back `read_count`
    /// words, which come from the registers it names for reading. `selection` must be the
    /// drive's selection in force (from [`crate::protocol::BlockSpec::selection`] with the
    /// drive's current selector values, or [`crate::protocol::BlockSpec::default_selection`]
    /// for a drive in its factory state): the frame carries only the words, the drive
    /// decides where they go. More words than the selection has, or a protocol without a
    /// block transfer, is refused before anything is sent. Not repeated on failure (it
    /// writes). The exchange allocates nothing; the result's lists are allocated.
    pub fn block_transfer(
        &mut self,
        selection: &crate::protocol::BlockSelection,
        writes: &[u16],
        read_count: u8,
    ) -> Result<BlockTransfer, TransactionError> {
        let request = Request::raw(CommandKind::Block, 0, 0);
        let protocol = self.protocol;
        let refuse = |what: &'static str, words: usize, max: usize| {
            TransactionError::new(
                Some(&request),
                TransactionErrorKind::Encode(EncodeError::BlockTooLong {
                    protocol: protocol.id.clone(),
                    what,
                    words,
                    max,
                }),
            )
        };
        if protocol.block_command().is_none() {
            return Err(TransactionError::new(
                Some(&request),
                TransactionErrorKind::Encode(EncodeError::UnsupportedCommand {
                    protocol: protocol.id.clone(),
                    kind: CommandKind::Block,
                    space: Space::Parameter,
                    data_type: DataType::Word,
                }),
            ));
        }
        if writes.len() > selection.write.len() {
            return Err(refuse("writes", writes.len(), selection.write.len()));
        }
        if usize::from(read_count) > selection.read.len() {
            return Err(refuse(
                "reads",
                usize::from(read_count),
                selection.read.len(),
            ));
        }
        let words = crate::codec::Words::from_slice(writes)
            .ok_or_else(|| refuse("writes", writes.len(), crate::codec::MAX_WORDS))?;
        self.block_transfer = Some((words, read_count));
        let outcome = self.exchange(&request);
        self.block_transfer = None;
        let answer = outcome?;
        let bytes = answer
            .block
            .and_then(|(offset, len)| self.reply.get(offset..offset + len))
            .unwrap_or(&[]);
        let little_endian = self
            .protocol
            .block_command()
            .and_then(|command| command.reply.field(Role::Words))
            .is_some_and(|field| field.format == crate::layout::Format::U16Le);
        let read: Vec<u16> = bytes
            .chunks_exact(2)
            .map(|pair| {
                if little_endian {
                    u16::from_le_bytes([pair[0], pair[1]])
                } else {
                    u16::from_be_bytes([pair[0], pair[1]])
                }
            })
            .collect();
        if read.len() != usize::from(read_count) {
            return Err(TransactionError::new(
                Some(&request),
                TransactionErrorKind::Mismatch {
                    field: ReplyField::Data,
                    expected: u32::from(read_count),
                    found: read.len() as u32,
                },
            ));
        }
        Ok(BlockTransfer {
            reads: selection.read.iter().copied().zip(read).collect(),
            writes: selection.write[..writes.len()].to_vec(),
            write_status: answer.write_status.unwrap_or(0),
            tripped: answer.tripped,
        })
    }

    /// Whether the block read's data field is least significant byte first.
    fn block_little_endian(&self) -> bool {
        self.protocol
            .block_read_command(Space::Parameter)
            .and_then(|command| {
                command.reply.parts.iter().find_map(|part| match part {
                    crate::layout::Part::Field(field) if field.role == Role::Data => {
                        Some(field.format == crate::layout::Format::UintLe)
                    }
                    _ => None,
                })
            })
            .unwrap_or(false)
    }

    /// Runs one request, with any steps the protocol needs first (selecting an array
    /// index, choosing RAM or EEPROM, setting the drive's persistence selector around a
    /// write it governs: see [`Master::persistence_selector`]). Every frame is built and
    /// checked before the first is sent: when the protocol cannot carry any of them,
    /// nothing goes on the line.
    pub fn transact(&mut self, request: &Request) -> Result<Answer, TransactionError> {
        if let Some(selector) = self.governing_selector(request) {
            // A write whose storage a register of the drive chooses: see `persistence`.
            return self.transact_governed(request, selector);
        }
        let on_port;
        let request = match self.port {
            Some(port) => {
                on_port = port.map(*request);
                &on_port
            }
            None => request,
        };
        let protocol = self.protocol;
        let main = self.main_request(request);
        let page = self.page_step(request);
        for step in protocol.pre_steps.iter() {
            if let Some(step) = step_request(step, request) {
                self.check_encodes(&step, &step)?;
            }
        }
        if let Some((step, _)) = &page {
            self.check_encodes(step, request)?;
        }
        // Errors of the main request name the caller's request, not the adjusted one.
        self.check_encodes(&main, request)?;
        let outcome = self.run_steps(request, &main, page);
        if self.broadcast_to.is_some() {
            // Which drives took a broadcast page switch is not known.
            self.pages.clear();
        } else if outcome.is_err() || self.resets_page(request) {
            // A drive that refused, was not heard or was reset may be on any page now.
            self.remember_page(None);
        }
        outcome
    }

    /// The exchanges of [`Master::transact`] once every frame is known to encode: the
    /// protocol's steps, the page switch, then the request itself.
    fn run_steps(
        &mut self,
        request: &Request,
        main: &Request,
        page: Option<(Request, u16)>,
    ) -> Result<Answer, TransactionError> {
        for step in self.protocol.pre_steps.iter() {
            if let Some(step) = step_request(step, request) {
                self.exchange(&step)?;
            }
        }
        if let Some((step, number)) = page {
            // A failed page switch is reported as the caller's request failing (the page
            // register is not one the caller named).
            self.exchange(&step).map_err(|error| TransactionError {
                request: Some(*request),
                ..error
            })?;
            self.remember_page(Some(number));
        }
        self.exchange(main).map_err(|error| TransactionError {
            request: Some(*request),
            ..error
        })
    }

    /// A block request (several registers in one exchange) with the page switch its first
    /// register needs first, as [`Master::transact`] makes it; the page is forgotten when
    /// anything fails.
    fn exchange_block(&mut self, request: &Request) -> Result<Answer, TransactionError> {
        let page = self.page_step(request);
        if let Some((step, _)) = &page {
            self.check_encodes(step, request)?;
        }
        let outcome = (|| {
            if let Some((step, number)) = page {
                self.exchange(&step).map_err(|error| TransactionError {
                    request: Some(*request),
                    ..error
                })?;
                self.remember_page(Some(number));
            }
            self.exchange(request)
        })();
        if outcome.is_err() {
            self.remember_page(None);
        }
        outcome
    }

    /// The page switch `request` needs first, with the page it selects: `None` when the
    /// register is not paged on this protocol, or its station is known to be on its page.
    fn page_step(&self, request: &Request) -> Option<(Request, u16)> {
        let paging = self.protocol.paging.as_ref()?;
        if request.wire_register || request.space != Space::Parameter {
            return None;
        }
        let (page, _) = self.protocol.page_of(request.register)?;
        if self.broadcast_to.is_none() && self.known_page(self.address) == Some(page) {
            return None;
        }
        // The page register's own type picks the command (a byte command's narrower layout
        // where the drive takes two data digits): its plain write, else its only write.
        let data_type = paging.select_data_type;
        let kind = [CommandKind::WriteRam, CommandKind::WritePersistent]
            .into_iter()
            .find(|kind| {
                self.protocol
                    .command_for(*kind, Space::Parameter, data_type)
                    .is_some()
            })
            .unwrap_or(CommandKind::WriteRam);
        let step = Request {
            wire_register: true,
            data_type,
            ..Request::raw(kind, paging.select_write, u32::from(page))
        };
        Some((step, page))
    }

    /// Whether `request` resets the drive's page ([`crate::protocol::Paging::forgotten_after`]).
    fn resets_page(&self, request: &Request) -> bool {
        request.kind.is_write()
            && !request.wire_register
            && self
                .protocol
                .paging
                .as_ref()
                .is_some_and(|p| p.forgotten_after.contains(&request.register))
    }

    /// `request` as sent once the protocol's steps have selected what it leaves out.
    fn main_request(&self, request: &Request) -> Request {
        let mut main = *request;
        if self.has_index_step() {
            main.index = None;
        }
        if self.has_persistence_step()
            && request.kind == CommandKind::WritePersistent
            && request.space == Space::Parameter
        {
            main.kind = CommandKind::WriteRam;
        }
        main
    }

    /// Builds `request`'s frame without sending it; a failure names `named`.
    fn check_encodes(
        &mut self,
        request: &Request,
        named: &Request,
    ) -> Result<(), TransactionError> {
        self.protocol
            .encode_request(request, self.address, &mut self.request)
            .map(|_| ())
            .map_err(|error| {
                TransactionError::new(Some(named), TransactionErrorKind::Encode(error))
            })
    }

    fn has_index_step(&self) -> bool {
        self.protocol
            .pre_steps
            .iter()
            .any(|s| matches!(s, PreStep::Index { .. }))
    }

    fn has_persistence_step(&self) -> bool {
        self.protocol
            .pre_steps
            .iter()
            .any(|s| matches!(s, PreStep::Persistence { .. }))
    }

    /// One request, repeated as [`Master::with_retries`] allows.
    fn exchange(&mut self, request: &Request) -> Result<Answer, TransactionError> {
        let mut retries = if request.kind.only_reads() {
            self.retries
        } else {
            0
        };
        let follow_up = self
            .protocol
            .command_for_request(request)
            .ok()
            .and_then(|command| command.follow_up.as_ref());
        let mut ask_again = false;
        loop {
            match self.exchange_once(request, ask_again) {
                Err(error) if retries > 0 && error.kind.worth_repeating() => {
                    retries -= 1;
                    // A garbled reply to a command with a follow-up is asked for again
                    // (the drive repeats it); anything else is sent again.
                    ask_again = follow_up.is_some() && error.kind.garbled_reply();
                }
                Ok(answer) => {
                    if let Some(follow_up) = follow_up {
                        self.send_follow_up(follow_up, true)
                            .map_err(|kind| TransactionError::new(Some(request), kind))?;
                    }
                    return Ok(answer);
                }
                outcome => return outcome,
            }
        }
    }

    /// Sends the master's answer to a reply ([`crate::protocol::FollowUp`]): nothing comes
    /// back, so it is done once the frame is on the line and the gap kept.
    fn send_follow_up(
        &mut self,
        follow_up: &crate::protocol::FollowUp,
        sound: bool,
    ) -> Result<(), TransactionErrorKind> {
        let len = follow_up
            .encode(sound, self.address, &mut self.request)
            .map_err(TransactionErrorKind::Encode)?;
        self.keep_frame_gap();
        let sent = Instant::now();
        self.transport
            .send(&self.request[..len])
            .map_err(TransactionErrorKind::Io)?;
        self.wait_on_line(sent, len);
        Ok(())
    }

    /// Sleeps until the frame gap since the last activity on the line has passed.
    fn keep_frame_gap(&self) {
        if let Some(last) = self.last_activity {
            let gap = self.frame_gap();
            let since = last.elapsed();
            if since < gap {
                std::thread::sleep(gap - since);
            }
        }
    }

    /// Waits until a frame of `len` bytes sent at `sent` is on the line and the frame gap
    /// after it has passed. The line's last activity is the frame's end, so the next frame
    /// does not keep the gap a second time.
    fn wait_on_line(&mut self, sent: Instant, len: usize) {
        let on_line = sent + self.settings.wire_time(len);
        let done = on_line + self.frame_gap();
        let now = Instant::now();
        if now < done {
            std::thread::sleep(done - now);
        }
        self.last_activity = Some(on_line.min(Instant::now()));
    }

    /// Whether the bytes so far cannot begin the protocol's error reply (a Modbus reply
    /// whose function code lacks the exception bit), so that only the command's own reply
    /// can still come: the read-ahead may then wait for all of its bytes. Only on a line
    /// known not to echo, where the reply starts at the first byte; a wrong guess (noise
    /// before an error reply) costs at most a longer wait within the deadline, never a
    /// decision, which is taken on the bytes.
    fn error_reply_ruled_out(&self, reading: &Collecting<'_>) -> bool {
        if self.echo != Some(false) || reading.filled == 0 {
            return false;
        }
        self.protocol.error_reply.as_ref().is_some_and(|error| {
            crate::codec::decode_prefix(error, &self.reply[..reading.filled]).is_err()
        })
    }

    /// Drops what arrived before the request: what the transport can clear, then whatever
    /// it still holds (a bounded amount, so a line full of noise cannot keep it here).
    fn discard_stale_input(&mut self) -> std::io::Result<()> {
        // After a timeout, a late reply may still be on its way: wait for it (or for the
        // window to pass) and drop it, so that it is not taken for the next reply.
        if let Some(until) = self.late_reply_until.take() {
            let mut dropped = 0usize;
            while Instant::now() < until && dropped < 4 * MAX_FRAME {
                let got = self.transport.receive(&mut self.reply, until)?;
                if got == 0 {
                    break;
                }
                dropped += got;
            }
        }
        self.transport.clear_input()?;
        let now = Instant::now();
        let mut dropped = 0usize;
        while dropped < 4 * MAX_FRAME {
            let got = self.transport.receive(&mut self.reply, now)?;
            if got == 0 {
                break;
            }
            dropped += got;
        }
        Ok(())
    }

    /// One request frame, one reply frame. `ask_again`: in place of the request, the
    /// command's follow-up asking for the last reply again.
    fn exchange_once(
        &mut self,
        request: &Request,
        ask_again: bool,
    ) -> Result<Answer, TransactionError> {
        let protocol = self.protocol;
        let fail = |kind| TransactionError::new(Some(request), kind);
        let io = |error| fail(TransactionErrorKind::Io(error));
        let cannot_send = |error| fail(TransactionErrorKind::Encode(error));
        let command = protocol.command_for_request(request).map_err(cannot_send)?;
        let len = if let (true, Some(follow_up)) = (ask_again, &command.follow_up) {
            follow_up
                .encode(false, self.address, &mut self.request)
                .map_err(cannot_send)?
        } else if let Some((words, read_count)) = self.block_transfer {
            // A block transfer: the words to write and the count of words asked back.
            let (layout, mut values) = protocol
                .request_values(request, self.address)
                .map_err(cannot_send)?;
            values.set(layout, Role::ReadCount, u32::from(read_count));
            let mut payload = [0u8; 2 * crate::codec::MAX_WORDS];
            let size = words.write_payload(layout, &mut payload);
            crate::codec::encode_with_payload(layout, &values, &payload[..size], &mut self.request)
                .map_err(cannot_send)?
        } else if let Some(to) = self.broadcast_to {
            protocol
                .encode_broadcast(request, &to, &mut self.request)
                .map_err(cannot_send)?
        } else if let Some(words) = self.block_write {
            // A block write: the request counts the words it carries; more than two go in
            // its data field as a payload, each in the field's byte order.
            let (layout, mut values) = protocol
                .request_values(request, self.address)
                .map_err(cannot_send)?;
            let count = words.as_slice().len();
            values.data_size = (count * 2) as u8;
            let mut payload = [0u8; 2 * crate::codec::MAX_WORDS];
            let little_endian = self.block_write_little_endian(command);
            for (word, pair) in words.as_slice().iter().zip(payload.chunks_exact_mut(2)) {
                pair.copy_from_slice(&if little_endian {
                    word.to_le_bytes()
                } else {
                    word.to_be_bytes()
                });
            }
            let payload = if count > 2 {
                &payload[..count * 2]
            } else {
                &[]
            };
            crate::codec::encode_with_payload(layout, &values, payload, &mut self.request)
                .map_err(cannot_send)?
        } else if self.block_words > 1 {
            // A block read: the request counts the words it asks for.
            let (layout, mut values) = protocol
                .request_values(request, self.address)
                .map_err(cannot_send)?;
            values.data_size = (self.block_words * 2).min(u16::from(u8::MAX)) as u8;
            crate::codec::encode(layout, &values, &mut self.request).map_err(cannot_send)?
        } else if self.reply_wait > 0 && command.request.has(Role::ReplyWait) {
            // The wait the master asks for, in the request's wait field.
            let (layout, mut values) = protocol
                .request_values(request, self.address)
                .map_err(cannot_send)?;
            values.set(layout, Role::ReplyWait, u32::from(self.reply_wait));
            crate::codec::encode(layout, &values, &mut self.request).map_err(cannot_send)?
        } else {
            protocol
                .encode_request(request, self.address, &mut self.request)
                .map_err(cannot_send)?
        };
        let expectation = Expectation {
            address: self.address,
            wire_register: if request.wire_register {
                Some(request.register)
            } else {
                protocol.to_wire(command, request.register)
            },
            index: request.index,
            data: request.kind.reports_data().then(|| {
                let mask = match request.data_type.size() {
                    0 => 0,
                    bytes @ 1..=3 => (1u32 << (8 * u32::from(bytes))) - 1,
                    _ => u32::MAX,
                };
                (request.data, mask)
            }),
            // A block read asks for its words; a single read for its data type's size.
            data_size: if self.block_words > 1 {
                Some((self.block_words * 2).min(u16::from(u8::MAX)) as u8)
            } else if let Some(words) = self.block_write {
                // A block write's reply repeats the count of registers written.
                Some((words.as_slice().len() * 2) as u8)
            } else {
                (request.kind.only_reads() && request.data_type.size() > 0)
                    .then_some(request.data_type.size())
            },
        };
        self.keep_frame_gap();
        self.discard_stale_input().map_err(io)?;
        let sent = Instant::now();
        self.transport.send(&self.request[..len]).map_err(io)?;
        if unanswered(command, request) {
            // Nothing comes back: done once the frame is on the line and the gap kept.
            self.wait_on_line(sent, len);
            self.reply_len = 0;
            return Ok(Answer {
                data: None,
                tripped: false,
                process: None,
                text: None,
                block: None,
                write_status: None,
                decimals: None,
            });
        }
        let timeout = self.reply_timeout(len);
        let deadline = Instant::now() + timeout;
        let silence_limit = self.silence_limit();
        let shortest = shortest_reply(protocol, command);
        let mut reading = Collecting {
            request,
            command,
            expectation,
            request_len: len,
            filled: 0,
            echo_passed: false,
            fallback: None,
            copy_fallback: false,
            corrupt: None,
            foreign: None,
            last_error: None,
            block_size: usize::from(self.block_words) * 2,
        };
        loop {
            // The deadline bounds the loop, however readily the transport delivers bytes.
            if Instant::now() >= deadline {
                return self.out_of_time(reading, timeout);
            }
            if reading.filled == self.reply.len() {
                // Only noise could fill the buffer: keep the last half and go on looking.
                self.reply.copy_within(MAX_FRAME / 2.., 0);
                reading.filled = MAX_FRAME - MAX_FRAME / 2;
                reading.echo_passed = true;
            }
            let got = self
                .transport
                .receive(&mut self.reply[reading.filled..], deadline)
                .map_err(io)?;
            if got == 0 {
                // A transport returns nothing only once the deadline has passed.
                return self.out_of_time(reading, timeout);
            }
            self.last_activity = Some(Instant::now());
            if let (Some(limit), Some(gap)) = (silence_limit, self.transport.last_gap()) {
                if reading.filled > 0 && gap > limit {
                    // A silence no frame holds: what came before is not part of the reply
                    // (a false start, noise, our own echo).
                    let filled = reading.filled;
                    self.reply.copy_within(filled..filled + got, 0);
                    reading.filled = 0;
                    reading.echo_passed = true;
                }
            }
            reading.filled += got;
            if let Some(outcome) = self.settle(&mut reading) {
                return outcome;
            }
            self.read_ahead(&reading, shortest, deadline);
        }
    }

    /// While a reply is incomplete, sleeps until nearly all the bytes it still needs at the
    /// least can have arrived ([`read_ahead_wait`]), so that a line delivering a byte at a
    /// time (a UART, a paced link) does not wake the master for every byte. Neither a reply
    /// nor an error reply is shorter than `shortest` (plus the echo of the request, where
    /// the line is known to echo), and bytes cannot cross the line faster than one a
    /// character time. Once the error reply is ruled out it waits for the reply's expected
    /// size: a shorter frame (another station's, noise) is then looked at up to that many
    /// characters later. The wait never passes the deadline and never changes a decision,
    /// which is taken on the bytes. Not done
    /// on a transport that reports the silence before what it delivers (the master splits
    /// frames at such a silence, which a batch of bytes would hide).
    fn read_ahead(&self, reading: &Collecting<'_>, shortest: usize, deadline: Instant) {
        if self.transport.last_gap().is_some() {
            return;
        }
        let echo = if self.echo == Some(true) && !reading.echo_passed {
            reading.request_len
        } else {
            0
        };
        let shortest = if self.error_reply_ruled_out(reading) {
            let data = reading.expectation.data_size.map_or(0, usize::from);
            shortest_frame_holding(&reading.command.reply, data)
        } else {
            shortest
        };
        let needed = (shortest + echo).saturating_sub(reading.filled);
        if let Some(wait) =
            read_ahead_wait(needed, self.settings.char_time(), Instant::now(), deadline)
        {
            std::thread::sleep(wait);
        }
    }

    /// Looks at the bytes received so far: `Some` when the exchange is decided.
    fn settle(&mut self, reading: &mut Collecting<'_>) -> Option<Result<Answer, TransactionError>> {
        let (filled, len) = (reading.filled, reading.request_len);
        let shared = filled.min(len);
        let echo_possible = !reading.echo_passed
            && self.echo != Some(false)
            && self.reply[..shared] == self.request[..shared];
        if !echo_possible {
            let search = self.search(reading, 0, filled);
            if !reading.echo_passed
                && search
                    .found
                    .as_ref()
                    .is_some_and(|(_, skipped)| *skipped == 0)
            {
                // The first bytes back are a reply, not our request: the line does not echo.
                self.learn_echo(false);
            }
            return self.decide(reading, search, 0);
        }
        if filled < len {
            // Perhaps our own request coming back: wait for the rest of it (or, should these
            // bytes be a whole reply after all, for the deadline).
            let found = self
                .echo
                .is_none()
                .then(|| self.search(reading, 0, filled).found)
                .flatten();
            if let Some((frame, skipped)) = found {
                reading.fallback = Some(
                    check_reply(reading.request, reading.block_size, frame).map(|answer| Answer {
                        text: answer.text.map(|(start, len)| (start + skipped, len)),
                        block: answer.block.map(|(start, len)| (start + skipped, len)),
                        ..answer
                    }),
                );
            }
            return None;
        }
        // A whole copy of the request. Is it a reply too (Modbus answers a single write with
        // the request's own bytes)?
        let copy = self
            .search(reading, 0, len)
            .found
            .filter(|(frame, skipped)| *skipped == 0 && frame.len() == len)
            .map(|(frame, _)| check_reply(reading.request, reading.block_size, frame));
        let after = (filled > len).then(|| self.search(reading, len, filled));
        let Some(copy) = copy else {
            // It cannot be a reply: it is our own request coming back.
            self.learn_echo(true);
            return after.and_then(|search| self.decide(reading, search, len));
        };
        if let Some(search) = after {
            if search.found.is_some() || search.corrupt.is_some() || search.foreign.is_some() {
                // A frame follows the copy: the copy was our own request coming back.
                self.learn_echo(true);
                return self.decide(reading, search, len);
            }
            if self.echo == Some(true) || search.waiting {
                reading.fallback = reading.fallback.take().or(match self.echo {
                    Some(true) => None,
                    _ => Some(copy),
                });
                return self.decide(reading, search, len);
            }
            if self.echo == Some(false) {
                // Noise after a reply on a line that does not echo.
                return Some(copy);
            }
        }
        match self.echo {
            // The line does not echo: the copy is the reply.
            Some(false) => Some(copy),
            // It does: the reply is still to come.
            Some(true) => None,
            // Not known yet: the copy answers only if no second one comes by the deadline.
            None => {
                if reading.fallback.is_none() {
                    reading.fallback = Some(copy);
                    reading.copy_fallback = true;
                }
                None
            }
        }
    }

    /// Searches `self.reply[from..to]` for the reply.
    fn search(&self, reading: &Collecting<'_>, from: usize, to: usize) -> Search<'static> {
        self.protocol
            .search_reply(reading.command, &reading.expectation, &self.reply[from..to])
    }

    /// What a search over the bytes after `base` means for the exchange: `Some` when it is
    /// decided, `None` to read on (remembering what was seen, for the deadline).
    fn decide(
        &mut self,
        reading: &mut Collecting<'_>,
        search: Search<'static>,
        base: usize,
    ) -> Option<Result<Answer, TransactionError>> {
        if let Some((frame, skipped)) = search.found {
            let answer =
                check_reply(reading.request, reading.block_size, frame).map(|answer| Answer {
                    text: answer
                        .text
                        .map(|(start, len)| (start + base + skipped, len)),
                    block: answer
                        .block
                        .map(|(start, len)| (start + base + skipped, len)),
                    ..answer
                });
            if search.waiting {
                // A frame that would answer may start inside this one: read on a little.
                reading.fallback = Some(answer);
                return None;
            }
            self.reply_len = reading.filled;
            return Some(answer);
        }
        reading.corrupt = reading.corrupt.take().or(search.corrupt);
        reading.foreign = reading.foreign.or(search.foreign);
        if search.last_error.is_some() {
            reading.last_error = search.last_error;
        }
        if search.waiting {
            return None;
        }
        // Nothing more can come of these bytes: a damaged frame decides now (the drive
        // answered, garbled). Noise, and a frame that answers something else (another
        // station's reply, a late reply to an earlier request), may still be followed by
        // the reply: the mismatch is reported at the deadline if nothing better comes.
        if let Some(error) = reading.corrupt.take() {
            return Some(Err(
                reading.fail(TransactionErrorKind::Decode(Box::new(error)))
            ));
        }
        None
    }

    /// The outcome at the reply deadline: the best answer held back, else what went wrong.
    fn out_of_time(
        &mut self,
        mut reading: Collecting<'_>,
        waited: Duration,
    ) -> Result<Answer, TransactionError> {
        if let Some(answer) = reading.fallback {
            if reading.copy_fallback {
                // Only the one copy came: the line does not echo.
                self.learn_echo(false);
            }
            self.reply_len = reading.filled;
            return answer;
        }
        let kind = if let Some(error) = reading.corrupt.take() {
            TransactionErrorKind::Decode(Box::new(error))
        } else if let Some(difference) = reading.foreign {
            mismatch_of(difference, reading.request)
        } else {
            let filled = reading.filled;
            self.late_reply_until = Some(Instant::now() + self.late_reply_window());
            TransactionErrorKind::Timeout {
                waited,
                received: self.reply[..filled.min(64)].to_vec(),
                received_len: filled,
                last_error: reading.last_error.take().map(Box::new),
            }
        };
        Err(reading.fail(kind))
    }

    /// Records what the latest reply showed about the line, unless the caller stated it.
    fn learn_echo(&mut self, echoes: bool) {
        if !self.echo_fixed {
            self.echo = Some(echoes);
        }
    }
}

/// The state of one exchange while its reply is read.
struct Collecting<'r> {
    request: &'r Request,
    command: &'static CommandSpec,
    expectation: Expectation,
    request_len: usize,
    /// Bytes in the reply buffer.
    filled: usize,
    /// Bytes were dropped since the request went out: no echo can be ahead any more.
    echo_passed: bool,
    /// An answer to give at the deadline if no better one comes.
    fallback: Option<Result<Answer, TransactionError>>,
    /// The fallback is a copy of the request on a line not known to echo.
    copy_fallback: bool,
    /// A frame whose checksum did not match.
    corrupt: Option<DecodeError>,
    /// A frame that answered something else.
    foreign: Option<Difference>,
    /// The furthest decode error seen.
    last_error: Option<DecodeError>,
    /// Bytes of data a block read expects (0: an ordinary request).
    block_size: usize,
}

impl Collecting<'_> {
    fn fail(&self, kind: TransactionErrorKind) -> TransactionError {
        TransactionError::new(Some(self.request), kind)
    }
}

/// The fewest bytes a frame of `layout` can have: its parts of fixed size (a part whose
/// size depends on the frame counts as none), with every byte between the first and last
/// part written as two digits in a hex-pairs layout.
fn shortest_frame(layout: &crate::layout::FrameLayout) -> usize {
    shortest_frame_holding(layout, 0)
}

/// [`shortest_frame`], with a data field whose size depends on the frame counted as
/// `data` bytes (what the request asked for: a Modbus 03 reply to a read of one word
/// holds 2).
fn shortest_frame_holding(layout: &crate::layout::FrameLayout, data: usize) -> usize {
    let data_index = layout.index_of(Role::Data);
    let sizes = || {
        layout.parts.iter().enumerate().map(move |(index, part)| {
            part.fixed_size()
                .unwrap_or(if Some(index) == data_index { data } else { 0 })
        })
    };
    let total: usize = sizes().sum();
    match layout.encoding {
        crate::layout::Encoding::HexPairs if layout.parts.len() >= 2 => {
            let ends = sizes().next().unwrap_or(0) + sizes().next_back().unwrap_or(0);
            ends + 2 * (total - ends)
        }
        _ => total,
    }
}

/// The fewest bytes any answer to `command` can have: its reply or the protocol's error
/// reply, whichever can be shorter.
fn shortest_reply(protocol: &Protocol, command: &CommandSpec) -> usize {
    let reply = shortest_frame(&command.reply);
    protocol
        .error_reply
        .as_ref()
        .map_or(reply, |error| reply.min(shortest_frame(error)))
}

/// How long to wait at `now` for `needed` more bytes of `char_time` each before reading
/// again: one character less than they take, so the wait ends before the last of them can
/// have arrived even when the master woke up to a character late for the bytes it has;
/// never past `deadline`. `None` when fewer than two are needed (reading at once costs no
/// more).
fn read_ahead_wait(
    needed: usize,
    char_time: Duration,
    now: Instant,
    deadline: Instant,
) -> Option<Duration> {
    if needed < 2 {
        return None;
    }
    let wait = char_time
        .saturating_mul(u32::try_from(needed - 1).unwrap_or(u32::MAX))
        .min(deadline.saturating_duration_since(now));
    (!wait.is_zero()).then_some(wait)
}

/// The mismatch error for a frame that answers something else than `request`.
fn mismatch_of(difference: Difference, request: &Request) -> TransactionErrorKind {
    TransactionErrorKind::Mismatch {
        field: match difference.role {
            Role::Address => ReplyField::Address,
            Role::Index => ReplyField::Index,
            Role::Data if request.kind.is_write() => ReplyField::Written,
            Role::Data => ReplyField::DataSize,
            _ => ReplyField::Register,
        },
        expected: difference.expected,
        found: difference.found,
    }
}

/// Whether `request` sent by `command` gets no reply: the command is never answered
/// (`reply: none`), or it writes a register whose writes are not (`no_reply: true`).
fn unanswered(command: &CommandSpec, request: &Request) -> bool {
    command.no_reply || (request.kind.is_write() && request.info.is_some_and(|info| info.no_reply))
}

/// A raw value in `info`'s engineering unit (unsigned; for percentages of positive values).
fn engineering(raw: u32, info: &crate::info::RegisterInfo) -> f64 {
    f64::from(raw) * info.scale
}

/// `info` as a reply stating `decimals` decimal places has it (see
/// [`crate::info::RegisterInfo::scaled_for_decimals`]); a typed error naming the register,
/// the decimals of its own scale and those received when none of its scales has them.
fn for_decimals(
    info: &'static crate::info::RegisterInfo,
    decimals: u8,
) -> Result<&'static crate::info::RegisterInfo, ValueError> {
    info.scaled_for_decimals(decimals)
        .ok_or(ValueError::WrongDecimals {
            register: info,
            expected: info.decimals(),
            received: decimals,
        })
}

/// The exchange `step` needs before `request`, if it needs one.
fn step_request(step: &PreStep, request: &Request) -> Option<Request> {
    match *step {
        PreStep::Index { register } => request.index.map(|index| Request {
            wire_register: true,
            index: None,
            info: None,
            ..Request::raw(CommandKind::WriteRam, register, u32::from(index))
        }),
        // Coil writes (process data) are not parameter writes: no selector for them.
        PreStep::Persistence {
            space,
            register,
            data_type,
            ram,
            persistent,
        } => (request.kind.is_write() && request.space == Space::Parameter).then(|| {
            let value = if request.kind == CommandKind::WritePersistent {
                persistent
            } else {
                ram
            };
            Request::raw(CommandKind::WriteRam, register, value)
                .in_space(space)
                .with_data_type(data_type)
        }),
    }
}

/// The answer a reply gives to `request` (whose station, register and index the search
/// already compared): an error reply becomes a rejection. `block_size`: the bytes of data a
/// block read expects (0: an ordinary request, which a block of registers does not answer).
fn check_reply(
    request: &Request,
    block_size: usize,
    reply: Reply<'static>,
) -> Result<Answer, TransactionError> {
    match reply {
        Reply::Error {
            error,
            info,
            tripped,
            ..
        } => Err(TransactionError::new(
            Some(request),
            TransactionErrorKind::Rejected {
                code: error,
                info,
                tripped,
            },
        )),
        Reply::Data {
            command,
            tripped,
            data,
            process,
            text,
            values,
            ..
        } => {
            let size = usize::from(values.data_size);
            // A reply without a data field counts what it answers (Modbus 10h's quantity).
            let wide = size > 4 && command.reply.has(Role::Data);
            if (block_size > 0 || wide) && size != block_size {
                return Err(TransactionError::new(
                    Some(request),
                    TransactionErrorKind::Mismatch {
                        field: ReplyField::Data,
                        expected: block_size as u32,
                        found: size as u32,
                    },
                ));
            }
            let block = wide
                .then(|| {
                    command.reply.index_of(Role::Data).map(|index| {
                        let slot = values.parts[index];
                        command
                            .reply
                            .wire_span(slot.value as usize, usize::from(slot.width))
                    })
                })
                .flatten()
                .or_else(|| {
                    // A block transfer's words.
                    command.reply.index_of(Role::Words).map(|index| {
                        let slot = values.parts[index];
                        (slot.value as usize, usize::from(slot.width))
                    })
                });
            if request.data_type == DataType::Text && text.is_none() {
                return Err(TransactionError::new(
                    Some(request),
                    TransactionErrorKind::Mismatch {
                        field: ReplyField::Text,
                        expected: 1,
                        found: 0,
                    },
                ));
            }
            // The decimals the reply states must be those of a scale the register has.
            let decimals = values
                .get(&command.reply, Role::Decimals)
                .map(|d| u8::try_from(d).unwrap_or(u8::MAX));
            if let (Some(decimals), Some(info), None) = (decimals, request.info, block) {
                for_decimals(info, decimals).map_err(|error| {
                    TransactionError::new(Some(request), TransactionErrorKind::Value(error))
                })?;
            }
            Ok(Answer {
                data: (command.reply.has(Role::Data) && block.is_none()).then_some(data),
                tripped,
                process,
                text,
                block,
                write_status: values.get(&command.reply, Role::WriteStatus),
                decimals,
            })
        }
    }
}

/// A request/reply exchange that failed: the request it concerns (stored once) and what
/// went wrong.
#[derive(Debug)]
pub struct TransactionError {
    /// The request the error is about: the caller's request for failures of the exchange
    /// itself, or the step's request when a step the protocol needs first failed
    /// (selecting an array index, choosing RAM or EEPROM). `None` when no request was sent:
    /// a value is refused before anything goes on the line, or a value read back does not
    /// convert (the value error names the register).
    pub request: Option<Request>,
    /// What went wrong.
    pub kind: TransactionErrorKind,
}

/// What went wrong in a failed exchange.
#[derive(Debug)]
pub enum TransactionErrorKind {
    /// The transport failed.
    Io(std::io::Error),
    /// The request could not be built.
    Encode(EncodeError),
    /// The value cannot be sent, or the value read back cannot be converted.
    Value(ValueError),
    /// No complete reply arrived in time.
    Timeout {
        /// The timeout that elapsed.
        waited: Duration,
        /// The first bytes received (at most 64).
        received: Vec<u8>,
        /// Number of bytes received.
        received_len: usize,
        /// The last decode error seen while waiting, if any.
        last_error: Option<Box<DecodeError>>,
    },
    /// The reply is not a valid frame.
    Decode(Box<DecodeError>),
    /// The drive answered with an error reply.
    Rejected {
        /// Error code received.
        code: u16,
        /// The manual's entry for the code.
        info: Option<&'static ErrorCodeInfo>,
        /// Whether the reply said the drive is tripped (lower-case command).
        tripped: bool,
    },
    /// The reply does not answer the request (wrong address, register or index, or a
    /// write reply reporting another value).
    Mismatch {
        /// Which part of the reply differs.
        field: ReplyField,
        /// Value expected.
        expected: u32,
        /// Value found.
        found: u32,
    },
}

impl TransactionErrorKind {
    /// Whether something came back that was not a sound frame: a reply that does not
    /// decode, or bytes that never made one before the timeout.
    pub fn garbled_reply(&self) -> bool {
        match self {
            TransactionErrorKind::Decode(_) => true,
            TransactionErrorKind::Timeout { received_len, .. } => *received_len > 0,
            _ => false,
        }
    }

    /// Whether sending the request again may succeed: no reply in time, a garbled reply or
    /// a reply to something else. A refusal by the drive, a request that cannot be built
    /// and a failing transport would fail again.
    pub fn worth_repeating(&self) -> bool {
        matches!(
            self,
            TransactionErrorKind::Timeout { .. }
                | TransactionErrorKind::Decode(_)
                | TransactionErrorKind::Mismatch { .. }
        )
    }
}

/// A part of a reply the master checks against its request.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ReplyField {
    /// The station address.
    Address,
    /// The register number on the wire.
    Register,
    /// The array index.
    Index,
    /// The text of a text read (expected 1: present; found 0: absent).
    Text,
    /// The process words (expected 2, found 0: absent).
    ProcessWords,
    /// The data of a read (expected 1: present; found 0: absent).
    Data,
    /// The value a write's reply reports written (expected: the value sent). A reply
    /// reporting another value answers an earlier write.
    Written,
    /// The number of data bytes a read's reply carries (expected: the size asked for). A
    /// reply of another size answers another read.
    DataSize,
}

impl ReplyField {
    /// Name used in messages (`register`, `process words`).
    pub const fn as_str(self) -> &'static str {
        match self {
            ReplyField::Address => "address",
            ReplyField::Register => "register",
            ReplyField::Index => "index",
            ReplyField::Text => "text",
            ReplyField::ProcessWords => "process words",
            ReplyField::Data => "data",
            ReplyField::Written => "value written",
            ReplyField::DataSize => "data size",
        }
    }
}

impl TransactionError {
    /// An error about `request` (`None`: no request was sent).
    pub fn new(request: Option<&Request>, kind: TransactionErrorKind) -> TransactionError {
        TransactionError {
            request: request.copied(),
            kind,
        }
    }
}

impl From<std::io::Error> for TransactionError {
    fn from(error: std::io::Error) -> Self {
        TransactionError::new(None, TransactionErrorKind::Io(error))
    }
}

impl From<ValueError> for TransactionError {
    fn from(error: ValueError) -> Self {
        TransactionError::new(None, TransactionErrorKind::Value(error))
    }
}

impl fmt::Display for TransactionError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let request = || {
            self.request
                .as_ref()
                .map_or_else(|| "the request".to_owned(), Request::describe)
        };
        match &self.kind {
            TransactionErrorKind::Io(error) if self.request.is_some() => {
                write!(f, "transport error during {}: {error}", request())
            }
            TransactionErrorKind::Io(error) => write!(f, "transport error: {error}"),
            TransactionErrorKind::Encode(error) => write!(f, "cannot send {}: {error}", request()),
            TransactionErrorKind::Value(error) => write!(f, "{error}"),
            TransactionErrorKind::Timeout {
                waited,
                received,
                received_len,
                last_error,
            } => {
                let waited = for_people(*waited);
                if *received_len == 0 {
                    write!(f, "no reply to {} within {waited}", request())?;
                } else {
                    write!(
                        f,
                        "no complete reply to {} within {waited}; received {received_len} byte(s): {}",
                        request(),
                        hex(received)
                    )?;
                    if *received_len > received.len() {
                        f.write_str(" ...")?;
                    }
                }
                if let Some(error) = last_error {
                    write!(f, "; last decode error: {error}")?;
                }
                Ok(())
            }
            TransactionErrorKind::Decode(error) => {
                write!(f, "invalid reply to {}: {error}", request())
            }
            TransactionErrorKind::Rejected {
                code,
                info,
                tripped,
            } => {
                write!(
                    f,
                    "drive rejected {}: error {code} ({code:04X}h) ",
                    request()
                )?;
                match info {
                    Some(info) => write!(f, "{} ({}): {}", info.name, info.name_zh, info.meaning)?,
                    None => f.write_str("(code not in the manual's table)")?,
                }
                if *tripped {
                    f.write_str("; the drive reports it is tripped")?;
                }
                Ok(())
            }
            TransactionErrorKind::Mismatch {
                field,
                expected,
                found,
            } => match field {
                // A block read's data is counted in bytes.
                ReplyField::Data if (*expected, *found) != (1, 0) => write!(
                    f,
                    "reply to {} carries {found} byte(s) of data, expected {expected}",
                    request()
                ),
                // Parts whose presence is what is checked: say what is missing.
                ReplyField::Text | ReplyField::ProcessWords | ReplyField::Data => {
                    write!(f, "reply to {} carries no {}", request(), field.as_str())
                }
                ReplyField::Address
                | ReplyField::Register
                | ReplyField::Index
                | ReplyField::Written
                | ReplyField::DataSize => write!(
                    f,
                    "reply to {} does not match: {} is {found:#X}, expected {expected:#X}",
                    request(),
                    field.as_str()
                ),
            },
        }
    }
}

impl std::error::Error for TransactionError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match &self.kind {
            TransactionErrorKind::Io(error) => Some(error),
            TransactionErrorKind::Encode(error) => Some(error),
            TransactionErrorKind::Decode(error) => Some(error.as_ref()),
            // The message is the value error's own, so it is not repeated as a source.
            TransactionErrorKind::Value(error) => error.source(),
            TransactionErrorKind::Timeout { .. }
            | TransactionErrorKind::Rejected { .. }
            | TransactionErrorKind::Mismatch { .. } => None,
        }
    }
}

/// A duration as people read it: `850 µs`, `120 ms`, `12.5 s`.
fn for_people(duration: Duration) -> String {
    let micros = duration.as_micros();
    if micros < 1_000 {
        format!("{micros} µs")
    } else if micros < 10_000_000 {
        format!("{} ms", (micros + 500) / 1_000)
    } else {
        format!("{:.1} s", duration.as_secs_f64())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::error::Error as _;

    #[test]
    fn read_ahead_waits_one_character_less_than_the_bytes_still_needed() {
        let now = Instant::now();
        let char_time = Duration::from_micros(1146);
        let far = now + Duration::from_secs(1);
        assert_eq!(read_ahead_wait(0, char_time, now, far), None);
        assert_eq!(read_ahead_wait(1, char_time, now, far), None);
        assert_eq!(read_ahead_wait(2, char_time, now, far), Some(char_time));
        assert_eq!(read_ahead_wait(7, char_time, now, far), Some(char_time * 6));
        // Never past the deadline, and not at all once it has come.
        let soon = now + Duration::from_millis(2);
        assert_eq!(
            read_ahead_wait(7, char_time, now, soon),
            Some(Duration::from_millis(2))
        );
        assert_eq!(read_ahead_wait(7, char_time, soon, now), None);
    }

    #[test]
    fn durations_read_as_people_write_them() {
        assert_eq!(for_people(Duration::from_micros(850)), "850 µs");
        assert_eq!(for_people(Duration::from_micros(120_400)), "120 ms");
        assert_eq!(for_people(Duration::from_micros(1_999_600)), "2000 ms");
        assert_eq!(for_people(Duration::from_millis(12_500)), "12.5 s");
    }

    #[test]
    fn a_silent_timeout_says_so_without_a_dangling_colon() {
        let request = Request::raw(CommandKind::Read, 0xFD00, 0);
        let error = TransactionError::new(
            Some(&request),
            TransactionErrorKind::Timeout {
                waited: Duration::from_micros(120_300),
                received: Vec::new(),
                received_len: 0,
                last_error: None,
            },
        );
        assert_eq!(
            error.to_string(),
            "no reply to read of register FD00 within 120 ms"
        );
        let error = TransactionError {
            kind: TransactionErrorKind::Timeout {
                waited: Duration::from_millis(40),
                received: b"garbage".to_vec(),
                received_len: 70,
                last_error: None,
            },
            ..error
        };
        assert_eq!(
            error.to_string(),
            "no complete reply to read of register FD00 within 40 ms; \
             received 70 byte(s): 67 61 72 62 61 67 65 ..."
        );
    }

    #[test]
    fn the_source_is_the_underlying_error() {
        let io = std::io::Error::new(std::io::ErrorKind::BrokenPipe, "gone");
        let error = TransactionError::from(io);
        assert_eq!(error.to_string(), "transport error: gone");
        assert_eq!(error.source().unwrap().to_string(), "gone");
        let request = Request::raw(CommandKind::Read, 1, 0);
        let decode = DecodeError::Truncated {
            layout: "reply".into(),
            len: 2,
        };
        let error = TransactionError::new(
            Some(&request),
            TransactionErrorKind::Decode(Box::new(decode.clone())),
        );
        assert_eq!(error.source().unwrap().to_string(), decode.to_string());
        assert!(error
            .to_string()
            .starts_with("invalid reply to read of register 0001: "));
    }
}
