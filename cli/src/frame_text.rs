//! What a frame says, for people, in one line: used by the virtual drive's log (`vfd sim
//! --verbose`), by `--trace` and by the traced line `vfd demo` shows.

use vfd_runtime::meaning::{decode_meaning, Direction, FrameMeaning};
use vfd_runtime::Protocol;

/// What a frame says, for people: command, station, register by code and name, data,
/// error code in the manual's notation, trip; a page switch as the protocol step it is; a
/// write the drive never answers as such; the master's follow-up to a reply (Eaton C, F)
/// as what it is; or why it is not a whole frame.
pub fn frame_text(
    drive: &'static vfd_runtime::DriveInfo,
    protocol: &'static Protocol,
    direction: Direction,
    bytes: &[u8],
) -> String {
    match decode_meaning(protocol, direction, bytes) {
        Ok(m) => meaning_text(drive, protocol, &m),
        Err(e) => match direction {
            Direction::Request => follow_up_text(protocol, bytes)
                .unwrap_or_else(|| format!("not a whole {}: {e}", direction.as_str())),
            Direction::Reply => format!("not a whole {}: {e}", direction.as_str()),
        },
    }
}

fn meaning_text(
    drive: &'static vfd_runtime::DriveInfo,
    protocol: &'static Protocol,
    m: &FrameMeaning,
) -> String {
    let mut parts = Vec::new();
    if let Some(code) = m.code {
        parts.push(vfd_runtime::protocol::code_label(code));
    }
    if let Some(a) = m.address {
        parts.push(format!("station {a}"));
    }
    let writing = m.kind.is_some_and(|k| k.is_write());
    let mut info = None;
    if let Some(r) = m.register {
        let space = m.space.unwrap_or(vfd_runtime::Space::Parameter);
        info = drive.register_for(space, r, writing);
        match info {
            Some(info) => parts.push(format!("{} {}", info.code, info.name)),
            None => parts.push(format!("register {r:04X}h")),
        }
    }
    let page_switch = protocol.paging.as_ref().and_then(|paging| {
        let wire = m.wire_register.filter(|_| m.register.is_none())?;
        match writing {
            true => (wire == paging.select_write).then_some(true),
            false => (Some(wire) == paging.select_read).then_some(false),
        }
    });
    match (page_switch, m.data) {
        (Some(true), Some(page)) => parts.push(format!("page switch to page {page}")),
        (Some(false), Some(page)) => parts.push(format!("page read: page {page}")),
        (Some(false), None) => parts.push("page read".to_owned()),
        (_, Some(d)) => parts.push(format!("data {d:04X}h")),
        _ => {}
    }
    if let Some(e) = m.error_code {
        let code = protocol
            .error_code(e)
            .map_or_else(|| format!("{e:02X}h"), |info| info.shown());
        parts.push(format!("error {code}"));
    }
    if m.tripped {
        parts.push("tripped".to_owned());
    }
    if writing && info.is_some_and(|i| i.no_reply) {
        parts.push("never answered".to_owned());
    }
    parts.join(", ")
}

/// The master's follow-up to a reply, when `bytes` are one whole: "the master acknowledges
/// the reply, station 1" (Eaton C) or "the master asks for the reply again" (F).
pub fn follow_up_text(protocol: &Protocol, bytes: &[u8]) -> Option<String> {
    let (sound, address, len) = protocol
        .commands
        .iter()
        .filter_map(|c| c.follow_up.as_ref())
        .find_map(|f| f.recognise(bytes))?;
    (len == bytes.len()).then(|| {
        format!(
            "follow-up: the master {}{}",
            if sound {
                "acknowledges the reply"
            } else {
                "asks for the reply again"
            },
            address.map_or_else(String::new, |a| format!(", station {a}"))
        )
    })
}
