//! Golden-frame checks for generated tests (cargo feature `testing`, off by default).
//!
//! `vfd-codegen` turns every example frame of a drive description into a `#[test]` that
//! calls these functions: a manual's bytes decode to what the manual says, re-encode to the
//! same bytes, and a misprinted frame is rejected for the stated reason. A crate that runs
//! generated golden tests enables the feature for its tests only:
//!
//! ```toml
//! [dev-dependencies]
//! vfd-runtime = { version = "0.1", features = ["testing"] }
//! ```
//!
//! The functions panic with a message naming the mismatch, like `assert_eq!`; the checks
//! themselves are [`crate::golden`]'s, which `vfd check` runs too.

use crate::golden::{self, StatedFields};
use crate::layout::Role;
use crate::meaning::{Direction, FrameMeaning};
use crate::{DecodeErrorKind, Protocol, Request};

#[track_caller]
fn holds(result: Result<(), golden::Mismatch>) {
    if let Err(mismatch) = result {
        panic!("{mismatch}");
    }
}

/// The request decodes to `expect` (what the generator's decoder read from the manual's
/// bytes), and the same request built from that meaning encodes to `bytes`.
#[track_caller]
pub fn request_round_trips(protocol: &'static Protocol, bytes: &[u8], expect: &FrameMeaning) {
    request_round_trips_stating(protocol, bytes, expect, &[]);
}

/// [`request_round_trips`] for an example that states values of fields of its layout
/// (`(Role::ReplyWait, 3)`): the request built from its meaning carries them.
#[track_caller]
pub fn request_round_trips_stating(
    protocol: &'static Protocol,
    bytes: &[u8],
    expect: &FrameMeaning,
    stated: StatedFields<'_>,
) {
    holds(golden::request_round_trips(protocol, bytes, expect, stated));
}

/// A request built through the typed API encodes to the manual's `bytes` (with the
/// manual's command, optional parts, digit counts and process words).
#[track_caller]
pub fn typed_request_encodes(protocol: &'static Protocol, request: &Request, bytes: &[u8]) {
    typed_request_encodes_stating(protocol, request, &[], bytes);
}

/// [`typed_request_encodes`] for an example that states values of fields of its layout.
#[track_caller]
pub fn typed_request_encodes_stating(
    protocol: &'static Protocol,
    request: &Request,
    stated: &[(Role, u32)],
    bytes: &[u8],
) {
    holds(golden::typed_request_encodes(
        protocol, request, stated, bytes,
    ));
}

/// The reply decodes to `expect` and re-encodes to `bytes`.
#[track_caller]
pub fn reply_round_trips(protocol: &'static Protocol, bytes: &[u8], expect: &FrameMeaning) {
    holds(golden::reply_round_trips(protocol, bytes, expect));
}

/// The bytes as printed in the manual are rejected, for the reason the erratum states.
#[track_caller]
pub fn printed_is_rejected(
    protocol: &'static Protocol,
    direction: Direction,
    bytes: &[u8],
    reason: DecodeErrorKind,
) {
    holds(golden::printed_is_rejected(
        protocol, direction, bytes, reason,
    ));
}

/// The reply answers the request, as the master judges a reply it receives
/// ([`Protocol::check_answer`]).
#[track_caller]
pub fn reply_answers(protocol: &'static Protocol, request: &[u8], reply: &[u8]) {
    holds(golden::reply_answers(protocol, request, reply));
}

/// The reply as printed in the manual decodes on its own, but the master passes it over:
/// it does not answer its request.
#[track_caller]
pub fn printed_does_not_answer(protocol: &'static Protocol, request: &[u8], printed: &[u8]) {
    holds(golden::printed_does_not_answer(protocol, request, printed));
}

/// The frame as printed in the manual decodes, but to something other than what the
/// manual says it means (`expect`): a letter case that contradicts the stated state, for
/// example.
#[track_caller]
pub fn printed_means_otherwise(
    protocol: &'static Protocol,
    direction: Direction,
    printed: &[u8],
    expect: &FrameMeaning,
) {
    holds(golden::printed_means_otherwise(
        protocol, direction, printed, expect,
    ));
}

/// A request the manual prints as one the drive does not answer: the decoder refuses it
/// for `reason`, and the drive's virtual drive stays silent.
#[track_caller]
pub fn drive_ignores(
    drive: &'static crate::DriveInfo,
    protocol: &'static Protocol,
    bytes: &[u8],
    reason: DecodeErrorKind,
) {
    printed_is_rejected(protocol, Direction::Request, bytes, reason);
    let mut virtual_drive = crate::virtual_drive::VirtualDrive::new(drive);
    let outcome = virtual_drive.respond(protocol, bytes);
    assert!(
        matches!(outcome, crate::virtual_drive::Outcome::Silent(_)),
        "the virtual drive answers {}: {outcome:?}",
        crate::error::hex(bytes)
    );
}

pub use crate::golden::Script;

/// Panics unless `error` is the drive's refusal with error code `code`.
#[track_caller]
pub fn refused_with(error: &crate::TransactionError, code: u16) {
    match &error.kind {
        crate::TransactionErrorKind::Rejected { code: got, .. } => {
            assert_eq!(*got, code, "refused with another code: {error}")
        }
        _ => panic!("expected the drive's refusal {code:02X}h, got: {error}"),
    }
}
