//! What a frame says, for people, in one line: used by the virtual drive's log (`vfd sim
//! --verbose`) and by the traced line `vfd demo` shows.

use vfd_runtime::meaning::{decode_meaning, Direction};
use vfd_runtime::Protocol;

/// What a frame says, for people: command, station, register by code and name, data,
/// error code, trip; or why it is not a whole frame.
pub fn frame_text(
    drive: &'static vfd_runtime::DriveInfo,
    protocol: &'static Protocol,
    direction: Direction,
    bytes: &[u8],
) -> String {
    match decode_meaning(protocol, direction, bytes) {
        Ok(m) => {
            let mut parts = Vec::new();
            if let Some(code) = m.code {
                parts.push(vfd_runtime::protocol::code_label(code));
            }
            if let Some(a) = m.address {
                parts.push(format!("station {a}"));
            }
            if let Some(r) = m.register {
                let space = m.space.unwrap_or(vfd_runtime::Space::Parameter);
                match drive.register_for(space, r, m.kind.is_some_and(|k| k.is_write())) {
                    Some(info) => parts.push(format!("{} {}", info.code, info.name)),
                    None => parts.push(format!("register {r:04X}h")),
                }
            }
            if let Some(d) = m.data {
                parts.push(format!("data {d:04X}h"));
            }
            if let Some(e) = m.error_code {
                parts.push(format!("error {e}"));
            }
            if m.tripped {
                parts.push("tripped".to_owned());
            }
            parts.join(", ")
        }
        Err(e) => format!("not a whole {}: {e}", direction.as_str()),
    }
}
