//! Mode-dependent reference scaling: a raw reference word is a percentage of full scale,
//! and a selector register chooses the span that percentage applies to (FC drives:
//! 4000h = 100 %, parameter 300 chooses between "of 303" and "of 303 - 302").

/// One end of a span: a number, or the value of another register (by id).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum SpanEnd {
    /// A constant.
    Number(f64),
    /// The engineering value of a register, by id.
    Register(&'static str),
}

/// The span used when the selector register holds `selector`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ScalingMode {
    /// Selector value.
    pub selector: u32,
    /// Low end of the span.
    pub low: SpanEnd,
    /// High end of the span.
    pub high: SpanEnd,
    /// The manual's wording of the rule.
    pub description: &'static str,
}

/// A drive's reference scaling.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ReferenceScaling {
    /// Raw value meaning 100 %.
    pub full_scale_raw: u32,
    /// Ids of the registers the scaling applies to.
    pub applies_to: &'static [&'static str],
    /// Id of the register choosing the mode.
    pub selector: &'static str,
    /// The modes.
    pub modes: &'static [ScalingMode],
}

impl ReferenceScaling {
    /// The percentage a raw reference word stands for.
    pub fn percent(&self, raw: u16) -> f64 {
        f64::from(raw) * 100.0 / f64::from(self.full_scale_raw)
    }

    /// The raw word for a percentage, if it fits 16 bits.
    pub fn raw(&self, percent: f64) -> Option<u16> {
        let raw = (percent * f64::from(self.full_scale_raw) / 100.0).round();
        (percent.is_finite() && (0.0..=f64::from(u16::MAX)).contains(&raw)).then_some(raw as u16)
    }

    /// The engineering value a raw reference stands for: percent x (high - low) of the
    /// mode the selector chooses. `value_of` gives register values by id (the selector's
    /// included); `None` when the selector's mode or a needed value is unknown.
    pub fn value(&self, raw: u16, value_of: impl Fn(&str) -> Option<f64>) -> Option<f64> {
        let selector = value_of(self.selector)?;
        let mode = self
            .modes
            .iter()
            .find(|m| f64::from(m.selector) == selector)?;
        let end = |end: SpanEnd| match end {
            SpanEnd::Number(value) => Some(value),
            SpanEnd::Register(id) => value_of(id),
        };
        Some(self.percent(raw) / 100.0 * (end(mode.high)? - end(mode.low)?))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    static SCALING: ReferenceScaling = ReferenceScaling {
        full_scale_raw: 0x4000,
        applies_to: &["reference"],
        selector: "range",
        modes: &[
            ScalingMode {
                selector: 1,
                low: SpanEnd::Number(0.0),
                high: SpanEnd::Register("max"),
                description: "",
            },
            ScalingMode {
                selector: 0,
                low: SpanEnd::Register("min"),
                high: SpanEnd::Register("max"),
                description: "",
            },
        ],
    };

    #[test]
    fn half_scale_is_half_of_the_span_the_selector_chooses() {
        let values = |range: f64| {
            move |id: &str| match id {
                "range" => Some(range),
                "max" => Some(50.0),
                "min" => Some(10.0),
                _ => None,
            }
        };
        assert_eq!(SCALING.percent(0x2000), 50.0);
        assert_eq!(SCALING.value(0x2000, values(1.0)), Some(25.0));
        assert_eq!(SCALING.value(0x2000, values(0.0)), Some(20.0));
        assert_eq!(SCALING.value(0x2000, values(7.0)), None);
        assert_eq!(SCALING.raw(30.0), Some(0x1333));
    }
}
