//! The commands of a protocol file (`commands[]`): codes, storage, follow-ups, address
//! maps and the steps some requests need first.

use schemars::JsonSchema;
use serde::Deserialize;
use vfd_runtime::{CommandKind, DataType, Space};

/// A command code or allowed value: one character (`R`) or a number (`0x03`).
#[derive(Debug, Clone, Deserialize, PartialEq, JsonSchema)]
#[serde(untagged)]
pub enum CodeModel {
    Number(u32),
    Text(String),
}

impl CodeModel {
    /// The code's value: a character's byte, or the number.
    pub fn value(&self) -> Option<u32> {
        match self {
            CodeModel::Number(n) => Some(*n),
            CodeModel::Text(text) => match text.as_bytes() {
                [byte] => Some(u32::from(*byte)),
                _ => None,
            },
        }
    }

    /// As written.
    pub fn shown(&self) -> String {
        match self {
            CodeModel::Number(n) => format!("{n:#X}"),
            CodeModel::Text(text) => text.clone(),
        }
    }
}

#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct CommandModel {
    /// The code on the wire; absent for layouts without a command field.
    pub code: Option<CodeModel>,
    /// What the command does: `read`, `write_ram`, `write_persistent`, `read_text` or `process`.
    pub kind: CommandKind,
    /// Name of the request's layout.
    pub request: String,
    /// Name of the normal reply's layout, or `none` for a command that is never answered
    /// (a master returns once the frame is sent; the virtual drive stays silent).
    pub reply: String,
    /// An extra command (default false): a drive gets it only by listing its code in
    /// `protocols[].commands`, and a request uses it only by naming its code (a second read
    /// command that some drives have).
    #[serde(default)]
    pub extra: bool,
    /// What a lower-case code means for this command: `sender_tripped` (a request whose
    /// letter is lower case says its sender, a master inverter, has tripped). Left out: as
    /// the protocol's `lowercase_means_tripped` says of replies.
    pub lowercase_means: Option<LowercaseMeans>,
    /// Data types carried (`word`, `double_word`, `bit`, `text`); empty: any.
    #[serde(default)]
    pub data_types: Vec<DataType>,
    /// `parameter` (default) or `coil`.
    pub space: Option<Space>,
    /// How register numbers become wire addresses (a default a drive file may override).
    pub address_map: Option<AddressMapModel>,
    /// Codes a normal reply may carry; empty: the request's code.
    #[serde(default)]
    pub reply_codes: Vec<CodeModel>,
    /// The code an error reply to this command carries, where the `error_reply` layout
    /// allows several (a Modbus exception to function 0x03 carries 0x83); left out: the one
    /// code the error layout allows.
    pub error_code: Option<CodeModel>,
    /// `by_instruction`: a plain write (`kind: write_ram`) whose storage is the
    /// instruction's, that is the register's: the protocol writes RAM and EEPROM with
    /// instructions of their own (a frequency written to RAM with one code and to EEPROM
    /// with another), so a RAM-only register's write goes to RAM and any other's to RAM
    /// and EEPROM. Said once here, not per register. Left out: the kind's storage.
    pub storage: Option<WriteStorage>,
    /// What the master sends after this command's reply: `{ ok: LAYOUT, again: LAYOUT }`,
    /// the acknowledgement of a sound reply and the request to send a garbled one again
    /// (Eaton: C and F after a read's E). Neither is answered by a frame of its own.
    pub follow_up: Option<FollowUpModel>,
    /// Notes for people reading the protocol file; nothing is generated from them.
    #[serde(default)]
    #[allow(dead_code)]
    pub description: String,
}

/// Where a write command's writes go (`commands[].storage`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum WriteStorage {
    /// Where the instruction (the register it addresses) stores: RAM for a RAM-only
    /// register, RAM and EEPROM for any other.
    ByInstruction,
}

/// The master's answer to a command's reply (`commands[].follow_up`).
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct FollowUpModel {
    /// The layout sent after a sound reply (the drive does nothing more).
    pub ok: String,
    /// The layout sent after a garbled reply: the drive sends the same reply again.
    pub again: String,
}

#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct AddressMapModel {
    /// Wire address = number x multiply + offset: the factor.
    pub multiply: u16,
    /// Wire address = number x multiply + offset: the offset.
    pub offset: i32,
}

#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct PreStepModel {
    /// What the step does: `index` or `persistence`.
    pub step: PreStepKind,
    /// The register the step writes.
    pub register: u16,
    /// `parameter` (default) or `coil`.
    pub space: Option<Space>,
    /// `word` (default), `double_word`, `bit` or `text`.
    pub data_type: Option<DataType>,
    /// Persistence: the value selecting RAM-only writes.
    pub ram: Option<u32>,
    /// Persistence: the value selecting RAM + EEPROM writes.
    pub persistent: Option<u32>,
    /// Notes for people reading the protocol file; nothing is generated from them.
    #[serde(default)]
    #[allow(dead_code)]
    pub description: String,
}

/// What a lower-case command letter means for one command.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum LowercaseMeans {
    /// A request with the lower-case letter says its sender has tripped.
    SenderTripped,
}

/// What a pre-step does.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum PreStepKind {
    /// Write the array index of an indexed parameter.
    Index,
    /// Switch between writing RAM only and RAM + EEPROM.
    Persistence,
}
