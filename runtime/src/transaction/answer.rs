//! What a reply answers: the [`Answer`] a sound reply gives a request (its data, the trip
//! flag, process words, where text or a block lies in the reply), or the error it amounts to.

use super::error::{ReplyField, TransactionError, TransactionErrorKind};
use crate::error::ValueError;
use crate::kinds::DataType;
use crate::layout::Role;
use crate::protocol::Reply;
use crate::register::Request;

/// What a successful exchange returned.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Answer {
    /// Data read, or the value the drive reports written; `None` when the reply carries no
    /// data (the protocol echoes nothing).
    pub data: Option<u32>,
    /// The drive said it is tripped (lower-case command letter in the reply).
    pub tripped: bool,
    /// Process words the reply carried (status word, output value).
    pub process: Option<[u16; 2]>,
    /// Offset and length of text in the reply, for text reads.
    pub text: Option<(usize, usize)>,
    /// Offset and length in the reply of the registers a block read returned
    /// ([`super::Master::read_words`]), or of the words a block transfer read
    /// ([`super::Master::block_transfer`]).
    pub block: Option<(usize, usize)>,
    /// The write status a block transfer's reply carries ([`Role::WriteStatus`]).
    pub write_status: Option<u32>,
    /// The decimal places the reply states for its value ([`Role::Decimals`], the Eaton
    /// unit digit); `None` when it states none. A read of a described register is checked
    /// against it (see [`crate::info::RegisterInfo::scaled_for_decimals`]): a reply whose
    /// decimals no scale of the register has fails with [`ValueError::WrongDecimals`].
    pub decimals: Option<u8>,
}

impl Answer {
    /// The answer to a request that gets no reply: done once its frame is on the line.
    pub const NONE: Answer = Answer {
        data: None,
        tripped: false,
        process: None,
        text: None,
        block: None,
        write_status: None,
        decimals: None,
    };

    /// The same answer found `offset` bytes into the buffer that holds the reply.
    pub(crate) fn shifted(self, offset: usize) -> Answer {
        Answer {
            text: self.text.map(|(start, len)| (start + offset, len)),
            block: self.block.map(|(start, len)| (start + offset, len)),
            ..self
        }
    }
}

pub(crate) fn for_decimals(
    info: &'static crate::info::RegisterInfo,
    decimals: u8,
) -> Result<&'static crate::info::RegisterInfo, ValueError> {
    info.scaled_for_decimals(decimals)
        .ok_or(ValueError::WrongDecimals {
            register: info,
            expected: info.decimals(),
            received: decimals,
        })
}

/// The answer a reply gives to `request` (whose station, register and index the search
/// already compared): an error reply becomes a rejection. `block_size`: the bytes of data a
/// block read expects (0: an ordinary request, which a block of registers does not answer).
pub(crate) fn check_reply(
    request: &Request,
    block_size: usize,
    reply: Reply<'static>,
) -> Result<Answer, TransactionError> {
    match reply {
        Reply::Error {
            error,
            info,
            tripped,
            ..
        } => Err(TransactionError::new(
            Some(request),
            TransactionErrorKind::Rejected {
                code: error,
                info,
                tripped,
            },
        )),
        Reply::Data {
            command,
            tripped,
            data,
            process,
            text,
            values,
            ..
        } => {
            let size = usize::from(values.data_size);
            // A reply without a data field counts what it answers (Modbus 10h's quantity).
            let wide = size > 4 && command.reply.has(Role::Data);
            if (block_size > 0 || wide) && size != block_size {
                return Err(TransactionError::new(
                    Some(request),
                    TransactionErrorKind::Mismatch {
                        field: ReplyField::Data,
                        expected: block_size as u32,
                        found: size as u32,
                    },
                ));
            }
            let block = wide
                .then(|| {
                    command.reply.index_of(Role::Data).map(|index| {
                        let slot = values.parts[index];
                        command
                            .reply
                            .wire_span(slot.value as usize, usize::from(slot.width))
                    })
                })
                .flatten()
                .or_else(|| {
                    // A block transfer's words.
                    command.reply.index_of(Role::Words).map(|index| {
                        let slot = values.parts[index];
                        (slot.value as usize, usize::from(slot.width))
                    })
                });
            if request.data_type == DataType::Text && text.is_none() {
                return Err(TransactionError::new(
                    Some(request),
                    TransactionErrorKind::Mismatch {
                        field: ReplyField::Text,
                        expected: 1,
                        found: 0,
                    },
                ));
            }
            // The decimals the reply states must be those of a scale the register has.
            let decimals = values
                .get(&command.reply, Role::Decimals)
                .map(|d| u8::try_from(d).unwrap_or(u8::MAX));
            if let (Some(decimals), Some(info), None) = (decimals, request.info, block) {
                for_decimals(info, decimals).map_err(|error| {
                    TransactionError::new(Some(request), TransactionErrorKind::Value(error))
                })?;
            }
            Ok(Answer {
                data: (command.reply.has(Role::Data) && block.is_none()).then_some(data),
                tripped,
                process,
                text,
                block,
                write_status: values.get(&command.reply, Role::WriteStatus),
                decimals,
            })
        }
    }
}
