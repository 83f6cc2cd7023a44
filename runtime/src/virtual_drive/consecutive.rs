//! Reads and writes that span consecutive registers (a Modbus read of ten words): the
//! registers the block covers, each in the data field's byte order, checked and stored or
//! read one by one, and the reply that carries them.

use super::outcome::{Outcome, Refusal};
use super::reply::data_little_endian;
use super::VirtualDrive;
use crate::info::RegisterInfo;
use crate::kinds::{CommandKind, DataType, Space};
use crate::protocol::{CommandSpec, DecodedRequest, PreStep, Protocol};

impl VirtualDrive {
    /// Whether `request` reads more than its first register: a read by the protocol's
    /// block-read command whose count goes beyond the register it names.
    pub(super) fn is_block_read(&self, protocol: &Protocol, request: &DecodedRequest<'_>) -> bool {
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
    pub(super) fn read_block(
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
    pub(super) fn is_block_write(&self, protocol: &Protocol, request: &DecodedRequest<'_>) -> bool {
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
    pub(super) fn write_block(
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
        for (info, raw) in writes {
            let index = if info.array_len == 0 {
                0
            } else {
                self.selected_index.min(u16::from(info.array_len) - 1)
            };
            self.storage
                .set(info, index, raw, persistent && !info.stored_in_ram_only());
            // As a write of the register alone: a command word (or a register holding one
            // of its bits) acts, a reset value resets.
            self.value_written(info, raw);
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
    pub(super) fn reply_block(
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
