//! Block operations: several consecutive registers read or written in one exchange where
//! the protocol counts its data (Modbus 03 and 10h), and the block transfer whose frame
//! carries only words while the drive's selection says which registers they are.

use super::answer::Answer;
use super::error::{ReplyField, TransactionError, TransactionErrorKind};
use super::exchange::{Exchange, ExchangeKind};
use super::line::Line;
use super::prepare::data_little_endian;
use super::session::Session;
use crate::codec::Words;
use crate::error::{EncodeError, ValueError};
use crate::kinds::{CommandKind, DataType, Space};
use crate::layout::{Encoding, Format, Role};
use crate::protocol::BlockSelection;
use crate::register::{Register, RegisterValue, Request, Writable};

/// What a block transfer ([`super::Master::block_transfer`]) returned.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct BlockTransfer {
    /// The words read, in order, each with the register its position selects (`None`: the
    /// position selects nothing and the drive sends 0).
    pub reads: Vec<(Option<u16>, u16)>,
    /// The registers the written words went to, in order (`None`: not selected).
    pub writes: Vec<Option<u16>>,
    /// The reply's write status: bit `n` set means word `n` was not written.
    pub write_status: u32,
    /// The reply said the drive is tripped.
    pub tripped: bool,
}

impl BlockTransfer {
    /// Whether word `position` (0: the first) was not written.
    pub fn write_failed(&self, position: usize) -> bool {
        position < 32 && self.write_status & (1 << position) != 0
    }

    /// The typed value of register `R`, when a read position selected it (`None`
    /// otherwise).
    pub fn value<R: Register>(&self) -> Option<Result<R::Value, ValueError>> {
        if R::INFO.space != Space::Parameter {
            return None;
        }
        self.reads
            .iter()
            .find(|(register, _)| *register == Some(R::INFO.address))
            .map(|(_, word)| R::Value::from_raw(u32::from(*word), R::INFO))
    }

    /// Whether the word written to register `R` was written: `None` when no write position
    /// selected `R`.
    pub fn written<R: Register>(&self) -> Option<bool> {
        self.writes
            .iter()
            .position(|register| *register == Some(R::INFO.address))
            .map(|position| !self.write_failed(position))
    }
}

/// The word a block transfer writes for `value` of register `R`: its raw value, checked
/// against the register's range as a typed write is (the frame carries 16-bit words).
pub fn block_word<R: Writable>(value: &R::Value) -> Result<u16, ValueError> {
    value.to_raw(R::INFO).map(|raw| raw as u16)
}

impl Session {
    /// Reads `words.len()` consecutive 16-bit registers (see [`super::Master::read_words`]).
    pub(crate) async fn read_words(
        &mut self,
        line: &mut impl Line,
        start: u16,
        words: &mut [u16],
    ) -> Result<Answer, TransactionError> {
        let request = Request::raw(CommandKind::Read, start, 0);
        let protocol = self.protocol;
        let max = if protocol.block_read_command(Space::Parameter).is_some() {
            protocol.max_words_per_read
        } else {
            1
        };
        if words.is_empty() || words.len() > usize::from(max) {
            return Err(TransactionError::new(
                Some(&request),
                TransactionErrorKind::Encode(EncodeError::TooManyWords {
                    protocol: protocol.id.clone(),
                    words: words.len(),
                    max,
                }),
            ));
        }
        if words.len() == 1 {
            let answer = self.transact(line, &request).await?;
            words[0] = answer.data.map(|d| d as u16).ok_or_else(|| {
                TransactionError::new(
                    Some(&request),
                    TransactionErrorKind::Mismatch {
                        field: ReplyField::Data,
                        expected: 1,
                        found: 0,
                    },
                )
            })?;
            return Ok(answer);
        }
        let exchange = Exchange::new(
            request,
            ExchangeKind::BlockRead {
                words: words.len() as u16,
            },
        );
        let answer = self.run(line, &exchange, None).await?;
        let little_endian = self.block_little_endian();
        // Two words fit a number: the data field's bytes again, in its byte order.
        let number = match answer.data {
            Some(data) if little_endian => data.to_le_bytes(),
            Some(data) => data.to_be_bytes(),
            None => [0; 4],
        };
        let bytes = match (answer.block, answer.data) {
            (Some((offset, len)), _) => self.last_reply().get(offset..offset + len).unwrap_or(&[]),
            (None, Some(_)) => {
                if little_endian {
                    &number[..4]
                } else {
                    &number[4usize.saturating_sub(words.len() * 2)..]
                }
            }
            (None, None) => &[],
        };
        // Blocks written as hex digits (Modbus ASCII): two digits per byte.
        let mut digits = [0u8; 2 * 125];
        let hex = protocol
            .block_read_command(Space::Parameter)
            .is_some_and(|c| c.reply.encoding == Encoding::HexPairs);
        let bytes = if hex && answer.block.is_some() {
            let n = crate::codec::hex_digits_to_bytes(bytes, &mut digits);
            &digits[..n]
        } else {
            bytes
        };
        for (word, pair) in words.iter_mut().zip(bytes.chunks_exact(2)) {
            let pair = [pair[0], pair[1]];
            *word = if little_endian {
                u16::from_le_bytes(pair)
            } else {
                u16::from_be_bytes(pair)
            };
        }
        Ok(answer)
    }

    /// Writes `words` to consecutive 16-bit registers (see [`super::Master::write_words`]).
    pub(crate) async fn write_words(
        &mut self,
        line: &mut impl Line,
        start: u16,
        words: &[u16],
    ) -> Result<Answer, TransactionError> {
        let mut request = Request::raw(CommandKind::WriteRam, start, 0);
        let protocol = self.protocol;
        let command = protocol.block_write_command(Space::Parameter);
        let max = if command.is_some() {
            protocol.max_words_per_write
        } else {
            1
        };
        let too_many = |request: &Request| {
            TransactionError::new(
                Some(request),
                TransactionErrorKind::Encode(EncodeError::TooManyWordsToWrite {
                    protocol: protocol.id.clone(),
                    words: words.len(),
                    max,
                }),
            )
        };
        if words.is_empty() || words.len() > usize::from(max) {
            return Err(too_many(&request));
        }
        if let [only] = *words {
            request.data = u32::from(only);
            return self.transact(line, &request).await;
        }
        let Some(command) = command else {
            return Err(too_many(&request));
        };
        request.command = Some(command.code);
        if let [first, second] = *words {
            // Two words are a number, as a double-word register's write carries them.
            request.data_type = DataType::DoubleWord;
            request.data = if data_little_endian(&command.request) {
                u32::from(first) | (u32::from(second) << 16)
            } else {
                (u32::from(first) << 16) | u32::from(second)
            };
        }
        let list = Words::from_slice(words).ok_or_else(|| too_many(&request))?;
        self.run(
            line,
            &Exchange::new(request, ExchangeKind::BlockWrite(list)),
            None,
        )
        .await
    }

    /// The value of a register `words.len()` words wide (see [`super::Master::join_words`]).
    pub(crate) fn join_words(&self, words: &[u16]) -> u32 {
        let little_endian = self.block_little_endian();
        match *words {
            [only] => u32::from(only),
            [first, second] if little_endian => u32::from(first) | (u32::from(second) << 16),
            [first, second] => (u32::from(first) << 16) | u32::from(second),
            _ => 0,
        }
    }

    /// Runs one block transfer (see [`super::Master::block_transfer`]).
    pub(crate) async fn block_transfer(
        &mut self,
        line: &mut impl Line,
        selection: &BlockSelection,
        writes: &[u16],
        read_count: u8,
    ) -> Result<BlockTransfer, TransactionError> {
        let request = Request::raw(CommandKind::Block, 0, 0);
        let protocol = self.protocol;
        let refuse = |what: &'static str, words: usize, max: usize| {
            TransactionError::new(
                Some(&request),
                TransactionErrorKind::Encode(EncodeError::BlockTooLong {
                    protocol: protocol.id.clone(),
                    what,
                    words,
                    max,
                }),
            )
        };
        if protocol.block_command().is_none() {
            return Err(TransactionError::new(
                Some(&request),
                TransactionErrorKind::Encode(EncodeError::UnsupportedCommand {
                    protocol: protocol.id.clone(),
                    kind: CommandKind::Block,
                    space: Space::Parameter,
                    data_type: DataType::Word,
                }),
            ));
        }
        if writes.len() > selection.write.len() {
            return Err(refuse("writes", writes.len(), selection.write.len()));
        }
        if usize::from(read_count) > selection.read.len() {
            return Err(refuse(
                "reads",
                usize::from(read_count),
                selection.read.len(),
            ));
        }
        let words = Words::from_slice(writes)
            .ok_or_else(|| refuse("writes", writes.len(), crate::codec::MAX_WORDS))?;
        let kind = ExchangeKind::BlockTransfer {
            writes: words,
            read_count,
        };
        let prepared =
            super::prepare::prepare(protocol, &Exchange::new(request, kind), &self.station())
                .map_err(|error| {
                    TransactionError::new(Some(&request), TransactionErrorKind::Encode(error))
                })?;
        let answer = self.exchange(line, &prepared).await?;
        let bytes = answer
            .block
            .and_then(|(offset, len)| self.last_reply().get(offset..offset + len))
            .unwrap_or(&[]);
        let little_endian = protocol
            .block_command()
            .and_then(|command| command.reply.field(Role::Words))
            .is_some_and(|field| field.format == Format::U16Le);
        let read: Vec<u16> = bytes
            .chunks_exact(2)
            .map(|pair| {
                if little_endian {
                    u16::from_le_bytes([pair[0], pair[1]])
                } else {
                    u16::from_be_bytes([pair[0], pair[1]])
                }
            })
            .collect();
        if read.len() != usize::from(read_count) {
            return Err(TransactionError::new(
                Some(&request),
                TransactionErrorKind::Mismatch {
                    field: ReplyField::Data,
                    expected: u32::from(read_count),
                    found: read.len() as u32,
                },
            ));
        }
        Ok(BlockTransfer {
            reads: selection.read.iter().copied().zip(read).collect(),
            writes: selection.write[..writes.len()].to_vec(),
            write_status: answer.write_status.unwrap_or(0),
            tripped: answer.tripped,
        })
    }

    /// Whether the block read's data field is least significant byte first.
    fn block_little_endian(&self) -> bool {
        self.protocol
            .block_read_command(Space::Parameter)
            .is_some_and(|command| data_little_endian(&command.reply))
    }
}
