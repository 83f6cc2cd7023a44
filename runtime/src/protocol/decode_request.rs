//! Decoding request frames (what a drive, or the simulator, receives).

use super::decoded::{DecodedRequest, Found};
use super::frame_checks::furthest;
use super::Protocol;
use crate::broadcast::{self as broadcasts};
use crate::codec::{DecodeStatus, FrameValues};
use crate::error::DecodeError;
use crate::layout::{FrameLayout, Role};

fn process_of(layout: &FrameLayout, values: &FrameValues) -> Option<[u16; 2]> {
    match (
        values.get(layout, Role::Process1),
        values.get(layout, Role::Process2),
    ) {
        (Some(first), Some(second)) => Some([first as u16, second as u16]),
        _ => None,
    }
}
impl Protocol {
    /// Decodes a request frame starting at `bytes[0]`.
    pub fn decode_request(&self, bytes: &[u8]) -> Result<Found<DecodedRequest<'_>>, DecodeError> {
        let mut best: Option<DecodeError> = None;
        let mut incomplete = false;
        for command in self.commands.iter() {
            let layout = &command.request;
            match crate::plan::decode(layout, bytes) {
                Ok(DecodeStatus::Complete { values, len }) => {
                    // Commands may share a layout (W and P): the code decides.
                    if values
                        .get(layout, Role::Command)
                        .is_some_and(|code| !command.answers_to(code))
                    {
                        continue;
                    }
                    if let Err(error) = self.station_in_range(layout, &values) {
                        best = Some(furthest(best, error));
                        continue;
                    }
                    let wire = values.get(layout, Role::Register).map(|r| r as u16);
                    let station = values.get(layout, Role::Address);
                    let broadcast = station.and_then(|value| {
                        layout
                            .field(Role::Address)
                            .and_then(|field| broadcasts::from_field_value(field, value))
                    });
                    return Ok(Found::Frame {
                        frame: DecodedRequest {
                            command,
                            address: station.filter(|_| broadcast.is_none()).map(|a| a as u8),
                            broadcast,
                            wire_register: wire,
                            register: wire.and_then(|w| {
                                self.from_wire(command, w, values.get(layout, Role::Data))
                            }),
                            index: values.get(layout, Role::Index).map(|i| i as u16),
                            data: values.get(layout, Role::Data).unwrap_or(0),
                            process: process_of(layout, &values),
                            words: values.words(layout, bytes),
                            data_words: values.data_words(layout, bytes),
                            values,
                            len,
                        },
                        skipped: 0,
                    });
                }
                Ok(DecodeStatus::Incomplete) => incomplete = true,
                Err(error) => best = Some(furthest(best, error)),
            }
        }
        if incomplete {
            return Ok(Found::Incomplete);
        }
        Err(self.no_match("request", best))
    }

    /// Decodes exactly one request frame: `bytes` must hold the whole frame and nothing else.
    pub fn decode_request_exact(&self, bytes: &[u8]) -> Result<DecodedRequest<'_>, DecodeError> {
        match self.decode_request(bytes)? {
            Found::Frame { frame, .. } => self.exact(frame.len, bytes.len()).map(|()| frame),
            Found::Incomplete => Err(DecodeError::Truncated {
                layout: self.id.clone(),
                len: bytes.len(),
            }),
        }
    }
}
