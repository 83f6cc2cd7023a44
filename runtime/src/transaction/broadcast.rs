//! Broadcast writes: one frame to every station (or a group), where the drive's description
//! allows it. Whether a station answers depends on the installation (a VF-AS1 network
//! answers only if it has the station the rule names), so the caller states it.

use super::answer::Answer;
use super::error::{TransactionError, TransactionErrorKind};
use super::exchange::{Exchange, ExchangeKind};
use super::line::Line;
use super::prepare::{prepare, Station};
use super::script::step_request;
use super::session::Session;
use crate::broadcast::{self as broadcasts, Broadcast, BroadcastAnswer};
use crate::error::EncodeError;
use crate::layout::Role;
use crate::register::Request;
use std::time::Instant;

/// Whether a broadcast gets an answer on this installation: the caller knows which
/// stations exist.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BroadcastReply {
    /// No station answers: the master returns once the frame is on the line (its wire time
    /// and the frame gap).
    None,
    /// This station answers, with its own number in the reply (VF-AS1: station 00 for
    /// every station, the lowest of a group such as 09 for `*9`, where it exists).
    From(u8),
}

impl Session {
    /// Broadcasts `request` (a write) to the stations `to` addresses (see
    /// [`super::Master::broadcast`]).
    pub(crate) async fn broadcast(
        &mut self,
        line: &mut impl Line,
        request: &Request,
        to: Broadcast,
        reply: BroadcastReply,
    ) -> Result<Option<Answer>, TransactionError> {
        let protocol = self.protocol;
        let refuse = |reason: &'static str| {
            TransactionError::new(
                Some(request),
                TransactionErrorKind::Encode(EncodeError::NoBroadcast {
                    protocol: protocol.id.clone(),
                    kind: request.kind,
                    reason,
                }),
            )
        };
        // The reply, where one comes, is from the station named to answer.
        let station = Station {
            address: match reply {
                BroadcastReply::From(station) => Some(station),
                BroadcastReply::None => self.address,
            },
            ..self.station()
        };
        let exchange = Exchange::new(*request, ExchangeKind::Broadcast(to));
        let prepared = prepare(protocol, &exchange, &station).map_err(|error| {
            TransactionError::new(Some(request), TransactionErrorKind::Encode(error))
        })?;
        if protocol
            .pre_steps
            .iter()
            .any(|step| step_request(step, request).is_some())
        {
            return Err(refuse(
                "it needs a step first (index or RAM/EEPROM selection), which cannot be broadcast",
            ));
        }
        if !request.wire_register
            && request.space == crate::kinds::Space::Parameter
            && protocol.page_of(request.register).is_some()
        {
            // Which page each drive is on is not known, and a switch cannot be confirmed.
            return Err(refuse(
                "the register lies on a page, whose switch cannot be broadcast",
            ));
        }
        let rule = protocol
            .broadcast
            .as_ref()
            .ok_or_else(|| refuse("no rule"))?;
        let radix = prepared
            .command()
            .request
            .field(Role::Address)
            .map_or(10, broadcasts::field_radix);
        match reply {
            BroadcastReply::From(station) => {
                if rule.answered_by == BroadcastAnswer::None {
                    return Err(refuse(
                        "the drive never answers a broadcast over this protocol",
                    ));
                }
                if !broadcasts::addresses(&to, station, radix) {
                    return Err(refuse(
                        "the station named to answer is not among the stations addressed",
                    ));
                }
                // A broadcast may reset drives or switch their pages: which, is not known.
                self.pages.clear();
                self.exchange_once(line, &prepared, false).await.map(Some)
            }
            BroadcastReply::None => {
                let len = prepared.bytes().len();
                self.pages.clear();
                self.exchange_once(line, &prepared.unanswered(), false)
                    .await?;
                if rule.answered_by != BroadcastAnswer::None {
                    // A station may answer although the caller says none exists: the next
                    // exchange drops what comes within the reply window.
                    self.late_reply_until = Some(Instant::now() + self.reply_timeout(len));
                }
                Ok(None)
            }
        }
    }
}
