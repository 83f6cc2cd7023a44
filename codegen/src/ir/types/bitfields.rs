//! Bit-field words: their fields and worked values.

use serde::Serialize;

/// A bit-field layout of a word.
#[derive(Debug, Clone, Serialize)]
pub struct BitfieldIr {
    /// Identifier.
    pub id: String,
    /// Rust type name.
    pub type_name: String,
    /// English name.
    pub name: String,
    /// Chinese name.
    pub name_zh: String,
    /// Manual section.
    pub source: String,
    /// Remarks.
    pub note: String,
    /// Codes of the registers whose value it is.
    pub registers: Vec<String>,
    /// Fields, in file order.
    pub fields: Vec<BitIr>,
    /// Worked examples.
    pub examples: Vec<BitExampleIr>,
}

impl BitfieldIr {
    /// Bits the manual marks reserved.
    pub fn reserved_mask(&self) -> u16 {
        self.fields
            .iter()
            .filter(|f| f.reserved)
            .fold(0, |mask, f| mask | f.mask())
    }
}

/// One field of a bit-field word.
#[derive(Debug, Clone, Serialize)]
pub struct BitIr {
    /// Identifier (`reserved_<lsb>` for unnamed reserved bits).
    pub id: String,
    /// Rust accessor name.
    pub method: String,
    /// Lowest bit.
    pub lsb: u8,
    /// Width in bits.
    pub width: u8,
    /// Reserved by the manual.
    pub reserved: bool,
    /// English name.
    pub name: String,
    /// Chinese name.
    pub name_zh: String,
    /// Meaning of 0.
    pub zero: String,
    /// Meaning of 1.
    pub one: String,
    /// Chinese meaning of 0.
    pub zero_zh: String,
    /// Chinese meaning of 1.
    pub one_zh: String,
    /// Code table giving the meanings of a multi-bit field's values.
    pub code_table: Option<String>,
    /// Remarks.
    pub note: String,
}

impl BitIr {
    /// The field's bits within the word.
    pub fn mask(&self) -> u16 {
        (((1u32 << self.width) - 1) << self.lsb) as u16
    }
}

/// A worked bit-field example.
#[derive(Debug, Clone, Serialize)]
pub struct BitExampleIr {
    /// The word.
    pub value: u16,
    /// Ids of the fields it sets.
    pub set: Vec<String>,
    /// Multi-bit fields and their values, by id.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub fields: Vec<(String, u16)>,
    /// The manual's words.
    pub description: String,
    /// Manual section.
    pub source: String,
}
