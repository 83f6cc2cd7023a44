//! Register numbers on the wire: a register's own numbers ([`WireNumber`]), pages and
//! address maps.

use super::command::CommandSpec;
use super::Protocol;
use crate::layout::List;

/// A register's own numbers on the wire in one protocol, for reading and for writing.
#[derive(Debug, Clone, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct WireNumber {
    /// The register's number in the drive description.
    pub register: u16,
    /// Its number in read requests; `None`: it cannot be read over this protocol.
    pub read: Option<u16>,
    /// Its number in write requests; `None`: it cannot be written over this protocol.
    pub write: Option<u16>,
    /// When several registers share its write number (the DV1's parameter clears 1102h-1106h
    /// are all Eaton HFC), the data values that pick this one; empty otherwise.
    #[cfg_attr(feature = "serde", serde(skip_serializing_if = "<[u32]>::is_empty"))]
    pub data: List<u32>,
}
impl Protocol {
    /// The number `command` carries on the wire for register `number`: the register's own
    /// number in this protocol ([`Protocol::wire_numbers`]) for the command's direction,
    /// else the command's address map.
    /// A paged register ([`Protocol::paging`]) carries its offset in its page through the
    /// address map: the frame is right only once its page is selected.
    pub fn to_wire(&self, command: &CommandSpec, number: u16) -> Option<u16> {
        match self.wire_numbers.iter().find(|w| w.register == number) {
            Some(own) if command.kind.is_write() => own.write,
            Some(own) => own.read,
            None => command
                .address_map
                .to_wire(self.page_of(number).map_or(number, |(_, offset)| offset)),
        }
    }

    /// The page and offset of register `number` on this protocol, if it is paged (a
    /// register with its own wire numbers never is).
    pub fn page_of(&self, number: u16) -> Option<(u16, u16)> {
        let paging = self.paging.as_ref()?;
        if self.wire_numbers.iter().any(|w| w.register == number) {
            return None;
        }
        paging.locate(number)
    }

    /// The register a number on the wire stands for in a request of `command` carrying
    /// `data`: the register whose own number it is for that direction (of several sharing
    /// a write number, the one whose values include the data), else the command's address
    /// map undone.
    pub fn from_wire(&self, command: &CommandSpec, wire: u16, data: Option<u32>) -> Option<u16> {
        let mut own = self.wire_numbers.iter().filter(|w| {
            if command.kind.is_write() {
                w.write == Some(wire)
            } else {
                w.read == Some(wire)
            }
        });
        let first = own.next();
        let picked = data.and_then(|data| {
            first
                .into_iter()
                .chain(own)
                .find(|w| w.data.contains(&data))
        });
        match picked.or(first) {
            Some(own) => Some(own.register),
            // On a protocol with pages, any other number is an offset in a page (or the
            // page register): the frame alone does not say which register it is.
            None if self.paging.is_some() => None,
            // A register with numbers of its own here (or none at all: `{}`, a register
            // known by another protocol's numbers) is not reached by its plain number.
            None => command
                .address_map
                .from_wire(wire)
                .filter(|number| !self.wire_numbers.iter().any(|w| w.register == *number)),
        }
    }
}
