//! The virtual drive: the slave side of every described drive and protocol, generated from
//! the same description as the master. It decodes requests with the protocol's layouts and
//! encodes replies with them; the register table gives ranges, access and "writable while
//! running"; the drive's `behaviour:` section ([`crate::behaviour`]) drives a simulated
//! motor on a clock that tests advance. Nothing here names a drive or a protocol.
//!
//! One concern per file: `storage` (RAM, EEPROM, values in effect), `motor` (the behaviour
//! model), `held` (registers shown at a value), `respond` (one request, one reply),
//! `outcome` (a reply or silence, and why a request is refused), `reply` (encoding replies
//! and error replies), `bad_checksum` (requests whose checksum does not match),
//! `data_width` (data of another width than the register's), `broadcast`, `consecutive`
//! (runs of registers), `block` (block transfers), `pages` (paged registers),
//! `unsupported` (function codes the drive does not know), `faults` (misbehaviour on
//! request), `tally` (what a station saw on its line), `link` (in-process transport) and
//! `serve` (a loop over any transport, in wall time, for one drive or several stations of
//! a multi-drop bus).
//!
//! In process, a typed master is two lines away:
//!
//! ```text
//! let sim = Simulator::new(&my_drive::DRIVE);
//! let mut master = sim.master(&my_drive::protocols::BINARY);
//! ```
//!
//! (see `vfd_drives::guide` for a complete, tested example).

mod bad_checksum;
mod block;
mod broadcast;
mod consecutive;
mod data_width;
mod faults;
mod held;
mod link;
mod motor;
mod outcome;
mod pages;
mod reply;
mod respond;
mod serve;
mod station;
mod storage;
mod tally;
mod unreadable;
mod unsupported;

pub use faults::Fault;
pub use link::SimLink;
pub use outcome::{Outcome, Refusal};
pub use serve::{same_framing, serve, serve_bus, BusStation};
pub use tally::Tally;

use crate::drive::DriveInfo;
use crate::error::DecodeErrorKind;
use crate::info::RegisterInfo;
use crate::protocol::{DecodedRequest, DriveProtocol, Found, Protocol};
use crate::transaction::Master;
use motor::Motor;
use std::borrow::Cow;
use std::collections::VecDeque;
use std::sync::{Arc, Mutex, MutexGuard, PoisonError};
use std::time::Duration;
use storage::Storage;

/// The longest simulated step: ramps are integrated in steps no longer than this.
const MAX_STEP: Duration = Duration::from_millis(100);

/// A simulated drive: its registers, its motor, its clock and the faults it is told to
/// commit. Use it through a [`Simulator`] (shared between a test and its master).
#[derive(Debug)]
pub struct VirtualDrive {
    drive: &'static DriveInfo,
    address: u8,
    storage: Storage,
    motor: Motor,
    now: Duration,
    selected_index: u16,
    persistent_writes: bool,
    faults: VecDeque<Fault>,
    noise: bool,
    echo: bool,
    requests: u64,
    /// What happened on the line to this station ([`Tally`]).
    tally: Tally,
    /// Unplugged from its bus: it neither answers nor acts on frames.
    unplugged: bool,
    /// The simulated time until which it starts up after a power cycle, answering nothing.
    silent_until: Duration,
    /// The last request of a command whose lower case speaks of its sender said the sender
    /// (a master inverter) has tripped.
    sender_tripped: bool,
    /// Bytes that were no frame came since the line was last silent: where the protocol
    /// says so, they reject the frame that follows ([`crate::serial::BeforeStart`]).
    garbage: bool,
    /// The serial port it serves (a port id of the description's `ports`): that port's
    /// copies of the behaviour's registers act. `None`: the registers as the behaviour
    /// names them.
    port: Option<&'static str>,
    /// The page it is on, on a protocol with pages (`None`: the protocol's initial page).
    page: Option<u16>,
    /// The command code and bytes of the last reply, while its master's follow-up is
    /// awaited ([`crate::protocol::FollowUp`]).
    awaiting_follow_up: Option<(u32, Vec<u8>)>,
    /// Registers shown at a value whatever the behaviour model computes
    /// ([`VirtualDrive::hold`]), until a power cycle.
    held: Vec<(&'static RegisterInfo, u32)>,
    /// Unreadable frames for this station in a row, since the last it could read
    /// ([`crate::behaviour::Refusals::retries_exceeded`]).
    unreadable_in_a_row: u32,
}

/// Bytes the drive sends in answer to one request, and how.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Transmission {
    /// The bytes.
    pub bytes: Vec<u8>,
    /// Sent only after the master's reply timeout.
    pub delayed: bool,
    /// Sent one byte at a time with gaps of this many character times.
    pub split: Option<u32>,
    /// Held back this long after the request before it is sent: the wait the drive's
    /// reply-delay registers set (VF-AS1 F805 / F825).
    pub wait: Duration,
    /// Length of the request answered, in bytes (for the reply timing).
    pub request_len: usize,
}

impl VirtualDrive {
    /// A drive in its factory state: every register at its default, at the lowest station
    /// number its first protocol accepts (at least 1), motor stopped, clock at zero.
    pub fn new(drive: &'static DriveInfo) -> VirtualDrive {
        let address = drive
            .protocols
            .first()
            .map_or(1, |p| p.address_range.0.max(1));
        let mut virtual_drive = VirtualDrive {
            drive,
            address,
            storage: Storage::new(drive.registers),
            motor: Motor::default(),
            now: Duration::ZERO,
            selected_index: 0,
            persistent_writes: false,
            faults: VecDeque::new(),
            noise: false,
            echo: false,
            requests: 0,
            tally: Tally::default(),
            unplugged: false,
            silent_until: Duration::ZERO,
            sender_tripped: false,
            garbage: false,
            port: None,
            page: None,
            awaiting_follow_up: None,
            held: Vec::new(),
            unreadable_in_a_row: 0,
        };
        virtual_drive.place_station();
        virtual_drive.refresh();
        virtual_drive
    }

    /// The described drive.
    pub fn drive(&self) -> &'static DriveInfo {
        self.drive
    }

    /// Its station number.
    pub fn address(&self) -> u8 {
        self.address
    }

    /// Sets its station number (and the register holding it, where the description names
    /// one: `addressing.register`, as if set on the panel before power-on).
    pub fn set_address(&mut self, address: u8) {
        self.address = address;
        self.set_station_register(address);
    }

    /// The serial port it serves, for a drive with several (`None`: not chosen).
    pub fn port(&self) -> Option<&'static str> {
        self.port
    }

    /// Serves the port `name` (an id or English name of the description's `ports`): the
    /// command word and frequency command of that port act. Returns false, changing
    /// nothing, when the drive has no such port.
    pub fn set_port(&mut self, name: &str) -> bool {
        match self.drive.ports.and_then(|ports| ports.port(name)) {
            Some(port) => {
                self.port = Some(port.id);
                self.refresh();
                true
            }
            None => false,
        }
    }

    /// The id of the register `id` names on the port served (its port's copy).
    pub(crate) fn served(&self, id: &'static str) -> &'static str {
        match (self.port, self.drive.register(id)) {
            (Some(port), Some(info)) => self.drive.on_port(info, port).id,
            _ => id,
        }
    }

    /// `info` as it is with its scale selector's present value (itself when its scale is
    /// fixed).
    pub(crate) fn scaled(&self, info: &'static RegisterInfo) -> &'static RegisterInfo {
        let Some(scale_by) = info.scale_by else {
            return info;
        };
        let selector = self
            .drive
            .register(scale_by.register)
            .map(|selector| self.storage.in_effect(selector, 0));
        info.scaled_for(selector)
    }

    /// Simulated time since power-up.
    pub fn now(&self) -> Duration {
        self.now
    }

    /// Advances the simulated clock: the output ramps, monitors follow.
    pub fn advance(&mut self, elapsed: Duration) {
        let mut left = elapsed;
        while !left.is_zero() {
            let step = left.min(MAX_STEP);
            self.step(step);
            left -= step;
        }
        self.now += elapsed;
    }

    /// Power off and on: values written to RAM only are lost, the motor stops, a trip is
    /// cleared and parameters that take effect after a reset take their stored values. The
    /// drive then stays silent for the start-up delay its manual gives
    /// (`serial.timing.startup_delay_ms`), on the simulated clock.
    pub fn power_cycle(&mut self) {
        self.silent_until = self.now + self.drive.serial.timing.startup_delay;
        self.storage.power_cycle(self.drive.registers);
        self.motor = Motor::default();
        self.selected_index = 0;
        self.persistent_writes = false;
        self.page = None;
        self.awaiting_follow_up = None;
        self.held.clear();
        self.refresh();
    }

    /// The raw value in RAM of the register with this code or id (element 0 of arrays).
    pub fn raw(&self, name: &str) -> Option<u32> {
        let info = self.drive.register(name)?;
        Some(self.storage.get(info, 0))
    }

    /// The raw value in EEPROM of the register with this code or id (element 0 of arrays):
    /// what RAM holds after a power cycle. Writes go there when they are persistent (a
    /// persistent command, or the drive's persistence selector choosing RAM and EEPROM).
    pub fn eeprom_raw(&self, name: &str) -> Option<u32> {
        let info = self.drive.register(name)?;
        Some(self.storage.get_eeprom(info, 0))
    }

    /// The raw value the drive acts on: for parameters that take effect after a reset, the
    /// value at the last reset.
    pub fn raw_in_effect(&self, name: &str) -> Option<u32> {
        let info = self.drive.register(name)?;
        Some(self.storage.in_effect(info, 0))
    }

    /// Sets a register as the operator panel would (no checks, RAM only). Returns false
    /// when there is no such register.
    pub fn set_raw(&mut self, name: &str, raw: u32) -> bool {
        let Some(info) = self.drive.register(name) else {
            return false;
        };
        self.storage.set(info, 0, raw, false);
        self.refresh();
        true
    }

    /// Sets a register as it stood at power-on (no checks): in RAM and EEPROM and in effect
    /// at once, as a setting made on the panel before the drive was switched on (a setting
    /// that takes effect after a reset has taken it). Returns false when there is no such
    /// register.
    pub fn preset(&mut self, name: &str, raw: u32) -> bool {
        let Some(info) = self.drive.register(name) else {
            return false;
        };
        self.storage.set(info, 0, raw, true);
        self.storage.take_effect(std::slice::from_ref(&info));
        self.refresh();
        true
    }

    /// Sets the register that selects `variant`'s variant of its protocol (the one it is
    /// in, [`Protocol::variant`]) to the value that selects it, in RAM and EEPROM and in
    /// effect at once, as if set on the panel before power-on. Returns false, changing
    /// nothing, when no register of the drive selects it.
    pub fn select_variant(&mut self, variant: &Protocol) -> bool {
        let Some(variants) = &variant.variants else {
            return false;
        };
        let (Some(selector), Some(value)) = (
            &variants.selected_by,
            variants.value_selecting(usize::from(variants.current)),
        ) else {
            return false;
        };
        let Some(info) = self
            .drive
            .register_at(crate::kinds::Space::Parameter, selector.register)
        else {
            return false;
        };
        self.storage.set(info, 0, value, true);
        self.storage.take_effect(std::slice::from_ref(&info));
        self.refresh();
        true
    }

    /// The output, signed (negative in reverse), in the frequency command's units.
    pub fn output(&self) -> f64 {
        self.motor.output
    }

    /// Commits `fault` (see [`Fault`] for how long it lasts).
    pub fn inject(&mut self, fault: Fault) {
        match fault {
            Fault::Noise => self.noise = true,
            Fault::EchoRequest => self.echo = true,
            fault => self.faults.push_back(fault),
        }
    }

    /// Stops every fault.
    pub fn clear_faults(&mut self) {
        self.faults.clear();
        self.noise = false;
        self.echo = false;
    }

    /// Whether `fault` is pending (noise and echo: in force).
    pub fn has_fault(&self, fault: &Fault) -> bool {
        match fault {
            Fault::Noise => self.noise,
            Fault::EchoRequest => self.echo,
            other => self.faults.contains(other),
        }
    }

    /// The number of request frames received so far, whatever station they address and
    /// whether or not a fault kept the reply from the master (a test counts with it how
    /// often a master sent a request).
    pub fn requests(&self) -> u64 {
        self.requests
    }

    /// What this station saw on its line so far: requests addressed to it (answered or
    /// not), replies sent, writes carried out.
    pub fn tally(&self) -> Tally {
        self.tally
    }

    /// Unplugs the drive from its line (`true`) or plugs it back (`false`). Unplugged, it
    /// neither answers nor acts on any frame (a dead station on a multi-drop bus), but
    /// still counts the requests addressed to it ([`Tally::addressed`]), so a test can
    /// tell that a master tried it. Its motor and clock go on.
    pub fn set_unplugged(&mut self, unplugged: bool) {
        self.unplugged = unplugged;
    }

    /// Whether the drive is unplugged ([`VirtualDrive::set_unplugged`]).
    pub fn unplugged(&self) -> bool {
        self.unplugged
    }

    /// Whether the last drive-to-drive frame said its sender (the master inverter) has
    /// tripped (a lower-case code of a command whose lower case means so). The model records
    /// it only: what a receiver then does (stop, alarm, trip) is set by parameters the
    /// behaviour model does not describe yet.
    pub fn sender_tripped(&self) -> bool {
        self.sender_tripped
    }

    /// Whether it is still starting up after a power cycle (and answers nothing).
    pub fn starting_up(&self) -> bool {
        self.now < self.silent_until
    }

    /// The line has been silent for a frame gap: bytes received before no longer belong
    /// to the next frame (see [`crate::serial::BeforeStart`]).
    pub fn line_silent(&mut self) {
        self.garbage = false;
    }

    /// The wait before its replies over `protocol` that its reply-delay registers set (the
    /// longest, where there are several); zero when the protocol has none.
    pub fn reply_delay(&self, protocol: &Protocol) -> Duration {
        let Some(delay) = &protocol.timing.reply_delay else {
            return Duration::ZERO;
        };
        delay
            .registers
            .iter()
            .filter_map(|number| {
                self.drive
                    .register_at(crate::kinds::Space::Parameter, *number)
            })
            .map(|info| delay.of_raw(self.storage.get(info, 0)))
            .max()
            .unwrap_or(Duration::ZERO)
    }

    /// Answers one whole request frame (no bytes before or after it). Over a protocol with
    /// variants, the frame is read in the variant the drive's selector register selects;
    /// a frame in another variant's form gets the description's mismatch error.
    pub fn respond(&mut self, protocol: &Protocol, frame: &[u8]) -> Outcome {
        let own = self.in_force(protocol).own;
        if let Some((len, again)) = self.take_follow_up(own.as_ref(), frame) {
            if len == frame.len() {
                return match again {
                    Some(reply) => Outcome::Reply(reply),
                    None => Outcome::Silent("the master's follow-up to a reply"),
                };
            }
        }
        let outcome = self.respond_to_request(protocol, frame);
        let code = own.decode_request_exact(frame).ok().map(|r| r.command.code);
        if let Some(code) = code {
            let reply = match &outcome {
                Outcome::Reply(bytes) => Some(bytes.as_slice()),
                Outcome::Silent(_) => None,
            };
            self.note_reply(protocol, code, reply);
        }
        outcome
    }

    fn respond_to_request(&mut self, protocol: &Protocol, frame: &[u8]) -> Outcome {
        let variants = self.in_force(protocol);
        let protocol = variants.own.as_ref();
        match protocol.decode_request_exact(frame) {
            Ok(request) if self.unplugged => {
                self.requests += 1;
                self.count_addressed(&request);
                Outcome::Silent("unplugged from the line")
            }
            Ok(_) if self.starting_up() => {
                self.requests += 1;
                Outcome::Silent("starting up after power-on")
            }
            Ok(request) => {
                self.requests += 1;
                self.count_addressed(&request);
                let outcome = self.answer(protocol, &request);
                self.follow_station_register();
                if matches!(outcome, Outcome::Reply(_)) {
                    self.tally.answered += 1;
                }
                outcome
            }
            Err(error) => {
                let other = variants
                    .others
                    .iter()
                    .find_map(|other| other.decode_request_exact(frame).ok());
                if let Some(request) = other {
                    self.requests += 1;
                    return self.answer_mismatch(protocol, &request, variants.mismatch);
                }
                // As on the line (`take_frames`): a drive whose manual gives codes for
                // unreadable frames reads a bad checksum's station from the frame and counts
                // them in a row; otherwise the frame is read with its checksum put right;
                // a frame unreadable either way gets the malformed frame's code.
                let checksum = error.kind() == DecodeErrorKind::ChecksumMismatch;
                let whole = |found: Option<unreadable::Unreadable>| match found {
                    Some(unreadable::Unreadable::Frame { len, outcome }) if len == frame.len() => {
                        Some(outcome)
                    }
                    _ => None,
                };
                if checksum {
                    if let Some(outcome) = whole(self.unreadable(protocol, frame, true)) {
                        return outcome;
                    }
                }
                match bad_checksum::repaired(protocol, frame, true) {
                    bad_checksum::Repaired::Frame(request) => {
                        self.requests += 1;
                        self.count_addressed(&request);
                        self.answer_bad_checksum(protocol, &request)
                    }
                    _ if checksum => self.refuse(protocol, None, Refusal::BadChecksum),
                    _ => whole(self.unreadable(protocol, frame, false))
                        .unwrap_or(Outcome::Silent("not a request frame")),
                }
            }
        }
    }

    /// The variant of `protocol` in force (the one its selector register's value at the
    /// last reset selects, else `protocol` as it is) and its other variants.
    fn in_force<'p>(&self, protocol: &'p Protocol) -> InForce<'p> {
        let Some(variants) = &protocol.variants else {
            return InForce {
                own: Cow::Borrowed(protocol),
                others: Vec::new(),
                mismatch: None,
            };
        };
        let current = usize::from(variants.current);
        let selected = variants
            .selected_by
            .as_ref()
            .and_then(|selector| {
                self.drive
                    .register_at(crate::kinds::Space::Parameter, selector.register)
            })
            .and_then(|info| variants.selected_by_value(self.storage.in_effect(info, 0)))
            .unwrap_or(current);
        let own = match protocol.in_variant(selected) {
            Some(own) if selected != current => Cow::Owned(own),
            _ => Cow::Borrowed(protocol),
        };
        let others = (0..variants.choices.len())
            .filter(|index| *index != selected)
            .filter_map(|index| protocol.in_variant(index))
            .collect();
        InForce {
            own,
            others,
            mismatch: variants.mismatch_error,
        }
    }

    /// Answers a request that came in another variant's form than the one in force: the
    /// error reply with `code`, in the variant in force, when the request is for this
    /// station; silence otherwise, or when the description names no code.
    fn answer_mismatch(
        &self,
        protocol: &Protocol,
        request: &DecodedRequest<'_>,
        code: Option<u16>,
    ) -> Outcome {
        if self.starting_up() {
            return Outcome::Silent("starting up after power-on");
        }
        if request.broadcast.is_some() || request.address.is_some_and(|a| a != self.address) {
            return Outcome::Silent("another station's request");
        }
        match code {
            Some(code) => self.error_reply(protocol, Some(request), code),
            None => Outcome::Silent("the frame is in another variant of the protocol"),
        }
    }

    /// Takes the request frames out of `input` (bytes received so far; noise before a
    /// start sequence is skipped, an unfinished frame is left in it) and returns what the
    /// drive sends in answer, faults applied. Over a protocol with variants, frames are
    /// read in the variant in force (see [`VirtualDrive::respond`]); a frame that another
    /// variant's form would continue (a CR that an LF may follow) waits for the next byte
    /// or for the line's silence ([`VirtualDrive::receive_before_silence`]).
    pub fn receive(&mut self, protocol: &Protocol, input: &mut Vec<u8>) -> Vec<Transmission> {
        self.take_frames(protocol, input, false)
    }

    /// [`VirtualDrive::receive`] for bytes the line's silence follows (a master's whole
    /// burst): a frame that another variant's form could still have continued is taken
    /// as it stands, and a frame that never completed in the variant in force but is whole
    /// in another's gets the mismatch error.
    pub fn receive_before_silence(
        &mut self,
        protocol: &Protocol,
        input: &mut Vec<u8>,
    ) -> Vec<Transmission> {
        self.take_frames(protocol, input, true)
    }

    fn take_frames(
        &mut self,
        protocol: &Protocol,
        input: &mut Vec<u8>,
        settled: bool,
    ) -> Vec<Transmission> {
        let mut sent = Vec::new();
        if input.is_empty() {
            return sent;
        }
        let variants = self.in_force(protocol);
        let protocol = variants.own.as_ref();
        let start = protocol
            .commands
            .first()
            .and_then(|c| c.request.start_bytes())
            .unwrap_or(&[]);
        loop {
            if let Some((len, again)) = self.take_follow_up(protocol, input) {
                drop(input.drain(..len));
                if let Some(reply) = again {
                    // Asking for the reply again is a request of its own.
                    self.requests += 1;
                    if !self.noise && !self.unplugged {
                        if let Some(transmission) = self.commit_faults(protocol, &[], reply) {
                            sent.push(transmission);
                        }
                    }
                }
                continue;
            }
            if !start.is_empty() {
                match find(input, start) {
                    Some(offset) => {
                        self.garbage |= offset > 0;
                        drop(input.drain(..offset));
                    }
                    None => {
                        let keep = input.len().min(start.len() - 1);
                        self.garbage |= input.len() > keep;
                        input.drain(..input.len() - keep);
                        break;
                    }
                }
            }
            if input.is_empty() {
                break;
            }
            let decoded = match variants.read(input, settled) {
                Read::Own(decoded) => Ok(decoded),
                Read::Wait => break,
                Read::Other(frame) => Err(frame),
            };
            let (outcome, used) = match decoded {
                Err(frame) => {
                    // Another variant's frame: the mismatch error, in the variant in force.
                    self.requests += 1;
                    (
                        self.answer_mismatch(protocol, &frame, variants.mismatch),
                        frame.len,
                    )
                }
                Ok(Ok(Found::Frame { frame, .. })) => {
                    self.requests += 1;
                    self.count_addressed(&frame);
                    let mut pending = self.faults.front().cloned();
                    let rejected = std::mem::take(&mut self.garbage)
                        && protocol.timing.before_start == crate::serial::BeforeStart::Reject;
                    let outcome = if self.unplugged {
                        Outcome::Silent("unplugged from the line")
                    } else if self.starting_up() {
                        Outcome::Silent("starting up after power-on")
                    } else if rejected {
                        Outcome::Silent("bytes before the start sequence reject the frame")
                    } else if pending == Some(Fault::AnswerBroadcast) {
                        self.faults.pop_front();
                        pending = None;
                        let own = self.address;
                        self.address = frame.address.unwrap_or(own);
                        // A broadcast is answered as if it addressed this station alone.
                        let frame = crate::protocol::DecodedRequest {
                            address: frame.address.or(frame.broadcast.map(|_| own)),
                            broadcast: None,
                            ..frame
                        };
                        let outcome = self.answer(protocol, &frame);
                        self.address = own;
                        outcome
                    } else {
                        self.answer(protocol, &frame)
                    };
                    let outcome = match (pending, outcome) {
                        (Some(Fault::WrongStation), Outcome::Reply(_)) => {
                            self.faults.pop_front();
                            let own = self.address;
                            let other = own.wrapping_add(1);
                            self.address = frame.address.map_or(own, |_| other);
                            let mut wrong = frame;
                            wrong.address = frame.address.map(|_| other);
                            let outcome = self.answer(protocol, &wrong);
                            self.address = own;
                            outcome
                        }
                        (_, outcome) => outcome,
                    };
                    // A write of the station register moves the station (its reply is
                    // already made, from the station addressed).
                    self.follow_station_register();
                    let reply = match &outcome {
                        Outcome::Reply(bytes) => Some(bytes.as_slice()),
                        Outcome::Silent(_) => None,
                    };
                    self.note_reply(protocol, frame.command.code, reply);
                    (outcome, frame.len)
                }
                Ok(Ok(Found::Incomplete)) => break,
                Ok(Err(error)) => {
                    let checksum = error.kind() == DecodeErrorKind::ChecksumMismatch;
                    // A drive whose manual gives codes for unreadable frames reads their
                    // station from the frame and counts them in a row.
                    let unreadable = if checksum {
                        self.unreadable(protocol, input, true)
                    } else {
                        None
                    };
                    match unreadable {
                        Some(unreadable::Unreadable::Frame { len, outcome }) => (outcome, len),
                        Some(unreadable::Unreadable::Wait) if !settled => break,
                        _ => match bad_checksum::repaired(protocol, input, false) {
                            bad_checksum::Repaired::Frame(request) => {
                                self.requests += 1;
                                self.count_addressed(&request);
                                (self.answer_bad_checksum(protocol, &request), request.len)
                            }
                            bad_checksum::Repaired::Incomplete if !settled => break,
                            _ if checksum => {
                                let outcome = self.refuse(protocol, None, Refusal::BadChecksum);
                                (outcome, input.len().min(start.len().max(1)))
                            }
                            _ => match unsupported::lacking(protocol, input, settled) {
                                unsupported::Lacking::Wait => break,
                                unsupported::Lacking::Frame {
                                    len,
                                    address,
                                    function,
                                } => {
                                    self.requests += 1;
                                    (self.answer_lacking(protocol, address, function), len)
                                }
                                unsupported::Lacking::No => {
                                    match self.unreadable(protocol, input, false) {
                                        Some(unreadable::Unreadable::Frame { len, outcome }) => {
                                            (outcome, len)
                                        }
                                        Some(unreadable::Unreadable::Wait) if !settled => break,
                                        _ => (
                                            Outcome::Silent("framing error"),
                                            if start.is_empty() { input.len() } else { 1 },
                                        ),
                                    }
                                }
                            },
                        },
                    }
                }
            };
            let request: Vec<u8> = input.drain(..used).collect();
            if self.noise || self.unplugged {
                // The line is jammed, or the drive is off it: no reply gets through.
                continue;
            }
            if self.echo {
                // The line returns what the master sent, whether the drive answers or not.
                sent.push(Transmission {
                    bytes: request.clone(),
                    delayed: false,
                    split: None,
                    wait: Duration::ZERO,
                    request_len: request.len(),
                });
            }
            if let Outcome::Reply(bytes) = outcome {
                if let Some(transmission) = self.commit_faults(protocol, &request, bytes) {
                    self.tally.answered += 1;
                    sent.push(transmission);
                }
            }
        }
        sent
    }

    /// Counts `request` in [`Tally::addressed`] when it is for this station: its own
    /// number, a broadcast, or a frame without a station number (a point-to-point line).
    fn count_addressed(&mut self, request: &DecodedRequest<'_>) {
        if request.broadcast.is_some() || request.address.is_none_or(|a| a == self.address) {
            self.tally.addressed += 1;
            self.unreadable_in_a_row = 0;
        }
    }

    /// Applies the next pending fault to a reply.
    fn commit_faults(
        &mut self,
        protocol: &Protocol,
        request: &[u8],
        mut bytes: Vec<u8>,
    ) -> Option<Transmission> {
        let mut transmission = Transmission {
            bytes: Vec::new(),
            delayed: false,
            split: None,
            wait: self.reply_delay(protocol) + requested_wait(protocol, request),
            request_len: request.len(),
        };
        match self.faults.pop_front() {
            Some(Fault::DropReply) => return None,
            Some(Fault::CorruptChecksum) => {
                faults::corrupt_checksum(protocol, &mut bytes);
            }
            Some(Fault::Delay) => transmission.delayed = true,
            Some(Fault::GarbageBefore(garbage)) => transmission.bytes.extend(garbage),
            Some(Fault::SplitBytes(gap)) => transmission.split = Some(gap),
            Some(other) => self.faults.push_front(other),
            None => {}
        }
        transmission.bytes.extend(bytes);
        Some(transmission)
    }
}

/// A protocol in the variant a drive has in force, and its other variants.
struct InForce<'p> {
    /// The variant in force.
    own: Cow<'p, Protocol>,
    /// The others.
    others: Vec<Protocol>,
    /// The error code a frame in another variant's form gets.
    mismatch: Option<u16>,
}

/// What the bytes at the start of the input are, read in the variant in force.
enum Read<'a> {
    /// As the variant in force reads them (a frame, an unfinished one, or an error).
    Own(Result<Found<DecodedRequest<'a>>, crate::error::DecodeError>),
    /// A whole frame of another variant.
    Other(DecodedRequest<'a>),
    /// A frame in force that another variant's form would continue: the next byte (or
    /// the line's silence) decides.
    Wait,
}

impl InForce<'_> {
    /// Reads the frame at the start of `input`. A frame whole in the variant in force is
    /// its frame unless another variant's frame goes on past it (then that frame is the
    /// one received), or, before the line's silence (`settled`), may still go on. A frame
    /// the variant in force cannot read, or that never completed in it by the silence, is
    /// another variant's when one reads it whole.
    fn read<'a>(&'a self, input: &[u8], settled: bool) -> Read<'a> {
        let own = self.own.decode_request(input);
        if self.others.is_empty() {
            return Read::Own(own);
        }
        let whole_other = || {
            self.others
                .iter()
                .find_map(|other| match other.decode_request(input) {
                    Ok(Found::Frame { frame, .. }) => Some(frame),
                    _ => None,
                })
        };
        match &own {
            Ok(Found::Frame { frame, .. }) => {
                let len = frame.len;
                for other in &self.others {
                    match other.decode_request(input) {
                        Ok(Found::Frame { frame, .. }) if frame.len > len => {
                            return Read::Other(frame)
                        }
                        Ok(Found::Incomplete) if !settled => return Read::Wait,
                        _ => {}
                    }
                }
                Read::Own(own)
            }
            Ok(Found::Incomplete) if !settled => Read::Own(own),
            _ => match whole_other() {
                Some(frame) => Read::Other(frame),
                None => Read::Own(own),
            },
        }
    }
}

fn find(haystack: &[u8], needle: &[u8]) -> Option<usize> {
    haystack.windows(needle.len()).position(|w| w == needle)
}

/// A virtual drive shared between a test (or a server) and the masters talking to it.
/// Cloning it shares the same drive.
#[derive(Debug, Clone)]
pub struct Simulator {
    drive: Arc<Mutex<VirtualDrive>>,
}

impl Simulator {
    /// A drive in its factory state (see [`VirtualDrive::new`]).
    pub fn new(drive: &'static DriveInfo) -> Simulator {
        Simulator::from_drive(VirtualDrive::new(drive))
    }

    /// Shares `drive`.
    pub fn from_drive(drive: VirtualDrive) -> Simulator {
        Simulator {
            drive: Arc::new(Mutex::new(drive)),
        }
    }

    /// The drive, locked. A poisoned lock only means a thread panicked while holding it;
    /// the drive's state is still usable.
    pub fn lock(&self) -> MutexGuard<'_, VirtualDrive> {
        self.drive.lock().unwrap_or_else(PoisonError::into_inner)
    }

    /// An in-process transport to the drive, speaking `protocol`.
    pub fn link(&self, protocol: &'static Protocol) -> SimLink {
        SimLink::new(self.clone(), protocol)
    }

    /// A typed master connected to the drive over `protocol`, with the drive's default
    /// serial settings and timing, addressing the drive's station.
    pub fn master<D: 'static>(&self, protocol: &'static DriveProtocol<D>) -> Master<SimLink, D> {
        let info = self.lock().drive;
        let address = self.lock().address;
        Master::new(
            self.link(protocol.protocol()),
            protocol,
            info.serial.default,
            info.serial.timing,
        )
        .with_address(Some(address))
    }

    /// Advances the simulated clock (see [`VirtualDrive::advance`]).
    pub fn advance(&self, elapsed: Duration) {
        self.lock().advance(elapsed);
    }

    /// Commits `fault` (see [`VirtualDrive::inject`]).
    pub fn inject(&self, fault: Fault) {
        self.lock().inject(fault);
    }

    /// Whether `fault` is pending or in force.
    pub fn has_fault(&self, fault: &Fault) -> bool {
        self.lock().has_fault(fault)
    }

    /// Stops every fault (see [`VirtualDrive::clear_faults`]).
    pub fn clear_faults(&self) {
        self.lock().clear_faults();
    }

    /// Request frames received so far (see [`VirtualDrive::requests`]).
    pub fn requests(&self) -> u64 {
        self.lock().requests()
    }

    /// What the station saw so far (see [`VirtualDrive::tally`]).
    pub fn tally(&self) -> Tally {
        self.lock().tally()
    }

    /// Requests addressed to this station so far, answered or not (see
    /// [`Tally::addressed`]).
    pub fn requests_received(&self) -> u64 {
        self.lock().tally().addressed
    }

    /// Unplugs the drive or plugs it back (see [`VirtualDrive::set_unplugged`]).
    pub fn set_unplugged(&self, unplugged: bool) {
        self.lock().set_unplugged(unplugged);
    }

    /// Trips the drive (see [`VirtualDrive::inject_trip`]).
    pub fn inject_trip(&self, code: u16) {
        self.lock().inject_trip(code);
    }

    /// Powers the drive off and on (see [`VirtualDrive::power_cycle`]).
    pub fn power_cycle(&self) {
        self.lock().power_cycle();
    }
}

/// The wait before the reply a request asks for ([`crate::Role::ReplyWait`], in tens of
/// milliseconds), where its layout carries one.
fn requested_wait(protocol: &Protocol, request: &[u8]) -> Duration {
    protocol
        .decode_request_exact(request)
        .ok()
        .and_then(|decoded| {
            decoded
                .values
                .get(&decoded.command.request, crate::Role::ReplyWait)
        })
        .map_or(Duration::ZERO, |tens| {
            Duration::from_millis(10 * u64::from(tens))
        })
}
