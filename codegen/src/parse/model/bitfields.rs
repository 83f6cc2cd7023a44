//! Bit-field words (`bitfields:`): their bits, bit groups and worked values.

use schemars::JsonSchema;
use serde::Deserialize;
use std::collections::BTreeMap;

#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct BitfieldModel {
    /// Lower snake case: registers name the word by it; it becomes a Rust type.
    pub id: String,
    /// The word's name in English.
    pub name: String,
    /// The word's name as the manual prints it in Chinese.
    #[serde(default)]
    pub name_zh: String,
    /// The manual section describing the word.
    pub source: String,
    /// Anything the manual says about the word that fits nowhere else.
    #[serde(default)]
    pub note: String,
    /// The word's bits and bit groups.
    pub fields: Vec<BitModel>,
    /// The manual's worked values of the word; each becomes a test.
    #[serde(default)]
    pub examples: Vec<BitExampleModel>,
}

#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct BitModel {
    /// A one-bit field.
    pub bit: Option<u8>,
    /// A multi-bit field as `"msb:lsb"`.
    pub bits: Option<String>,
    /// Lower snake case name of the field (an accessor in Rust); required unless `reserved`.
    pub id: Option<String>,
    /// The bits carry nothing (no accessor is generated).
    #[serde(default)]
    pub reserved: bool,
    /// What the field means, in English.
    #[serde(default)]
    pub name: String,
    /// What the field means, as the manual prints it in Chinese.
    #[serde(default)]
    pub name_zh: String,
    /// What a one-bit field's 0 means.
    #[serde(default)]
    pub zero: String,
    /// What a one-bit field's 1 means.
    #[serde(default)]
    pub one: String,
    /// What a one-bit field's 0 means, in Chinese.
    #[serde(default)]
    pub zero_zh: String,
    /// What a one-bit field's 1 means, in Chinese.
    #[serde(default)]
    pub one_zh: String,
    /// Code table giving the meanings of a multi-bit field's values.
    pub code_table: Option<String>,
    /// Anything the manual says about the field that fits nowhere else.
    #[serde(default)]
    pub note: String,
}

#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct BitExampleModel {
    /// The word's raw value.
    pub value: u32,
    /// The ids of the one-bit fields that are 1 in it.
    pub set: Vec<String>,
    /// The values of multi-bit fields in it, by field id (`{ character: 0x30 }`); fields
    /// left out are 0.
    #[serde(default)]
    pub fields: BTreeMap<String, u32>,
    /// What the manual says the value does.
    pub description: String,
    /// The manual section giving the example.
    pub source: String,
}
