//! The manual's formulas between registers (`conversions:`).

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// A formula of the manual between registers (`conversions:`).
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ConversionModel {
    /// Lower snake case: it names the generated function.
    pub id: String,
    /// What the result is, in English.
    pub name: String,
    /// The manual section giving the formula.
    pub source: String,
    /// The formula with `+ - * /` and parentheses over numbers and the inputs' names
    /// (`"(speed * poles * 10 + 6) / 12"`).
    pub formula: String,
    /// The inputs, in the generated function's argument order.
    pub inputs: Vec<ConversionInputModel>,
    /// The result's unit (`Hz`, `rpm`); left out for plain numbers.
    pub unit: Option<String>,
    /// The register the result goes to or comes from, when it is one (code or id).
    pub result: Option<String>,
    /// `truncate`: the result is cut to a whole number, as the drive's integer arithmetic
    /// does; left out: exact.
    pub rounding: Option<RoundingModel>,
    /// When the formula applies: the selector register (code or id) and its value
    /// (`{ register: F810, value: 0 }`); left out: always.
    pub when: Option<ConversionWhenModel>,
    /// Anything the manual says about the formula that fits nowhere else.
    #[serde(default)]
    pub note: String,
    /// The manual's worked numbers; each becomes a test.
    pub examples: Vec<ConversionExampleModel>,
}

/// How a conversion's result is rounded.
#[derive(Debug, Clone, Copy, Deserialize, Serialize, JsonSchema, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum RoundingModel {
    /// Cut towards zero to a whole number.
    Truncate,
}

/// The condition under which a conversion applies.
#[derive(Debug, Clone, Deserialize, Serialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ConversionWhenModel {
    /// Code or id of the register.
    pub register: String,
    /// Its value (`0`), or `nonzero`.
    pub value: ConditionValueModel,
}

/// A selector value a conversion applies for.
#[derive(Debug, Clone, Deserialize, Serialize, JsonSchema, PartialEq)]
#[serde(untagged)]
pub enum ConditionValueModel {
    /// This value.
    Value(u32),
    /// `nonzero`: any value but 0.
    Word(String),
}

/// One input of a conversion.
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ConversionInputModel {
    /// The name the formula uses (lower snake case; also the argument's name).
    pub name: String,
    /// The register it comes from (code or id), when it is one: the value is the
    /// register's raw word times its scale (a code table's value as is).
    pub register: Option<String>,
    /// Multiplies the register's value first (F856 counts pole pairs: `times: 2` gives
    /// the poles).
    pub times: Option<f64>,
    /// What the input is, when it is no register (the received percentage).
    #[serde(default)]
    pub description: String,
}

/// A worked example of a conversion: its inputs and result.
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ConversionExampleModel {
    /// Input values by name (the register's own value, before `times`).
    pub inputs: BTreeMap<String, f64>,
    /// The result the manual gives.
    pub result: f64,
    /// The manual section giving the numbers.
    pub source: String,
}
