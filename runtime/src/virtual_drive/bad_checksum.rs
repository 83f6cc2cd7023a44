//! A request whose checksum does not match: read as the frame it would be with the right
//! checksum, so that the drive's refusal (the manual's sum-check error, where the behaviour
//! model gives one) names the sender's station, and a frame for another station, or a
//! broadcast, stays unanswered, as any other request for them does. Which layout the frame
//! has is found as for a sound frame: the layout whose checksum, put right, makes a whole
//! frame (a read and a write of the same family fail at different places; the one failing
//! only at its checksum is the frame sent).

use super::outcome::{Outcome, Refusal};
use super::VirtualDrive;
use crate::codec::DecodeStatus;
use crate::error::DecodeError;
use crate::layout::{Encoding, Format, FrameLayout, Part};
use crate::protocol::{DecodedRequest, Found, Protocol};

/// What the bytes at the start of the input are, read with their checksum put right.
pub(super) enum Repaired<'p> {
    /// A whole request whose only fault is its checksum (boxed: a decoded request is
    /// large, and the other variants carry nothing).
    Frame(Box<DecodedRequest<'p>>),
    /// The start of such a request: more bytes may complete it.
    Incomplete,
    /// No request of the protocol, whatever its checksum.
    No,
}

/// Reads `bytes` as a request of `protocol` whose checksum does not match: the first
/// command layout whose checksum fails is given the checksum it should have, and the
/// bytes so mended are decoded as any request. `exact`: the frame must take all of
/// `bytes` (a whole frame handed over, not a stream).
pub(super) fn repaired<'p>(protocol: &'p Protocol, bytes: &[u8], exact: bool) -> Repaired<'p> {
    let mut incomplete = false;
    for layout in protocol.commands.iter().map(|c| &c.request) {
        let Err(DecodeError::ChecksumMismatch {
            part,
            offset,
            computed,
            ..
        }) = crate::plan::decode(layout, bytes)
        else {
            continue;
        };
        let Some(mended) = mend(layout, bytes, &part, offset, computed) else {
            continue;
        };
        match protocol.decode_request(&mended) {
            Ok(Found::Frame { frame, .. }) if !exact || frame.len == bytes.len() => {
                return Repaired::Frame(Box::new(frame))
            }
            Ok(Found::Incomplete) if !exact => incomplete = true,
            _ => {}
        }
    }
    if incomplete {
        Repaired::Incomplete
    } else {
        Repaired::No
    }
}

/// `bytes` with the checksum `part` of `layout` (its value at `offset`) set to `value`;
/// `None` where its format cannot be written back here (a frame of hex pairs, whose
/// offsets count decoded bytes).
fn mend(
    layout: &FrameLayout,
    bytes: &[u8],
    part: &str,
    offset: usize,
    value: u32,
) -> Option<Vec<u8>> {
    if layout.encoding != Encoding::Binary {
        return None;
    }
    let format = layout.parts.iter().find_map(|p| match p {
        Part::Checksum(spec) if spec.name == part => Some(spec.format),
        _ => None,
    })?;
    let written: Vec<u8> = match format {
        // Two digits, as the decoder reads a hex checksum.
        Format::Hex => format!("{:02X}", value & 0xFF).into_bytes(),
        Format::U8 => vec![value as u8],
        Format::U16Be => (value as u16).to_be_bytes().to_vec(),
        Format::U16Le => (value as u16).to_le_bytes().to_vec(),
        Format::U32Be => value.to_be_bytes().to_vec(),
        Format::U32Le => value.to_le_bytes().to_vec(),
        _ => return None,
    };
    let mut mended = bytes.to_vec();
    mended
        .get_mut(offset..offset + written.len())?
        .copy_from_slice(&written);
    // Only the checksum was wrong: the mended bytes must now pass this layout.
    match crate::plan::decode(layout, &mended) {
        Ok(DecodeStatus::Complete { .. } | DecodeStatus::Incomplete) => Some(mended),
        Err(_) => None,
    }
}

impl VirtualDrive {
    /// Answers a request whose checksum does not match (`request`: read with its checksum
    /// put right): the refusal for a bad checksum, naming this station, when the request is
    /// for it; silence for another station's request or a broadcast, which no station
    /// answers.
    pub(super) fn answer_bad_checksum(
        &self,
        protocol: &Protocol,
        request: &DecodedRequest<'_>,
    ) -> Outcome {
        if self.starting_up() {
            return Outcome::Silent("starting up after power-on");
        }
        if request.broadcast.is_some() {
            return Outcome::Silent("a broadcast with a bad checksum");
        }
        if request.address.is_some_and(|a| a != self.address) {
            return Outcome::Silent("another station's request");
        }
        self.refuse(protocol, Some(request), Refusal::BadChecksum)
    }
}
