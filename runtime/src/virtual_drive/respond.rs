//! Answering one request: the reverse of the master. The request is decoded with the
//! protocol's layouts, checked against the register table and the drive's state, and the
//! reply (or the manual's error reply) is encoded with the same layouts ([`super::reply`]);
//! broadcasts, runs of consecutive registers and block transfers each have a file of
//! their own.

use super::data_width;
use super::motor::engineering;
use super::outcome::{Outcome, Refusal};
use super::pages::Paged;
use super::reply::data_little_endian;
use super::VirtualDrive;
use crate::info::RegisterInfo;
use crate::kinds::{CommandKind, DataType, Space};
use crate::protocol::{CommandSpec, DecodedRequest, PreStep, Protocol};

impl VirtualDrive {
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
            Paged::Plain => request,
            Paged::Register(register) => {
                paged = DecodedRequest {
                    register: Some(register),
                    ..*request
                };
                &paged
            }
            Paged::Done(outcome) => return outcome,
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
        if self
            .target_of(request)
            .is_ok_and(|info| data_width::wrong_width(protocol, request.command, info.data_type))
        {
            return Outcome::Silent(data_width::MALFORMED);
        }
        if request.command.no_reply {
            self.unanswered(protocol, request);
            return Outcome::Silent("the command is never answered");
        }
        if request.command.kind.is_write() && self.target_of(request).is_ok_and(|i| i.no_reply) {
            // Carried out as any write (a refusal included), but never answered.
            if self.write(protocol, request).is_ok() {
                self.tally.writes += 1;
            }
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
                Ok(()) => {
                    self.tally.writes += 1;
                    self.reply(protocol, request, request.data, 0)
                }
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
        if result.is_ok() && request.command.kind.is_write() {
            self.tally.writes += 1;
        }
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
        let written = match &command.percent_of {
            Some(_) => self.write_percent(request),
            None => self.write(protocol, request).map(|_| ()),
        };
        if written.is_ok() {
            self.tally.writes += 1;
        }
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
    pub(super) fn target_of(
        &self,
        request: &DecodedRequest<'_>,
    ) -> Result<&'static RegisterInfo, Refusal> {
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
        if own != 2 || !size.is_multiple_of(2) {
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
        if first.space == Space::Coil && first.data_type == DataType::Bit {
            return self.read_coils(first, request);
        }
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

    /// A read of coils from a coil of its own (`data_type: bit`): the request's quantity of
    /// consecutive coils, one bit each, the first in the lowest bit (on while it holds a
    /// non-zero value, FF00h as written). Each coil read must be described.
    fn read_coils(
        &self,
        first: &'static RegisterInfo,
        request: &DecodedRequest<'_>,
    ) -> Result<(u32, u8), Refusal> {
        let quantity =
            coil_quantity(request).unwrap_or(u32::from(request.values.data_size.max(1)) * 8);
        if quantity == 0 || quantity > 32 {
            return Err(Refusal::OutOfRange);
        }
        // Eight coils to a data byte, the last one filled with zeros.
        let size = quantity.div_ceil(8) as u8;
        let mut data = 0u32;
        for i in 0..quantity {
            let address = u16::try_from(u32::from(first.address) + i)
                .map_err(|_| Refusal::UnknownRegister)?;
            let coil = self
                .drive
                .register_for(Space::Coil, address, false)
                .filter(|info| info.data_type == DataType::Bit)
                .ok_or(Refusal::UnknownRegister)?;
            if coil.access == crate::kinds::Access::WriteOnly {
                return Err(Refusal::UnknownRegister);
            }
            if self.storage.get(coil, 0) != 0 {
                data |= 1 << i;
            }
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
                // The instruction decides: a RAM-only register's in RAM, any other's in RAM
                // and EEPROM.
                _ if request.command.stored_by_instruction => !info.ram_only,
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
    pub(super) fn check_value(
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
    pub(super) fn check_combinations(
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

    /// Whether the last drive-to-drive frame said its sender (the master inverter) has
    /// tripped (a lower-case code of a command whose lower case means so). The model records
    /// it only: what a receiver then does (stop, alarm, trip) is set by parameters the
    /// behaviour model does not describe yet.
    pub fn sender_tripped(&self) -> bool {
        self.sender_tripped
    }
}

/// The number of coils a request asks for: the value its quantity part (a length counting
/// coils, eight to a data byte) received.
fn coil_quantity(request: &DecodedRequest<'_>) -> Option<u32> {
    request
        .command
        .request
        .parts
        .iter()
        .zip(request.values.parts.iter())
        .find_map(|(part, value)| match part {
            crate::layout::Part::Length(length) if length.times == 8 && value.present => {
                Some(value.value)
            }
            _ => None,
        })
}
