//! Multi-step examples: one call of the master and every frame it puts on the line.

use serde::Serialize;

/// A multi-step example: one call of the master and every frame it puts on the line.
#[derive(Debug, Clone, Serialize)]
pub struct SequenceIr {
    /// Identifier.
    pub id: String,
    /// Id of the protocol (within the drive).
    pub protocol: String,
    /// Manual section.
    pub source: String,
    /// The manual's words.
    pub description: String,
    /// The manual's Chinese words.
    pub description_zh: String,
    /// The station addressed.
    pub address: Option<u8>,
    /// Id of the register the call reads or writes.
    pub register: String,
    /// What the call does.
    pub call: SequenceCallIr,
    /// The write goes to RAM and EEPROM.
    pub persistent: bool,
    /// The persistence selector's value the master is told first.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub selector_given: Option<u32>,
    /// What it returns.
    pub result: SequenceResultIr,
    /// The frames, in order.
    pub steps: Vec<SequenceStepIr>,
    /// The protocol variant the frames are in (`None`: the first).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub variant: Option<String>,
    /// The reply-wait field's value in the master's requests (0 when left out).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub reply_wait: Option<u8>,
}

/// The call of a sequence.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum SequenceCallIr {
    /// A typed read.
    Read,
    /// A typed write of this value (RAM).
    Write(f64),
    /// A write of this raw word, sent as given.
    WriteRaw(u32),
}

/// The result of a sequence's call.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum SequenceResultIr {
    /// This value read.
    Value(f64),
    /// The write succeeded.
    Written,
    /// The drive refused with this code (its id).
    Error(u16, String),
}

/// One frame of a sequence.
#[derive(Debug, Clone, Serialize)]
pub struct SequenceStepIr {
    /// Who sends it.
    pub from: crate::parse::model::Sender,
    /// The bytes.
    pub bytes: Vec<u8>,
    /// How the manual shows it.
    pub shown: crate::parse::model::Shown,
    /// What it is, for people.
    #[serde(skip_serializing_if = "String::is_empty")]
    pub note: String,
}
