//! Rules writes over the link follow: where parameter writes go (`persistence:`) and which
//! combinations of register values the manual forbids (`forbidden_combinations:`).

use schemars::JsonSchema;
use serde::Deserialize;

/// A register of the drive that chooses where parameter writes over the link go
/// (`persistence:`).
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct PersistenceModel {
    /// Code or id of the selector register.
    pub selector: String,
    /// The selector's value with which parameter writes go to RAM only.
    pub ram: u32,
    /// The selector's value with which parameter writes go to RAM and EEPROM.
    pub persistent: u32,
    /// The register numbers (before any address map) whose writes the selector governs;
    /// left out: every parameter. RAM-only registers are never governed.
    #[serde(default)]
    pub registers: Vec<AddressSpanModel>,
    /// Where the manual says it.
    pub source: String,
    /// Remarks.
    #[serde(default)]
    pub note: String,
}

/// Register numbers `from` through `to`.
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct AddressSpanModel {
    /// The first register number.
    pub from: u16,
    /// The last register number.
    pub to: u16,
}

/// Values of several registers the manual forbids together (`forbidden_combinations:`).
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ForbiddenCombinationModel {
    /// Unique lower snake case name (`two_stop_bits_with_parity`).
    pub id: String,
    /// The manual's rule, in its words (quoted by the error a forbidden write gets).
    pub rule: String,
    /// What the rule says, in English.
    pub meaning: String,
    /// Where the manual says it.
    pub source: String,
    /// The conditions, all holding at once: at least two, each about another register.
    pub when: Vec<CombinationConditionModel>,
}

/// One condition of a forbidden combination: the register holds one of these values.
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct CombinationConditionModel {
    /// The register, by code, id or alias.
    pub register: String,
    /// Its values (in its unit, as its range gives them) that fulfil the condition.
    pub values: Vec<f64>,
}
