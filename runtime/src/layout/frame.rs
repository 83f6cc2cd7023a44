//! A [`FrameLayout`]: the ordered parts of one frame, and questions about them.

use super::bits::BitsSpec;
use super::borrowed::{List, Text};
use super::field::FieldSpec;
use super::format::Encoding;
use super::part::Part;
use super::plan::FramePlan;
use super::role::Role;

/// One frame layout, for example "ASCII read request" or "binary error reply".
///
/// Two layouts are equal when their name, parts and encoding are: the plan is derived
/// from them.
#[derive(Debug, Clone)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct FrameLayout {
    /// Name used in error messages, e.g. `read_request`.
    pub name: Text,
    /// The parts in wire order.
    pub parts: List<Part>,
    /// How the frame's bytes go on the wire.
    pub encoding: Encoding,
    /// The layout's [`FramePlan`] (its fast encoder and decoder), computed from the parts
    /// by [`FramePlan::of`] (generated layouts hold it as const data; see
    /// [`FrameLayout::planned`]); `None`: the interpreter handles every frame. A plan must
    /// be the one computed from these parts: after changing the parts, call
    /// [`FrameLayout::planned`] again.
    #[cfg_attr(feature = "serde", serde(skip))]
    pub plan: Option<FramePlan>,
}

impl PartialEq for FrameLayout {
    fn eq(&self, other: &FrameLayout) -> bool {
        self.name == other.name && self.parts == other.parts && self.encoding == other.encoding
    }
}

impl FrameLayout {
    /// The literal bytes sent as they are around a [`Encoding::HexPairs`] frame: the first
    /// part's and the last part's, when they are required literals.
    pub fn verbatim_ends(&self) -> (&[u8], &[u8]) {
        fn literal(part: Option<&Part>) -> &[u8] {
            match part {
                Some(Part::Literal {
                    bytes,
                    optional: false,
                    ..
                }) => bytes,
                _ => &[],
            }
        }
        let head = literal(self.parts.first());
        let tail = if self.parts.len() > 1 {
            literal(self.parts.last())
        } else {
            &[]
        };
        (head, tail)
    }

    /// Where `len` bytes that begin at byte `start` of the frame's bytes lie on the wire:
    /// the same place, or for [`Encoding::HexPairs`] the hex digits that carry them.
    pub fn wire_span(&self, start: usize, len: usize) -> (usize, usize) {
        match self.encoding {
            Encoding::Binary => (start, len),
            Encoding::HexPairs => {
                let head = self.verbatim_ends().0.len();
                (head + 2 * start.saturating_sub(head), 2 * len)
            }
        }
    }

    /// Index of the first field with this role (plain fields only; see [`Self::locate`]).
    pub fn index_of(&self, role: Role) -> Option<usize> {
        self.parts
            .iter()
            .position(|part| matches!(part, Part::Field(field) if field.role == role))
    }

    /// Where the value with this role lives: a field, or bits of a word.
    pub fn locate(&self, role: Role) -> Option<(usize, Option<&BitsSpec>)> {
        self.parts
            .iter()
            .enumerate()
            .find_map(|(index, part)| match part {
                Part::Field(field) if field.role == role => Some((index, None)),
                Part::Word(word) => word
                    .fields
                    .iter()
                    .find(|bits| bits.role == role)
                    .map(|bits| (index, Some(bits))),
                _ => None,
            })
    }

    /// Whether the layout carries a value with this role.
    pub fn has(&self, role: Role) -> bool {
        self.locate(role).is_some()
    }

    /// Whether the layout's register value (a field, or bits of a word) allows any number
    /// that fits it (no `allowed` list), or the layout has none.
    pub fn register_takes_any(&self) -> bool {
        match self.locate(Role::Register) {
            Some((_, Some(bits))) => bits.allowed.is_empty(),
            Some((index, None)) => match &self.parts[index] {
                Part::Field(field) => field.allowed.is_empty(),
                _ => true,
            },
            None => true,
        }
    }

    /// Whether the layout's register value (a field, or bits of a word) can carry the wire
    /// number `wire`: it fits the field's format and width (or the bits' width), and the
    /// field allows it. A layout without a register value carries none.
    pub fn carries_register(&self, wire: u16) -> bool {
        let wire = u32::from(wire);
        match self.locate(Role::Register) {
            Some((_, Some(bits))) => {
                wire <= bits.mask() >> bits.lsb
                    && (bits.allowed.is_empty() || bits.allowed.contains(&wire))
            }
            Some((index, None)) => match &self.parts[index] {
                Part::Field(field) => {
                    wire <= field.format.max_value(field.width)
                        && (field.allowed.is_empty() || field.allowed.contains(&wire))
                }
                _ => false,
            },
            None => false,
        }
    }

    /// The codes the layout's command field (or command bits of a word) allows; empty when
    /// it allows any or has none.
    pub fn allowed_commands(&self) -> &[u32] {
        for part in self.parts.iter() {
            match part {
                Part::Field(field) if field.role == Role::Command => return &field.allowed,
                Part::Word(word) => {
                    if let Some(bits) = word.fields.iter().find(|b| b.role == Role::Command) {
                        return &bits.allowed;
                    }
                }
                _ => {}
            }
        }
        &[]
    }

    /// The field with this role.
    pub fn field(&self, role: Role) -> Option<&FieldSpec> {
        self.parts.iter().find_map(|part| match part {
            Part::Field(field) if field.role == role => Some(field),
            _ => None,
        })
    }

    /// The first byte sequence of the layout when it is a required literal (the start character).
    pub fn start_bytes(&self) -> Option<&[u8]> {
        match self.parts.first() {
            Some(Part::Literal {
                bytes,
                optional: false,
                ..
            }) => Some(bytes),
            _ => None,
        }
    }
}
