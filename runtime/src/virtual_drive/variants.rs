//! Protocols with variants (framings a selector register chooses between): the variant a
//! drive has in force, reading the input in it or in another variant, and answering a frame
//! in another variant's form with the description's mismatch error.

use super::outcome::Outcome;
use super::VirtualDrive;
use crate::protocol::{DecodedRequest, Found, Protocol};
use std::borrow::Cow;

/// A protocol in the variant a drive has in force, and its other variants.
pub(super) struct InForce<'p> {
    /// The variant in force.
    pub(super) own: Cow<'p, Protocol>,
    /// The others.
    pub(super) others: Vec<Protocol>,
    /// The error code a frame in another variant's form gets.
    pub(super) mismatch: Option<u16>,
}

/// What the bytes at the start of the input are, read in the variant in force.
pub(super) enum Read<'a> {
    /// As the variant in force reads them (a frame, an unfinished one, or an error).
    Own(Result<Found<DecodedRequest<'a>>, crate::error::DecodeError>),
    /// A whole frame of another variant.
    Other(DecodedRequest<'a>),
    /// A frame in force that another variant's form would continue: the next byte (or
    /// the line's silence) decides.
    Wait,
}

impl VirtualDrive {
    /// The variant of `protocol` in force (the one its selector register's value at the
    /// last reset selects, else `protocol` as it is) and its other variants.
    pub(super) fn in_force<'p>(&self, protocol: &'p Protocol) -> InForce<'p> {
        let Some(variants) = &protocol.variants else {
            return InForce {
                own: Cow::Borrowed(protocol),
                others: Vec::new(),
                mismatch: None,
            };
        };
        let current = usize::from(variants.current);
        let selected = variants
            .selected_by
            .as_ref()
            .and_then(|selector| {
                self.drive
                    .register_at(crate::kinds::Space::Parameter, selector.register)
            })
            .and_then(|info| variants.selected_by_value(self.storage.in_effect(info, 0)))
            .unwrap_or(current);
        let own = match protocol.in_variant(selected) {
            Some(own) if selected != current => Cow::Owned(own),
            _ => Cow::Borrowed(protocol),
        };
        let others = (0..variants.choices.len())
            .filter(|index| *index != selected)
            .filter_map(|index| protocol.in_variant(index))
            .collect();
        InForce {
            own,
            others,
            mismatch: variants.mismatch_error,
        }
    }

    /// Answers a request that came in another variant's form than the one in force: the
    /// error reply with `code`, in the variant in force, when the request is for this
    /// station; silence otherwise, or when the description names no code.
    pub(super) fn answer_mismatch(
        &self,
        protocol: &Protocol,
        request: &DecodedRequest<'_>,
        code: Option<u16>,
    ) -> Outcome {
        if self.starting_up() {
            return Outcome::Silent("starting up after power-on");
        }
        if request.broadcast.is_some() || request.address.is_some_and(|a| a != self.address) {
            return Outcome::Silent("another station's request");
        }
        match code {
            Some(code) => self.error_reply(protocol, Some(request), code),
            None => Outcome::Silent("the frame is in another variant of the protocol"),
        }
    }
}

impl InForce<'_> {
    /// Reads the frame at the start of `input`. A frame whole in the variant in force is
    /// its frame unless another variant's frame goes on past it (then that frame is the
    /// one received), or, before the line's silence (`settled`), may still go on. A frame
    /// the variant in force cannot read, or that never completed in it by the silence, is
    /// another variant's when one reads it whole.
    pub(super) fn read<'a>(&'a self, input: &[u8], settled: bool) -> Read<'a> {
        let own = self.own.decode_request(input);
        if self.others.is_empty() {
            return Read::Own(own);
        }
        let whole_other = || {
            self.others
                .iter()
                .find_map(|other| match other.decode_request(input) {
                    Ok(Found::Frame { frame, .. }) => Some(frame),
                    _ => None,
                })
        };
        match &own {
            Ok(Found::Frame { frame, .. }) => {
                let len = frame.len;
                for other in &self.others {
                    match other.decode_request(input) {
                        Ok(Found::Frame { frame, .. }) if frame.len > len => {
                            return Read::Other(frame)
                        }
                        Ok(Found::Incomplete) if !settled => return Read::Wait,
                        _ => {}
                    }
                }
                Read::Own(own)
            }
            Ok(Found::Incomplete) if !settled => Read::Own(own),
            _ => match whole_other() {
                Some(frame) => Read::Other(frame),
                None => Read::Own(own),
            },
        }
    }
}
