//! A request whose data field is not as wide as the register's: where a protocol tells
//! data types apart by the width of the data field alone (two hex digits for a byte, four
//! for a word), a request of one width for a register of the other is a malformed frame.
//! It is answered as the drive answers any malformed frame (not at all: a refusal needs a
//! frame the drive can read), and never acted on.

use crate::kinds::DataType;
use crate::layout::{FrameLayout, Part, Role};
use crate::protocol::{CommandSpec, Protocol};

/// Why the drive stays silent to such a request.
pub(super) const MALFORMED: &str =
    "a malformed frame: its data field is not as wide as the register's data";

/// Whether a request of `command` carries data of the wrong width for a register of
/// `data_type`: `command` does not carry that type, and another command of the same kind
/// and space does, with a request that differs from `command`'s only in its data field.
pub(super) fn wrong_width(protocol: &Protocol, command: &CommandSpec, data_type: DataType) -> bool {
    if command.carries(data_type) {
        return false;
    }
    protocol.commands.iter().any(|other| {
        other.kind == command.kind
            && other.space == command.space
            && other.carries(data_type)
            && only_data_differs(&other.request, &command.request)
    })
}

/// Whether `a` and `b` are the same parts but for their data fields, which differ.
fn only_data_differs(a: &FrameLayout, b: &FrameLayout) -> bool {
    let data = |part: &Part| matches!(part, Part::Field(field) if field.role == Role::Data);
    a.parts.len() == b.parts.len()
        && a.parts != b.parts
        && a.parts
            .iter()
            .zip(b.parts.iter())
            .all(|(x, y)| x == y || (data(x) && data(y)))
}
