//! Check: no two registers share an address in one numbering (`space`), except one
//! read-only and one write-only register (one address read as one thing and written as
//! another, the DV1's 1001h). A coil and a parameter may share a number (the WJ200's coil
//! 0001h and holding register 0001h): Modbus reaches them by different functions.

use crate::diagnostics::Diagnostics;
use crate::validate::Context;
use std::collections::HashMap;
use vfd_runtime::Access;

/// No two registers of one numbering (`space`) share an address, unless one is
/// `read-only` and the other `write-only`: a read then means the first, a write the second.
pub fn register_addresses_are_unique(drive: &Context, out: &mut Diagnostics) {
    let mut seen: HashMap<(vfd_runtime::Space, u32), Vec<usize>> = HashMap::new();
    for (index, register) in drive.model.registers.iter().enumerate() {
        let path = format!("registers[{index}].address");
        if register.address > 0xFFFF {
            out.push(
                drive
                    .source
                    .error(
                        &path,
                        format!("address {:#X} does not fit in 16 bits", register.address),
                    )
                    .hint("communication numbers run from 0x0000 to 0xFFFF"),
            );
        }
        let space = register.space.unwrap_or(vfd_runtime::Space::Parameter);
        let earlier = seen.entry((space, register.address)).or_default();
        if let Some(&first) = earlier.first() {
            let other = &drive.model.registers[first];
            let access =
                |r: &crate::parse::model::RegisterModel| r.access.unwrap_or(Access::ReadWrite);
            let pair = [access(other), access(register)];
            let by_direction = earlier.len() == 1
                && (pair == [Access::ReadOnly, Access::WriteOnly]
                    || pair == [Access::WriteOnly, Access::ReadOnly]);
            if !by_direction {
                out.push(
                    drive
                        .source
                        .error(&path, format!("duplicate register address {:04X}h: `{}` (registers[{first}]) already uses it", register.address, other.id))
                        .hint("each communication number may be described once; check the manual's table for a typo. Two registers may share an address only when one is `access: read-only` and the other `access: write-only` (read as one thing, written as another)"),
                );
            }
        }
        earlier.push(index);
    }
}

#[cfg(test)]
mod tests {
    use super::register_addresses_are_unique as check;
    use crate::validate::testing::{assert_at, assert_column, check_yaml, only, valid_with, VALID};

    #[test]
    fn accepts_distinct_addresses() {
        assert!(check_yaml(check, VALID).is_empty());
    }

    #[test]
    fn reports_the_second_register_at_an_address() {
        let yaml = valid_with(&[("0x0012, id: upper", "0x0011, id: upper")]);
        let found = check_yaml(check, &yaml);
        let diagnostic = only(&found);
        assert_at(
            diagnostic,
            &yaml,
            "registers[2].address",
            "duplicate register address 0011h: `maximum_frequency` (registers[1]) already uses it",
            "upper_limit_frequency",
        );
        assert_column(diagnostic, &yaml, "0x0011, id: upper");
    }

    #[test]
    fn accepts_a_coil_and_a_parameter_with_one_number() {
        let yaml = valid_with(&[(
            "  - { address: 0x0011, id: maximum_frequency",
            "  - { space: coil, address: 0x0011, id: run_coil, code: C11, name: Run, data_type: bit, source: \"7.1\" }\n  - { address: 0x0011, id: maximum_frequency",
        )]);
        assert!(check_yaml(check, &yaml).is_empty());
    }

    #[test]
    fn accepts_a_read_only_and_a_write_only_register_at_one_address() {
        let yaml = valid_with(&[(
            "bitfield: command_word, ram_only: true, source: \"7.1\" }",
            "bitfield: command_word, access: write-only, ram_only: true, source: \"7.1\" }\n  - { address: 0xFA00, id: status, code: FA00R, name: Status, access: read-only, source: \"7.1\" }",
        )]);
        assert!(check_yaml(check, &yaml).is_empty());
    }

    #[test]
    fn reports_a_shared_address_both_directions_can_reach() {
        // A write-only and a read-write register: a write would mean either.
        let yaml = valid_with(&[(
            "bitfield: command_word, ram_only: true, source: \"7.1\" }",
            "bitfield: command_word, access: write-only, ram_only: true, source: \"7.1\" }\n  - { address: 0xFA00, id: status, code: FA00R, name: Status, source: \"7.1\" }",
        )]);
        let found = check_yaml(check, &yaml);
        let diagnostic = only(&found);
        assert_eq!(diagnostic.path, "registers[5].address");
        assert_eq!(
            diagnostic.message,
            "duplicate register address FA00h: `command` (registers[4]) already uses it"
        );
        // A third register at an address read one way and written the other.
        let yaml = valid_with(&[(
            "bitfield: command_word, ram_only: true, source: \"7.1\" }",
            "bitfield: command_word, access: write-only, ram_only: true, source: \"7.1\" }\n  - { address: 0xFA00, id: status, code: FA00R, name: Status, access: read-only, source: \"7.1\" }\n  - { address: 0xFA00, id: other, code: FA00W, name: Other, access: write-only, source: \"7.1\" }",
        )]);
        let found = check_yaml(check, &yaml);
        assert_eq!(only(&found).path, "registers[6].address");
    }

    #[test]
    fn reports_an_address_beyond_16_bits() {
        let yaml = valid_with(&[("0xFA00, id: command,", "0x1FA00, id: command,")]);
        let found = check_yaml(check, &yaml);
        assert_at(
            only(&found),
            &yaml,
            "registers[4].address",
            "address 0x1FA00 does not fit in 16 bits",
            "id: command,",
        );
    }
}
