//! A protocol typed by the drive it belongs to ([`DriveProtocol`]).

use super::Protocol;
use crate::error::EncodeError;
use crate::register::DriveRequest;
use std::fmt;
use std::marker::PhantomData;

/// A protocol of drive `D` (a generated drive module's `Drive` marker): it encodes only
/// requests for that drive's registers, and a [`crate::transaction::Master`] built on it
/// sends only those. It dereferences to the untyped [`Protocol`] for everything else
/// (decoding, and tools that work with any drive).
pub struct DriveProtocol<D: 'static> {
    protocol: &'static Protocol,
    drive: PhantomData<fn() -> D>,
}

impl<D: 'static> DriveProtocol<D> {
    /// `protocol`, as drive `D` speaks it.
    pub const fn new(protocol: &'static Protocol) -> Self {
        DriveProtocol {
            protocol,
            drive: PhantomData,
        }
    }

    /// The untyped protocol.
    pub const fn protocol(&self) -> &'static Protocol {
        self.protocol
    }

    /// The same protocol in its variant `id` (see [`Protocol::variant`]); `None`: no such
    /// variant.
    pub fn variant(&self, id: &str) -> Option<DriveProtocol<D>> {
        self.protocol.variant(id).map(DriveProtocol::new)
    }

    /// Encodes a request for one of the drive's registers; see [`Protocol::encode_request`].
    pub fn encode_request(
        &self,
        request: &DriveRequest<D>,
        address: Option<u8>,
        out: &mut [u8],
    ) -> Result<usize, EncodeError> {
        self.protocol.encode_request(request, address, out)
    }
}

impl<D: 'static> std::ops::Deref for DriveProtocol<D> {
    type Target = Protocol;
    fn deref(&self) -> &Protocol {
        self.protocol
    }
}

impl<D: 'static> fmt::Debug for DriveProtocol<D> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        self.protocol.fmt(f)
    }
}
