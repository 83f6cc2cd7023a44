//! The data of a frame plan: steps, one per part, that generated code and the interpreter share.

use super::borrowed::{List, Text};
use super::checksum_spec::ChecksumAlgorithm;
use super::field::Presence;
use super::format::Format;
use super::length::Counts;
use super::role::Role;
use super::values::{FrameValues, Roles};

/// The steps of one layout, one per part, in wire order (see [`crate::plan`]).
#[derive(Debug, Clone)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct FramePlan {
    /// One step per part of the layout, at the part's index.
    pub steps: List<Step>,
    /// The same steps compiled for this layout alone: functions the generator writes
    /// for each generated layout, which run the steps one after the other with every
    /// argument a constant (see [`crate::plan::Decoder`] and [`crate::plan::Encoder`]). `None` for a plan computed at
    /// run time, which [`FramePlan::decode`] and [`FramePlan::encode`] run step by step.
    #[cfg_attr(feature = "serde", serde(skip))]
    pub compiled: Option<Compiled>,
}

/// Two plans are equal when their steps are (compiled functions run the same steps).
impl PartialEq for FramePlan {
    fn eq(&self, other: &FramePlan) -> bool {
        self.steps == other.steps
    }
}

/// A plan's steps compiled for one layout by the generator.
#[derive(Debug, Clone, Copy)]
pub struct Compiled {
    /// Runs [`FramePlan::decode`]'s steps.
    pub decode: fn(&[u8]) -> Option<PlannedFrame>,
    /// Runs [`FramePlan::encode`]'s steps.
    pub encode: EncodeFn,
}

/// The signature of a compiled encoder: roles, data size, the protocol's default optional
/// parts, the output buffer (see [`FramePlan::encode`]).
pub type EncodeFn = fn(&Roles, u8, &[Text], &mut [u8]) -> Option<usize>;

/// What a plan does for one part. Lists (literal bytes, allowed values, bit fields,
/// markers) stay in the layout's part; a step holds what the fast path decides on.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub enum Step {
    /// Fixed bytes (the part's).
    Literal {
        /// Present on decode only when the next bytes equal them; on encode only when named
        /// among the protocol's default optional parts.
        optional: bool,
    },
    /// A value field.
    Field(FieldStep),
    /// A word of bit fields, in a fixed binary format.
    Word {
        /// `u16be`, `u16le`, `u32be` or `u32le`.
        format: Format,
    },
    /// A computed length, in a fixed binary format.
    Length(LengthStep),
    /// A checksum over earlier parts.
    Checksum(ChecksumStep),
}

/// A value field's step.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct FieldStep {
    /// What it means.
    pub role: Role,
    /// Wire format: a digit format, a fixed binary format, or `uint_be`/`uint_le`.
    pub format: Format,
    /// Digits or bytes written (and the most digits read).
    pub width: u8,
    /// The fewest digits read.
    pub min_width: u8,
    /// How a decoder tells it is there, when it may be left out.
    pub optional: Option<Presence>,
    /// Sized by the length part that covers it alone (a Modbus byte count).
    pub by_length: bool,
    /// The part lists the values it accepts.
    pub checked: bool,
    /// The part has broadcast encodings with open digits (`**`, `*9`): frames holding
    /// one go to the interpreter.
    pub open_digits: bool,
}

/// A length's step.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct LengthStep {
    /// `u8` or `u16be`.
    pub format: Format,
    /// What it counts.
    pub counts: Counts,
    /// See [`crate::LengthSpec::times`].
    pub times: u8,
    /// See [`crate::LengthSpec::per`].
    pub per: u8,
}

/// A checksum's step.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct ChecksumStep {
    /// The algorithm.
    pub algorithm: ChecksumAlgorithm,
    /// `hex` (two digits) or a fixed binary format.
    pub format: Format,
    /// First part covered.
    pub covers_from: u8,
    /// Last part covered, when coverage stops before the checksum.
    pub covers_through: Option<u8>,
    /// May be left out (present when its marker is there).
    pub optional: bool,
}

/// A frame decoded by a plan: what [`crate::codec::decode`] returns for it, with its
/// roles gathered as [`FrameValues::roles`] gathers them.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PlannedFrame {
    /// Every part's value.
    pub values: FrameValues,
    /// The values of the roles the frame carries.
    pub roles: Roles,
    /// Frame length in bytes.
    pub len: usize,
}
