//! The master's answer to a reply that needs one (`follow_up:`): `ok` and `again` frames.

use crate::codec::{self, DecodeStatus, FrameValues, Roles};
use crate::error::EncodeError;
use crate::layout::{FrameLayout, Role};

/// The master's answer to a reply (`follow_up:` of a protocol file's command): `ok` after a
/// sound reply (the drive does nothing more), `again` after a garbled one (the drive sends
/// the same reply again). Neither is answered by a new frame of its own.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct FollowUp {
    /// Sent after a sound reply.
    pub ok: FrameLayout,
    /// Sent after a garbled reply, to have it sent again.
    pub again: FrameLayout,
}

impl FollowUp {
    /// The layout for a sound (`true`) or a garbled (`false`) reply.
    pub fn layout(&self, sound: bool) -> &FrameLayout {
        if sound {
            &self.ok
        } else {
            &self.again
        }
    }

    /// Encodes the follow-up for station `address` into `out`; returns its length. A field
    /// of role `command` carries the one code its layout allows (the NAK character).
    pub fn encode(
        &self,
        sound: bool,
        address: Option<u8>,
        out: &mut [u8],
    ) -> Result<usize, EncodeError> {
        let layout = self.layout(sound);
        let mut values = FrameValues::default();
        let roles = Roles {
            address: address.map(u32::from),
            command: layout.allowed_commands().first().copied(),
            ..Roles::default()
        };
        values.fill(layout, &roles);
        codec::encode(layout, &values, out)
    }

    /// Whether `bytes` begin with this follow-up: `true` for the acknowledgement, `false`
    /// for the request to send again, with the station it names and its length.
    pub fn recognise(&self, bytes: &[u8]) -> Option<(bool, Option<u8>, usize)> {
        [true, false].into_iter().find_map(|sound| {
            let layout = self.layout(sound);
            match crate::plan::decode(layout, bytes) {
                Ok(DecodeStatus::Complete { values, len }) => Some((
                    sound,
                    values
                        .get(layout, Role::Address)
                        .and_then(|a| u8::try_from(a).ok()),
                    len,
                )),
                _ => None,
            }
        })
    }
}
