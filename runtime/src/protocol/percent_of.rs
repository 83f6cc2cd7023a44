//! A command's data as a percentage of another register's value (`percent_of:`).

use crate::layout::{List, Text};

/// A command's data as a percentage of another register's value (the Toshiba S command
/// carries a frequency in 0.01 % of the maximum frequency): `raw = value / reference x 100
/// / step`, truncated, and back `value = raw x step / 100 x reference`.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct PercentOf {
    /// Code of the register whose value is 100 %.
    pub register: Text,
    /// The percentage one raw step stands for (0.01).
    pub step: f64,
    /// Conversions (ids of the drive's `conversions`) a receiving drive turns the raw
    /// percentage into its register's value with, the first that applies; empty: the plain
    /// proportion ([`PercentOf::from_raw`]).
    pub received_by: List<Text>,
}

impl PercentOf {
    /// The raw word for `value` when `reference` (the register's value in the same unit) is
    /// 100 %, truncated toward zero as the manuals do; `None` when the reference is not
    /// positive or the result does not fit 16 bits (no other range is checked).
    pub fn to_raw(&self, value: f64, reference: f64) -> Option<u32> {
        if !(reference > 0.0 && self.step > 0.0 && value.is_finite()) {
            return None;
        }
        // A hair above, so that 50 / 100 % at 0.01 % steps is 5000, not 4999.
        let raw = (value / reference * 100.0 / self.step + 1e-9).floor();
        (0.0..=f64::from(u16::MAX))
            .contains(&raw)
            .then_some(raw as u32)
    }

    /// The value `raw` stands for when `reference` is 100 % (not truncated).
    pub fn from_raw(&self, raw: u32, reference: f64) -> f64 {
        f64::from(raw) * self.step / 100.0 * reference
    }
}
