//! Searching received bytes for the reply to one request ([`Search`],
//! [`Protocol::search_reply`]).

use super::command::CommandSpec;
use super::decoded::Reply;
use super::expectation::{Difference, Expectation};
use super::frame_checks::{furthest, no_open_station};
use super::Protocol;
use crate::codec::Progress;
use crate::error::DecodeError;
use crate::layout::Role;

/// What [`Protocol::search_reply`] made of the bytes received so far.
#[derive(Debug, Clone, PartialEq)]
pub struct Search<'p> {
    /// The reply that answers the request, and the number of bytes before it.
    pub found: Option<(Reply<'p>, usize)>,
    /// More bytes could still bring a reply. With `found`: a frame that would answer the
    /// request starts inside the one found, and bytes follow the found one (a reply is
    /// followed by silence, so it may have been a false start).
    pub waiting: bool,
    /// The first whole frame that answers something else, and how it differs.
    pub foreign: Option<Difference>,
    /// The first whole frame whose checksum does not match its bytes.
    pub corrupt: Option<DecodeError>,
    /// The error of the attempt that got furthest, when no frame was found.
    pub last_error: Option<DecodeError>,
}

/// What the bytes at one offset may be.
enum Candidate<'p> {
    /// A whole frame that answers the request.
    Fits(Reply<'p>),
    /// The start of a frame that may still answer it.
    Waiting,
    /// A whole frame that answers something else.
    Foreign(Difference),
    /// Not a frame of the protocol.
    Invalid(DecodeError),
}

impl Protocol {
    /// Looks for the reply to a request of `command` in `bytes`, whatever comes before it:
    /// every offset where a frame may start (where the protocol's start sequence is, or
    /// every byte when it has none) is tried with the command's reply layout and the
    /// error-reply layout, and frames that do not meet `expectation` are passed over. Of
    /// frames that overlap, the one starting last wins: bytes that follow a frame and hold
    /// another one beginning inside it mean the first was a false start that a weak
    /// checksum let through. See [`Search`] for what is reported when nothing fits.
    pub fn search_reply<'p>(
        &'p self,
        command: &'p CommandSpec,
        expectation: &Expectation,
        bytes: &[u8],
    ) -> Search<'p> {
        let mut search = Search {
            found: None,
            waiting: false,
            foreign: None,
            corrupt: None,
            last_error: None,
        };
        for offset in 0..bytes.len() {
            if self.reply_may_start(&bytes[offset..]) == Some(false) {
                continue;
            }
            if let Some((frame, at)) = &search.found {
                if offset >= at + frame.len() {
                    break;
                }
            }
            match self.candidate_at(command, expectation, &bytes[offset..]) {
                Candidate::Fits(reply) => {
                    search.found = Some((reply, offset));
                    search.waiting = false;
                }
                Candidate::Waiting => search.waiting = true,
                Candidate::Foreign(difference) => {
                    search.foreign = search.foreign.or(Some(difference));
                }
                Candidate::Invalid(error) => {
                    if search.corrupt.is_none()
                        && error.kind() == crate::error::DecodeErrorKind::ChecksumMismatch
                    {
                        search.corrupt = Some(error.clone());
                    }
                    search.last_error = Some(furthest(search.last_error.take(), error));
                }
            }
        }
        if let Some((frame, at)) = &search.found {
            // Nothing follows the frame: it is the reply, whatever may start inside it.
            if at + frame.len() == bytes.len() {
                search.waiting = false;
            }
            search.last_error = None;
        }
        search
    }

    /// What the bytes starting at `bytes[0]` may be, for a request of `command`.
    fn candidate_at<'p>(
        &'p self,
        command: &'p CommandSpec,
        expectation: &Expectation,
        bytes: &[u8],
    ) -> Candidate<'p> {
        let mut waiting = false;
        let mut foreign = None;
        let mut best: Option<DecodeError> = None;
        let layouts = [
            Some((&command.reply, true)),
            self.error_reply.as_ref().map(|l| (l, false)),
        ];
        for (layout, normal) in layouts.into_iter().flatten() {
            match crate::plan::decode_prefix(layout, bytes) {
                Ok(Progress::Complete { values, len }) => {
                    let reply = if normal {
                        match self.data_reply_from(command, values, len) {
                            Ok(reply) => reply,
                            Err(error) => {
                                best = Some(furthest(best, error));
                                continue;
                            }
                        }
                    } else {
                        if let Err(error) = no_open_station(layout, &values)
                            .and_then(|()| self.station_in_range(layout, &values))
                            .and_then(|()| self.error_function_known(layout, &values))
                        {
                            best = Some(furthest(best, error));
                            continue;
                        }
                        self.error_reply_from(layout, values, len)
                    };
                    let size = expectation
                        .data_size
                        .filter(|size| normal && values.data_size != 0 && values.data_size != *size)
                        .map(|size| Difference {
                            role: Role::Data,
                            expected: u32::from(size),
                            found: u32::from(values.data_size),
                        });
                    match expectation.difference(&values.roles(layout)).or(size) {
                        None => return Candidate::Fits(reply),
                        Some(difference) => foreign = foreign.or(Some(difference)),
                    }
                }
                Ok(Progress::Incomplete { values }) => {
                    if expectation.difference(&values.roles(layout)).is_none() {
                        waiting = true;
                    }
                }
                Err(error) => best = Some(furthest(best, error)),
            }
        }
        if waiting {
            Candidate::Waiting
        } else if let Some(difference) = foreign {
            Candidate::Foreign(difference)
        } else {
            Candidate::Invalid(best.unwrap_or(DecodeError::Truncated {
                layout: self.id.clone(),
                len: bytes.len(),
            }))
        }
    }
}
