//! Pages and follow-ups on the drive's side: the page register a protocol with pages
//! ([`crate::protocol::Paging`]) switches, the paged offsets it turns back into registers,
//! and the master's answer to a reply ([`crate::protocol::FollowUp`]): an acknowledgement
//! ends the exchange, a request to send again repeats the last reply.

use super::data_width;
use super::outcome::{Outcome, Refusal};
use super::VirtualDrive;
use crate::protocol::{DecodedRequest, Protocol};

/// What the page logic made of a request.
pub(super) enum Paged {
    /// Not a paged access: answer the request as decoded.
    Plain,
    /// A paged access to this register (on the current page): answer the request as
    /// addressing it.
    Register(u16),
    /// A read or a switch of the page register, or a refused paged access: answered.
    Done(Outcome),
}

impl VirtualDrive {
    /// The page the drive is on over `protocol` (its initial page until switched).
    pub fn page(&self, protocol: &Protocol) -> Option<u16> {
        let paging = protocol.paging.as_ref()?;
        Some(self.page.unwrap_or(paging.initial))
    }

    /// Puts the drive on `page` over `protocol`, as a master's page switch would; returns
    /// false, changing nothing, when the protocol has no such page.
    pub fn set_page(&mut self, protocol: &Protocol, page: u16) -> bool {
        let on_it = protocol.paging.as_ref().is_some_and(|p| p.has_page(page));
        if on_it {
            self.page = Some(page);
        }
        on_it
    }

    /// Resolves a request on a protocol with pages: the page register's read and write,
    /// and a paged offset (a wire number no register owns, which the decoder leaves
    /// unnamed; the command's address map undone) as the register on the current page.
    pub(super) fn unpage(&mut self, protocol: &Protocol, request: &DecodedRequest<'_>) -> Paged {
        let Some(paging) = &protocol.paging else {
            return Paged::Plain;
        };
        let command = request.command;
        if request.command.space != crate::kinds::Space::Parameter {
            return Paged::Plain;
        }
        let writing = command.kind.is_write();
        let selects = request.wire_register.is_some_and(|wire| {
            if writing {
                wire == paging.select_write
            } else {
                paging.select_read == Some(wire)
            }
        });
        if selects {
            if !writing {
                // Answered by the read that carries the page register's type (a byte
                // read's two data digits), where the request alone does not say which.
                let carrying = protocol.commands.iter().find(|c| {
                    c.kind == command.kind
                        && c.space == command.space
                        && c.carries(paging.select_data_type)
                        && c.request.parts == command.request.parts
                });
                let carried;
                let request = match carrying {
                    Some(command) => {
                        carried = DecodedRequest {
                            command,
                            ..*request
                        };
                        &carried
                    }
                    None => request,
                };
                let page = self.page.unwrap_or(paging.initial);
                return Paged::Done(self.reply(protocol, request, u32::from(page), 0));
            }
            if data_width::wrong_width(protocol, command, paging.select_data_type) {
                return Paged::Done(Outcome::Silent(data_width::MALFORMED));
            }
            let page = u16::try_from(request.data)
                .ok()
                .filter(|p| paging.has_page(*p));
            return Paged::Done(match page {
                Some(page) => {
                    self.page = Some(page);
                    self.reply(protocol, request, request.data, 0)
                }
                None => self.refuse(protocol, Some(request), Refusal::OutOfRange),
            });
        }
        if let Some(number) = request.register {
            // A register of its own wire number: not paged.
            if writing && paging.forgotten_after.contains(&number) {
                // A reset: the drive starts again on its initial page.
                self.page = None;
            }
            return Paged::Plain;
        }
        let Some(number) = request
            .wire_register
            .and_then(|wire| command.address_map.from_wire(wire))
        else {
            return Paged::Plain;
        };
        if number >= paging.page_size() {
            return Paged::Done(self.refuse(protocol, Some(request), Refusal::UnknownRegister));
        }
        let page = self.page.unwrap_or(paging.initial);
        match paging.register(page, number) {
            Some(register) => Paged::Register(register),
            None => Paged::Done(self.refuse(protocol, Some(request), Refusal::UnknownRegister)),
        }
    }

    /// Takes a follow-up at the start of `input`, when the last reply awaits one: `Some`
    /// with the bytes it used and what the drive sends (the last reply again, or nothing).
    pub(super) fn take_follow_up(
        &mut self,
        protocol: &Protocol,
        input: &[u8],
    ) -> Option<(usize, Option<Vec<u8>>)> {
        let (code, _) = self.awaiting_follow_up.as_ref()?;
        let follow_up = protocol
            .commands
            .iter()
            .find(|c| c.code == *code)
            .and_then(|c| c.follow_up.as_ref())?;
        let (sound, address, len) = follow_up.recognise(input)?;
        if address.is_some_and(|a| a != self.address) {
            return Some((len, None));
        }
        if sound {
            self.awaiting_follow_up = None;
            return Some((len, None));
        }
        let again = self
            .awaiting_follow_up
            .as_ref()
            .map(|(_, reply)| reply.clone());
        Some((len, again))
    }

    /// Notes the reply sent to a request of command `code`, so that a follow-up asking for
    /// it again can be answered; any other frame ends the wait.
    pub(super) fn note_reply(&mut self, protocol: &Protocol, code: u32, reply: Option<&[u8]>) {
        let awaits = protocol
            .commands
            .iter()
            .any(|c| c.code == code && c.follow_up.is_some());
        // An error reply gets no follow-up (the Eaton D): only a normal reply awaits one.
        let refused = |reply: &[u8]| {
            protocol.error_reply.as_ref().is_some_and(|layout| {
                matches!(
                    crate::codec::decode(layout, reply),
                    Ok(crate::codec::DecodeStatus::Complete { len, .. }) if len == reply.len()
                )
            })
        };
        self.awaiting_follow_up = match reply {
            Some(reply) if awaits && !refused(reply) => Some((code, reply.to_vec())),
            _ => None,
        };
    }
}
