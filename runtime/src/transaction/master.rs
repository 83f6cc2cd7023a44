//! The blocking master: the typed API over a [`Transport`], each call running the shared
//! engine to its end on the calling thread.

use super::answer::Answer;
use super::blocks::BlockTransfer;
use super::broadcast::BroadcastReply;
use super::error::TransactionError;
use super::line::{finish, Blocking};
use super::reading::Reading;
use super::session::Session;
use crate::broadcast::Broadcast;
use crate::error::EncodeError;
use crate::protocol::{BlockSelection, DriveProtocol, Protocol};
use crate::register::{Persistable, Register, Request, Writable};
use crate::serial::{DriveTiming, SerialSettings};
use crate::transport::Transport;
use std::marker::PhantomData;
use std::time::{Duration, Instant};

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
///
/// **Which checks a write makes, and which are the caller's.** Before anything is sent a
/// typed write checks the value against the register's own range from the manual (a
/// [`crate::error::ValueError`] names the register and the range), that the register can be
/// written at all and, for `write_persistent`, that it is not RAM only (these two at
/// compile time). It does **not** check a bound that *another register* sets
/// ([`crate::info::RegisterInfo::min_bound`] / `max_bound`: the frequency command is
/// limited by FH): the master would have to read that register,
/// and it does not know whether the caller changed it since. The `vfd` tool reads the
/// bounding register and refuses such a value; a library caller that needs the same
/// refusal reads the bounding register first and compares. Otherwise the drive itself
/// refuses the value (an error reply, [`crate::transaction::TransactionErrorKind::Rejected`], with the
/// manual's meaning) or, on drives that do not check, clamps or takes it. Combinations of
/// values the manual forbids (the description's `forbidden_combinations`) are the caller's
/// too, as is whether the register may change while the motor runs.
pub struct Master<T, D: 'static = AnyDrive> {
    pub(super) transport: T,
    pub(super) session: Session,
    drive: PhantomData<fn() -> D>,
}

impl<T> Master<T, AnyDrive> {
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

impl<T, D: 'static> Master<T, D> {
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
            session: Session::new(protocol, settings, timing),
            drive: PhantomData,
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

    /// The transport, e.g. to close it.
    pub fn into_transport(self) -> T {
        self.transport
    }

    /// The page the master knows station `address` to be on (`None`: unknown, so the next
    /// paged access selects its page first). See [`Protocol::paging`].
    pub fn known_page(&self, address: Option<u8>) -> Option<u16> {
        self.session.known_page(address)
    }

    /// Forgets the pages of every station: call it after reconnecting to a line whose
    /// drives may have been reset or switched by another master (a new master starts
    /// knowing none).
    pub fn forget_pages(&mut self) {
        self.session.pages.clear();
    }

    /// Talks in the protocol's variant `id` (`cr_lf`: every frame ends in CR LF), the one
    /// the drive is set to ([`Protocol::variant`]): requests are sent in it and replies
    /// are expected in it. An unknown variant is refused, naming the protocol's variants.
    pub fn with_variant(mut self, id: &str) -> Result<Self, EncodeError> {
        self.session.set_variant(id)?;
        Ok(self)
    }

    /// The id of the protocol variant the master talks in (`None`: the protocol has none).
    pub fn variant(&self) -> Option<&'static str> {
        self.session.protocol.variant_id()
    }

    /// Talks to the drive's port `port` (of a drive with several serial ports): a request
    /// for a register that exists once per port goes to this port's copy, as the
    /// description's `ports.registers` pairs them (one port's command word becomes the
    /// other's). `None`: registers are sent as given.
    pub fn with_port(mut self, port: Option<crate::drive::Port>) -> Self {
        self.session.port = port;
        self
    }

    /// The latency added to the drive's processing time in every reply timeout, for the
    /// adapter and the host (USB serial adapters buffer for up to 16 ms; a loaded machine
    /// schedules late). Default: [`crate::serial::HOST_LATENCY`].
    pub fn with_host_latency(mut self, latency: Duration) -> Self {
        self.session.host_latency = latency;
        self
    }

    /// Keeps at least `gap` of silence between the master's frames, for a slow gateway or
    /// USB adapter that needs more than the protocol's own gap. A shorter `gap` than the
    /// protocol's changes nothing: the protocol's gap is never shortened. It does not
    /// change how long a silence inside a reply may be. Default: zero (the protocol's gap).
    pub fn with_min_gap(mut self, gap: Duration) -> Self {
        self.session.min_gap = gap;
        self
    }

    /// Addresses requests to station `address` (`None`: send no address, which the
    /// Toshiba-style protocols accept when one drive is on the line).
    pub fn with_address(mut self, address: Option<u8>) -> Self {
        self.session.set_address(address);
        self
    }

    /// Repeats a request whose exchange failed (no reply in time, a garbled reply, a reply
    /// to something else) up to `retries` more times, **for requests that only read**
    /// ([`crate::kinds::CommandKind::Read`], [`crate::kinds::CommandKind::ReadText`]: register and text reads, including
    /// the read after an index step). Writes, process-data exchanges and the steps before a
    /// request (index and RAM/EEPROM selection) are never repeated: a write whose reply was
    /// lost may have been carried out. A refusal by the drive, a value or request that
    /// cannot be sent and transport failures are not retried either. A read then takes at
    /// most `retries + 1` reply timeouts. Default: 0.
    pub fn with_retries(mut self, retries: u8) -> Self {
        self.session.retries = retries;
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
        self.session.set_local_echo(echo);
        self
    }

    /// The bytes of the last reply taken as the answer (empty before the first). A text
    /// read's [`Answer::text`] is an offset and length within it, so tools that work with
    /// any drive read text this way.
    pub fn last_reply(&self) -> &[u8] {
        self.session.last_reply()
    }

    /// Asks the drive to wait `wait` before each reply, in protocols whose requests carry
    /// a wait ([`crate::layout::Role::ReplyWait`], in tens of milliseconds: the Eaton protocol's wait-time
    /// digit, 0-150 ms; some RS-485 converters need the line turned round slowly). It is
    /// rounded up to 10 ms and kept within what the field can carry; the reply timeout
    /// grows by it. Protocols without such a field ignore it.
    pub fn with_reply_wait(mut self, wait: Duration) -> Self {
        self.session.set_reply_wait(wait);
        self
    }

    /// The wait each reply is asked for ([`Master::with_reply_wait`]), where the protocol's
    /// requests carry one.
    pub fn reply_wait(&self) -> Duration {
        self.session.reply_wait()
    }

    /// States the drive's wait before every reply, where registers of the drive set one
    /// (the protocol's [`crate::serial::ReplyDelay`]: VF-AS1 F805 / F825): it is added to
    /// every reply timeout. Without it the master takes the description's factory setting.
    pub fn with_reply_delay(mut self, delay: Duration) -> Self {
        self.session.reply_delay = Some(delay);
        self
    }

    /// The drive's wait before replying that the master allows for: the value stated or
    /// read, else the factory setting of the protocol's reply-delay registers (zero when
    /// the protocol has none).
    pub fn reply_delay(&self) -> Duration {
        self.session.reply_delay()
    }

    /// The silence kept between frames: the protocol's gap in character times (Modbus
    /// RTU: 3.5), or the drive's floor in milliseconds where that is longer (DV1 Modbus
    /// RTU: 10 ms; VF-AS1: 2 ms), or [`Master::with_min_gap`] where that is longer still.
    pub fn frame_gap(&self) -> Duration {
        self.session.frame_gap()
    }

    /// When the line was last busy as this master saw it: the end of its last frame sent
    /// or received (`None` before its first exchange). Masters that share one line (several
    /// stations on one bus, each with its own master) hand it on with
    /// [`Master::note_line_activity`], so that the next keeps the frame gap after the
    /// other's frames too.
    pub fn line_activity(&self) -> Option<Instant> {
        self.session.last_activity
    }

    /// Tells the master the line was busy until `at` (another master's frame on the same
    /// line): its next request keeps the frame gap after it. An earlier instant than the
    /// one it knows changes nothing.
    pub fn note_line_activity(&mut self, at: Instant) {
        let last = &mut self.session.last_activity;
        if last.is_none_or(|known| known < at) {
            *last = Some(at);
        }
    }

    /// Changes how often a failed read is repeated (see [`Master::with_retries`]), for
    /// the next requests.
    pub fn set_retries(&mut self, retries: u8) {
        self.session.retries = retries;
    }

    /// The longest silence a frame may hold, from the protocol's timing (the frame gap): a
    /// longer one inside a reply starts a new frame. `None` when the protocol states no
    /// gap.
    pub fn silence_limit(&self) -> Option<Duration> {
        self.session.silence_limit()
    }

    /// The value the master believes the drive's persistence selector (the description's
    /// `persistence.selector`, DV1 07-11) holds in RAM; `None` when it does not know (at
    /// first, after a failed write it governs, after [`Master::forget_persistence_selector`]).
    pub fn persistence_selector(&self) -> Option<u32> {
        self.session.selector.value
    }

    /// Tells the master that the persistence selector holds `value` in the drive's RAM
    /// (set on the operator panel, or known from an earlier read), so that the next
    /// governed write neither reads nor sets it when it already chooses what the write
    /// asks for (a remembered `persistent` is otherwise read again before each persistent
    /// write, since a power cycle may have brought back another value).
    pub fn assume_persistence_selector(&mut self, value: u32) {
        self.session.selector.value = Some(value);
        self.session.selector.assumed = true;
    }

    /// Forgets the persistence selector's value, so that the next governed write reads or
    /// sets it again (after another master or the operator panel may have changed it).
    pub fn forget_persistence_selector(&mut self) {
        self.session.selector.value = None;
        self.session.selector.assumed = false;
    }

    /// The value of a register `words.len()` words wide (1 or 2) that [`Master::read_words`]
    /// returned, as a read of that register alone gives it (Modbus: the high word first).
    pub fn join_words(&self, words: &[u16]) -> u32 {
        self.session.join_words(words)
    }
}

/// The requests: each runs the shared engine over the transport to its end.
impl<T: Transport, D: 'static> Master<T, D> {
    /// The reply timeout for a request of `request_len` bytes: both frames' wire time, the
    /// drive's processing time, its wait before replying ([`Master::reply_delay`]), the
    /// host latency and what the transport adds ([`Transport::allowance`]: a network).
    pub fn reply_timeout(&self, request_len: usize) -> Duration {
        self.session.reply_timeout(request_len) + self.transport.allowance()
    }

    /// Reads the protocol's reply-delay registers (allowing the longest wait they can set
    /// while reading them) and from then on allows for the longest value read. Returns it;
    /// zero, without an exchange, when the protocol has no such register.
    pub fn read_reply_delay(&mut self) -> Result<Duration, TransactionError> {
        finish(
            self.session
                .read_reply_delay(&mut Blocking(&mut self.transport)),
        )
    }

    /// Reads register `R`: its typed value, and whether the reply said the drive is tripped.
    pub fn read<R: Register<Drive = D>>(&mut self) -> Result<Reading<R::Value>, TransactionError> {
        let request = Request::read::<R>();
        finish(
            self.session
                .read_value::<R>(&mut Blocking(&mut self.transport), &request),
        )
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
        finish(
            self.session
                .read_value::<R>(&mut Blocking(&mut self.transport), &request),
        )
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
        let line = &mut Blocking(&mut self.transport);
        finish(
            self.session
                .write_percent_of::<R, F>(line, code, value, reference),
        )
    }

    /// Reads element `index` of the array register `R`. Refuses indexes beyond the array.
    pub fn read_at<R: Register<Drive = D>>(
        &mut self,
        index: u16,
    ) -> Result<Reading<R::Value>, TransactionError> {
        let request = Request::read::<R>().at_index(index)?;
        finish(
            self.session
                .read_value::<R>(&mut Blocking(&mut self.transport), &request),
        )
    }

    /// Reads the text register `R` (text parameters such as an ordering number).
    pub fn read_text<R: Register<Drive = D>>(&mut self) -> Result<String, TransactionError> {
        finish(
            self.session
                .read_text::<R>(&mut Blocking(&mut self.transport)),
        )
    }

    /// Writes `value` to register `R` in RAM only. Returns the value the drive reports
    /// written (its echo), or `None` when the protocol's reply carries no data. On a drive
    /// whose own register chooses where parameter writes go (DV1 07-11), the master sets it
    /// to RAM only first (see [`Master::persistence_selector`]).
    pub fn write_ram<R: Writable<Drive = D>>(
        &mut self,
        value: R::Value,
    ) -> Result<Option<R::Value>, TransactionError> {
        let request = Request::write_ram::<R>(value)?;
        finish(
            self.session
                .write_value::<R>(&mut Blocking(&mut self.transport), &request),
        )
    }

    /// Writes `value` to element `index` of the array register `R` in RAM only. Returns
    /// the value the drive reports written, if its reply carries one.
    pub fn write_ram_at<R: Writable<Drive = D>>(
        &mut self,
        index: u16,
        value: R::Value,
    ) -> Result<Option<R::Value>, TransactionError> {
        let request = Request::write_ram::<R>(value)?.at_index(index)?;
        finish(
            self.session
                .write_value::<R>(&mut Blocking(&mut self.transport), &request),
        )
    }

    /// Writes `value` to register `R` in RAM and EEPROM (persistent; EEPROM wears out).
    /// Returns the value the drive reports written, if its reply carries one. On a drive
    /// whose own register chooses where parameter writes go (DV1 07-11), the master sets it
    /// to RAM and EEPROM around the write and back (see [`Master::persistence_selector`]).
    pub fn write_persistent<R: Persistable<Drive = D>>(
        &mut self,
        value: R::Value,
    ) -> Result<Option<R::Value>, TransactionError> {
        let request = Request::write_persistent::<R>(value)?;
        finish(
            self.session
                .write_value::<R>(&mut Blocking(&mut self.transport), &request),
        )
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
        finish(
            self.session
                .write_value::<R>(&mut Blocking(&mut self.transport), &request),
        )
    }

    /// Sends process words (control word, reference) and returns those the drive answers
    /// with (status word, output value).
    pub fn exchange_process(
        &mut self,
        control: u16,
        reference: u16,
    ) -> Result<[u16; 2], TransactionError> {
        let line = &mut Blocking(&mut self.transport);
        finish(self.session.exchange_process(line, control, reference))
    }

    /// A diagnostic echo (Modbus 08, sub-function 0000h): sends `data` and returns what the
    /// drive sends back, which must be the same (a reply carrying other data answers another
    /// request). Refused before anything is sent when the protocol has no echo command.
    pub fn echo(&mut self, data: u16) -> Result<u16, TransactionError> {
        finish(self.session.echo(&mut Blocking(&mut self.transport), data))
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
        finish(
            self.session
                .read_words(&mut Blocking(&mut self.transport), start, words),
        )
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
        finish(
            self.session
                .write_words(&mut Blocking(&mut self.transport), start, words),
        )
    }

    /// Runs one block transfer ([`crate::kinds::CommandKind::Block`]): writes `writes` to the registers
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
        selection: &BlockSelection,
        writes: &[u16],
        read_count: u8,
    ) -> Result<BlockTransfer, TransactionError> {
        let line = &mut Blocking(&mut self.transport);
        finish(
            self.session
                .block_transfer(line, selection, writes, read_count),
        )
    }

    /// Runs one request, with any steps the protocol needs first (selecting an array
    /// index, choosing RAM or EEPROM, setting the drive's persistence selector around a
    /// write it governs: see [`Master::persistence_selector`]). Every frame is built and
    /// checked before the first is sent: when the protocol cannot carry any of them,
    /// nothing goes on the line.
    pub fn transact(&mut self, request: &Request) -> Result<Answer, TransactionError> {
        finish(
            self.session
                .transact(&mut Blocking(&mut self.transport), request),
        )
    }

    /// Broadcasts `request` (a write) to the stations `to` addresses. With
    /// [`BroadcastReply::From`], waits for that station's reply as for any request and
    /// returns what it says; with [`BroadcastReply::None`], returns `Ok(None)` after the
    /// request's wire time and the frame gap, so that the next frame cannot run into it.
    ///
    /// Refused before anything is sent (an [`EncodeError::NoBroadcast`]): a request that
    /// reads, a protocol the drive takes no broadcasts over, a command its rule does not
    /// list, a group the station field cannot carry, a request that needs a step first
    /// (array index, RAM/EEPROM selection), a reply from a station the broadcast does not
    /// address, and any reply where the description says none comes (Modbus).
    ///
    /// Where the description says a station may answer but the caller says none does, a
    /// reply may still come: the next exchange waits out the reply window first and drops
    /// it, so that it is not taken for the next reply.
    pub fn broadcast(
        &mut self,
        request: &Request,
        to: Broadcast,
        reply: BroadcastReply,
    ) -> Result<Option<Answer>, TransactionError> {
        let line = &mut Blocking(&mut self.transport);
        finish(self.session.broadcast(line, request, to, reply))
    }

    /// Broadcasts a RAM write of `value` to register `R` (see [`Master::broadcast`]).
    /// Returns the value the answering station reports written, if one answers and its
    /// reply carries one.
    pub fn broadcast_write_ram<R: Writable<Drive = D>>(
        &mut self,
        value: R::Value,
        to: Broadcast,
        reply: BroadcastReply,
    ) -> Result<Option<R::Value>, TransactionError> {
        let answer = self.broadcast(&Request::write_ram::<R>(value)?, to, reply)?;
        super::reading::value_written::<R>(answer.unwrap_or(Answer::NONE))
    }

    /// Broadcasts a persistent (RAM and EEPROM) write of `value` to register `R` (see
    /// [`Master::broadcast`]); EEPROM wears out on every drive addressed.
    pub fn broadcast_write_persistent<R: Persistable<Drive = D>>(
        &mut self,
        value: R::Value,
        to: Broadcast,
        reply: BroadcastReply,
    ) -> Result<Option<R::Value>, TransactionError> {
        let answer = self.broadcast(&Request::write_persistent::<R>(value)?, to, reply)?;
        super::reading::value_written::<R>(answer.unwrap_or(Answer::NONE))
    }
}
