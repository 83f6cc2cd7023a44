//! Check: every field of a bit-field word fits each register whose value the word is. A
//! register is as wide as its data type: a byte 8 bits (its protocols carry it in the
//! narrower data field of their byte commands, two hex digits where a word takes four), a
//! word 16, a double word 32. A bit 9 in a byte register could never be read or written.

use crate::diagnostics::Diagnostics;
use crate::parse::model::RegisterModel;
use crate::validate::{bit_span, Context};
use vfd_runtime::DataType;

/// Bit fields fit the registers that use them.
pub fn bit_fields_fit_their_registers(drive: &Context, out: &mut Diagnostics) {
    let widths: Vec<Option<Width>> = drive.model.registers.iter().map(width_of).collect();
    for (i, bitfield) in drive.model.bitfields.iter().enumerate() {
        let users: Vec<(usize, &RegisterModel, Width)> = drive
            .model
            .registers
            .iter()
            .enumerate()
            .filter(|(_, r)| r.bitfield.as_deref() == Some(bitfield.id.as_str()))
            .filter_map(|(index, r)| widths[index].map(|w| (index, r, w)))
            .collect();
        for (j, field) in bitfield.fields.iter().enumerate() {
            // A malformed or overlapping span is `bit_fields_do_not_overlap`'s to report.
            let Ok((lsb, span)) = bit_span(field.bit, field.bits.as_deref()) else {
                continue;
            };
            let msb = u32::from(lsb) + u32::from(span) - 1;
            let Some((index, register, width)) = users
                .iter()
                .filter(|(_, _, width)| msb >= width.bits)
                .min_by_key(|(_, _, width)| width.bits)
            else {
                continue;
            };
            let name = field.id.as_deref().unwrap_or("reserved");
            let (bits, fit) = if span == 1 {
                (format!("bit {msb}"), "does not fit")
            } else {
                (format!("bits {msb}-{lsb}"), "do not fit")
            };
            out.push(
                drive
                    .source
                    .error(
                        &format!("bitfields[{i}].fields[{j}]"),
                        format!(
                            "{bits} (`{name}`) of `{}` {fit} register {} (registers[{index}]): {}, bits {}-0",
                            bitfield.id,
                            register.code,
                            width.why,
                            width.bits - 1
                        ),
                    )
                    .hint("check the bit number against the manual's table, or the register's data type (`data_type: byte` is 8 bits wide)"),
            );
        }
    }
}

/// How many bits a register carries, and why no more.
#[derive(Debug, Clone, Copy)]
struct Width {
    bits: u32,
    why: &'static str,
}

/// The register's width, by its data type; `None` for registers that are no bit-field
/// word's (or carry no bits: coils and text).
fn width_of(register: &RegisterModel) -> Option<Width> {
    register.bitfield.as_ref()?;
    let (bits, why) = match register.data_type.unwrap_or(DataType::Word) {
        DataType::Byte => (8, "a byte"),
        DataType::Word => (16, "a word"),
        DataType::DoubleWord => (32, "a double word"),
        DataType::Bit | DataType::Text => return None,
    };
    Some(Width { bits, why })
}

#[cfg(test)]
mod tests {
    use super::bit_fields_fit_their_registers as check;
    use crate::validate::testing::{assert_at, check_yaml, valid_with, VALID};

    #[test]
    fn accepts_fields_within_a_word() {
        assert!(check_yaml(check, VALID).is_empty());
    }

    #[test]
    fn reports_a_bit_beyond_a_byte_register() {
        // The test drive's command word (bits 15, 10 and reserved 14-11, 9-0) on a byte:
        // the lowest offending field is reported once, naming the register.
        let yaml = valid_with(&[(
            "bitfield: command_word, ram_only: true,",
            "bitfield: command_word, data_type: byte, ram_only: true,",
        )]);
        let found = check_yaml(check, &yaml);
        assert_eq!(found.len(), 4, "{found:#?}");
        assert_at(
            &found[2],
            &yaml,
            "bitfields[0].fields[2]",
            "bit 10 (`run`) of `command_word` does not fit register FA00 (registers[4]): a byte, bits 7-0",
            "{ bit: 10, id: run,",
        );
        let found = check_yaml(
            check,
            &yaml.replace(
                r#"{ bits: "9:0", reserved: true }"#,
                r#"{ bits: "7:0", reserved: true }"#,
            ),
        );
        assert_eq!(found.len(), 3, "{found:#?}");
        assert!(found[0].message.starts_with("bit 15 (`command_enabled`)"));
        assert!(found[1].message.starts_with("bits 14-11 (`reserved`)"));
    }
}
