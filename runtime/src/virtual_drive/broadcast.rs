//! Broadcasts on the virtual drive: carried out when the drive's rule lists the command
//! and the drive is among the stations addressed, answered only by the station the rule
//! names.

use super::outcome::Outcome;
use super::VirtualDrive;
use crate::broadcast::{self as broadcasts, Broadcast};
use crate::layout::Role;
use crate::protocol::{DecodedRequest, Protocol};

impl VirtualDrive {
    /// A broadcast: carried out when the drive's rule lists the command and the drive is
    /// among the stations addressed, answered (with the drive's own number) only when the
    /// rule names this drive to answer.
    pub(super) fn answer_broadcast(
        &mut self,
        protocol: &Protocol,
        request: &DecodedRequest<'_>,
        broadcast: Broadcast,
    ) -> Outcome {
        let Some(rule) = &protocol.broadcast else {
            return Outcome::Silent("the drive takes no broadcasts over this protocol");
        };
        if !request.command.kind.is_write() || !rule.commands.contains(&request.command.code) {
            return Outcome::Silent("a command the drive does not carry out when broadcast");
        }
        let radix = request
            .command
            .request
            .field(Role::Address)
            .map_or(10, broadcasts::field_radix);
        if !broadcasts::addresses(&broadcast, self.address, radix) {
            return Outcome::Silent("a broadcast to other stations");
        }
        let own = DecodedRequest {
            address: Some(self.address),
            broadcast: None,
            ..*request
        };
        let outcome = self.answer(protocol, &own);
        let answers =
            rule.responder(&broadcast, protocol.address_range.0, radix) == Some(self.address);
        match outcome {
            Outcome::Reply(_) if answers => outcome,
            _ => Outcome::Silent("a broadcast another station answers, or none"),
        }
    }
}
