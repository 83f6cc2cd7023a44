//! The decoding state shared by the parts of one frame, what decoding a part gives,
//! and the errors several parts report.

use crate::error::DecodeError;
use crate::layout::{FrameLayout, MAX_PARTS};

/// Decoding state shared by the parts of one frame.
pub(super) struct Cursor<'b> {
    pub(super) bytes: &'b [u8],
    pub(super) pos: usize,
    /// End of the frame, once a length part covering the last part has been read.
    pub(super) frame_end: Option<usize>,
    /// Sizes fixed by length parts that cover exactly one later part (`u16::MAX`: none).
    pub(super) sized: [u16; MAX_PARTS],
}

/// What decoding one part gave: the part is done (read or absent), or needs more bytes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum PartOutcome {
    Done,
    Incomplete,
}

/// A part that ran past the end a length part set (`end`), reaching `pos`.
pub(super) fn length_error(
    layout: &FrameLayout,
    part: &str,
    end: usize,
    pos: usize,
) -> DecodeError {
    DecodeError::LengthMismatch {
        layout: layout.name.clone(),
        part: part.to_owned().into(),
        offset: end,
        received: end as u32,
        actual: pos as u32,
    }
}

/// Where `rest` first differs from `literal` (0 when they agree as far as both go).
pub(super) fn mismatch_at(rest: &[u8], literal: &[u8]) -> usize {
    rest.iter()
        .zip(literal)
        .position(|(a, b)| a != b)
        .unwrap_or(0)
}
