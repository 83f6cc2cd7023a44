//! Part of the `examples_decode` check: the value an example states (`examples[].value`)
//! is the data its frames carry, in the unit and scale of the register they name.

use crate::diagnostics::Diagnostics;
use crate::frames::{register_of, DecodedExample, DecodedFrame};
use crate::validate::{decimals, ranges, with_unit, Context};

/// The example's `value` is the data of its reply, else of its request, in the register's
/// unit; reported at `<base>.value`.
pub(super) fn check_example_value(
    drive: &Context,
    base: &str,
    value: f64,
    example: &DecodedExample,
    out: &mut Diagnostics,
) {
    let path = format!("{base}.value");
    // Frames that do not decode are reported as such, and a paged offset without its page
    // (paged_examples_name_their_place): the value has nothing to be judged by.
    if example
        .reply_then_request()
        .all(|frame| frame.decoded().is_none())
        || example
            .request
            .as_ref()
            .is_some_and(DecodedFrame::register_unknown_for_its_page)
    {
        return;
    }
    // The value belongs to the data of the reply, else of the request.
    let mut register = None;
    let mut data = None;
    for decoded in example
        .reply_then_request()
        .filter_map(DecodedFrame::as_stated)
    {
        if register.is_none() {
            register = register_of(&drive.model, &decoded);
        }
        if data.is_none() {
            data = decoded.data;
        }
    }
    let Some(register) = register else {
        out.push(
            drive
                .source
                .error(&path, "`value` needs a frame naming a described register")
                .hint("describe the register, or drop `value`"),
        );
        return;
    };
    let Some(data) = data else {
        out.push(
            drive
                .source
                .error(&path, "`value` needs a frame carrying data")
                .hint("the value is the data in engineering units"),
        );
        return;
    };
    if !ranges::has_sound_scale(register) {
        return; // `scales_are_positive` reports the scale.
    }
    let scale = ranges::scale_of(register);
    let data_type = register.data_type.unwrap_or(vfd_runtime::DataType::Word);
    let raw = vfd_runtime::units::raw_to_number(data, register.signed, data_type);
    if (raw * scale - value).abs() > scale / 2.0 {
        out.push(
            drive
                .source
                .error(
                    &path,
                    format!(
                        "data {data:04X}h is {} in `{}`, not {}",
                        with_unit(register, format!("{:.*}", decimals(scale), raw * scale)),
                        register.code,
                        with_unit(register, value.to_string())
                    ),
                )
                .hint("check the register's scale and the example"),
        );
    }
}
