//! Scales chosen by another register: a register's own (`scale_by`) and a reference
//! word's percentage of a span.

use serde::Serialize;

/// A scale chosen by another register.
#[derive(Debug, Clone, Serialize)]
pub struct ScaleByIr {
    /// Code of the selector register.
    pub register: String,
    /// One choice per selector value.
    pub choices: Vec<ScaleChoiceIr>,
    /// The scale and range for every selector value `choices` does not list (its `value`
    /// is unused: 0).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub otherwise: Option<ScaleChoiceIr>,
}

/// The scale and range a register has for one selector value.
#[derive(Debug, Clone, Serialize)]
pub struct ScaleChoiceIr {
    /// The selector's value.
    pub value: u32,
    /// Engineering value of one raw step.
    pub scale: f64,
    /// Lowest raw value.
    pub raw_min: i64,
    /// Highest raw value.
    pub raw_max: i64,
}

/// Mode-dependent reference scaling.
#[derive(Debug, Clone, Serialize)]
pub struct ReferenceScalingIr {
    /// Manual section.
    pub source: String,
    /// Raw value meaning 100 %.
    pub full_scale_raw: u32,
    /// Ids of the registers it applies to.
    pub applies_to: Vec<String>,
    /// Id of the register choosing the mode.
    pub selector: String,
    /// Remarks.
    pub note: String,
    /// The modes.
    pub modes: Vec<ScalingModeIr>,
}

/// One mode of a reference scaling.
#[derive(Debug, Clone, Serialize)]
pub struct ScalingModeIr {
    /// Selector value.
    pub selector: u32,
    /// Low end of the span.
    pub low: SpanEndIr,
    /// High end of the span.
    pub high: SpanEndIr,
    /// The manual's wording of the rule.
    pub description: String,
}

/// One end of a span: a number, or another register's value (by id).
#[derive(Debug, Clone, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum SpanEndIr {
    /// A constant.
    Number(f64),
    /// The engineering value of a register, by id.
    Register(String),
}
