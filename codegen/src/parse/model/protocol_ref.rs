//! How a drive speaks a protocol file (`protocols[]`): its numbering, commands, limits,
//! timing, block transfer, broadcasts, pages and variants.

use super::commands::{AddressMapModel, CodeModel, PreStepModel};
use super::error_codes::ProtocolErrorCodesModel;
use super::register::WireNumberModel;
use schemars::JsonSchema;
use serde::Deserialize;
use std::collections::BTreeMap;
use vfd_runtime::serial::BeforeStart;
use vfd_runtime::{BroadcastAnswer, DataType};

#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ProtocolRef {
    /// The name this drive file uses for the protocol (in `examples[].protocol`).
    pub id: String,
    /// The protocol file it is: `protocols/<uses>.yaml`.
    pub uses: String,
    /// The manual section describing the protocol.
    pub source: String,
    /// How this drive numbers registers on the wire, per address space (overrides the
    /// protocol file): `{ parameter: { multiply: 10, offset: -1 }, coil: { multiply: 1, offset: -1 } }`.
    #[serde(default)]
    pub address_maps: BTreeMap<String, AddressMapModel>,
    /// Steps this drive needs before some requests (added to the protocol file's).
    #[serde(default)]
    pub pre_steps: Vec<PreStepModel>,
    /// The station numbers this protocol reaches, where narrower than the drive's
    /// `addressing` (a two-digit ASCII station: 0-99; Modbus: 1-247).
    pub addressing: Option<StationRangeModel>,
    /// The codes of the protocol file's commands this drive carries out, where it
    /// implements only some (`[0x03, 0x06]`); left out: all of them.
    pub commands: Option<Vec<CodeModel>>,
    /// The data types this drive carries over the protocol, where fewer than the protocol
    /// file's commands allow (`[word]`: one register per Modbus request); left out: all.
    pub data_types: Option<Vec<DataType>>,
    /// The most registers this drive returns to one read, where fewer than the protocol
    /// file's `max_words_per_read` (`12`; `1`: one register per read); left out: the
    /// protocol file's.
    pub max_words_per_read: Option<u16>,
    /// The most registers one write of several carries on this drive, where fewer than the
    /// protocol file's `max_words_per_write` (DV1: `12`); left out: the protocol file's.
    pub max_words_per_write: Option<u16>,
    /// The longest frame on the wire in bytes, where the drive's manual makes it shorter
    /// than the protocol file's `max_frame_len` (DV1 Modbus RTU: `33`, a write of its 12
    /// registers); it sizes buffers and reply timeouts. At least the longest frame the
    /// drive's commands make at its word limits; left out: the protocol file's.
    pub max_frame_len: Option<u16>,
    /// A read or write of several registers is carried out for the registers that can be,
    /// and refused only when none can (DV1 l. 473: 若有 1 个及以上可以操作就不视为错误): a
    /// register that does not exist reads as 0, one that does not exist or refuses its
    /// value is left as it is. Left out (false): one such register refuses the request.
    #[serde(default)]
    pub partial_blocks: bool,
    /// The codes this protocol's error replies carry as the manual gives them for this
    /// drive (its own Modbus exception table, whose numbers mean something else than the
    /// drive's `error_codes`): they name this protocol's error replies in place of the
    /// drive's table and of the protocol file's own.
    pub error_codes: Option<ProtocolErrorCodesModel>,
    /// Per command (by code): the registers it may address on this drive, and what its data
    /// is when not a value in the register's own unit
    /// (`[{ code: S, registers: [FA01, FA05], percent_of: FH, step: 0.01 }]`).
    #[serde(default)]
    pub command_registers: Vec<CommandRegistersModel>,
    /// What the protocol's block-transfer command (`kind: block`) writes and reads on this
    /// drive; left out, the drive has no block transfer and the command is dropped.
    pub block: Option<BlockModel>,
    /// Silence between frames in character times, where this drive's manual states its own
    /// (overrides the protocol file's `frame_gap_chars`; VF-AS1 Toshiba protocol: 3.5).
    pub frame_gap_chars: Option<f32>,
    /// The shortest silence between frames in milliseconds, whatever the baud rate: the gap
    /// is the longer of this and `frame_gap_chars` (DV1 Modbus RTU: 10; VF-AS1: 2).
    pub frame_gap_ms: Option<f32>,
    /// The longest silence between two bytes of one frame, in character times; the drive
    /// drops a frame with a longer one (VF-AS1: 1.5). Left out: no limit but
    /// `serial.timing.frame_abandon_ms`.
    pub max_inner_gap_chars: Option<f32>,
    /// What the drive makes of bytes before a frame's start sequence: `skip` (the default:
    /// the frame begins at its start) or `reject` (the frame is not answered; VF-AS1).
    pub before_start: Option<BeforeStart>,
    /// Registers whose value delays every reply (VF-AS1 F805 / F825): the master adds the
    /// wait to its reply timeout, the virtual drive waits that long.
    pub reply_delay: Option<ReplyDelayModel>,
    /// Which commands the drive carries out when broadcast over this protocol (the address
    /// part's `broadcast:` encodings in the protocol file) and which station answers. Left
    /// out: the drive takes no broadcasts over this protocol.
    pub broadcast: Option<BroadcastRuleModel>,
    /// Parameters this protocol reaches through pages: a request carries a parameter's
    /// offset in its page, after the page register has been set (DV1 Eaton protocol: HFF).
    pub pages: Option<PagesModel>,
    /// Which of the protocol file's `variants` the drive speaks: the register that selects
    /// it (its code table's value ids are variant ids) and the error the drive answers a
    /// frame in another variant's form with (`{ register: 07-06, mismatch_error:
    /// protocol_error }`). Left out: the drive speaks the first variant.
    pub variant: Option<VariantRuleModel>,
    /// What the drive answers to a well-formed request with a function (command code) it
    /// does not carry out, where its manual says (`{ error_code: 0x01, source: "..." }`:
    /// the error reply with exception 01). Left out: the manual does not say, and the
    /// virtual drive stays silent, so a master waits for its time-out.
    pub unsupported_function: Option<UnsupportedFunctionModel>,
}

/// What a drive answers to a function it lacks (`protocols[].unsupported_function`).
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct UnsupportedFunctionModel {
    /// The error code its error reply carries: one of the protocol's error codes (the
    /// reply's function code is the request's, marked as the commands' error codes are:
    /// Modbus function + 80h).
    pub error_code: u16,
    /// Where the manual says so.
    pub source: String,
}

/// A protocol's parameter pages (`protocols[].pages`): which register numbers lie on which
/// page, and the register that switches pages.
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct PagesModel {
    /// The manual section describing the pages.
    pub source: String,
    /// The page register's numbers on the wire: `{ read: 0x7F, write: 0xFF }` (`read` may
    /// be left out when it cannot be read back).
    pub select: WireNumberModel,
    /// The page register's data type: `byte` where the page switch carries a narrower data
    /// field than a word's (two hex digits where words take four), so that it goes out with
    /// the protocol's write command that carries bytes, in that command's own layout.
    /// Default `word`.
    pub data_type: Option<DataType>,
    /// The ranges of register numbers laid out on pages.
    pub ranges: Vec<PageRangeModel>,
    /// Codes or ids of registers whose write resets the drive's page (an inverter reset):
    /// the master selects the page again before the next paged access.
    #[serde(default)]
    pub forgotten_after: Vec<String>,
    /// The page a drive is on after power-on or a reset (what the virtual drive starts on);
    /// default 0.
    #[serde(default)]
    pub initial: u16,
    /// What the manual does not say and the description assumes (`[initial]`).
    #[serde(default)]
    pub assumed: Vec<String>,
    /// Notes for people; nothing is generated from them.
    #[serde(default)]
    pub note: String,
}

/// Register numbers `registers[0]..=registers[1]`, laid out `size` to a page from
/// `first_page` on (`protocols[].pages.ranges[]`).
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct PageRangeModel {
    /// What the range is (`P mode`, `group mode`).
    pub name: String,
    /// The lowest and the highest register number of the range.
    pub registers: [u32; 2],
    /// Registers per page.
    pub size: u16,
    /// The page of the range's first register.
    pub first_page: u16,
    /// Pages the range skips (no register lies on them).
    #[serde(default)]
    pub missing_pages: Vec<u16>,
}

/// How a drive selects the variant of a protocol it speaks (`protocols[].variant`).
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct VariantRuleModel {
    /// The register (code or id) whose value selects the variant: a parameter with a
    /// `code_table` whose values' ids are the protocol file's variant ids (DV1 07-06:
    /// `1: cr`, `2: cr_lf`). Every variant must be selected by some value.
    pub register: String,
    /// The id of the error code (in the table naming this protocol's error replies) the
    /// drive answers a frame in another variant's form with (DV1: `protocol_error`, H03);
    /// left out: the drive does not answer such a frame.
    pub mismatch_error: Option<String>,
}

/// What one command of a protocol may address on this drive, and what its data means.
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct CommandRegistersModel {
    /// The command's code in the protocol file (`S`, `0x06`).
    pub code: CodeModel,
    /// Codes or ids of the registers it may address; any other is refused before sending.
    pub registers: Vec<String>,
    /// Code or id of the register whose value is 100 %: the data is a percentage of it,
    /// not a value in the addressed register's unit (the unit must be the same).
    pub percent_of: Option<String>,
    /// With `percent_of`: the percentage one raw step stands for (default 0.01).
    pub step: Option<f64>,
    /// With `percent_of`: the conversions (ids under `conversions:`) a receiving drive
    /// turns the raw percentage into its register's value with, the first whose `when`
    /// holds (VF-AS1: frequency points when F810 is not 0, else the plain ratio). Left out:
    /// the plain proportion of the 100 % register.
    #[serde(default)]
    pub received_by: Vec<String>,
}

/// A drive's block transfer: which registers the words of a block-transfer request are
/// written to and which registers its reply reads, position by position.
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct BlockModel {
    /// The manual section describing it.
    pub source: String,
    /// The selector registers (codes or ids) of the words written, in word order (`[F870,
    /// F871]`). Each has a `code_table` whose values say which `register` they select.
    pub write: Vec<String>,
    /// The selector registers of the words read, in word order (`[F875, ..., F879]`).
    pub read: Vec<String>,
    /// Selections that replace the selectors' while a register holds a value.
    #[serde(default)]
    pub modes: Vec<BlockModeModel>,
    /// The bit field naming the reply's write-status bits (bit `n`: word `n` not written).
    pub status: Option<String>,
    /// What the manual leaves open.
    #[serde(default)]
    pub note: String,
}

/// A block-transfer mode: while `register` holds `value`, the words go to and come from
/// fixed registers.
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct BlockModeModel {
    /// The register (code or id) that turns the mode on (`FA80`).
    pub register: String,
    /// The value that turns it on.
    pub value: u32,
    /// The registers written, in word order.
    pub write: Vec<String>,
    /// The registers read, in word order.
    pub read: Vec<String>,
    /// The manual section describing it.
    pub source: String,
}

/// Registers that set a wait before every reply (`protocols[].reply_delay`).
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ReplyDelayModel {
    /// The registers (code or id), each with a unit of time (`s` or `ms`) and a range. With
    /// several (one per port), the longest value applies: the master cannot tell which port
    /// it is on.
    pub registers: Vec<String>,
}

/// A drive's broadcast rule for one protocol (`protocols[].broadcast`).
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct BroadcastRuleModel {
    /// The command codes the drive carries out when broadcast: writes only (`[W, P]`,
    /// `[0x06, 0x10]`); a broadcast read is refused before anything is sent.
    pub commands: Vec<CodeModel>,
    /// Which station answers: `none` (Modbus) or `lowest_matching` (the lowest station the
    /// broadcast addresses: 00 for every station, 09 for the group `*9`).
    pub answered_by: BroadcastAnswer,
}

/// A range of station numbers.
#[derive(Debug, Clone, Copy, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct StationRangeModel {
    /// Lowest station number.
    pub min: u8,
    /// Highest station number.
    pub max: u8,
}
