//! The manual's multi-step examples (`sequences[]`): one call and every frame it makes.

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// A multi-step example (`sequences[]`): one call of the master, and every frame on the
/// line it makes, in order.
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SequenceModel {
    /// Identifier (snake case; names the generated test).
    pub id: String,
    /// Id of the protocol (within this drive file).
    pub protocol: String,
    /// The protocol file's variant the frames are in (`cr_lf`); left out: the first.
    pub variant: Option<String>,
    /// The value of the reply-wait field in the master's requests (the wait digit of the
    /// computer-link family, tens of milliseconds: `3` asks for 30 ms), as the frames
    /// print it; the test's master asks for that wait (`Master::with_reply_wait`).
    /// Left out: 0.
    pub reply_wait: Option<u8>,
    /// The manual section (and lines) the steps come from.
    pub source: String,
    /// What the sequence does, in the manual's words.
    pub description: String,
    /// The manual's Chinese words.
    #[serde(default)]
    pub description_zh: String,
    /// The station the manual's frames address.
    pub address: Option<u8>,
    /// The one call: `{ read: 02-15 }`, `{ write: 02-15, value: 50.0 }` (through the typed
    /// API, range checked) or `{ write: 02-15, raw: 0xC350 }` (sent as given).
    pub call: SequenceCallModel,
    /// What the master is told before the call, by register code or id: the raw value of
    /// the drive's persistence selector (`{ 07-11: 0 }`: the factory setting, so a
    /// persistent write goes out alone).
    #[serde(default)]
    pub given: BTreeMap<String, u32>,
    /// What the call returns: `{ value: 60.0 }`, `{ written: true }` or `{ error: ID }` (an
    /// error code's id, the drive's or the protocol's).
    pub result: SequenceResultModel,
    /// The frames on the line, in order.
    pub steps: Vec<SequenceStepModel>,
}

/// The call a sequence makes.
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SequenceCallModel {
    /// Code or id of the register read.
    pub read: Option<String>,
    /// Code or id of the register written (RAM).
    pub write: Option<String>,
    /// The value written, in the register's unit.
    pub value: Option<f64>,
    /// The raw word written, without a range check (to show a refusal).
    pub raw: Option<u32>,
    /// The write goes to RAM and EEPROM (`write_persistent`); default false (RAM).
    #[serde(default)]
    pub persistent: bool,
}

/// What a sequence's call returns.
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SequenceResultModel {
    /// The value read, in the register's unit.
    pub value: Option<f64>,
    /// The write succeeded.
    #[serde(default)]
    pub written: bool,
    /// The id of the error code the drive answers with.
    pub error: Option<String>,
}

/// Who sends a sequence's frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum Sender {
    /// The master (a request, a page switch, a follow-up).
    Master,
    /// The drive (a reply).
    Drive,
}

/// How the manual shows a sequence's frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum Shown {
    /// Printed byte for byte.
    #[default]
    Printed,
    /// Left out by the manual as the same as an earlier example's ("略").
    Elided,
    /// Not printed: it follows from the manual's format tables.
    Derived,
}

/// One frame of a sequence.
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SequenceStepModel {
    /// `master` or `drive`.
    pub from: Sender,
    /// The frame as text.
    pub ascii: Option<String>,
    /// The frame as hex byte pairs.
    pub hex: Option<String>,
    /// `printed` (default), `elided` or `derived`.
    #[serde(default)]
    pub shown: Shown,
    /// What the step is, for people (`page switch`, `the master's C`).
    #[serde(default)]
    pub note: String,
}
