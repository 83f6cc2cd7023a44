//! Scales chosen by another register: a register's own (`scale_by:`) and a reference
//! word's percentage of a span (`reference_scaling:`).

use super::range::{BoundModel, RangeModel};
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

/// A register's scale chosen by another register's value (`scale_by:`).
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ScaleByModel {
    /// Code or id of the register whose value chooses the scale.
    pub register: String,
    /// One entry per value of that register.
    pub values: Vec<ScaleChoiceModel>,
    /// The scale (and range) for every value `values` does not list (DV1: 00-08 = 0 gives
    /// two decimals, any other value one).
    pub otherwise: Option<ScaleOtherwiseModel>,
}

/// The scale (and range) a register has for the selector values a `scale_by` does not list.
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ScaleOtherwiseModel {
    /// Engineering value of one raw step with these values.
    pub scale: f64,
    /// The range with these values, in engineering units (left out: the register's).
    pub range: Option<RangeModel>,
}

/// The scale (and range) a register has for one value of its selector.
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ScaleChoiceModel {
    /// The selector's value.
    pub value: u32,
    /// Engineering value of one raw step with this choice.
    pub scale: f64,
    /// The range with this choice, in engineering units (left out: the register's).
    pub range: Option<RangeModel>,
}

/// A reference word that is a percentage of a span chosen by a selector register.
#[derive(Debug, Clone, Deserialize, Serialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ReferenceScalingModel {
    /// The manual section describing the scaling.
    pub source: String,
    /// The raw value meaning 100 %.
    pub full_scale_raw: u32,
    /// Ids of the registers scaled this way.
    pub applies_to: Vec<String>,
    /// Id of the register choosing the mode.
    pub selector: String,
    /// Anything the manual says about the scaling that fits nowhere else.
    #[serde(default)]
    pub note: String,
    /// The spans, one per selector value: value = percent x (high - low).
    pub modes: Vec<ScalingModeModel>,
}

#[derive(Debug, Clone, Deserialize, Serialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ScalingModeModel {
    /// The selector register's value choosing this mode.
    pub selector: u32,
    /// The span's low end: a number or a register id.
    pub low: BoundModel,
    /// The span's high end: a number or a register id.
    pub high: BoundModel,
    /// What the mode means.
    pub description: String,
}
