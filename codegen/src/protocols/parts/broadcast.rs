//! A station field's broadcast encodings (`broadcast:`).

use super::PartContext;
use crate::diagnostics::Diagnostics;
use std::borrow::Cow;
use vfd_runtime::{BroadcastAddress, Format, Role};

/// A station field's broadcast encodings: `literal` text or a `value` addressing every
/// station, and a `wildcard` character for groups (digit formats of fixed width only).
pub(super) fn broadcast_address(
    model: &crate::parse::model::BroadcastAddressModel,
    role: Role,
    format: Format,
    width: u8,
    context: &PartContext<'_>,
    out: &mut Diagnostics,
) -> Option<BroadcastAddress> {
    if role != Role::Address {
        return context.fail(
            out,
            "broadcast",
            format!(
                "`broadcast` belongs on the station address field, not on a {} field",
                role.as_str()
            ),
            "move it to the part with `field: address`",
        );
    }
    let all_bytes = model.literal.clone().unwrap_or_default().into_bytes();
    if model.literal.is_some() && model.value.is_some() {
        return context.fail(
            out,
            "broadcast",
            "`broadcast` gives both `literal` and `value`",
            "every station is addressed either by text in the field's place or by one value",
        );
    }
    if model.literal.as_deref() == Some("") {
        return context.fail(
            out,
            "broadcast.literal",
            "the broadcast text is empty",
            "e.g. literal: \"**\"",
        );
    }
    if let Some(value) = model.value {
        let fits = match format.fixed_len() {
            Some(len @ 1..=3) => value < 1 << (8 * len),
            Some(_) => true,
            None if format.is_digits() => {
                let radix: u64 = if format == Format::Hex { 16 } else { 10 };
                u64::from(value) < radix.pow(u32::from(width))
            }
            None => value < 1 << (8 * u32::from(width.min(3))),
        };
        if !fits {
            return context.fail(
                out,
                "broadcast.value",
                format!(
                    "broadcast value {value:#X} does not fit the {} field",
                    format.as_str()
                ),
                "give the station value the manual names for a broadcast",
            );
        }
    }
    let wildcard = match model.wildcard.as_deref() {
        None => None,
        Some(text) => {
            let [byte] = text.as_bytes() else {
                return context.fail(
                    out,
                    "broadcast.wildcard",
                    format!("wildcard `{text}` is not one character"),
                    "e.g. wildcard: \"*\"",
                );
            };
            if !format.is_digits() || width == 0 || width > 7 || byte.is_ascii_hexdigit() {
                return context.fail(
                    out,
                    "broadcast.wildcard",
                    format!("a wildcard digit needs a decimal or hex station field of 1-7 digits and a character that is no digit, not `{text}` in a {} field", format.as_str()),
                    "group addressing leaves digits of a text station number open; binary fields cannot carry it",
                );
            }
            Some(*byte)
        }
    };
    if all_bytes.is_empty() && model.value.is_none() && wildcard.is_none() {
        return context.fail(
            out,
            "broadcast",
            "`broadcast` gives no encoding",
            "give `literal` (\"**\"), `value` (0xFF) or `wildcard` (\"*\")",
        );
    }
    Some(BroadcastAddress {
        all_bytes: Cow::Owned(all_bytes),
        all_value: model.value,
        wildcard,
    })
}
