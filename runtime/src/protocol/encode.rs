//! Encoding requests and broadcasts: the values a request's frame carries, checked against
//! the protocol.

use super::command::CommandSpec;
use super::frame_checks::is_optional;
use super::Protocol;
use crate::broadcast::{self as broadcasts, Broadcast};
use crate::codec::{self, FrameValues, Roles};
use crate::error::EncodeError;
use crate::kinds::CommandKind;
use crate::layout::{FrameLayout, Role};
use crate::register::Request;

/// Room for the probe frame [`Protocol::default_address`] encodes.
const MAX_FRAME_PROBE: usize = 256;
impl Protocol {
    /// Builds the request's frame values: its layout and the values to encode, with the
    /// protocol's default optional parts included. Callers may adjust presentation (digits,
    /// optional parts) before calling [`codec::encode`].
    pub fn request_values(
        &self,
        request: &Request,
        address: Option<u8>,
    ) -> Result<(&FrameLayout, FrameValues), EncodeError> {
        let command = self.command_for_request(request)?;
        self.request_values_for(command, request, address)
    }

    /// Like [`Protocol::request_values`] with the command chosen by the caller (for
    /// example the one a captured frame used).
    pub fn request_values_for<'c>(
        &self,
        command: &'c CommandSpec,
        request: &Request,
        address: Option<u8>,
    ) -> Result<(&'c FrameLayout, FrameValues), EncodeError> {
        let layout = &command.request;
        let roles = self.request_roles(command, request, address)?;
        let mut values = FrameValues {
            data_size: request.data_type.size(),
            ..FrameValues::default()
        };
        for name in self.default_optional_parts.iter() {
            values.include(layout, &[name]);
        }
        values.fill(layout, &roles);
        Ok((layout, values))
    }

    /// The values of every role a request of `command` carries, once the request is
    /// checked against the protocol (register, station); what
    /// [`Protocol::request_values_for`] fills the frame values with.
    #[inline]
    fn request_roles(
        &self,
        command: &CommandSpec,
        request: &Request,
        address: Option<u8>,
    ) -> Result<Roles, EncodeError> {
        let layout = &command.request;
        let wire = if request.wire_register {
            Some(request.register)
        } else {
            self.to_wire(command, request.register)
        };
        let own = self
            .wire_numbers
            .iter()
            .any(|w| w.register == request.register);
        let wire = wire.ok_or_else(|| match own {
            // The drive file gives the register its own numbers here, but none for this
            // direction (a Modbus-only monitor over the Eaton protocol).
            true if !request.wire_register => EncodeError::NotInProtocol {
                protocol: self.id.clone(),
                register: request.register,
                writing: command.kind.is_write(),
            },
            _ => EncodeError::RegisterOutOfRange {
                protocol: self.id.clone(),
                register: request.register,
            },
        })?;
        if !request.wire_register && !command.serves_register(request.register) {
            return Err(EncodeError::RegisterNotServed {
                protocol: self.id.clone(),
                code: command.code,
                register: request.register,
            });
        }
        let [first, second] = request.process.unwrap_or(self.default_process);
        let roles = Roles {
            address: address.map(u32::from),
            command: Some(
                request
                    .command
                    .filter(|code| command.answers_to(*code))
                    .unwrap_or(command.code),
            ),
            register: Some(u32::from(wire)),
            index: Some(u32::from(request.index.unwrap_or(0))),
            data: Some(request.data),
            error_code: None,
            process_1: Some(u32::from(first)),
            process_2: Some(u32::from(second)),
            decimals: None,
        };
        if let Some(address) = address {
            let (min, max) = self.address_range;
            if address < min || address > max {
                return Err(EncodeError::AddressOutOfRange {
                    protocol: self.id.clone(),
                    address,
                    min,
                    max,
                });
            }
        } else if layout
            .locate(Role::Address)
            .is_some_and(|(index, _)| !is_optional(&layout.parts[index]))
        {
            return Err(EncodeError::AddressRequired {
                protocol: self.id.clone(),
            });
        }
        Ok(roles)
    }

    /// The station a tool addresses by default: none where the protocol's frames may leave
    /// the station out, else its lowest station (at least 1, as a drive answers out of the
    /// box). Found by encoding a probe read without a station.
    pub fn default_address(&self) -> Option<u8> {
        let mut frame = [0u8; MAX_FRAME_PROBE];
        let needs_one = (1..=16).any(|register| {
            let probe = Request::raw(CommandKind::Read, register, 0);
            matches!(
                self.encode_request(&probe, None, &mut frame),
                Err(EncodeError::AddressRequired { .. })
            )
        });
        needs_one.then_some(self.address_range.0.max(1))
    }

    /// Encodes `request` for the station `address` (or for whichever drive listens, when
    /// `None` and the protocol lets the address out) into `out`; returns the frame length.
    pub fn encode_request(
        &self,
        request: &Request,
        address: Option<u8>,
        out: &mut [u8],
    ) -> Result<usize, EncodeError> {
        let command = self.command_for_request(request)?;
        self.encode_request_for(command, request, address, out)
    }

    /// Like [`Protocol::encode_request`] with the command already chosen (by
    /// [`Protocol::command_for_request`]), so that a request is looked up once.
    pub fn encode_request_for(
        &self,
        command: &CommandSpec,
        request: &Request,
        address: Option<u8>,
        out: &mut [u8],
    ) -> Result<usize, EncodeError> {
        if let Some(plan) = &command.request.plan {
            let roles = self.request_roles(command, request, address)?;
            let size = request.data_type.size();
            let optional = &self.default_optional_parts;
            if let Some(len) = plan.encode(&command.request, &roles, size, optional, out) {
                crate::tally::encoding();
                return Ok(len);
            }
        }
        let (layout, values) = self.request_values_for(command, request, address)?;
        codec::encode(layout, &values, out)
    }

    /// Encodes `request` as a broadcast to the stations `to` addresses. Refused before
    /// anything is built: a protocol the drive takes no broadcasts over, a command the
    /// drive's rule does not list, any request that reads (only writes may be broadcast),
    /// and a group the station field cannot carry.
    pub fn encode_broadcast(
        &self,
        request: &Request,
        to: &Broadcast,
        out: &mut [u8],
    ) -> Result<usize, EncodeError> {
        let (layout, values) = self.broadcast_values(request, to)?;
        codec::encode(layout, &values, out)
    }

    /// The frame values of `request` broadcast to `to` (see [`Protocol::encode_broadcast`]).
    pub fn broadcast_values(
        &self,
        request: &Request,
        to: &Broadcast,
    ) -> Result<(&FrameLayout, FrameValues), EncodeError> {
        let command = self.command_for_request(request)?;
        self.broadcast_values_for(command, request, to)
    }

    /// Like [`Protocol::broadcast_values`] with the command already chosen (by
    /// [`Protocol::command_for_request`]).
    pub fn broadcast_values_for<'c>(
        &self,
        command: &'c CommandSpec,
        request: &Request,
        to: &Broadcast,
    ) -> Result<(&'c FrameLayout, FrameValues), EncodeError> {
        let refuse = |reason: &'static str| EncodeError::NoBroadcast {
            protocol: self.id.clone(),
            kind: request.kind,
            reason,
        };
        if !request.kind.is_write() {
            return Err(refuse(
                "only writes may be broadcast: no station could answer a read for all of them",
            ));
        }
        let rule = self
            .broadcast
            .as_ref()
            .ok_or_else(|| refuse("the drive takes no broadcasts over this protocol"))?;
        if !rule.commands.contains(&command.code) {
            return Err(refuse(
                "the drive does not carry out this command when broadcast",
            ));
        }
        let layout = &command.request;
        let field = layout
            .field(Role::Address)
            .filter(|field| broadcasts::field_carries(field, to))
            .ok_or_else(|| refuse("the station field has no encoding for these stations"))?;
        let value = broadcasts::field_value(field, to);
        let placeholder = self.address_range.0;
        let (layout, mut values) = self.request_values_for(command, request, Some(placeholder))?;
        values.set(layout, Role::Address, value);
        Ok((layout, values))
    }

    /// Which station answers a broadcast to `to` by the drive's rule (`None`: none does, or
    /// the drive takes no broadcasts over this protocol).
    pub fn broadcast_responder(&self, request: &Request, to: &Broadcast) -> Option<u8> {
        let rule = self.broadcast.as_ref()?;
        let command = self.command_for_request(request).ok()?;
        let field = command.request.field(Role::Address)?;
        rule.responder(to, self.address_range.0, broadcasts::field_radix(field))
    }
}
