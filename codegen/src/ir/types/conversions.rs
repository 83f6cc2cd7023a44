//! The manual's formulas between registers, parsed.

use serde::Serialize;
use vfd_runtime::units::Unit;

/// A formula of the manual, parsed.
#[derive(Debug, Clone, Serialize)]
pub struct ConversionIr {
    /// Identifier (the function's name).
    pub id: String,
    /// What the result is.
    pub name: String,
    /// Manual section.
    pub source: String,
    /// The formula as written.
    pub formula: String,
    /// The formula in postfix order, as the runtime evaluates it.
    pub program: Vec<vfd_runtime::conversion::Op>,
    /// The inputs, in argument order.
    pub inputs: Vec<ConversionInputIr>,
    /// The result's unit.
    pub unit: Unit,
    /// Code of the register the result belongs to, if any.
    pub result: Option<String>,
    /// The result is cut to a whole number.
    pub truncate: bool,
    /// The selector register (code) and value it applies for (`None` value: nonzero).
    pub when: Option<(String, Option<u32>)>,
    /// Remarks.
    pub note: String,
    /// Worked examples: input values in argument order, and the result.
    pub examples: Vec<(Vec<f64>, f64, String)>,
}

/// One input of a conversion.
#[derive(Debug, Clone, Serialize)]
pub struct ConversionInputIr {
    /// Its name in the formula and as an argument.
    pub name: String,
    /// Code of the register it comes from, if any.
    pub register: Option<String>,
    /// The factor applied to the register's value first.
    pub times: f64,
    /// What it is, when it is no register.
    pub description: String,
}
