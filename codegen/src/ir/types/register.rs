//! A register: how its value is typed in Rust, its raw bounds, its facts and its special
//! values.

use super::scaling::{ScaleByIr, ScaleChoiceIr};
use crate::parse::model::{InferredFact, WarningModel as WarningIr};
use serde::Serialize;
use vfd_runtime::units::Unit;
use vfd_runtime::{Access, DataType, Space, TakesEffect};

/// How a register's value is typed in Rust.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
#[serde(tag = "kind", content = "type", rename_all = "snake_case")]
pub enum ValueKind {
    /// A runtime quantity type, by name (`Hertz`).
    Quantity(String),
    /// A generated code-table enum, by type name.
    CodeTable(String),
    /// A generated bit-field word, by type name.
    Bitfield(String),
    /// A plain unsigned word.
    Raw,
    /// A plain signed word.
    RawSigned,
    /// A plain number with a scale other than 1.
    Scaled,
    /// A plain unsigned double word.
    RawDouble,
    /// A plain signed double word.
    RawSignedDouble,
    /// Text.
    Text,
}

/// One end of a register's range.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct BoundIr {
    /// The static bound, in raw steps.
    pub raw: i64,
    /// Code of the register that sets this bound at run time (`FH`), if any.
    pub register: Option<String>,
}

/// A register (or parameter, or coil).
#[derive(Debug, Clone, Serialize)]
pub struct RegisterIr {
    /// Number before any protocol's address map.
    pub address: u16,
    /// Identifier.
    pub id: String,
    /// Rust type name.
    pub type_name: String,
    /// The manual's code (`FH`, `FA01`, `3-03`).
    pub code: String,
    /// Other names the manual gives it (`P.33`).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub aliases: Vec<String>,
    /// English name.
    pub name: String,
    /// Chinese name.
    pub name_zh: String,
    /// The manual's description.
    pub description: String,
    /// Remarks.
    pub note: String,
    /// Engineering unit.
    pub unit: Unit,
    /// Engineering value of one raw step.
    pub scale: f64,
    /// Two's-complement signed.
    pub signed: bool,
    /// Lowest accepted value; `None` when the manual gives no range.
    pub min: Option<BoundIr>,
    /// Highest accepted value; `None` when the manual gives no range.
    pub max: Option<BoundIr>,
    /// Factory default, in engineering units.
    pub default: Option<f64>,
    /// Access over the serial link.
    pub access: Access,
    /// Writes go to RAM only.
    pub ram_only: bool,
    /// A persistent write is accepted but stored in RAM only.
    pub persistent_write_to_ram: bool,
    /// May be written while the motor runs (false when the manual does not say).
    pub writable_while_running: bool,
    /// The manual does not say whether it may be written while running (`unknown`): a
    /// master attempts the write and reports a refusal; the virtual drive accepts it.
    pub while_running_unknown: bool,
    /// Only effective when set from the panel.
    pub panel_only: bool,
    /// When a written value takes effect.
    pub takes_effect: TakesEffect,
    /// Shape on the wire.
    pub data_type: DataType,
    /// Address space.
    pub space: Space,
    /// Number of array elements (0: not an array).
    pub array_len: u8,
    /// How the value is typed in Rust.
    pub value: ValueKind,
    /// Id of the code table naming its values (complete or not), if any.
    pub code_table: Option<String>,
    /// Manual section.
    pub source: String,
    /// Facts inferred by the description, not stated by the manual.
    pub inferred: Vec<InferredFact>,
    /// Safety warnings about this register.
    pub warnings: Vec<WarningIr>,
    /// Writes to it are never answered.
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub no_reply: bool,
    /// The manual gives it no number of its own: its protocols reach it by its wire numbers
    /// only, and `address` is a number no frame carries.
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub wire_only: bool,
    /// Its place on pages as the description gives it (`on_page`): protocol id, page,
    /// offset.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub on_page: Vec<(String, u16, u16)>,
    /// Code of the live register whose value this one holds from the last trip.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub held_at_trip_of: Option<String>,
    /// Code of the other register at its address, when two share it (one read-only, one
    /// write-only: read as one, written as the other).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub shares_address_with: Option<String>,
    /// Shows the live value, but keeps its value while the drive is tripped.
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub live_except_while_tripped: bool,
    /// Its scale chosen by another register.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub scale_by: Option<ScaleByIr>,
    /// Its copies on each port (port id, register code), when it exists once per port.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub per_port: Vec<(String, String)>,
    /// Values it takes besides its range, each with its raw word.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub special_values: Vec<SpecialValueIr>,
}

/// A value a register takes besides its range.
#[derive(Debug, Clone, Serialize)]
pub struct SpecialValueIr {
    /// The value as the manual writes it.
    pub value: f64,
    /// Its raw word.
    pub raw: u32,
    /// Identifier.
    pub id: String,
    /// English meaning.
    pub name: String,
    /// Chinese meaning.
    pub name_zh: String,
}

impl RegisterIr {
    /// The register as one of its scale choices makes it (`scale_by`): that choice's scale
    /// and raw range, the same bounding registers, and no default (the default is given in
    /// the register's own scale).
    pub fn with_scale_choice(&self, choice: &ScaleChoiceIr) -> RegisterIr {
        let mut chosen = self.clone();
        chosen.scale = choice.scale;
        chosen.scale_by = None;
        chosen.default = None;
        chosen.min = Some(BoundIr {
            raw: choice.raw_min,
            register: self.min.as_ref().and_then(|b| b.register.clone()),
        });
        chosen.max = Some(BoundIr {
            raw: choice.raw_max,
            register: self.max.as_ref().and_then(|b| b.register.clone()),
        });
        chosen
    }

    /// Whether the register may be written (text is read only, whatever `access` says).
    pub fn writable(&self) -> bool {
        self.access != Access::ReadOnly && self.data_type != DataType::Text
    }

    /// Whether the register may be written persistently (EEPROM).
    pub fn persistable(&self) -> bool {
        self.writable() && !self.ram_only
    }

    /// The lowest and highest raw values the word accepts without a range.
    pub fn raw_limits(&self) -> (i64, i64) {
        self.data_type.raw_limits(self.signed)
    }

    /// The factory value as the raw word on the wire (two's complement for signed
    /// values), when the description gives a default.
    pub fn default_raw(&self) -> Option<u32> {
        let default = self.default?;
        if let Some(special) = self.special_values.iter().find(|s| s.value == default) {
            return Some(special.raw);
        }
        let raw = (default / self.scale).round() as i64;
        let bits = u32::from(self.data_type.size().max(1)) * 8;
        let mask = if bits >= 32 {
            u32::MAX
        } else {
            (1u32 << bits) - 1
        };
        Some((raw as u32) & mask)
    }

    /// Static raw bounds: the range's, else the word's.
    pub fn raw_range(&self) -> (i64, i64) {
        let (low, high) = self.raw_limits();
        (
            self.min.as_ref().map_or(low, |b| b.raw),
            self.max.as_ref().map_or(high, |b| b.raw),
        )
    }
}
