//! Protocols: a protocol file's shared layouts, and a protocol as one drive speaks it
//! (its commands, limits, timing, pages and the table naming its error replies).

use super::error_codes::ErrorCodesIr;
use serde::Serialize;
use vfd_runtime::{AddressMap, CommandKind, DataType, FrameLayout, PreStep, Space};

/// A protocol file (`protocols/<id>.yaml`): its frame layouts, shared by every drive that
/// uses it.
#[derive(Debug, Clone, Serialize)]
pub struct ProtocolFileIr {
    /// File id (`toshiba-ascii`).
    pub id: String,
    /// Rust name of its module of layouts (`toshiba_ascii`).
    pub module: String,
    /// English name.
    pub name: String,
    /// Chinese name.
    pub name_zh: String,
    /// What it is.
    pub description: String,
    /// Whether frames are text.
    pub text: bool,
    /// Every layout a command or the error reply uses, by name, in the file's order.
    pub layouts: Vec<FrameLayout>,
    /// The protocol file it is `based_on`, read with it (an input of the build, not part
    /// of the snapshot: the layouts above are already merged).
    #[serde(skip)]
    pub based_on: Option<String>,
}

/// A protocol as one drive speaks it.
#[derive(Debug, Clone, Serialize)]
pub struct ProtocolIr {
    /// Id within the drive (`ascii`).
    pub id: String,
    /// Rust name of its `static` (`ASCII`).
    pub const_name: String,
    /// The protocol file it uses (`toshiba-ascii`).
    pub uses: String,
    /// Manual section.
    pub source: String,
    /// English name.
    pub name: String,
    /// Commands, with their layouts named.
    pub commands: Vec<CommandIr>,
    /// Name of the error-reply layout, when the protocol has error replies.
    pub error_reply: Option<String>,
    /// A lower-case command letter in a reply means "tripped".
    pub lowercase_means_tripped: bool,
    /// Longest frame in bytes.
    pub max_frame_len: u16,
    /// Station numbers this drive accepts.
    pub address_range: (u8, u8),
    /// Optional parts requests include by default.
    pub default_optional_parts: Vec<String>,
    /// Steps some requests need first.
    pub pre_steps: Vec<PreStep>,
    /// Process words sent when the caller gives none, as the protocol file states them
    /// (`None`: it states none, and 0000h 0000h are sent).
    pub default_process: Option<[u16; 2]>,
    /// Silence between frames, in character times.
    pub frame_gap_chars: f32,
    /// The most registers one read carries (1: one per read).
    pub max_words_per_read: u16,
    /// The most registers one write carries (1: one per write).
    pub max_words_per_write: u16,
    /// A read or write of several registers skips the registers it cannot access.
    pub partial_blocks: bool,
    /// What a block transfer writes and reads on this drive (`None`: no block transfer).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub block: Option<vfd_runtime::BlockSpec>,
    /// The manual sections and the note of the drive's `block:` (empty without one).
    #[serde(skip_serializing_if = "String::is_empty")]
    pub block_source: String,
    /// See `block_source`.
    #[serde(skip_serializing_if = "String::is_empty")]
    pub block_note: String,
    /// The drive's timing rules beyond the gap in characters.
    pub timing: vfd_runtime::serial::LinkTiming,
    /// The drive's entry states `before_start` (the manual says what bytes before a
    /// frame's start do); `false`: `timing.before_start` is the library's default, which
    /// the page marks assumed.
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub before_start_stated: bool,
    /// The drive's broadcast rule, when it takes broadcasts over this protocol.
    pub broadcast: Option<vfd_runtime::broadcast::BroadcastRule>,
    /// Registers with their own numbers on the wire in this protocol.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub wire_numbers: Vec<vfd_runtime::protocol::WireNumber>,
    /// Parameters reached through pages on this protocol.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub paging: Option<vfd_runtime::protocol::Paging>,
    /// What the description says of its pages for people: the manual section, the name of
    /// each range, what is assumed and the note.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub pages_doc: Option<PagesDocIr>,
    /// The drive's persistence selector, as the runtime protocol carries it.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub persistence: Option<vfd_runtime::PersistenceSelector>,
    /// The table its error replies are named from.
    pub error_table: ErrorTableIr,
    /// The protocol's variants, the register selecting one and the mismatch error.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub variants: Option<vfd_runtime::variant::Variants>,
    /// The error code the drive answers a function it lacks with, and where the manual
    /// says so (`protocols[].unsupported_function`); `None`: the manual does not say.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub unsupported_function: Option<UnsupportedFunctionIr>,
}

/// What a drive answers to a function it lacks.
#[derive(Debug, Clone, Serialize)]
pub struct UnsupportedFunctionIr {
    /// The error code of the reply.
    pub error_code: u16,
    /// The manual section saying so.
    pub source: String,
}

/// Where a protocol's error replies take their meaning from.
#[derive(Debug, Clone, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ErrorTableIr {
    /// The drive's own table ([`DriveIr::error_codes`](crate::ir::DriveIr::error_codes)),
    /// which applies to this protocol.
    Drive,
    /// The protocol file's own table (empty when it has none): the drive's does not apply.
    Protocol(ErrorCodesIr),
}

/// One command of a protocol.
#[derive(Debug, Clone, Serialize)]
pub struct CommandIr {
    /// The code on the wire (letter, AK nibble, function code; 0 when the layout has none).
    pub code: u32,
    /// What it does.
    pub kind: CommandKind,
    /// Data types it carries (empty: any).
    pub data_types: Vec<DataType>,
    /// Address space.
    pub space: Space,
    /// Register number to wire number.
    pub address_map: AddressMap,
    /// Request layout, by name.
    pub request: String,
    /// Reply layout, by name.
    pub reply: String,
    /// Codes a normal reply may carry (empty: the request's).
    pub reply_codes: Vec<u32>,
    /// The code an error reply to it carries, where the error layout allows several.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub error_code: Option<u32>,
    /// Never answered (`reply: none`).
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub no_reply: bool,
    /// Used only when a request names its code (`extra: true`).
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub extra: bool,
    /// A lower-case code in the request says the sender has tripped.
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub lowercase_means_sender_tripped: bool,
    /// The registers it may address (numbers before the address map; empty: any).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub registers: Vec<u16>,
    /// Its data is a percentage of this register (code), this many % per raw step; a
    /// receiving drive applies the first of these conversions that holds.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub percent_of: Option<(String, f64, Vec<String>)>,
    /// The master's follow-up to its replies: the layouts (by name) sent after a sound and
    /// after a garbled reply.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub follow_up: Option<(String, String)>,
    /// A plain write whose storage is the instruction's (`storage: by_instruction`).
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub stored_by_instruction: bool,
}

/// The people's side of a protocol's pages (`protocols[].pages`).
#[derive(Debug, Clone, Serialize)]
pub struct PagesDocIr {
    /// Manual section.
    pub source: String,
    /// Each range's name, in the order of the ranges.
    pub range_names: Vec<String>,
    /// Keys the description assumes (`initial`).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub assumed: Vec<String>,
    /// Note.
    #[serde(skip_serializing_if = "String::is_empty")]
    pub note: String,
}
