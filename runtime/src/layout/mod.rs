//! Frame layouts as data: the parts a protocol description builds frames from.
//!
//! A [`FrameLayout`] is an ordered list of [`Part`]s. Generated code holds layouts in
//! `static` items (every list is a borrowed [`Cow`](std::borrow::Cow)); the code generator
//! builds the same types at run time (owned) to check a description's example frames while
//! reading it.

// Layers, each file using only those above it: `borrowed`, `format` and `role`; the part
// specifications `field`, `bits`, `length` and `checksum_spec`; `part`; `values`; `plan`;
// `frame`; `frame_values` on top.
mod bits;
mod borrowed;
mod checksum_spec;
mod field;
mod format;
mod frame;
mod frame_values;
mod length;
mod part;
mod plan;
mod role;
mod values;

pub use bits::{BitsSpec, WordSpec};
pub use borrowed::{List, Text};
pub use checksum_spec::{ChecksumAlgorithm, ChecksumSpec};
pub use field::{BroadcastAddress, FieldSpec, Presence, SizedBy};
pub use format::{checksum_size, Encoding, Format};
pub use frame::FrameLayout;
pub use length::{Counts, LengthSpec};
pub use part::Part;
pub use plan::{
    ChecksumStep, Compiled, EncodeFn, FieldStep, FramePlan, LengthStep, PlannedFrame, Step,
};
pub use role::Role;
pub use values::{FieldValue, FrameValues, Roles, MAX_PARTS};
