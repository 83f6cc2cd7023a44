//! Check: bit fields fit the word and do not overlap.

use crate::diagnostics::Diagnostics;
use crate::validate::bit_span;
use crate::validate::Context;

/// Bit fields fit the word and do not overlap.
pub fn bit_fields_do_not_overlap(drive: &Context, out: &mut Diagnostics) {
    for (i, bitfield) in drive.model.bitfields.iter().enumerate() {
        let mut owner: [Option<usize>; 16] = [None; 16];
        for (j, field) in bitfield.fields.iter().enumerate() {
            let path = format!("bitfields[{i}].fields[{j}]");
            match bit_span(field.bit, field.bits.as_deref()) {
                Err(message) => out.push(
                    drive
                        .source
                        .error(&path, message)
                        .hint("write `bit: 15` for one bit or `bits: \"13:12\"` for several"),
                ),
                Ok((lsb, width)) => {
                    for bit in lsb..lsb + width {
                        if let Some(first) = owner[usize::from(bit)] {
                            let other = bitfield.fields[first].id.as_deref().unwrap_or("reserved");
                            out.push(
                                drive
                                    .source
                                    .error(&path, format!("bit {bit} of `{}` is already used by `{other}` (fields[{first}])", bitfield.id))
                                    .hint("bit fields of one word must not overlap; check the manual's bit table"),
                            );
                            break;
                        }
                        owner[usize::from(bit)] = Some(j);
                    }
                }
            }
        }
    }
}
