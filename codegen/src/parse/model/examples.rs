//! The manual's worked examples: values and their raw words (`value_examples:`), and
//! example frames (`examples:`) with what they decode to.

use super::commands::CodeModel;
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use vfd_runtime::DecodeErrorKind;

#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ValueExampleModel {
    /// Code or id of the register.
    pub register: String,
    /// The engineering value; it must round to `raw`.
    pub value: f64,
    /// The raw word on the wire.
    pub raw: u32,
    /// The manual section giving the example.
    pub source: String,
    /// What the manual says.
    pub description: String,
    /// The values of other registers the example assumes, by code or id (`{ FA09: 0 }`
    /// for a register whose `scale_by` names FA09).
    #[serde(default)]
    pub given: BTreeMap<String, u32>,
}

#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ExampleModel {
    /// Unique lower snake case name; it names the golden test.
    pub id: String,
    /// A protocol id of this drive (`protocols[].id`).
    pub protocol: String,
    /// The protocol file's variant the frames are in (`cr_lf`: the terminator is CR LF);
    /// left out: the first variant, the one the layouts are written in.
    pub variant: Option<String>,
    /// On a protocol with pages (`protocols[].pages`), the page the drive is on for these
    /// frames: the request's register field is an offset on it, and `expect.register`
    /// names the register it reaches there (checked); the virtual drive is put on the page
    /// before the example is played to it.
    pub page: Option<u16>,
    /// The manual section with the frame.
    pub source: String,
    /// What the exchange does, in English.
    pub description: String,
    /// What the exchange does, as the manual says it in Chinese.
    #[serde(default)]
    pub description_zh: String,
    /// The request frame, if the manual gives one.
    pub request: Option<FrameModel>,
    /// The reply frame, if the manual gives one.
    pub reply: Option<FrameModel>,
    /// The manual prints the request and says nothing comes back (a broadcast no station
    /// answers, a command never answered): the example gives no `reply`, and `vfd check`
    /// plays the request to the virtual drive, which must stay silent.
    #[serde(default)]
    pub no_reply: bool,
    /// A request the manual prints as one the drive does not answer (a format error): the
    /// decoder refuses it and the virtual drive stays silent.
    pub unanswered_request: Option<UnansweredModel>,
    /// The data word's value in the register's engineering unit.
    pub value: Option<f64>,
    /// The drive settings the frames assume, where the frames depend on more than their
    /// bytes (a block transfer's selectors): register (code or id) -> value, in the
    /// register's unit (a code for code tables), as `default` is written; the virtual drive
    /// built from the description holds them as set before power-on when `vfd check` plays
    /// the example to it.
    #[serde(default)]
    pub settings: BTreeMap<String, f64>,
    /// Why the virtual drive built from this description cannot give the example's reply
    /// to its request (a state its behaviour model does not reach, such as a trip). Without
    /// it, `vfd check` plays the request to the virtual drive, under `settings`, and requires
    /// the example's reply byte for byte.
    pub not_simulated: Option<String>,
}

/// A request the drive does not answer, as the manual prints it.
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct UnansweredModel {
    /// The frame as text (text protocols).
    pub ascii: Option<String>,
    /// The frame as hex byte pairs (binary protocols).
    pub hex: Option<String>,
    /// The decoder's reason for refusing it.
    pub rejected_as: DecodeErrorKind,
    /// Why the drive does not answer it, as the manual says.
    pub reason: String,
}

/// Frame bytes, written as text (`ascii`) or as hex pairs (`hex`).
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct BytesModel {
    /// The frame as text (text protocols); `\r` and other escapes as in YAML double quotes.
    pub ascii: Option<String>,
    /// The frame as hex byte pairs separated by spaces (binary protocols).
    pub hex: Option<String>,
}

#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct FrameModel {
    /// The corrected frame as text (text protocols).
    pub ascii: Option<String>,
    /// The corrected frame as hex byte pairs (binary protocols).
    pub hex: Option<String>,
    /// What the frame must decode to.
    pub expect: ExpectModel,
    /// What the manual prints, when it differs from the bytes above (an erratum).
    pub printed: Option<BytesModel>,
    /// Why the printed bytes are wrong; required with `printed`.
    pub erratum: Option<String>,
    /// The decoder's reason for refusing the printed bytes, or, for a printed frame that
    /// is valid on its own, why it is still wrong (`does_not_answer_request`,
    /// `contradicts_expect`).
    pub printed_rejected_as: Option<PrintedRejection>,
}

/// Why the bytes a manual prints for a frame are wrong, as the library shows it: the
/// decoder refuses them (a [`DecodeErrorKind`]), or they decode but are wrong in their
/// exchange.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum PrintedRejection {
    /// A byte where the layout has a fixed one.
    UnexpectedByte,
    /// A value the layout does not allow.
    NotAllowed,
    /// The checksum does not match the bytes.
    ChecksumMismatch,
    /// A length field disagrees with the frame.
    LengthMismatch,
    /// The frame ends early.
    Truncated,
    /// Bytes follow the frame.
    TrailingBytes,
    /// A reply that decodes, but carries another station, register, index or written value
    /// than its request: the master passes it over as the answer to something else.
    DoesNotAnswerRequest,
    /// A frame that decodes, but to something other than `expect` (the manual's stated
    /// meaning): a letter case that contradicts the stated state, for example.
    ContradictsExpect,
}

impl PrintedRejection {
    /// The name written in drive files.
    pub fn as_str(self) -> &'static str {
        match self.decode_kind() {
            Some(kind) => kind.as_str(),
            None if self == PrintedRejection::DoesNotAnswerRequest => "does_not_answer_request",
            None => "contradicts_expect",
        }
    }

    /// The decoder's error kind, for a rejection the decoder itself makes.
    pub fn decode_kind(self) -> Option<DecodeErrorKind> {
        Some(match self {
            PrintedRejection::UnexpectedByte => DecodeErrorKind::UnexpectedByte,
            PrintedRejection::NotAllowed => DecodeErrorKind::NotAllowed,
            PrintedRejection::ChecksumMismatch => DecodeErrorKind::ChecksumMismatch,
            PrintedRejection::LengthMismatch => DecodeErrorKind::LengthMismatch,
            PrintedRejection::Truncated => DecodeErrorKind::Truncated,
            PrintedRejection::TrailingBytes => DecodeErrorKind::TrailingBytes,
            PrintedRejection::DoesNotAnswerRequest | PrintedRejection::ContradictsExpect => {
                return None
            }
        })
    }
}

#[derive(Debug, Clone, Default, Deserialize, PartialEq, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ExpectModel {
    /// Station number.
    pub address: Option<u8>,
    /// The stations a broadcast request addresses: `all`, or a group written with `*` for
    /// each open digit (`"*9"`, `"1*"`).
    pub broadcast: Option<String>,
    /// The command code: a letter (`R`) or a number (`0x03`).
    pub command: Option<CodeModel>,
    /// Register number as the drive file numbers it (before the protocol's address map).
    pub register: Option<u32>,
    /// Register number on the wire, for frames addressing no described register (the FC
    /// Modbus index register 0008h).
    pub wire_register: Option<u32>,
    /// Array index (indexed parameters).
    pub index: Option<u32>,
    /// The data word, raw.
    pub data: Option<u32>,
    /// The code of an error reply.
    pub error_code: Option<u32>,
    /// Process words (control word and reference, or status word and output value).
    pub process: Option<[u32; 2]>,
    /// Text carried by the frame.
    pub text: Option<String>,
    /// The words of a block transfer (written by the request, read by the reply).
    pub words: Option<Vec<u32>>,
    /// How many words a block-transfer request asks back.
    pub read_count: Option<u32>,
    /// A block-transfer reply's write status.
    pub write_status: Option<u32>,
    /// A request's reply-wait field (the wait digit of the computer-link family: tens of
    /// milliseconds before the drive answers), as printed; the golden test encodes with it.
    /// Left out: not checked, and the frame's digit is used.
    pub reply_wait: Option<u32>,
    /// The reply says the drive has tripped.
    #[serde(default)]
    pub tripped: bool,
}
