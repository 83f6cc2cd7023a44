//! A shared protocol file as a whole (`drives/protocols/<id>.yaml`): who the protocol is,
//! its variants and the base it is built on.

use super::commands::{CommandModel, PreStepModel};
use super::error_codes::ProtocolErrorCodesModel;
use super::parts::{PartModel, PartRefModel};
use schemars::JsonSchema;
use serde::Deserialize;
use std::collections::BTreeMap;
use vfd_runtime::Encoding;

/// A shared protocol file (`drives/protocols/<id>.yaml`).
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ProtocolFile {
    /// Who the protocol is and its frame-wide settings.
    pub protocol: ProtocolMeta,
    /// Reusable frame parts by name; layouts list them.
    #[serde(default)]
    pub parts: BTreeMap<String, PartModel>,
    /// Another protocol file whose parts, layouts, commands, error reply and error codes
    /// this one takes, with the changes said here (Modbus ASCII: Modbus RTU's frames with
    /// another start, checksum and end). What this file gives itself replaces the base's.
    pub based_on: Option<BasedOnModel>,
    /// Frame layouts by name: the parts of a frame in order, each the name of a part or a part written in place.
    /// Required unless the file is `based_on` another.
    #[serde(default)]
    pub layouts: BTreeMap<String, Vec<PartRefModel>>,
    /// The commands: which layouts a request and its reply use. Required unless the file
    /// is `based_on` another.
    #[serde(default)]
    pub commands: Vec<CommandModel>,
    /// Name of the layout of an error reply.
    pub error_reply: Option<String>,
    /// The codes the protocol's error replies carry, as the protocol itself defines them
    /// (Modbus exception codes): used for a drive whose own `error_codes` do not apply to
    /// this protocol.
    pub error_codes: Option<ProtocolErrorCodesModel>,
    /// Variants of the protocol: other bytes for some literal parts (a terminator that is
    /// CR or CR LF as a drive setting chooses). The first is the protocol as its `parts`
    /// are written; a drive's `protocols[].variant` says which register selects one.
    #[serde(default)]
    pub variants: Vec<VariantModel>,
}

/// A variant of a protocol (`variants[]`).
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct VariantModel {
    /// Lower snake case identifier (`cr_lf`): the value id that selects it in a drive's
    /// code table, and the name masters and tools are told (`--variant cr_lf`).
    pub id: String,
    /// The variant's name in English.
    pub name: String,
    /// The variant's name as the manual prints it in Chinese.
    #[serde(default)]
    pub name_zh: String,
    /// Shared literal parts (keys under `parts:`) with other bytes in this variant, each
    /// `{ literal: ... }` or `{ literal_hex: ... }`; none in the first variant.
    #[serde(default)]
    pub literals: BTreeMap<String, VariantLiteralModel>,
}

/// The bytes of a literal part in a variant: exactly one of the keys.
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct VariantLiteralModel {
    /// The bytes, as text.
    pub literal: Option<String>,
    /// The bytes, as hex pairs.
    pub literal_hex: Option<String>,
}

/// A protocol file built on another (`based_on:`): the base's layouts, each changed the
/// same way.
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct BasedOnModel {
    /// The base protocol file's id (its file name without `.yaml`), in the same folder. A
    /// base may not itself be based on another.
    pub protocol: String,
    /// Parts put before the first part of every layout of the base (a start literal).
    #[serde(default)]
    pub prepend: Vec<String>,
    /// Parts put after the last part of every layout of the base (an end literal).
    #[serde(default)]
    pub append: Vec<String>,
    /// Parts of the base's layouts replaced, wherever a layout names them: base part name
    /// -> the name of the part used instead (`{ crc: lrc }`).
    #[serde(default)]
    pub replace: BTreeMap<String, String>,
}

#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ProtocolMeta {
    /// The file's name without `.yaml`; drive files name it in `protocols[].uses`.
    pub id: String,
    /// The protocol's name in English.
    pub name: String,
    /// The protocol's name as the manuals print it in Chinese.
    #[serde(default)]
    pub name_zh: String,
    /// Prose for the reference pages.
    #[serde(default)]
    pub description: String,
    /// Frames are printable text.
    pub text: bool,
    /// The longest frame in bytes: sizes buffers and reply timeouts.
    pub max_frame_len: u16,
    /// A reply with a lower-case command letter says the drive has tripped.
    #[serde(default)]
    pub lowercase_means_tripped: bool,
    /// Optional parts included in the requests the library builds.
    #[serde(default)]
    pub default_optional_parts: Vec<String>,
    /// Steps some requests need first.
    #[serde(default)]
    pub pre_steps: Vec<PreStepModel>,
    /// Process words sent when the caller gives none.
    pub default_process: Option<[u16; 2]>,
    /// Silence between frames in character times.
    #[serde(default)]
    pub frame_gap_chars: f32,
    /// How frames go on the wire: `binary` (the default: as the parts give them) or
    /// `hex_pairs` (Modbus ASCII: a literal first and last part as they are, every byte in
    /// between as two hex digits; lengths and checksums over the bytes, not the digits).
    #[serde(default)]
    pub encoding: Encoding,
    /// The most 16-bit registers one read request may carry (Modbus 03: 125), when the
    /// protocol's read command counts its data (a length part with `counts: data_size`);
    /// left out: 1, one register per read.
    pub max_words_per_read: Option<u16>,
    /// The most 16-bit registers one write request may carry (Modbus 10h: 123), when a
    /// RAM write command's data field is sized by a length part; left out: 1, one register
    /// (of its own width) per write.
    pub max_words_per_write: Option<u16>,
}
