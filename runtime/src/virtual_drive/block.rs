//! Block transfers ([`CommandKind::Block`](crate::kinds::CommandKind::Block)) on the
//! virtual drive: the words of the request go to the registers the drive's block selection
//! names, the reply carries the registers it names for reading and a write-status bit per
//! word that was not written.

use super::outcome::Outcome;
use super::reply::{encode_with, mirror_optional_parts, reply_code};
use super::VirtualDrive;
use crate::codec::{FrameValues, Roles, Words};
use crate::kinds::{DataType, Space};
use crate::layout::Role;
use crate::protocol::{BlockSelection, DecodedRequest, Protocol};

impl VirtualDrive {
    /// The selection in force: the selectors' values at the last reset (they take effect
    /// after a reset) and the mode registers' values.
    pub fn block_selection(&self, protocol: &Protocol) -> Option<BlockSelection> {
        let spec = protocol.block.as_ref()?;
        Some(spec.selection(|register| {
            self.drive
                .register_at(Space::Parameter, register)
                .map(|info| self.storage.in_effect(info, 0))
        }))
    }

    /// Answers a block transfer. More words to write than the selection has is a format
    /// error (no reply); a read count above the selection's is answered with no words.
    /// The words read are taken before the request's words are written (the reply shows
    /// the values before the change). A word whose position selects nothing, or that its
    /// register refuses, is not written and sets its bit in the write status.
    pub(super) fn block(&mut self, protocol: &Protocol, request: &DecodedRequest<'_>) -> Outcome {
        let Some(selection) = self.block_selection(protocol) else {
            return Outcome::Silent("the drive has no block transfer");
        };
        let command = request.command;
        let writes = request.words.as_slice();
        if writes.len() > selection.write.len() {
            return Outcome::Silent("more words to write than the block selection has");
        }
        let asked = request
            .values
            .get(&command.request, Role::ReadCount)
            .unwrap_or(0) as usize;
        let count = if asked > selection.read.len() {
            0
        } else {
            asked
        };
        let reads: Vec<u16> = selection.read[..count]
            .iter()
            .map(|register| {
                register
                    .and_then(|register| self.drive.register_for(Space::Parameter, register, false))
                    .map_or(0, |info| self.storage.get(info, 0) as u16)
            })
            .collect();
        let mut status = 0u32;
        for (position, (word, target)) in writes.iter().zip(&selection.write).enumerate() {
            let raw = u32::from(*word);
            let info = target
                .and_then(|register| self.drive.register_for(Space::Parameter, register, true))
                .filter(|info| self.check_write(info, raw, false).is_ok());
            match info {
                Some(info) => {
                    self.storage.set(info, 0, raw, false);
                    self.value_written(info, raw);
                }
                None if position < 32 => status |= 1 << position,
                None => {}
            }
        }
        self.refresh();
        let layout = &command.reply;
        let mut values = FrameValues::default();
        mirror_optional_parts(&command.request, &request.values, layout, &mut values);
        let roles = Roles {
            address: request.address.map(u32::from),
            command: Some(self.shown(protocol, reply_code(command, DataType::Word))),
            ..Roles::default()
        };
        values.fill(layout, &roles);
        values.set(layout, Role::WriteStatus, status);
        let payload = Words::from_slice(&reads)
            .map(|words| words.payload(layout))
            .unwrap_or_default();
        encode_with(layout, &values, &payload, protocol)
    }
}
