//! Checks a decoded frame must pass (station in range, known error function, nothing left
//! over) and how failed attempts are ranked.

use super::decoded::Reply;
use super::Protocol;
use crate::broadcast::{self as broadcasts};
use crate::codec::FrameValues;
use crate::error::DecodeError;
use crate::layout::{Format, FrameLayout, Part, Role};
use std::borrow::Cow;

impl Protocol {
    /// Refuses a frame whose station field holds one station outside the protocol's
    /// station range (the description's `addressing`), as [`Protocol::encode_request`]
    /// refuses to address it: a YD1000 frame from station 64 (range 0-63) is no frame of
    /// the drive. A broadcast encoding in the field (Modbus 0, `**`, FFh) is no station.
    pub(super) fn station_in_range(
        &self,
        layout: &FrameLayout,
        values: &FrameValues,
    ) -> Result<(), DecodeError> {
        let Some((index, None)) = layout.locate(Role::Address) else {
            return Ok(());
        };
        let slot = values.parts[index];
        let Part::Field(field) = &layout.parts[index] else {
            return Ok(());
        };
        if !slot.present || broadcasts::from_field_value(field, slot.value).is_some() {
            return Ok(());
        }
        let (min, max) = self.address_range;
        if (u32::from(min)..=u32::from(max)).contains(&slot.value) {
            return Ok(());
        }
        Err(DecodeError::StationOutOfRange {
            layout: layout.name.clone(),
            part: field.name.clone(),
            offset: layout.wire_span(part_offset(layout, values, index), 0).0,
            station: slot.value,
            min,
            max,
        })
    }

    /// Refuses an error reply whose function code is the error code of none of the drive's
    /// commands, when each of them names one (Modbus: a drive without function 08 sends
    /// no 88h, although the shared protocol file's layout allows it).
    pub(super) fn error_function_known(
        &self,
        layout: &FrameLayout,
        values: &FrameValues,
    ) -> Result<(), DecodeError> {
        let Some(code) = values.get(layout, Role::Command) else {
            return Ok(());
        };
        let codes: Option<Vec<u32>> = self.commands.iter().map(|c| c.error_code).collect();
        match codes {
            Some(codes) if !codes.is_empty() && !codes.contains(&code) => {
                Err(DecodeError::NotAllowed {
                    layout: layout.name.clone(),
                    part: layout
                        .index_of(Role::Command)
                        .map_or(Cow::Borrowed("command"), |i| {
                            layout.parts[i].name().to_owned().into()
                        }),
                    offset: layout
                        .wire_span(
                            layout
                                .index_of(Role::Command)
                                .map_or(0, |i| part_offset(layout, values, i)),
                            0,
                        )
                        .0,
                    value: code,
                    format: Format::U8,
                })
            }
            _ => Ok(()),
        }
    }

    pub(super) fn exact(&self, len: usize, available: usize) -> Result<(), DecodeError> {
        if len == available {
            Ok(())
        } else {
            Err(DecodeError::TrailingBytes {
                layout: self.id.clone(),
                len,
                extra: available - len,
            })
        }
    }

    pub(super) fn no_match(&self, what: &'static str, best: Option<DecodeError>) -> DecodeError {
        let closest = best.unwrap_or(DecodeError::Truncated {
            layout: self.id.clone(),
            len: 0,
        });
        DecodeError::NoLayoutMatches {
            protocol: self.id.clone(),
            what,
            closest: Box::new(closest),
        }
    }
}

/// A reply comes from one station: a station field with open digits (`**`, `*9`) is a
/// broadcast request's, never a reply's.
pub(super) fn no_open_station(
    layout: &FrameLayout,
    values: &FrameValues,
) -> Result<(), DecodeError> {
    match layout.locate(Role::Address) {
        Some((index, None))
            if values.parts[index].present
                && crate::layout::BroadcastAddress::is_open(values.parts[index].value) =>
        {
            Err(DecodeError::NotAllowed {
                layout: layout.name.clone(),
                part: layout.parts[index].name().to_owned().into(),
                offset: 0,
                value: values.parts[index].value & 0xFF_FFFF,
                format: Format::Decimal,
            })
        }
        _ => Ok(()),
    }
}

/// Where the part at `index` of `layout` begins in a frame, counting the fixed sizes of
/// the parts before it (an optional part counted when present, digits by the count read);
/// the station field follows only fixed parts in every layout.
fn part_offset(layout: &FrameLayout, values: &FrameValues, index: usize) -> usize {
    layout.parts[..index]
        .iter()
        .zip(values.parts.iter())
        .map(|(part, slot)| match part {
            Part::Literal { bytes, .. } if slot.present => bytes.len(),
            Part::Field(_) if slot.width > 0 => usize::from(slot.width),
            part => part.fixed_size().unwrap_or(0),
        })
        .sum()
}

pub(super) fn is_optional(part: &Part) -> bool {
    match part {
        Part::Field(field) => field.optional.is_some(),
        _ => false,
    }
}

/// Sorts one decoding attempt: a reply is returned, "more bytes needed" and errors are noted.
pub(super) fn settle<'p>(
    attempt: Result<Option<Reply<'p>>, DecodeError>,
    best: &mut Option<DecodeError>,
    incomplete: &mut bool,
) -> Option<Reply<'p>> {
    match attempt {
        Ok(Some(reply)) => Some(reply),
        Ok(None) => {
            *incomplete = true;
            None
        }
        Err(error) => {
            *best = Some(furthest(best.take(), error));
            None
        }
    }
}

/// Keeps the error that got further into the frame: it names the most telling problem.
pub(super) fn furthest(best: Option<DecodeError>, error: DecodeError) -> DecodeError {
    // A whole frame from a station the drive cannot have says more than a layout that
    // failed further on.
    let whole = |e: &DecodeError| matches!(e, DecodeError::StationOutOfRange { .. });
    match best {
        Some(best) if whole(&best) && !whole(&error) => best,
        Some(_) if whole(&error) => error,
        Some(best) if best.offset() >= error.offset() => best,
        _ => error,
    }
}
