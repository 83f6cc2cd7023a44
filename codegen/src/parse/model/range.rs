//! A register's range: bounds that are numbers or name another register.

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

/// A range bound: a number in engineering units, or the code of another register.
#[derive(Debug, Clone, Deserialize, Serialize, PartialEq, JsonSchema)]
#[serde(untagged)]
pub enum BoundModel {
    Number(f64),
    Register(String),
}

#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct RangeModel {
    /// Lowest value in engineering units, or the code or id of a register giving it.
    pub min: BoundModel,
    /// Highest value in engineering units, or the code or id of a register giving it.
    pub max: BoundModel,
}
