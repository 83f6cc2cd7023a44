//! A protocol is a set of frame layouts tied to commands, plus the error-reply layout, the
//! drive's error-code table and any steps a request needs first; this module encodes
//! requests and decodes replies with it.
//!
//! [`Protocol`] lives here; its files each hold one idea, layered so that none uses a file
//! above it:
//!
//! - vocabulary: [`AddressMap`], [`FollowUp`], [`PercentOf`], [`Paging`], [`PreStep`],
//!   [`PersistenceSelector`], [`BlockSpec`] (`block`), then [`CommandSpec`] (`command`),
//!   which uses the first three;
//! - views of a protocol: `wire_numbers` ([`Protocol::to_wire`]), `command_lookup`
//!   ([`Protocol::command_for_request`]), `error_codes`, `variants` ([`Protocol::variant`]
//!   and the [`VariantCache`] each protocol owns), `unplanned`, `drive_protocol`, `debug`;
//! - frames: `decoded` (what decoding finds), `frame_checks` (checks shared by the
//!   decoders), `encode`, `decode_request`, `decode_reply`;
//! - answers: `expectation` ([`Protocol::check_answer`]) and, on top, `search`
//!   ([`Protocol::search_reply`]).

mod address_map;
mod block;
mod command;
mod command_lookup;
mod debug;
mod decode_reply;
mod decode_request;
mod decoded;
mod drive_protocol;
mod encode;
mod error_codes;
mod expectation;
mod follow_up;
mod frame_checks;
mod paging;
mod percent_of;
mod persistence;
mod pre_step;
mod search;
mod unplanned;
mod variants;
mod wire_numbers;

use crate::broadcast::BroadcastRule;
pub use crate::info::ErrorCodeInfo;
pub use crate::kinds::{CommandKind, DataType, Space};
use crate::layout::{FrameLayout, List, Text};
pub use crate::register::Request;
use crate::serial::LinkTiming;
pub use crate::variant::{Variant, VariantLiteral, VariantSelector, VariantValue, Variants};
pub use address_map::AddressMap;
pub use block::{BlockChoice, BlockMode, BlockSelection, BlockSelector, BlockSpec};
pub use command::{code_label, command_reads_blocks, command_writes_blocks, CommandSpec};
pub use decoded::{DecodedRequest, Found, Reply};
pub use drive_protocol::DriveProtocol;
pub use expectation::{Difference, Expectation, NotAnAnswer};
pub use follow_up::FollowUp;
pub use paging::{PageRange, Paging};
pub use percent_of::PercentOf;
pub use persistence::PersistenceSelector;
pub use pre_step::PreStep;
pub use search::Search;
pub use variants::VariantCache;
pub use wire_numbers::WireNumber;

/// A protocol as one drive speaks it.
#[derive(Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct Protocol {
    /// Identifier within the drive (`ascii`).
    pub id: Text,
    /// Human name.
    pub name: Text,
    /// Commands.
    pub commands: List<CommandSpec>,
    /// Layout of error replies, if the protocol has them.
    pub error_reply: Option<FrameLayout>,
    /// A lower-case command letter in a reply means the drive is tripped.
    pub lowercase_means_tripped: bool,
    /// Longest frame, in bytes, used to size buffers and derive reply timeouts.
    pub max_frame_len: u16,
    /// Lowest and highest station address.
    pub address_range: (u8, u8),
    /// Optional parts (by name) included in requests unless the caller says otherwise.
    pub default_optional_parts: List<Text>,
    /// The drive's error codes.
    pub error_codes: List<ErrorCodeInfo>,
    /// Steps some requests need first.
    pub pre_steps: List<PreStep>,
    /// Process words sent with requests that carry them when the caller gives none
    /// (FC: a control word with "data valid" clear, so the drive ignores it).
    pub default_process: [u16; 2],
    /// Silence between frames, in character times (Modbus RTU: 3.5); 0 for none.
    pub frame_gap_chars: f32,
    /// The most 16-bit registers one read may carry (Modbus 03: 125); 1 when every read
    /// carries one register. Above 1, a read command whose request counts its data
    /// (a length part counting `data_size`) reads consecutive registers in one exchange:
    /// see [`Protocol::block_read_command`] and
    /// [`crate::transaction::Master::read_words`].
    pub max_words_per_read: u16,
    /// The most 16-bit registers one write may carry (Modbus 10h: 123; the DV1: 12); 1 when
    /// every write carries one register (of its own width). Above 1, a write command whose
    /// request's data field is sized by a length part writes consecutive registers in one
    /// exchange: see [`Protocol::block_write_command`] and
    /// [`crate::transaction::Master::write_words`].
    pub max_words_per_write: u16,
    /// A read or write of several registers is carried out for the registers that can be,
    /// and refused only when none can (the DV1: "若有 1 个及以上可以操作就不视为错误"): a
    /// register that does not exist reads as 0, one that does not exist or refuses its value
    /// is left as it is. `false`: one such register refuses the whole request.
    pub partial_blocks: bool,
    /// What a block-transfer command ([`CommandKind::Block`]) writes and reads on this
    /// drive; `None`: the drive has no block transfer (and no such command).
    pub block: Option<BlockSpec>,
    /// The drive's timing rules for this protocol beyond `frame_gap_chars` (gap floor in
    /// milliseconds, inner-gap limit, bytes before the start, reply delay register).
    pub timing: LinkTiming,
    /// Which commands the drive carries out when broadcast and which station answers;
    /// `None`: the drive takes no broadcasts over this protocol (its address field's
    /// broadcast encodings, if any, are not used).
    pub broadcast: Option<BroadcastRule>,
    /// Registers with their own numbers on the wire in this protocol, by direction (the
    /// Eaton command codes of the DV1's 10xxh registers); the others go through their
    /// command's address map ([`Protocol::to_wire`]).
    pub wire_numbers: List<WireNumber>,
    /// Parameters reached through pages on this protocol (`None`: no pages): a request
    /// carries a paged register's offset in its page, after the page is selected
    /// ([`Protocol::to_wire`], [`crate::transaction::Master::transact`]).
    pub paging: Option<Paging>,
    /// The drive's register choosing where parameter writes go (the description's
    /// `persistence:`, the same in every protocol of the drive); `None`: the command's kind
    /// says it (or a [`PreStep::Persistence`] does).
    pub persistence: Option<PersistenceSelector>,
    /// The protocol's variants (other bytes for some literal parts, such as the
    /// terminator) and which one this protocol is in; `None`: it has none. See
    /// [`Protocol::variant`].
    pub variants: Option<Variants>,
    /// The error code the drive answers a well-formed request with when its function
    /// (command code) is not one of [`Protocol::commands`] (DV1 and VF-AS1 Modbus:
    /// exception 01); the reply carries the request's function marked as every command's
    /// error code marks it ([`Protocol::error_code_of_function`]). `None`: the manual does
    /// not say, and the virtual drive stays silent.
    pub unsupported_function: Option<u16>,
    /// The variants built from this protocol on first use ([`Protocol::variant`]); every
    /// protocol is built with [`VariantCache::new`]. Not part of the protocol's value (see
    /// [`VariantCache`]): it does not show in `Debug` and is not serialized.
    #[cfg_attr(feature = "serde", serde(skip))]
    pub variant_cache: VariantCache,
}
