//! Finding the command that carries a request, a block transfer, or reads a register.

use super::command::{command_reads_blocks, command_writes_blocks, CommandSpec};
use super::Protocol;
use crate::error::EncodeError;
use crate::kinds::{CommandKind, DataType, Space};
use crate::register::Request;

impl Protocol {
    /// The first command of `kind` serving `space` and carrying `data_type`.
    pub fn command_for(
        &self,
        kind: CommandKind,
        space: Space,
        data_type: DataType,
    ) -> Option<&CommandSpec> {
        self.commands
            .iter()
            .find(|c| !c.extra && c.kind == kind && c.space == space && c.carries(data_type))
    }

    /// The first command of `kind` serving `space` and carrying `data_type` whose request
    /// carries register `number` on the wire: the number its address map (or the
    /// register's own wire number) gives fits the request's register field, and the field
    /// allows it. A protocol whose commands of one kind reach different tables of the drive
    /// by their function code (one function reading parameters, another status values)
    /// tells them apart so, each command's address map putting the numbers of its table in
    /// its field. When no command carries the number, the first of the kind whose register
    /// field takes any number (its request then reports the number out of range); a command
    /// whose field allows only some numbers (the function code standing for its one
    /// register) is never taken for another register.
    pub fn command_for_register(
        &self,
        kind: CommandKind,
        space: Space,
        data_type: DataType,
        number: u16,
    ) -> Option<&CommandSpec> {
        let mut candidates = self.commands.iter().filter(move |c| {
            !c.extra && c.kind == kind && c.space == space && c.carries(data_type)
        });
        candidates
            .clone()
            .find(|c| {
                self.to_wire(c, number)
                    .is_some_and(|wire| c.request.carries_register(wire))
            })
            .or_else(|| candidates.find(|c| c.request.register_takes_any()))
    }

    /// The read command that reads several consecutive 16-bit registers of `space` in one
    /// exchange, when the protocol allows more than one ([`Protocol::max_words_per_read`]):
    /// a read of words whose request counts its data (a length part counting `data_size`)
    /// and whose reply's data field is sized by a length part.
    pub fn block_read_command(&self, space: Space) -> Option<&CommandSpec> {
        if self.max_words_per_read < 2 {
            return None;
        }
        self.command_for(CommandKind::Read, space, DataType::Word)
            .filter(|command| command_reads_blocks(command))
    }

    /// The command that writes several consecutive registers in one exchange, when the
    /// protocol allows more than one ([`Protocol::max_words_per_write`]): a RAM write of
    /// `space` whose request's data field is sized by a length part (Modbus 10h).
    pub fn block_write_command(&self, space: Space) -> Option<&CommandSpec> {
        if self.max_words_per_write < 2 {
            return None;
        }
        self.commands.iter().find(|c| {
            c.kind == CommandKind::WriteRam && c.space == space && command_writes_blocks(c)
        })
    }

    /// The block-transfer command, when the drive has one (a [`CommandKind::Block`] command
    /// and a [`BlockSpec`](super::BlockSpec)).
    pub fn block_command(&self) -> Option<&CommandSpec> {
        self.block.as_ref()?;
        self.commands.iter().find(|c| c.kind == CommandKind::Block)
    }

    /// The command that carries `request`, or the typed reason there is none.
    pub fn command_for_request(&self, request: &Request) -> Result<&CommandSpec, EncodeError> {
        crate::tally::lookup();
        if let Some(code) = request.command {
            return self
                .commands
                .iter()
                .find(|c| {
                    c.answers_to(code)
                        && c.kind == request.kind
                        && c.space == request.space
                        && c.carries(request.data_type)
                })
                .ok_or_else(|| EncodeError::NoSuchCommand {
                    protocol: self.id.clone(),
                    code,
                    kind: request.kind,
                });
        }
        let command = self
            .command_for_number(request)
            .or_else(|| self.persistent_by_instruction(request))
            .ok_or_else(|| EncodeError::UnsupportedCommand {
                protocol: self.id.clone(),
                kind: request.kind,
                space: request.space,
                data_type: request.data_type,
            })?;
        if command.stored_by_instruction
            && request.kind == CommandKind::WriteRam
            && self.stored_in_eeprom_by_instruction(request)
        {
            return Err(EncodeError::StoredInEeprom {
                protocol: self.id.clone(),
                register: request.register,
            });
        }
        Ok(command)
    }

    /// The command of `request`'s kind, space and data type that carries its register: by
    /// its register number ([`Protocol::command_for_register`]), or for a request by wire
    /// number alone, the first whose register field carries that number as it is.
    fn command_for_number(&self, request: &Request) -> Option<&CommandSpec> {
        if !request.wire_register {
            return self.command_for_register(
                request.kind,
                request.space,
                request.data_type,
                request.register,
            );
        }
        self.commands
            .iter()
            .filter(|c| {
                !c.extra
                    && c.kind == request.kind
                    && c.space == request.space
                    && c.carries(request.data_type)
            })
            .find(|c| c.request.carries_register(request.register))
            .or_else(|| {
                self.command_for(request.kind, request.space, request.data_type)
                    .filter(|c| c.request.register_takes_any())
            })
    }

    /// For a persistent write where the protocol has no persistent command: its plain
    /// write whose storage is the instruction's, when the request's register is not RAM
    /// only (its instruction then stores in RAM and EEPROM).
    fn persistent_by_instruction(&self, request: &Request) -> Option<&CommandSpec> {
        if request.kind != CommandKind::WritePersistent
            || request.info.is_some_and(|info| info.ram_only)
        {
            return None;
        }
        self.commands.iter().find(|c| {
            !c.extra
                && c.kind == CommandKind::WriteRam
                && c.stored_by_instruction
                && c.space == request.space
                && c.carries(request.data_type)
        })
    }

    /// Whether a write of `request`'s register through a write whose storage is the
    /// instruction's goes to EEPROM: a described register that is neither RAM only nor kept
    /// in RAM, and that the drive's persistence selector does not govern (the master sets
    /// that selector for the writes it governs).
    fn stored_in_eeprom_by_instruction(&self, request: &Request) -> bool {
        request.info.is_some_and(|info| !info.stored_in_ram_only())
            && !self
                .persistence
                .as_ref()
                .is_some_and(|selector| selector.governs_request(request))
    }

    /// Whether `info` can be read over this protocol: a read command serves its space and
    /// data type, and the register has a wire number for it (a register the description
    /// numbers only for other protocols, or whose number the address map cannot carry,
    /// cannot). What a backup or a watch over this protocol may include.
    pub fn can_read(&self, info: &crate::info::RegisterInfo) -> bool {
        let kind = if info.data_type == DataType::Text {
            CommandKind::ReadText
        } else {
            CommandKind::Read
        };
        self.command_for_register(kind, info.space, info.data_type, info.address)
            .is_some_and(|command| {
                self.to_wire(command, info.address)
                    .is_some_and(|wire| command.request.carries_register(wire))
            })
    }
}
