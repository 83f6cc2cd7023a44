//! The kind of an exchange as a value: what one frame asks of the drive, which decides how
//! the frame is built and what answers it ([`super::prepare`] turns it into bytes).

use crate::broadcast::Broadcast;
use crate::codec::Words;
use crate::register::Request;

/// What one frame asks besides its request.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ExchangeKind {
    /// The request alone, as the protocol encodes it: a register read or write, process
    /// data, an echo, or a step another request needs first (an array index, RAM or
    /// EEPROM, a page switch).
    Single,
    /// A block read: `words` consecutive 16-bit registers from the request's register, in
    /// a request that counts them (Modbus 03's quantity). The reply must carry that many.
    BlockRead {
        /// Registers read (2 or more).
        words: u16,
    },
    /// A block write: these words to consecutive registers from the request's register, in
    /// a request whose data field a length part sizes (Modbus 10h).
    BlockWrite(Words),
    /// A block transfer ([`crate::kinds::CommandKind::Block`]): these words written to the
    /// positions the drive's selection names, and `read_count` words asked back.
    BlockTransfer {
        /// The words written, in position order.
        writes: Words,
        /// The words asked back.
        read_count: u8,
    },
    /// A broadcast of the request to the stations `to` addresses. The reply, where one
    /// comes, is from the station the exchange's station names.
    Broadcast(Broadcast),
}

/// What to send: a request and the kind of exchange it makes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Exchange {
    /// The request (register, kind, data).
    pub request: Request,
    /// What the frame asks besides.
    pub kind: ExchangeKind,
}

impl Exchange {
    /// `request` alone.
    pub fn single(request: Request) -> Exchange {
        Exchange {
            request,
            kind: ExchangeKind::Single,
        }
    }

    /// `request` with what else its frame asks.
    pub fn new(request: Request, kind: ExchangeKind) -> Exchange {
        Exchange { request, kind }
    }
}
