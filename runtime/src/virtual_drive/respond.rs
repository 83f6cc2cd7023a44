//! Answering one request: the reverse of the master. The request is decoded with the
//! protocol's layouts, checked against the register table and the drive's state, and the
//! reply (or the manual's error reply) is encoded with the same layouts.

use super::motor::engineering;
use super::VirtualDrive;
use crate::behaviour::Refusals;
use crate::broadcast::{self as broadcasts, Broadcast};
use crate::codec::{self, FrameValues, Roles};
use crate::info::RegisterInfo;
use crate::kinds::{CommandKind, DataType, Space};
use crate::layout::{FrameLayout, Part, Role};
use crate::protocol::{CommandSpec, DecodedRequest, PreStep, Protocol};

/// Why the virtual drive refused a request.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Refusal {
    /// No register at that number (or index).
    UnknownRegister,
    /// A write to a read-only register (or a persistent write of a RAM-only one).
    ReadOnly,
    /// A value outside the register's range, bounds named after other registers included.
    OutOfRange,
    /// A write to a register that cannot change while the motor runs.
    WhileRunning,
    /// A frame whose checksum does not match.
    BadChecksum,
    /// A write to the command word or the frequency command while the mode register is
    /// outside the mode the behaviour model requires.
    WrongMode,
}

impl Refusal {
    /// The error code `refusals` gives for it; `None`: the drive stays silent.
    pub fn code(self, refusals: &Refusals) -> Option<u16> {
        match self {
            Refusal::UnknownRegister => refusals.unknown_register,
            Refusal::ReadOnly => refusals.read_only,
            Refusal::OutOfRange => refusals.out_of_range,
            Refusal::WhileRunning => refusals.while_running,
            Refusal::BadChecksum => refusals.bad_checksum,
            Refusal::WrongMode => refusals.wrong_mode,
        }
    }
}

/// What the drive does with one request frame.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Outcome {
    /// It answers with these bytes.
    Reply(Vec<u8>),
    /// It stays silent, for this reason.
    Silent(&'static str),
}

/// The code a normal reply to `command` carries for a register of `data_type`: the
/// request's own code, or the reply code listed at the data type's position.
pub(super) fn reply_code(command: &CommandSpec, data_type: DataType) -> u32 {
    match command.reply_codes.len() {
        0 => command.code,
        1 => command.reply_codes[0],
        _ => command
            .data_types
            .iter()
            .position(|t| *t == data_type)
            .and_then(|i| command.reply_codes.get(i).copied())
            .unwrap_or(command.reply_codes[0]),
    }
}

/// The code of an error reply to `command`: the code the protocol file gives it, else the
/// one code the error layout allows, else the request's own code.
fn error_code_for(layout: &FrameLayout, command: Option<&CommandSpec>) -> u32 {
    match (
        command.and_then(|c| c.error_code),
        layout.allowed_commands(),
    ) {
        (Some(code), _) => code,
        (None, [only]) => *only,
        _ => command.map_or(0, |c| c.code),
    }
}

impl VirtualDrive {
    /// Lower-case letters while tripped, when the protocol says so.
    pub(super) fn shown(&self, protocol: &Protocol, code: u32) -> u32 {
        if protocol.lowercase_means_tripped && self.motor.trip.is_some() {
            if let Ok(byte) = u8::try_from(code) {
                return u32::from(byte.to_ascii_lowercase());
            }
        }
        code
    }

    /// Answers a decoded request addressed to this drive.
    pub(crate) fn answer(&mut self, protocol: &Protocol, request: &DecodedRequest<'_>) -> Outcome {
        if let Some(broadcast) = request.broadcast {
            return self.answer_broadcast(protocol, request, broadcast);
        }
        if let Some(address) = request.address {
            if address != self.address {
                return Outcome::Silent("another station's request");
            }
        }
        if let (Some(process), Some(behaviour)) = (request.process, self.behaviour()) {
            self.process_words(behaviour, process);
        }
        let paged;
        let request = match self.unpage(protocol, request) {
            super::pages::Paged::Plain => request,
            super::pages::Paged::Register(register) => {
                paged = DecodedRequest {
                    register: Some(register),
                    ..*request
                };
                &paged
            }
            super::pages::Paged::Done(outcome) => return outcome,
        };
        let narrowed;
        let request = match self.command_carrying(protocol, request) {
            Some(command) => {
                narrowed = DecodedRequest {
                    command,
                    ..*request
                };
                &narrowed
            }
            None => request,
        };
        if request.command.no_reply {
            self.unanswered(protocol, request);
            return Outcome::Silent("the command is never answered");
        }
        if request.command.kind.is_write() && self.target_of(request).is_ok_and(|i| i.no_reply) {
            // Carried out as any write (a refusal included), but never answered.
            let _ = self.write(protocol, request);
            return Outcome::Silent("writes of this register are never answered");
        }
        if self.is_block_read(protocol, request) {
            return match self.read_block(protocol, request) {
                Ok(block) => self.reply_block(protocol, request, &block),
                Err(refusal) => self.refuse(protocol, Some(request), refusal),
            };
        }
        if self.is_block_write(protocol, request) {
            return match self.write_block(protocol, request) {
                Ok(()) => self.reply(protocol, request, request.data, 0),
                Err(refusal) => self.refuse(protocol, Some(request), refusal),
            };
        }
        let widest = request.command.data_types.iter().map(|t| t.size()).max();
        if widest.is_some_and(|widest| request.values.data_size > widest) {
            // More data than any type the command carries (a Modbus read of two words where
            // the drive reads one): a data range error, as the manual's refusals say.
            return self.refuse(protocol, Some(request), Refusal::OutOfRange);
        }
        if request
            .register
            .is_some_and(|number| !request.command.serves_register(number))
        {
            return self.refuse(protocol, Some(request), Refusal::UnknownRegister);
        }
        let result = match request.command.kind {
            kind if kind.is_write() && request.command.percent_of.is_some() => {
                self.write_percent(request).map(|()| (request.data, 0))
            }
            CommandKind::Block => return self.block(protocol, request),
            CommandKind::Read => self.read(protocol, request),
            CommandKind::WriteRam | CommandKind::WritePersistent => self.write(protocol, request),
            CommandKind::Process => Ok((0, 0)),
            // The query comes back unchanged.
            CommandKind::Echo => Ok((request.data, 0)),
            CommandKind::ReadText => Err(Refusal::UnknownRegister),
        };
        match result {
            Ok((data, data_size)) => self.reply(protocol, request, data, data_size),
            Err(refusal) => self.refuse(protocol, Some(request), refusal),
        }
    }

    /// Carries out a command that is never answered: a write of a register it may address
    /// (RAM only; for data that is a percentage of another register, converted to the
    /// addressed register's unit first, without range checks), and the sender's trip state
    /// when its lower case says so. A register it may not address is ignored (the manual's
    /// error cannot be sent back).
    fn unanswered(&mut self, protocol: &Protocol, request: &DecodedRequest<'_>) {
        let command = request.command;
        if command.lowercase_means_sender_tripped {
            self.sender_tripped = request.sender_tripped();
        }
        let Some(number) = request.register else {
            return;
        };
        if !command.serves_register(number) || !command.kind.is_write() {
            return;
        }
        let _ = match &command.percent_of {
            Some(_) => self.write_percent(request),
            None => self.write(protocol, request).map(|_| ()),
        };
    }

    /// A write whose data is a percentage of another register: converted to the addressed
    /// register's unit and stored in RAM, without range checks (the drive makes none).
    fn write_percent(&mut self, request: &DecodedRequest<'_>) -> Result<(), Refusal> {
        let Some(percent_of) = &request.command.percent_of else {
            return Err(Refusal::UnknownRegister);
        };
        let info = self.target_of(request)?;
        if !request
            .register
            .is_some_and(|n| request.command.serves_register(n))
        {
            return Err(Refusal::UnknownRegister);
        }
        if info.access == crate::kinds::Access::ReadOnly || info.data_type == DataType::Text {
            return Err(Refusal::ReadOnly);
        }
        // The first of the description's conversions that holds (frequency points chosen
        // by parameters), else the plain proportion `value = percent x reference / 100`;
        // truncated to the register's step.
        let converted = percent_of
            .received_by
            .iter()
            .find_map(|id| self.convert(id, &[f64::from(request.data)]));
        let value = converted.unwrap_or_else(|| {
            self.value_of(&percent_of.register)
                .map_or(0.0, |reference| {
                    percent_of.from_raw(request.data, reference)
                })
        });
        let raw = (value / info.scale + 1e-9)
            .floor()
            .clamp(0.0, f64::from(u32::MAX)) as u32;
        self.storage.set(info, 0, raw, false);
        self.value_written(info, raw);
        self.refresh();
        Ok(())
    }

    /// A broadcast: carried out when the drive's rule lists the command and the drive is
    /// among the stations addressed, answered (with the drive's own number) only when the
    /// rule names this drive to answer.
    fn answer_broadcast(
        &mut self,
        protocol: &Protocol,
        request: &DecodedRequest<'_>,
        broadcast: Broadcast,
    ) -> Outcome {
        let Some(rule) = &protocol.broadcast else {
            return Outcome::Silent("the drive takes no broadcasts over this protocol");
        };
        if !request.command.kind.is_write() || !rule.commands.contains(&request.command.code) {
            return Outcome::Silent("a command the drive does not carry out when broadcast");
        }
        let radix = request
            .command
            .request
            .field(Role::Address)
            .map_or(10, broadcasts::field_radix);
        if !broadcasts::addresses(&broadcast, self.address, radix) {
            return Outcome::Silent("a broadcast to other stations");
        }
        let own = DecodedRequest {
            address: Some(self.address),
            broadcast: None,
            ..*request
        };
        let outcome = self.answer(protocol, &own);
        let answers =
            rule.responder(&broadcast, protocol.address_range.0, radix) == Some(self.address);
        match outcome {
            Outcome::Reply(_) if answers => outcome,
            _ => Outcome::Silent("a broadcast another station answers, or none"),
        }
    }

    /// The error reply for `refusal`, or silence when the protocol has no code for it.
    pub(crate) fn refuse(
        &self,
        protocol: &Protocol,
        request: Option<&DecodedRequest<'_>>,
        refusal: Refusal,
    ) -> Outcome {
        let refusals = self
            .behaviour()
            .map_or(&Refusals::SILENT, |b| b.refusals(&protocol.id));
        match refusal.code(refusals) {
            Some(code) => self.error_reply(protocol, request, code),
            None => Outcome::Silent("the manual gives no error reply for this"),
        }
    }

    /// The protocol's error reply carrying the error code `code`, answering `request` (its
    /// station, register and optional parts) or, for a frame that could not be read, with
    /// the protocol's default optional parts.
    pub(crate) fn error_reply(
        &self,
        protocol: &Protocol,
        request: Option<&DecodedRequest<'_>>,
        code: u16,
    ) -> Outcome {
        let Some(layout) = &protocol.error_reply else {
            return Outcome::Silent("the manual gives no error reply for this");
        };
        let command = error_code_for(layout, request.map(|r| r.command));
        let mut values = FrameValues::default();
        match request {
            Some(request) => mirror_optional_parts(
                &request.command.request,
                &request.values,
                layout,
                &mut values,
            ),
            None => {
                for name in protocol.default_optional_parts.iter() {
                    values.include(layout, &[name]);
                }
            }
        }
        let roles = Roles {
            address: request.and_then(|r| r.address).map(u32::from),
            command: Some(self.shown(protocol, command)),
            register: request.and_then(|r| r.wire_register).map(u32::from),
            index: request.and_then(|r| r.index).map(u32::from),
            error_code: Some(u32::from(code)),
            ..self.process_roles(layout)
        };
        values.fill(layout, &roles);
        encode(layout, &values, protocol)
    }

    /// Whether `request` reads more than its first register: a read by the protocol's
    /// block-read command whose count goes beyond the register it names.
    fn is_block_read(&self, protocol: &Protocol, request: &DecodedRequest<'_>) -> bool {
        let command = request.command;
        if !protocol
            .block_read_command(command.space)
            .is_some_and(|block| std::ptr::eq(block, command))
        {
            return false;
        }
        let own = self
            .target_of(request)
            .map_or(2, |info| info.data_type.size().max(1));
        request.values.data_size > own
    }

    /// The registers a block read covers, each in the reply data field's byte order, in
    /// address order. A block that does not begin and end on whole registers, names a
    /// number with no register, or exceeds the protocol's count is refused.
    fn read_block(
        &self,
        protocol: &Protocol,
        request: &DecodedRequest<'_>,
    ) -> Result<Vec<u8>, Refusal> {
        let command = request.command;
        let size = usize::from(request.values.data_size);
        let words = size / 2;
        if size % 2 != 0 || words > usize::from(protocol.max_words_per_read) {
            return Err(Refusal::OutOfRange);
        }
        let wire = request.wire_register.ok_or(Refusal::UnknownRegister)?;
        let little_endian = data_little_endian(&command.reply);
        let mut block = Vec::with_capacity(size);
        let mut word = 0usize;
        let mut found = 0usize;
        while word < words {
            let info = u16::try_from(usize::from(wire) + word * word_step(command.space))
                .ok()
                .and_then(|at| protocol.from_wire(command, at, None))
                .and_then(|number| self.drive.register_for(command.space, number, false))
                .filter(|info| info.data_type != DataType::Text)
                .filter(|info| word + usize::from(info.data_type.size().clamp(2, 4)) / 2 <= words);
            let Some(info) = info else {
                if !protocol.partial_blocks {
                    return Err(Refusal::UnknownRegister);
                }
                // A register the drive does not have reads as 0 in a block it answers.
                block.extend_from_slice(&[0, 0]);
                word += 1;
                continue;
            };
            found += 1;
            let width = usize::from(info.data_type.size().clamp(2, 4));
            let index = if info.array_len == 0 {
                0
            } else {
                self.selected_index.min(u16::from(info.array_len) - 1)
            };
            let raw = self.storage.get(info, index);
            if little_endian {
                block.extend_from_slice(&raw.to_le_bytes()[..width]);
            } else {
                block.extend_from_slice(&raw.to_be_bytes()[4 - width..]);
            }
            word += width / 2;
        }
        if found == 0 {
            return Err(Refusal::UnknownRegister);
        }
        Ok(block)
    }

    /// Whether `request` writes more than its first register: a write by the protocol's
    /// block-write command whose data goes beyond the register it names (or names none).
    fn is_block_write(&self, protocol: &Protocol, request: &DecodedRequest<'_>) -> bool {
        let command = request.command;
        if !protocol
            .block_write_command(command.space)
            .is_some_and(|block| std::ptr::eq(block, command))
        {
            return false;
        }
        let own = self
            .target_of(request)
            .map_or(2, |info| info.data_type.size().max(1));
        request.values.data_size > own
    }

    /// Writes the consecutive registers a block write carries, word `n` to the register
    /// `n` words after the first (a double-word register takes two, high word first in a
    /// big-endian data field). More words than [`Protocol::max_words_per_write`] is a data
    /// value error. A register that does not exist, or refuses its value, refuses the
    /// whole request, or with [`Protocol::partial_blocks`] is left as it is as long as one
    /// register of the block is written. Nothing is written when the request is refused.
    fn write_block(
        &mut self,
        protocol: &Protocol,
        request: &DecodedRequest<'_>,
    ) -> Result<(), Refusal> {
        let command = request.command;
        let size = usize::from(request.values.data_size);
        let count = size / 2;
        if size % 2 != 0 || count > usize::from(protocol.max_words_per_write) {
            return Err(Refusal::OutOfRange);
        }
        let little_endian = data_little_endian(&command.request);
        let words: Vec<u16> = if size > 4 {
            request.data_words.as_slice().to_vec()
        } else {
            let bytes = if little_endian {
                request.data.to_le_bytes()[..size].to_vec()
            } else {
                request.data.to_be_bytes()[4 - size..].to_vec()
            };
            bytes
                .chunks_exact(2)
                .map(|pair| {
                    let pair = [pair[0], pair[1]];
                    if little_endian {
                        u16::from_le_bytes(pair)
                    } else {
                        u16::from_be_bytes(pair)
                    }
                })
                .collect()
        };
        if words.len() != count {
            return Err(Refusal::OutOfRange);
        }
        let wire = request.wire_register.ok_or(Refusal::UnknownRegister)?;
        let persistent = command.kind == CommandKind::WritePersistent
            || (command.space == Space::Parameter
                && self.persistent_writes
                && protocol
                    .pre_steps
                    .iter()
                    .any(|step| matches!(step, PreStep::Persistence { .. })));
        let mut writes: Vec<(&'static RegisterInfo, u32)> = Vec::new();
        let mut refused = None;
        let mut at = 0usize;
        while at < count {
            let (outcome, width) = self.block_word(protocol, command, wire, at, &words);
            at += width;
            match outcome {
                Ok((info, raw)) => match self.check_value(info, raw, persistent) {
                    Ok(()) => writes.push((info, raw)),
                    Err(refusal) if protocol.partial_blocks => {
                        refused.get_or_insert(refusal);
                    }
                    Err(refusal) => return Err(refusal),
                },
                Err(refusal) if protocol.partial_blocks => {
                    refused.get_or_insert(refusal);
                }
                Err(refusal) => return Err(refusal),
            }
        }
        // The manual's forbidden combinations, over the values the whole block leaves.
        let block = writes.clone();
        let mut kept = Vec::with_capacity(writes.len());
        for (info, raw) in writes {
            match self.check_combinations(info, raw, &block) {
                Ok(()) => kept.push((info, raw)),
                Err(refusal) if protocol.partial_blocks => {
                    refused.get_or_insert(refusal);
                }
                Err(refusal) => return Err(refusal),
            }
        }
        let writes = kept;
        if writes.is_empty() {
            return Err(refused.unwrap_or(Refusal::UnknownRegister));
        }
        let command_register = self.behaviour().map(|b| self.served(b.command.register));
        for (info, raw) in writes {
            let index = if info.array_len == 0 {
                0
            } else {
                self.selected_index.min(u16::from(info.array_len) - 1)
            };
            self.storage
                .set(info, index, raw, persistent && !info.stored_in_ram_only());
            if command_register == Some(info.id) {
                self.command_written(raw);
            }
        }
        self.refresh();
        Ok(())
    }

    /// The register word `at` of a block write goes to, with its value and how many words
    /// it takes; a word with no register (or a double word the block cuts) takes one.
    #[allow(clippy::type_complexity)]
    fn block_word(
        &self,
        protocol: &Protocol,
        command: &CommandSpec,
        wire: u16,
        at: usize,
        words: &[u16],
    ) -> (Result<(&'static RegisterInfo, u32), Refusal>, usize) {
        let info = u16::try_from(usize::from(wire) + at * word_step(command.space))
            .ok()
            .and_then(|number| protocol.from_wire(command, number, Some(u32::from(words[at]))))
            .filter(|number| command.serves_register(*number))
            .and_then(|number| self.drive.register_for(command.space, number, true));
        let Some(info) = info else {
            return (Err(Refusal::UnknownRegister), 1);
        };
        if info.data_type == DataType::Text {
            return (Err(Refusal::ReadOnly), 1);
        }
        if info.data_type.size() <= 2 {
            return (Ok((info, u32::from(words[at]))), 1);
        }
        let Some(&low_or_high) = words.get(at + 1) else {
            return (Err(Refusal::OutOfRange), 1);
        };
        let raw = if data_little_endian(&command.request) {
            u32::from(words[at]) | (u32::from(low_or_high) << 16)
        } else {
            (u32::from(words[at]) << 16) | u32::from(low_or_high)
        };
        (Ok((info, raw)), 2)
    }

    /// The reply to a block read: up to 4 bytes as a number, more as the data field's bytes.
    fn reply_block(
        &self,
        protocol: &Protocol,
        request: &DecodedRequest<'_>,
        block: &[u8],
    ) -> Outcome {
        if block.len() <= 4 {
            let fold = |acc: u32, byte: &u8| (acc << 8) | u32::from(*byte);
            let data = if data_little_endian(&request.command.reply) {
                block.iter().rev().fold(0, fold)
            } else {
                block.iter().fold(0, fold)
            };
            return self.reply(protocol, request, data, block.len() as u8);
        }
        self.reply_with(protocol, request, 0, block.len() as u8, block)
    }

    pub(super) fn reply(
        &self,
        protocol: &Protocol,
        request: &DecodedRequest<'_>,
        data: u32,
        data_size: u8,
    ) -> Outcome {
        self.reply_with(protocol, request, data, data_size, &[])
    }

    /// A normal reply carrying `data`, or the `block` of registers when there is one.
    fn reply_with(
        &self,
        protocol: &Protocol,
        request: &DecodedRequest<'_>,
        data: u32,
        data_size: u8,
        block: &[u8],
    ) -> Outcome {
        let command = request.command;
        let layout = &command.reply;
        let mut values = FrameValues {
            data_size: if data_size == 0 {
                request.values.data_size
            } else {
                data_size
            },
            ..FrameValues::default()
        };
        mirror_optional_parts(&command.request, &request.values, layout, &mut values);
        let data_type = match data_size {
            4 => DataType::DoubleWord,
            _ => DataType::Word,
        };
        let roles = Roles {
            address: request.address.map(u32::from),
            command: Some(self.shown(protocol, reply_code(command, data_type))),
            register: request.wire_register.map(u32::from),
            index: request.index.map(u32::from),
            data: Some(data),
            // The decimals of the scale in force (a scale selector's choice, if any).
            decimals: self
                .target_of(request)
                .ok()
                .map(|info| u32::from(self.scaled(info).decimals())),
            ..self.process_roles(layout)
        };
        values.fill(layout, &roles);
        encode_with(layout, &values, block, protocol)
    }

    /// Status word and output as the reply's process words, when the drive has them.
    fn process_roles(&self, layout: &FrameLayout) -> Roles {
        let Some(process) = self.behaviour().and_then(|b| b.process.as_ref()) else {
            return Roles::default();
        };
        if !layout.has(Role::Process1) {
            return Roles::default();
        }
        let word = |id: &str| {
            self.drive
                .register(id)
                .map(|info| self.storage.get(info, 0))
        };
        Roles {
            process_1: word(process.status),
            process_2: word(process.output),
            ..Roles::default()
        }
    }

    /// Process words from the master: control word and reference, applied only when the
    /// control word acts (its required bits are set).
    fn process_words(&mut self, behaviour: &crate::behaviour::Behaviour, words: [u16; 2]) {
        let Some(process) = &behaviour.process else {
            return;
        };
        let [control, reference] = words.map(u32::from);
        if !behaviour
            .command
            .require
            .iter()
            .all(|bit| bit.is_active(control))
        {
            return;
        }
        if let Some(info) = self.drive.register(process.reference) {
            self.storage.set(info, 0, reference, false);
        }
        if let Some(info) = self.drive.register(process.control) {
            self.storage.set(info, 0, control, false);
        }
        self.command_written(control);
    }

    /// Of commands whose requests are alike (a read of a word and a read of a byte, told
    /// apart only by their replies' data width), the one that carries the data type of the
    /// register the request names, where the decoded command does not: its reply has the
    /// register's width. `None`: the decoded command answers.
    fn command_carrying<'p>(
        &self,
        protocol: &'p Protocol,
        request: &DecodedRequest<'_>,
    ) -> Option<&'p CommandSpec> {
        let decoded = request.command;
        let info = self.target_of(request).ok()?;
        if decoded.carries(info.data_type) {
            return None;
        }
        protocol.commands.iter().find(|c| {
            c.kind == decoded.kind
                && c.space == decoded.space
                && c.carries(info.data_type)
                && c.request.parts == decoded.request.parts
        })
    }

    /// The register a request names, in the command's space (of two sharing the number,
    /// the one the request's direction reaches).
    fn target_of(&self, request: &DecodedRequest<'_>) -> Result<&'static RegisterInfo, Refusal> {
        let number = request.register.ok_or(Refusal::UnknownRegister)?;
        self.drive
            .register_for(
                request.command.space,
                number,
                request.command.kind.is_write(),
            )
            .ok_or(Refusal::UnknownRegister)
    }

    fn index_of(&self, info: &RegisterInfo, request: &DecodedRequest<'_>) -> Result<u16, Refusal> {
        if info.array_len == 0 {
            return Ok(0);
        }
        let index = request.index.unwrap_or(self.selected_index);
        if index >= u16::from(info.array_len) {
            return Err(Refusal::UnknownRegister);
        }
        Ok(index)
    }

    /// Registers a request of `size` bytes covers, from `first`: one, or consecutive
    /// 16-coil words in coil space.
    fn covered(
        &self,
        first: &'static RegisterInfo,
        size: u8,
        writing: bool,
    ) -> Result<Vec<&'static RegisterInfo>, Refusal> {
        let own = first.data_type.size().max(1);
        if size <= own {
            return Ok(vec![first]);
        }
        let mut covered = vec![first];
        let mut address = first.address;
        if first.space == Space::Coil {
            // 16-coil words, the next word 16 coils on.
            for _ in 1..size / own {
                address = address.checked_add(16).ok_or(Refusal::UnknownRegister)?;
                covered.push(
                    self.drive
                        .register_for(Space::Coil, address, writing)
                        .ok_or(Refusal::UnknownRegister)?,
                );
            }
            return Ok(covered);
        }
        // Consecutive one-word registers (a Modbus write of several registers), each of its
        // own: the data carries one word per register.
        if own != 2 || size % 2 != 0 {
            return Err(Refusal::OutOfRange);
        }
        for _ in 1..size / 2 {
            address = address.checked_add(1).ok_or(Refusal::UnknownRegister)?;
            let next = self
                .drive
                .register_for(first.space, address, writing)
                .ok_or(Refusal::UnknownRegister)?;
            if next.data_type.size() != 2 {
                return Err(Refusal::OutOfRange);
            }
            covered.push(next);
        }
        Ok(covered)
    }

    fn read(
        &mut self,
        _protocol: &Protocol,
        request: &DecodedRequest<'_>,
    ) -> Result<(u32, u8), Refusal> {
        let first = self.target_of(request)?;
        let index = self.index_of(first, request)?;
        let size = request.values.data_size;
        let registers = self.covered(first, size, false)?;
        if registers.len() == 1 {
            return Ok((
                self.storage.get(first, index),
                first.data_type.size().max(size),
            ));
        }
        // Coil words: the first register in the lowest bits.
        let mut data = 0u32;
        for (i, info) in registers.iter().enumerate() {
            data |= (self.storage.get(info, 0) & 0xFFFF) << (16 * i);
        }
        Ok((data, size))
    }

    fn write(
        &mut self,
        protocol: &Protocol,
        request: &DecodedRequest<'_>,
    ) -> Result<(u32, u8), Refusal> {
        let space = request.command.space;
        let mut persistent = request.command.kind == CommandKind::WritePersistent;
        for step in protocol.pre_steps.iter() {
            match *step {
                PreStep::Index { register } => {
                    if space == Space::Parameter && request.wire_register == Some(register) {
                        self.selected_index = request.data as u16;
                        return Ok((request.data, 0));
                    }
                }
                PreStep::Persistence {
                    space: selector_space,
                    register,
                    persistent: selects,
                    ..
                } => {
                    if space == selector_space && request.register == Some(register) {
                        self.persistent_writes = request.data == selects;
                    } else if space == Space::Parameter && self.persistent_writes {
                        persistent = true;
                    }
                }
            }
        }
        let first = self.target_of(request)?;
        let index = self.index_of(first, request)?;
        let registers = self.covered(first, request.values.data_size, true)?;
        let words: Vec<(&'static RegisterInfo, u32)> = if registers.len() == 1 {
            vec![(first, request.data)]
        } else {
            // Coil words put the first register in the lowest bits (a little-endian data
            // field); registers written most significant byte first (Modbus 10h) put it in
            // the highest.
            let last = registers.len() - 1;
            let little_endian = data_little_endian(&request.command.request);
            registers
                .iter()
                .enumerate()
                .map(|(i, info)| {
                    let shift = if little_endian { i } else { last - i };
                    (*info, (request.data >> (16 * shift)) & 0xFFFF)
                })
                .collect()
        };
        for (info, raw) in &words {
            self.check_write(info, *raw, persistent)?;
        }
        // A drive whose persistence selector governs parameter writes stores them where
        // the selector's value before this request says (the selector's own write too).
        let selected = protocol.persistence.as_ref().and_then(|selector| {
            let value = self
                .drive
                .register_at(selector.space, selector.register)
                .map(|info| self.storage.get(info, 0))?;
            Some((selector, value == selector.persistent))
        });
        for (info, raw) in words {
            let index = if info.array_len == 0 { 0 } else { index };
            let persistent = match selected {
                Some((selector, to_eeprom))
                    if selector.governs(info.space, info.address, info.stored_in_ram_only()) =>
                {
                    to_eeprom
                }
                _ => persistent,
            };
            self.storage
                .set(info, index, raw, persistent && !info.stored_in_ram_only());
            self.value_written(info, raw);
        }
        self.refresh();
        Ok((request.data, 0))
    }

    /// Whether the drive takes `raw` for `info`: access, running state, range and bounds,
    /// and the combinations the manual forbids with what the other registers hold.
    pub(super) fn check_write(
        &self,
        info: &'static RegisterInfo,
        raw: u32,
        persistent: bool,
    ) -> Result<(), Refusal> {
        self.check_value(info, raw, persistent)?;
        self.check_combinations(info, raw, &[])
    }

    /// [`VirtualDrive::check_write`] without the forbidden combinations.
    fn check_value(
        &self,
        info: &'static RegisterInfo,
        raw: u32,
        persistent: bool,
    ) -> Result<(), Refusal> {
        if info.access == crate::kinds::Access::ReadOnly
            || info.data_type == DataType::Text
            || (persistent && info.ram_only && info.space == Space::Parameter)
        {
            return Err(Refusal::ReadOnly);
        }
        if !self.in_required_mode(info) {
            return Err(Refusal::WrongMode);
        }
        // `unknown` (the manual has no while-running column): accepted, since refusing would
        // invent a rule the manual does not state.
        if !info.writable_while_running && !info.while_running_unknown && self.is_running() {
            return Err(Refusal::WhileRunning);
        }
        let signed = if info.signed {
            match info.data_type.size() {
                4 => i64::from(raw as i32),
                _ => i64::from(raw as u16 as i16),
            }
        } else {
            i64::from(raw)
        };
        // A value taken besides the range (99999 as FFFFh) is accepted as it is.
        if info.special_raw(raw).is_some() {
            return Ok(());
        }
        // A register whose scale another register chooses has that choice's range.
        let info = self.scaled(info);
        if signed < info.raw_min || signed > info.raw_max {
            return Err(Refusal::OutOfRange);
        }
        let value = engineering(info, raw);
        let bound = |code: Option<&str>| code.and_then(|code| self.value_of(code));
        if bound(info.min_bound).is_some_and(|low| value < low - 1e-9)
            || bound(info.max_bound).is_some_and(|high| value > high + 1e-9)
        {
            return Err(Refusal::OutOfRange);
        }
        Ok(())
    }

    /// Refuses writing `raw` to `info` when it would make a combination of values the
    /// manual forbids (two stop bits with parity), as a value the drive does not accept:
    /// the other registers holding what `pending` writes in the same request, else what
    /// they hold now.
    fn check_combinations(
        &self,
        info: &'static RegisterInfo,
        raw: u32,
        pending: &[(&'static RegisterInfo, u32)],
    ) -> Result<(), Refusal> {
        let drive = self.drive;
        drive
            .check_combinations(info, raw, |code| {
                let other = drive.register(code)?;
                pending
                    .iter()
                    .find(|(written, _)| std::ptr::eq(*written, other))
                    .map(|(_, value)| *value)
                    .or_else(|| Some(self.storage.get(other, 0)))
            })
            .map_err(|_| Refusal::OutOfRange)
    }
}

impl VirtualDrive {
    /// Whether a write to `info` may be taken in the present mode: always, unless it is the
    /// command word or the frequency command and the mode register the behaviour model
    /// names holds none of the values it requires.
    fn in_required_mode(&self, info: &RegisterInfo) -> bool {
        let Some(behaviour) = self.behaviour() else {
            return true;
        };
        let Some(mode) = behaviour.command.require_mode else {
            return true;
        };
        let gated = [behaviour.command.register, behaviour.frequency.command]
            .into_iter()
            .any(|id| self.served(id) == info.id);
        if !gated {
            return true;
        }
        self.drive
            .register(mode.register)
            .is_none_or(|mode_info| mode.values.contains(&self.storage.get(mode_info, 0)))
    }
}

/// Marks present in `reply` the optional parts that were present in the request (a
/// Toshiba-style reply carries the station number, `&SUM` and `)` only if the request did).
pub(super) fn mirror_optional_parts(
    request: &FrameLayout,
    request_values: &FrameValues,
    reply: &FrameLayout,
    values: &mut FrameValues,
) {
    for (index, part) in request.parts.iter().enumerate() {
        let optional = match part {
            Part::Field(field) => field.optional.is_some(),
            Part::Checksum(checksum) => checksum.optional,
            Part::Literal { optional, .. } => *optional,
            _ => false,
        };
        if optional && request_values.parts[index].present {
            values.include(reply, &[part.name()]);
        }
    }
}

/// Whether `layout`'s data field is least significant byte first.
fn data_little_endian(layout: &FrameLayout) -> bool {
    layout.parts.iter().any(|part| {
        matches!(part, Part::Field(field) if field.role == Role::Data
            && field.format == crate::layout::Format::UintLe)
    })
}

fn encode(layout: &FrameLayout, values: &FrameValues, protocol: &Protocol) -> Outcome {
    encode_with(layout, values, &[], protocol)
}

/// Encodes a reply, with `payload` for a data field carrying a block of registers.
pub(super) fn encode_with(
    layout: &FrameLayout,
    values: &FrameValues,
    payload: &[u8],
    protocol: &Protocol,
) -> Outcome {
    let mut out = vec![0u8; usize::from(protocol.max_frame_len).max(8) + 8];
    match codec::encode_with_payload(layout, values, payload, &mut out) {
        Ok(len) => {
            out.truncate(len);
            Outcome::Reply(out)
        }
        Err(_) => Outcome::Silent("the reply cannot be encoded"),
    }
}

/// How far apart the numbers of consecutive words of a block are: one register number in
/// the parameter space, 16 coils in coil space (a 16-coil word, as [`VirtualDrive`]'s
/// single-register requests count them too).
fn word_step(space: Space) -> usize {
    if space == Space::Coil {
        16
    } else {
        1
    }
}
