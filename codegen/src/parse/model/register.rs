//! A register (`registers[]`) and the facts written on it: whether it may be written while
//! running, what is inferred, special values, warnings, and its numbers on the wire or on
//! a page.

use super::range::RangeModel;
use super::scaling::ScaleByModel;
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use vfd_runtime::{Access, DataType, Space, TakesEffect};

/// A safety warning: what can go wrong, and where the manual says so.
#[derive(Debug, Clone, Deserialize, JsonSchema, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct WarningModel {
    /// The warning, in English (the manual's Chinese may follow in brackets).
    pub text: String,
    /// The manual section it comes from; empty when it follows from the description only.
    #[serde(default)]
    pub source: String,
}

/// Whether a register may be written while the motor runs, as the manual gives it: `true`,
/// `false`, or `unknown` where its table has no such column (the VF-AS1's section 7 table).
#[derive(Debug, Clone, Copy, JsonSchema, Serialize, PartialEq, Eq)]
#[serde(untagged)]
pub enum WhileRunning {
    /// Stated by the manual (or inferred, and then listed in `inferred`).
    Known(bool),
    /// `unknown`: the manual does not say. A master attempts the write and reports the
    /// drive's refusal; the virtual drive accepts it.
    Unknown(UnknownWord),
}

impl Default for WhileRunning {
    fn default() -> Self {
        WhileRunning::Known(false)
    }
}

impl WhileRunning {
    /// Known to be writable while running.
    pub fn writable(self) -> bool {
        self == WhileRunning::Known(true)
    }

    /// The manual does not say.
    pub fn is_unknown(self) -> bool {
        matches!(self, WhileRunning::Unknown(_))
    }
}

impl<'de> Deserialize<'de> for WhileRunning {
    fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct Visitor;
        impl serde::de::Visitor<'_> for Visitor {
            type Value = WhileRunning;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("true, false or unknown")
            }
            fn visit_bool<E: serde::de::Error>(self, value: bool) -> Result<WhileRunning, E> {
                Ok(WhileRunning::Known(value))
            }
            fn visit_str<E: serde::de::Error>(self, value: &str) -> Result<WhileRunning, E> {
                match value {
                    "unknown" => Ok(WhileRunning::Unknown(UnknownWord::Unknown)),
                    other => Err(E::invalid_value(
                        serde::de::Unexpected::Str(other),
                        &"true, false or unknown",
                    )),
                }
            }
        }
        deserializer.deserialize_any(Visitor)
    }
}

/// The word `unknown`: a fact the manual leaves open.
#[derive(Debug, Clone, Copy, Deserialize, JsonSchema, Serialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum UnknownWord {
    /// `unknown`.
    Unknown,
}

/// A register fact that can be marked as inferred (the description's reading, not the
/// manual's statement).
#[derive(Debug, Clone, Copy, Deserialize, JsonSchema, Serialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum InferredFact {
    /// The English name.
    Name,
    /// The unit.
    Unit,
    /// The step (`scale`).
    Scale,
    /// The range.
    Range,
    /// The default.
    Default,
    /// The access (read-only, read-write, write-only).
    Access,
    /// The data type (word, double word, ...).
    DataType,
    /// `ram_only`.
    RamOnly,
    /// `writable_while_running`.
    WritableWhileRunning,
    /// The address: derived by a rule of the manual, not printed for this register (DV1
    /// 00-08 at 2718h by the group-mode rule 10000 + group number).
    Address,
}

#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct RegisterModel {
    /// Communication number, 0x0000-0xFFFF, unique within its space. Left out for a
    /// register the manual gives no number of its own: one its protocols reach by its own
    /// numbers on the wire (`wire_numbers`, an instruction code such as H7A) or by its place
    /// on a page (`on_page`).
    #[serde(rename = "address")]
    pub given_address: Option<u32>,
    /// The register's number in the description: `address` as given, else the number its
    /// place on a page gives (`on_page`), else a number of its own that no frame carries
    /// (a register known by its wire numbers only). Set when the file is loaded
    /// (`load::register_numbers`).
    #[serde(skip)]
    pub address: u32,
    /// Unique lower snake case name; it becomes a Rust type (`upper_limit_frequency` -> `UpperLimitFrequency`).
    pub id: String,
    /// The manual's code or mnemonic for the register, unique.
    pub code: String,
    /// Other names the manual gives the register (the DV1's P numbers: `[P.33]` for 07-00),
    /// each unique among the codes, ids and aliases: usable wherever a register is named
    /// (ranges, relations, the command line, `DriveInfo::register`) and shown on the page;
    /// one that makes a Rust name becomes a type alias (`pub type P33 = Protocol;`).
    #[serde(default)]
    pub aliases: Vec<String>,
    /// The register's name in English.
    pub name: String,
    /// The register's name as the manual prints it in Chinese.
    #[serde(default)]
    pub name_zh: String,
    /// Prose for the reference page.
    #[serde(default)]
    pub description: String,
    /// Unit of the engineering value (`Hz`, `s`, `%`, `A`, `V`, `h`, `kW`, `rpm`); left out for plain numbers.
    #[serde(default)]
    pub unit: Option<String>,
    /// Engineering value of one raw step (default 1).
    #[serde(default)]
    pub scale: Option<f64>,
    /// The word is two's complement (default false).
    #[serde(default)]
    pub signed: bool,
    /// Allowed values in engineering units; a bound may name another register.
    pub range: Option<RangeModel>,
    /// Factory value in engineering units; must lie in the range.
    pub default: Option<f64>,
    /// `read-only`, `read-write` (default) or `write-only`.
    #[serde(default)]
    pub access: Option<Access>,
    /// No persistent (EEPROM) write is generated: the drive refuses the persistent command.
    #[serde(default)]
    pub ram_only: bool,
    /// The drive accepts the persistent (EEPROM) command for this register but keeps the
    /// value in RAM only (lost at power-off), as a manual's own example shows it accepted;
    /// unlike `ram_only`, which refuses it. Not with `ram_only`.
    #[serde(default)]
    pub persistent_write_to_ram: bool,
    /// May be written while the motor runs: `true`, `false` (default) or `unknown` (the
    /// manual's table has no such column).
    #[serde(default)]
    pub writable_while_running: WhileRunning,
    /// Only effective when set from the panel.
    #[serde(default)]
    pub panel_only: bool,
    /// `immediately` (default) or `after_reset`.
    #[serde(default)]
    pub takes_effect: Option<TakesEffect>,
    /// Id of the bit-field word the value is (no unit or scale then).
    pub bitfield: Option<String>,
    /// Id of the code table the value is a code of (no unit or scale then).
    pub code_table: Option<String>,
    /// `word` (default), `double_word`, `bit` or `text`.
    pub data_type: Option<DataType>,
    /// `parameter` (default) or `coil`.
    pub space: Option<Space>,
    /// Number of elements of an array (indexed) parameter.
    pub array: Option<u8>,
    /// The manual section describing the register.
    pub source: String,
    /// Anything the manual says that fits nowhere else.
    #[serde(default)]
    pub note: String,
    /// Facts of this register that are inferred rather than stated by the manual:
    /// `[unit, scale, writable_while_running, ...]`; the page marks them.
    #[serde(default)]
    pub inferred: Vec<InferredFact>,
    /// Safety warnings about writing or using this register.
    #[serde(default)]
    pub warnings: Vec<WarningModel>,
    /// Writes to it are never answered (an inverter reset): a master returns once the
    /// frame is sent (its wire time and the frame gap) instead of waiting for a reply, and
    /// the virtual drive stays silent.
    #[serde(default)]
    pub no_reply: bool,
    /// Its own numbers on the wire in some of the drive's protocols (by protocol id), for
    /// reading and for writing, where its command's address map does not give them (the
    /// DV1's 1002h is read as Eaton code 6Dh and written as EDh); a direction left out
    /// cannot be used over that protocol.
    #[serde(default)]
    pub wire_numbers: BTreeMap<String, WireNumberModel>,
    /// Its place on a page, per protocol with pages (`protocols[].pages`), where the manual
    /// gives the register by page and number only (`{ eaton: { page: 1, offset: 0x5F } }`):
    /// without an `address`, the register's number is the one the page ranges lay there;
    /// with one, the two must agree.
    #[serde(default)]
    pub on_page: BTreeMap<String, PagePlaceModel>,
    /// The live register (code or id) whose value this register holds from the moment of
    /// the last trip (`FD00` for FE00): the virtual drive copies it when it trips.
    pub held_at_trip_of: Option<String>,
    /// The register shows the live value but keeps the value it had while the drive is
    /// tripped.
    #[serde(default)]
    pub live_except_while_tripped: bool,
    /// The scale (and range) is chosen by another register's value:
    /// `{ register: FA09, values: [{ value: 0, scale: 0.01 }, { value: 1, scale: 0.1 }] }`.
    /// `scale` and `range` remain the register's when the selector is not known.
    pub scale_by: Option<ScaleByModel>,
    /// Values outside the range that the register also takes, each carried by its own raw
    /// word (`{ value: 99999, raw: 0xFFFF, id: no_check, name: No time-out check }`); a
    /// special value may be the default.
    #[serde(default)]
    pub special_values: Vec<SpecialValueModel>,
}

impl RegisterModel {
    /// Whether `name` is its code, id or one of its aliases (as written).
    pub fn is_named(&self, name: &str) -> bool {
        self.code == name || self.id == name || self.aliases.iter().any(|a| a == name)
    }
}

/// A value a register takes besides its range, with its own raw word.
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SpecialValueModel {
    /// The value as the manual writes it (`99999`), in the register's engineering terms.
    pub value: f64,
    /// The raw word carrying it (`0xFFFF`).
    pub raw: u32,
    /// Lower snake case name of the value.
    pub id: String,
    /// What it means, in English.
    pub name: String,
    /// What it means, as the manual prints it in Chinese.
    #[serde(default)]
    pub name_zh: String,
}

/// A register's place on a page of one protocol (`registers[].on_page`).
#[derive(Debug, Clone, Copy, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct PagePlaceModel {
    /// The page.
    pub page: u16,
    /// Its number on the page, before the command's address map (the read code: P.195 is
    /// 5Fh on page 1).
    pub offset: u16,
}

/// A register's own numbers on the wire in one protocol (`registers[].wire_numbers`).
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct WireNumberModel {
    /// Its number in read requests.
    pub read: Option<u32>,
    /// Its number in write requests.
    pub write: Option<u32>,
}
