//! Golden-frame checks: a manual's bytes decode to what the manual says, re-encode to the
//! same bytes, and a misprinted frame is rejected for the stated reason.

use vfd_runtime::codec::{self, FrameValues};
use vfd_runtime::layout::{FrameLayout, Part};
use vfd_runtime::{CommandKind, Protocol, Reply, Request};

/// What a frame should decode to (fields the manual states; `None` means "not in the frame").
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Expect {
    /// Station address.
    pub address: Option<u8>,
    /// Command letter as on the wire.
    pub command: Option<u8>,
    /// Register.
    pub register: Option<u16>,
    /// Data word.
    pub data: Option<u16>,
    /// Error code (error replies).
    pub error_code: Option<u16>,
    /// Lower-case command (tripped).
    pub tripped: bool,
}

/// Which way a frame goes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Direction {
    /// Master to drive.
    Request,
    /// Drive to master.
    Reply,
}

/// Copies presentation choices (optional parts present, digits used) from a decoded
/// frame onto values built from meaning, so both can be compared byte for byte.
fn adopt_presentation(layout: &FrameLayout, built: &mut FrameValues, decoded: &FrameValues) {
    for (index, part) in layout.parts.iter().enumerate() {
        let optional = match part {
            Part::Literal { optional, .. } => *optional,
            Part::Field(field) => field.optional.is_some(),
            Part::Checksum(spec) => spec.optional,
        };
        if optional {
            built.parts[index].present = decoded.parts[index].present;
        }
        built.parts[index].width = decoded.parts[index].width;
    }
}

/// The request decodes to `expect`, and the same request built from `expect` encodes to `bytes`.
#[track_caller]
pub fn request_round_trips(protocol: &'static Protocol, bytes: &[u8], expect: Expect) {
    let decoded = protocol
        .decode_request_exact(bytes)
        .unwrap_or_else(|e| panic!("request does not decode: {e}"));
    assert_eq!(
        Some(decoded.command.letter),
        expect.command,
        "command letter"
    );
    assert_eq!(decoded.address, expect.address, "address");
    assert_eq!(Some(decoded.register), expect.register, "register");
    if decoded.command.kind != CommandKind::Read {
        assert_eq!(Some(decoded.data), expect.data, "data");
    }
    let request = Request::raw(
        decoded.command.kind,
        expect.register.unwrap_or(0),
        expect.data.unwrap_or(0),
    );
    encodes_with_presentation(protocol, &request, expect.address, bytes);
}

/// A request built through the typed API encodes to the manual's `bytes` (with the
/// manual's choice of optional parts and digit counts).
#[track_caller]
pub fn typed_request_encodes(protocol: &'static Protocol, request: &Request, bytes: &[u8]) {
    let decoded = protocol
        .decode_request_exact(bytes)
        .unwrap_or_else(|e| panic!("request does not decode: {e}"));
    assert_eq!(request.kind, decoded.command.kind, "command kind");
    encodes_with_presentation(protocol, request, decoded.address, bytes);
}

#[track_caller]
fn encodes_with_presentation(
    protocol: &'static Protocol,
    request: &Request,
    address: Option<u8>,
    bytes: &[u8],
) {
    let decoded = protocol
        .decode_request_exact(bytes)
        .unwrap_or_else(|e| panic!("request does not decode: {e}"));
    let (layout, mut values) = protocol
        .request_values(request, address)
        .unwrap_or_else(|e| panic!("cannot build the request: {e}"));
    adopt_presentation(layout, &mut values, &decoded.values);
    let mut out = [0u8; 256];
    let len =
        codec::encode(layout, &values, &mut out).unwrap_or_else(|e| panic!("cannot encode: {e}"));
    assert_eq!(
        vfd_runtime::error::hex(&out[..len]),
        vfd_runtime::error::hex(bytes),
        "encoded request differs from the manual"
    );
}

/// The reply decodes to `expect` and re-encodes to `bytes`.
#[track_caller]
pub fn reply_round_trips(protocol: &'static Protocol, bytes: &[u8], expect: Expect) {
    let kind = expect
        .command
        .and_then(|letter| protocol.command_by_letter(letter))
        .map(|c| c.kind);
    let reply = protocol
        .decode_reply_exact(kind, bytes)
        .unwrap_or_else(|e| panic!("reply does not decode: {e}"));
    let (layout, values) = match reply {
        Reply::Data {
            command,
            address,
            tripped,
            register,
            data,
            values,
            ..
        } => {
            let letter = if tripped {
                command.letter.to_ascii_lowercase()
            } else {
                command.letter
            };
            assert_eq!(Some(letter), expect.command, "command letter");
            assert_eq!(address, expect.address, "address");
            assert_eq!(Some(register), expect.register, "register");
            assert_eq!(Some(data), expect.data, "data");
            assert_eq!(tripped, expect.tripped, "tripped");
            assert_eq!(expect.error_code, None, "expected an error reply");
            (&command.reply, values)
        }
        Reply::Error {
            address,
            tripped,
            code,
            info,
            values,
            ..
        } => {
            assert_eq!(Some(code), expect.error_code, "error code");
            assert_eq!(address, expect.address, "address");
            assert_eq!(tripped, expect.tripped, "tripped");
            assert!(
                info.is_some(),
                "error code {code:04X}h is not in the drive's table"
            );
            (
                protocol
                    .error_reply
                    .as_ref()
                    .expect("an error reply needs an error layout"),
                values,
            )
        }
    };
    let mut out = [0u8; 256];
    let len = codec::encode(layout, &values, &mut out)
        .unwrap_or_else(|e| panic!("cannot re-encode: {e}"));
    assert_eq!(
        vfd_runtime::error::hex(&out[..len]),
        vfd_runtime::error::hex(bytes),
        "re-encoded reply differs"
    );
}

/// The bytes as printed in the manual are rejected, for the reason the erratum states.
#[track_caller]
pub fn printed_is_rejected(
    protocol: &'static Protocol,
    direction: Direction,
    command: Option<u8>,
    bytes: &[u8],
    reason: &str,
) {
    let kind = command
        .and_then(|letter| protocol.command_by_letter(letter))
        .map(|c| c.kind);
    let error = match direction {
        Direction::Request => protocol.decode_request_exact(bytes).err(),
        Direction::Reply => protocol.decode_reply_exact(kind, bytes).err(),
    };
    let error = error.unwrap_or_else(|| {
        panic!(
            "the misprinted frame {} decodes without error",
            vfd_runtime::error::hex(bytes)
        )
    });
    assert_eq!(error.kind(), reason, "rejected for another reason: {error}");
}
