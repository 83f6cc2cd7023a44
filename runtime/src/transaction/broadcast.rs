//! Broadcast writes: one frame to every station (or a group), where the drive's description
//! allows it. Whether a station answers depends on the installation (a VF-AS1 network
//! answers only if it has the station the rule names), so the caller states it.

use super::{Answer, Master, TransactionError, TransactionErrorKind};
use crate::broadcast::{self as broadcasts, Broadcast, BroadcastAnswer};
use crate::error::EncodeError;
use crate::layout::Role;
use crate::register::{Persistable, RegisterValue, Request, Writable};
use crate::transport::Transport;
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

impl<T: Transport, D: 'static> Master<T, D> {
    /// Broadcasts `request` (a write) to the stations `to` addresses. With
    /// [`BroadcastReply::From`], waits for that station's reply as for any request and
    /// returns what it says; with [`BroadcastReply::None`], returns `Ok(None)` after the
    /// request's wire time and the frame gap, so that the next frame cannot run into it.
    ///
    /// Refused before anything is sent (an [`EncodeError::NoBroadcast`]): a request that
    /// reads, a protocol the drive takes no broadcasts over, a command its rule does not
    /// list, a group the station field cannot carry, a request that needs a step first
    /// (array index, RAM/EEPROM selection), a reply from a station the broadcast does not
    /// address, and any reply where the description says none comes (Modbus).
    ///
    /// Where the description says a station may answer but the caller says none does, a
    /// reply may still come: the next exchange waits out the reply window first and drops
    /// it, so that it is not taken for the next reply.
    pub fn broadcast(
        &mut self,
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
        let len = protocol
            .encode_broadcast(request, &to, &mut self.request)
            .map_err(|error| {
                TransactionError::new(Some(request), TransactionErrorKind::Encode(error))
            })?;
        if protocol
            .pre_steps
            .iter()
            .any(|step| super::step_request(step, request).is_some())
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
        let radix = protocol
            .command_for_request(request)
            .ok()
            .and_then(|command| command.request.field(Role::Address))
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
                let own = self.address;
                self.address = Some(station);
                self.broadcast_to = Some(to);
                let outcome = self.exchange_once(request, false);
                self.broadcast_to = None;
                self.address = own;
                outcome.map(Some)
            }
            BroadcastReply::None => {
                self.keep_frame_gap();
                let io =
                    |error| TransactionError::new(Some(request), TransactionErrorKind::Io(error));
                self.discard_stale_input().map_err(io)?;
                self.transport.send(&self.request[..len]).map_err(io)?;
                // The frame is on the line once its bytes have gone out; the next one
                // follows after the gap.
                std::thread::sleep(self.settings.wire_time(len) + self.frame_gap());
                let now = Instant::now();
                self.last_activity = Some(now);
                if rule.answered_by != BroadcastAnswer::None {
                    // A station may answer although the caller says none exists: the next
                    // exchange drops what comes within the reply window.
                    self.late_reply_until = Some(now + self.reply_timeout(len));
                }
                Ok(None)
            }
        }
    }

    /// Broadcasts a RAM write of `value` to register `R` (see [`Master::broadcast`]).
    /// Returns the value the answering station reports written, if one answers and its
    /// reply carries one.
    pub fn broadcast_write_ram<R: Writable<Drive = D>>(
        &mut self,
        value: R::Value,
        to: Broadcast,
        reply: BroadcastReply,
    ) -> Result<Option<R::Value>, TransactionError> {
        let answer = self.broadcast(&Request::write_ram::<R>(value)?, to, reply)?;
        Ok(answer
            .and_then(|answer| answer.data)
            .map(|data| R::Value::from_raw(data, R::INFO))
            .transpose()?)
    }

    /// Broadcasts a persistent (RAM and EEPROM) write of `value` to register `R` (see
    /// [`Master::broadcast`]); EEPROM wears out on every drive addressed.
    pub fn broadcast_write_persistent<R: Persistable<Drive = D>>(
        &mut self,
        value: R::Value,
        to: Broadcast,
        reply: BroadcastReply,
    ) -> Result<Option<R::Value>, TransactionError> {
        let answer = self.broadcast(&Request::write_persistent::<R>(value)?, to, reply)?;
        Ok(answer
            .and_then(|answer| answer.data)
            .map(|data| R::Value::from_raw(data, R::INFO))
            .transpose()?)
    }
}
