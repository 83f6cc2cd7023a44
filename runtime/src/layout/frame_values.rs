//! Reading and writing a frame's values by role, through its layout.

use super::frame::FrameLayout;
use super::part::Part;
use super::role::Role;
use super::values::{FrameValues, Roles};

impl FrameValues {
    /// Sets the value with `role` (a field or bits of a word) and marks it present.
    /// Returns false when the layout has no such value.
    pub fn set(&mut self, layout: &FrameLayout, role: Role, value: u32) -> bool {
        match layout.locate(role) {
            Some((index, None)) => {
                self.parts[index].present = true;
                self.parts[index].value = value;
                true
            }
            Some((index, Some(bits))) => {
                let slot = &mut self.parts[index];
                slot.present = true;
                slot.value = (slot.value & !bits.mask()) | ((value << bits.lsb) & bits.mask());
                true
            }
            None => false,
        }
    }

    /// The value with `role`, when the layout has it and the frame carries it. For a
    /// bytes field this is the offset of the bytes; see [`FrameValues::bytes`].
    pub fn get(&self, layout: &FrameLayout, role: Role) -> Option<u32> {
        let (index, bits) = layout.locate(role)?;
        let slot = self.parts[index];
        if !slot.present {
            return None;
        }
        Some(match bits {
            None => slot.value,
            Some(bits) => (slot.value & bits.mask()) >> bits.lsb,
        })
    }

    /// The bytes of the bytes field with `role` in `frame` (the frame these values were
    /// decoded from), as they lie on the wire: for an [`Encoding::HexPairs`](super::Encoding::HexPairs) layout, the
    /// hex digits that carry them (two per byte; [`FrameValues::words`] and
    /// [`FrameValues::data_words`] give their values).
    pub fn bytes<'f>(&self, layout: &FrameLayout, role: Role, frame: &'f [u8]) -> Option<&'f [u8]> {
        let index = layout.index_of(role)?;
        let slot = self.parts[index];
        let (start, len) = layout.wire_span(slot.value as usize, usize::from(slot.width));
        slot.present
            .then(|| frame.get(start..start + len))
            .flatten()
    }
    /// Marks every optional part named in `names` present (e.g. `["sum", "end"]`).
    pub fn include(&mut self, layout: &FrameLayout, names: &[&str]) {
        for (index, part) in layout.parts.iter().enumerate() {
            if names.iter().any(|name| *name == part.name()) {
                self.parts[index].present = true;
            }
        }
    }
}

impl FrameValues {
    /// Every role's value in one pass (the hot path's alternative to repeated [`FrameValues::get`]).
    pub fn roles(&self, layout: &FrameLayout) -> Roles {
        let mut roles = Roles::default();
        for (index, part) in layout.parts.iter().enumerate() {
            let slot = self.parts[index];
            if !slot.present {
                continue;
            }
            match part {
                Part::Field(field) => {
                    if let Some(target) = roles.slot(field.role) {
                        *target = Some(slot.value);
                    }
                }
                Part::Word(word) => {
                    for bits in word.fields.iter() {
                        if let Some(target) = roles.slot(bits.role) {
                            *target = Some((slot.value & bits.mask()) >> bits.lsb);
                        }
                    }
                }
                _ => {}
            }
        }
        roles
    }

    /// Sets every role given in `roles` in one pass; roles the layout lacks are ignored.
    pub fn fill(&mut self, layout: &FrameLayout, roles: &Roles) {
        let mut roles = *roles;
        for (index, part) in layout.parts.iter().enumerate() {
            match part {
                Part::Field(field) => {
                    if let Some(Some(value)) = roles.slot(field.role).map(|v| *v) {
                        self.parts[index].present = true;
                        self.parts[index].value = value;
                    }
                }
                Part::Word(word) => {
                    for bits in word.fields.iter() {
                        if let Some(Some(value)) = roles.slot(bits.role).map(|v| *v) {
                            let slot = &mut self.parts[index];
                            slot.present = true;
                            slot.value =
                                (slot.value & !bits.mask()) | ((value << bits.lsb) & bits.mask());
                        }
                    }
                }
                _ => {}
            }
        }
    }
}
