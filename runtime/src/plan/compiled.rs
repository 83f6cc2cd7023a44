//! [`crate::compiled_plan!`]: a layout's two compiled functions, written by the compiler
//! from the layout's parts and steps, so generated code states each layout once.

/// Writes the compiled decode and encode functions of a layout whose parts are the `const`
/// slice `$parts` and whose steps are the `const` array `$steps` (see
/// [`plan::steps`](crate::plan::steps)), one call per part index listed: the same per-part
/// functions a plan run step by step calls in a loop ([`plan::decode_part`](crate::plan::decode_part),
/// ...), here with the step and the part constants, so the compiler turns each function
/// into straight-line code for the layout.
///
/// ```
/// use std::borrow::Cow;
/// use vfd_runtime::plan::{Compiled, FramePlan, Step};
/// use vfd_runtime::{ChecksumAlgorithm, ChecksumSpec, Encoding, FieldSpec, Format, FrameLayout, Part, Role};
///
/// const PARTS: &[Part] = &[
///     Part::Field(FieldSpec::new("address", Role::Address, Format::U8, 1)),
///     Part::Field(FieldSpec::new("register", Role::Register, Format::U16Be, 2)),
///     Part::Checksum(ChecksumSpec::new("sum", ChecksumAlgorithm::Sum8, Format::U8, 0)),
/// ];
/// const STEPS: [Step; 3] = vfd_runtime::plan::steps(PARTS);
/// vfd_runtime::compiled_plan!(decode_ping, encode_ping: PARTS, STEPS, [0 1 2]);
/// const PING: FrameLayout = FrameLayout {
///     name: Cow::Borrowed("ping"),
///     parts: Cow::Borrowed(PARTS),
///     encoding: Encoding::Binary,
///     plan: Some(FramePlan {
///         steps: Cow::Borrowed(&STEPS),
///         compiled: Some(Compiled { decode: decode_ping, encode: encode_ping }),
///     }),
/// };
/// let frame = PING.plan.as_ref().unwrap().decode(&PING, &[0x01, 0x00, 0x10, 0x11]).unwrap();
/// assert_eq!(frame.len, 4);
/// ```
#[macro_export]
macro_rules! compiled_plan {
    ($decode:ident, $encode:ident: $parts:ident, $steps:ident, [$($index:literal)*]) => {
        fn $decode(bytes: &[u8]) -> ::core::option::Option<$crate::plan::PlannedFrame> {
            let mut d = $crate::plan::Decoder::new(bytes);
            $($crate::plan::decode_part(&mut d, $index, $steps[$index], &$parts[$index], $parts.len())?;)*
            $($crate::plan::check_length_part(&d, $index, $steps[$index])?;)*
            ::core::option::Option::Some(d.finish())
        }
        fn $encode(
            roles: &$crate::Roles,
            data_size: u8,
            include: &[$crate::layout::Text],
            out: &mut [u8],
        ) -> ::core::option::Option<usize> {
            if data_size > 4 {
                return ::core::option::Option::None;
            }
            let mut e = $crate::plan::Encoder::new(out);
            $($crate::plan::encode_part(&mut e, $index, $steps[$index], &$parts[$index], roles, data_size, include)?;)*
            $($crate::plan::fill_length_part(&mut e, $index, $steps[$index], data_size)?;)*
            $($crate::plan::fill_checksum_part(&mut e, $index, $steps[$index], &$parts[$index])?;)*
            ::core::option::Option::Some(e.finish())
        }
    };
}
