//! Variants of a protocol: named alternatives for some of its literal parts (a terminator
//! that is CR in one and CR LF in the other), of which a drive register may select the one
//! in force. A variant is a whole protocol of its own once its bytes are put in the
//! layouts ([`crate::protocol::Protocol::variant`]), so frames decode exactly in each.

use crate::layout::{FrameLayout, List, Part, Text};
use std::borrow::Cow;

/// The variants of a protocol, and which of them this protocol is.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct Variants {
    /// Index in `choices` of the variant this protocol's layouts are in.
    pub current: u8,
    /// Every variant, the protocol file's order; the first is the one its layouts are
    /// written in.
    pub choices: List<Variant>,
    /// The drive register whose value selects the variant in force, where the drive
    /// description names one.
    pub selected_by: Option<VariantSelector>,
    /// The error code a drive answers a frame in another variant's form with (the DV1's
    /// H03 for a terminator other than the one set); `None`: it does not answer it.
    pub mismatch_error: Option<u16>,
}

/// One variant: the bytes its literal parts have.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct Variant {
    /// Identifier, as the protocol file writes it (`cr_lf`).
    pub id: Text,
    /// Name for people (`CR LF`).
    pub name: Text,
    /// The manual's Chinese name (empty when it gives none).
    pub name_zh: Text,
    /// Every literal part some variant varies, with its bytes in this variant (the same
    /// parts in every variant, so that any variant can be put in any other's layouts).
    pub literals: List<VariantLiteral>,
}

/// The bytes of one literal part (by name) in a variant.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct VariantLiteral {
    /// The literal part's name in the layouts (`cr`).
    pub part: Text,
    /// Its bytes in the variant.
    pub bytes: List<u8>,
}

/// The register that selects a variant, and which value selects which.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct VariantSelector {
    /// The register's number (parameter space, before any address map).
    pub register: u16,
    /// Values and the variants (indexes in [`Variants::choices`]) they select; a value
    /// not listed selects none (the protocol stays as it is).
    pub values: List<VariantValue>,
}

/// One value of a [`VariantSelector`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct VariantValue {
    /// The register's raw value.
    pub value: u32,
    /// The variant it selects (index in [`Variants::choices`]).
    pub variant: u8,
}

impl Variants {
    /// The index of the variant called `id`.
    pub fn index_of(&self, id: &str) -> Option<usize> {
        self.choices.iter().position(|choice| choice.id == id)
    }

    /// The variant this protocol is in.
    pub fn current(&self) -> Option<&Variant> {
        self.choices.get(usize::from(self.current))
    }

    /// The variant the selector register's raw value `value` selects, if any.
    pub fn selected_by_value(&self, value: u32) -> Option<usize> {
        let selector = self.selected_by.as_ref()?;
        selector
            .values
            .iter()
            .find(|v| v.value == value)
            .map(|v| usize::from(v.variant))
            .filter(|index| *index < self.choices.len())
    }

    /// The selector register's value that selects the variant at `index`, if one does.
    pub fn value_selecting(&self, index: usize) -> Option<u32> {
        let selector = self.selected_by.as_ref()?;
        selector
            .values
            .iter()
            .find(|v| usize::from(v.variant) == index)
            .map(|v| v.value)
    }
}

impl Variant {
    /// `layout` with this variant's bytes in its literal parts of the names the variant
    /// lists (required and optional literals alike); other parts are unchanged.
    pub fn apply(&self, layout: &FrameLayout) -> FrameLayout {
        let parts = layout
            .parts
            .iter()
            .map(|part| match part {
                Part::Literal {
                    name,
                    bytes,
                    optional,
                } => {
                    let bytes = self
                        .literals
                        .iter()
                        .find(|literal| literal.part == *name)
                        .map_or_else(|| bytes.clone(), |literal| literal.bytes.clone());
                    Part::Literal {
                        name: name.clone(),
                        bytes,
                        optional: *optional,
                    }
                }
                other => other.clone(),
            })
            .collect();
        let applied = FrameLayout {
            name: layout.name.clone(),
            parts: Cow::Owned(parts),
            encoding: layout.encoding,
            plan: None,
        };
        // Other literal bytes make another plan (a layout without one stays without).
        if layout.plan.is_some() {
            applied.planned()
        } else {
            applied
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::layout::{Encoding, FieldSpec, Format, Role};

    #[test]
    fn a_variant_puts_its_bytes_in_the_literals_it_names() {
        static PARTS: [Part; 3] = [
            Part::literal("start", b"\x05"),
            Part::Field(FieldSpec::new("data", Role::Data, Format::Hex, 2)),
            Part::literal("cr", b"\r"),
        ];
        let layout = FrameLayout {
            name: Cow::Borrowed("request"),
            parts: Cow::Borrowed(&PARTS),
            encoding: Encoding::Binary,
            plan: None,
        };
        let variant = Variant {
            id: Cow::Borrowed("cr_lf"),
            name: Cow::Borrowed("CR LF"),
            name_zh: Cow::Borrowed(""),
            literals: Cow::Owned(vec![VariantLiteral {
                part: Cow::Borrowed("cr"),
                bytes: Cow::Borrowed(b"\r\n"),
            }]),
        };
        let applied = variant.apply(&layout);
        assert_eq!(applied.parts[0], PARTS[0]);
        assert_eq!(applied.parts[1], PARTS[1]);
        assert_eq!(applied.parts[2], Part::literal("cr", b"\r\n"));
        assert_eq!(applied.verbatim_ends().1, b"\r\n");
    }

    #[test]
    fn values_select_variants_and_back() {
        let variants = Variants {
            current: 0,
            choices: Cow::Owned(vec![
                Variant {
                    id: Cow::Borrowed("cr"),
                    name: Cow::Borrowed("CR"),
                    name_zh: Cow::Borrowed(""),
                    literals: Cow::Borrowed(&[]),
                },
                Variant {
                    id: Cow::Borrowed("cr_lf"),
                    name: Cow::Borrowed("CR LF"),
                    name_zh: Cow::Borrowed(""),
                    literals: Cow::Borrowed(&[]),
                },
            ]),
            selected_by: Some(VariantSelector {
                register: 0x33,
                values: Cow::Borrowed(&[
                    VariantValue {
                        value: 1,
                        variant: 0,
                    },
                    VariantValue {
                        value: 2,
                        variant: 1,
                    },
                ]),
            }),
            mismatch_error: Some(3),
        };
        assert_eq!(variants.index_of("cr_lf"), Some(1));
        assert_eq!(variants.selected_by_value(2), Some(1));
        assert_eq!(variants.selected_by_value(7), None);
        assert_eq!(variants.value_selecting(0), Some(1));
        assert_eq!(variants.current().map(|v| v.id.as_ref()), Some("cr"));
    }
}
