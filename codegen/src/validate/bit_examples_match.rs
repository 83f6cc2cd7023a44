//! Check: bit-field examples agree with the bit positions.

use crate::diagnostics::Diagnostics;
use crate::validate::bit_span;
use crate::validate::Context;

/// Bit-field examples (`8400h = command_enabled + run`) agree with the bit positions.
pub fn bit_examples_match(drive: &Context, out: &mut Diagnostics) {
    for (i, bitfield) in drive.model.bitfields.iter().enumerate() {
        for (j, example) in bitfield.examples.iter().enumerate() {
            let mut value = 0u32;
            for name in &example.set {
                match bitfield
                    .fields
                    .iter()
                    .find(|f| f.id.as_deref() == Some(name.as_str()))
                {
                    Some(field) => {
                        if let Ok((lsb, _)) = bit_span(field.bit, field.bits.as_deref()) {
                            value |= 1 << lsb;
                        }
                    }
                    None => out.push(
                        drive
                            .source
                            .error(
                                &format!("bitfields[{i}].examples[{j}].set"),
                                format!("`{name}` is not a field of `{}`", bitfield.id),
                            )
                            .hint("name fields by id"),
                    ),
                }
            }
            if value != example.value {
                out.push(
                    drive
                        .source
                        .error(
                            &format!("bitfields[{i}].examples[{j}].value"),
                            format!(
                                "the fields set give {value:04X}h, not {:04X}h",
                                example.value
                            ),
                        )
                        .hint("check the example against the bit table"),
                );
            }
        }
    }
}
