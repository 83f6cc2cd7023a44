//! The parts of a frame layout (`parts:`, `layouts:`): literals, fields, checksums, words
//! of bits, lengths, and the hand-written readers for the keys that take several shapes.

use super::commands::CodeModel;
use schemars::{json_schema, JsonSchema, Schema, SchemaGenerator};
use serde::de::value::MapAccessDeserializer;
use serde::de::{self, MapAccess, Unexpected, Visitor};
use serde::Deserialize;
use std::borrow::Cow;
use std::fmt;
use vfd_runtime::{ChecksumAlgorithm, Format, Role, SizedBy};

/// The suffix of a struct name asking the reader for "a mapping with these keys, or a
/// scalar": a scalar goes to the visitor as itself, a mapping is checked key by key (unknown
/// keys reported and skipped, missing required keys reported) before the visitor sees it.
pub const OR_SCALAR: &str = "|or_scalar";

/// `"Name|or_scalar"`, as a `&'static str`.
macro_rules! const_str_or_scalar {
    ($name:literal) => {
        concat!($name, "|or_scalar")
    };
}

/// The keys of [`PartModel`], for the reader (checked against the schema in a test).
pub const PART_FIELDS: &[&str] = &[
    "literal",
    "literal_hex",
    "field",
    "checksum",
    "word",
    "length",
    "name",
    "format",
    "width",
    "min_width",
    "size",
    "optional",
    "allowed",
    "fold_case",
    "marker",
    "covers_from",
    "covers_through",
    "fields",
    "counts",
    "times",
    "per",
    "broadcast",
];

/// A layout entry: the name of a shared part, or a part written in place.
#[derive(Debug, Clone)]
pub enum PartRefModel {
    Named(String),
    Inline(Box<PartModel>),
}

impl<'de> Deserialize<'de> for PartRefModel {
    /// Written by hand so that a mistake inside an inline part is reported as itself
    /// ("unknown field `fromat`") rather than as "no variant matched", with the path and
    /// position of the key at fault.
    fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct EntryVisitor;
        impl<'de> Visitor<'de> for EntryVisitor {
            type Value = PartRefModel;
            fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str("the name of a part or a part written as `{ ... }`")
            }
            fn visit_str<E: de::Error>(self, name: &str) -> Result<PartRefModel, E> {
                Ok(PartRefModel::Named(name.to_owned()))
            }
            fn visit_map<A: MapAccess<'de>>(self, map: A) -> Result<PartRefModel, A::Error> {
                PartModel::deserialize(MapAccessDeserializer::new(map))
                    .map(|part| PartRefModel::Inline(Box::new(part)))
            }
        }
        // Asked for as a struct that may also be a scalar (see `OR_SCALAR`), so that the
        // reader checks the keys of a part written in place as it does any struct's.
        deserializer.deserialize_struct(
            const_str_or_scalar!("PartModel"),
            PART_FIELDS,
            EntryVisitor,
        )
    }
}

impl JsonSchema for PartRefModel {
    fn schema_name() -> Cow<'static, str> {
        "PartRefModel".into()
    }

    /// As the hand-written `Deserialize` reads it: a string or a part.
    fn json_schema(generator: &mut SchemaGenerator) -> Schema {
        json_schema!({
            "description": "The name of a part under `parts`, or a part written in place as `{ ... }`.",
            "oneOf": [
                { "type": "string", "description": "The name of a part under `parts`." },
                generator.subschema_for::<PartModel>(),
            ],
        })
    }
}

#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct PartModel {
    /// Fixed bytes, as text; the first literal of a layout is its start sequence.
    pub literal: Option<String>,
    /// Fixed bytes, as hex pairs.
    pub literal_hex: Option<String>,
    /// A value field: its role.
    pub field: Option<Role>,
    /// A checksum: its algorithm.
    pub checksum: Option<ChecksumAlgorithm>,
    /// A word made of bit fields: its format (`u16be`).
    pub word: Option<Format>,
    /// A computed length: its format (`u8`).
    pub length: Option<Format>,
    /// Name for error messages and docs (defaults to the role or the part's key).
    pub name: Option<String>,
    /// How the value is written on the wire.
    pub format: Option<Format>,
    /// Digit formats: the number of digits encoded; byte formats: the number of bytes.
    pub width: Option<u8>,
    /// Digit formats: the fewest digits accepted on decode.
    pub min_width: Option<u8>,
    /// `rest` (up to the fixed parts before the frame end) or `length` (a length part covers
    /// it); left out, the format sizes the field.
    pub size: Option<SizedBy>,
    /// Whether the part may be left out, and how a decoder tells it is there.
    pub optional: Option<OptionalModel>,
    /// Values accepted on decode (letters or numbers).
    #[serde(default)]
    pub allowed: Vec<CodeModel>,
    /// Accept lower case too on decode.
    #[serde(default)]
    pub fold_case: bool,
    /// Bytes announcing an optional checksum; the checksum covers them.
    pub marker: Option<String>,
    /// Name of the first part a checksum covers.
    pub covers_from: Option<String>,
    /// Name of the last part a checksum covers, where it stops before the checksum (an ETX
    /// in between is left out); left out: up to the checksum.
    pub covers_through: Option<String>,
    /// Bit fields of a `word`.
    #[serde(default)]
    pub fields: Vec<BitsModel>,
    /// What a `length` counts.
    pub counts: Option<CountsModel>,
    /// A length: the count is multiplied by this.
    pub times: Option<u8>,
    /// A length: the count is divided by this.
    pub per: Option<u8>,
    /// A station address field: how one frame addresses every station, or a group
    /// (`{ literal: "**", wildcard: "*" }`, `{ value: 0xFF }`, Modbus `{ value: 0 }`).
    pub broadcast: Option<BroadcastAddressModel>,
}

/// The broadcast encodings of a station address part.
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct BroadcastAddressModel {
    /// Text written instead of the station number to address every station (`"**"`).
    pub literal: Option<String>,
    /// The station value that addresses every station (`0xFF`; Modbus `0`).
    pub value: Option<u32>,
    /// One character that stands for any digit of a digit-format station number: group
    /// addressing (`"*"`: `*9` is every station whose last digit is 9, `1*` every station
    /// whose first digit is 1).
    pub wildcard: Option<String>,
}

#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct BitsModel {
    /// The value's role for the transaction engine.
    pub field: Role,
    /// Name for error messages and docs (defaults to the role).
    pub name: Option<String>,
    /// `"msb:lsb"` or a single bit number.
    pub bits: String,
    /// Values accepted on decode.
    #[serde(default)]
    pub allowed: Vec<CodeModel>,
}

/// What a length counts: `{ from: part, through: part }` or `data_size`.
#[derive(Debug, Clone, PartialEq)]
pub enum CountsModel {
    Parts { from: String, through: String },
    DataSize,
}

impl<'de> Deserialize<'de> for CountsModel {
    /// By hand, so that a mistake names the value or the key at fault.
    fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        #[derive(Deserialize)]
        #[serde(deny_unknown_fields)]
        struct Parts {
            from: String,
            through: String,
        }
        struct CountsVisitor;
        impl<'de> Visitor<'de> for CountsVisitor {
            type Value = CountsModel;
            fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str("`data_size` or `{ from: part, through: part }`")
            }
            fn visit_str<E: de::Error>(self, value: &str) -> Result<CountsModel, E> {
                match value {
                    "data_size" => Ok(CountsModel::DataSize),
                    _ => Err(E::invalid_value(Unexpected::Str(value), &self)),
                }
            }
            fn visit_map<A: MapAccess<'de>>(self, map: A) -> Result<CountsModel, A::Error> {
                let Parts { from, through } = Parts::deserialize(MapAccessDeserializer::new(map))?;
                Ok(CountsModel::Parts { from, through })
            }
        }
        deserializer.deserialize_struct(
            const_str_or_scalar!("Parts"),
            &["from", "through"],
            CountsVisitor,
        )
    }
}

impl JsonSchema for CountsModel {
    fn schema_name() -> Cow<'static, str> {
        "CountsModel".into()
    }

    /// As the hand-written `Deserialize` reads it.
    fn json_schema(_: &mut SchemaGenerator) -> Schema {
        json_schema!({
            "description": "What a length counts: `{ from: part, through: part }` or `data_size`.",
            "oneOf": [
                { "const": "data_size", "description": "The bytes of the data the frame carries." },
                {
                    "type": "object",
                    "description": "The bytes from one part through another, both included.",
                    "properties": {
                        "from": { "type": "string", "description": "Name of the first part counted." },
                        "through": { "type": "string", "description": "Name of the last part counted." },
                    },
                    "required": ["from", "through"],
                    "additionalProperties": false,
                },
            ],
        })
    }
}

/// Whether a part may be left out: `true`/`false`, or for fields a presence rule
/// (`if_format_matches`, `{ if_byte_at_most: 0x3F }`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum OptionalModel {
    Flag(bool),
    IfFormatMatches,
    IfByteAtMost(u8),
}

impl<'de> Deserialize<'de> for OptionalModel {
    /// By hand, so that a mistake names the value at fault.
    fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        #[derive(Deserialize)]
        #[serde(deny_unknown_fields)]
        struct ByteAtMost {
            if_byte_at_most: u8,
        }
        struct OptionalVisitor;
        impl<'de> Visitor<'de> for OptionalVisitor {
            type Value = OptionalModel;
            fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str("true, false, `if_format_matches` or `{ if_byte_at_most: N }`")
            }
            fn visit_bool<E: de::Error>(self, flag: bool) -> Result<OptionalModel, E> {
                Ok(OptionalModel::Flag(flag))
            }
            fn visit_str<E: de::Error>(self, value: &str) -> Result<OptionalModel, E> {
                match value {
                    "if_format_matches" => Ok(OptionalModel::IfFormatMatches),
                    _ => Err(E::invalid_value(Unexpected::Str(value), &self)),
                }
            }
            fn visit_map<A: MapAccess<'de>>(self, map: A) -> Result<OptionalModel, A::Error> {
                let rule = ByteAtMost::deserialize(MapAccessDeserializer::new(map))?;
                Ok(OptionalModel::IfByteAtMost(rule.if_byte_at_most))
            }
        }
        deserializer.deserialize_struct(
            const_str_or_scalar!("ByteAtMost"),
            &["if_byte_at_most"],
            OptionalVisitor,
        )
    }
}

impl JsonSchema for OptionalModel {
    fn schema_name() -> Cow<'static, str> {
        "OptionalModel".into()
    }

    /// As the hand-written `Deserialize` reads it.
    fn json_schema(_: &mut SchemaGenerator) -> Schema {
        json_schema!({
            "description": "Whether a part may be left out: `true`/`false`, or for fields a presence rule (`if_format_matches`, `{ if_byte_at_most: 0x3F }`).",
            "oneOf": [
                { "type": "boolean", "description": "Always there (`false`) or perhaps left out (`true`)." },
                { "const": "if_format_matches", "description": "There when the bytes at its place match its format." },
                {
                    "type": "object",
                    "description": "There when the byte at its place is at most this value.",
                    "properties": {
                        "if_byte_at_most": { "type": "integer", "minimum": 0, "maximum": 255 },
                    },
                    "required": ["if_byte_at_most"],
                    "additionalProperties": false,
                },
            ],
        })
    }
}

#[cfg(test)]
mod part_fields_tests {
    use super::{PartModel, PART_FIELDS};

    #[test]
    fn the_reader_knows_every_key_of_a_part() {
        let schema = schemars::SchemaGenerator::default().into_root_schema_for::<PartModel>();
        let value = schema.to_value();
        let mut keys: Vec<&str> = value["properties"]
            .as_object()
            .expect("properties")
            .keys()
            .map(String::as_str)
            .collect();
        let mut listed = PART_FIELDS.to_vec();
        keys.sort_unstable();
        listed.sort_unstable();
        assert_eq!(keys, listed, "PART_FIELDS must list PartModel's keys");
    }
}
