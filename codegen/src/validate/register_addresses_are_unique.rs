//! Check: no two registers share an address.

use crate::diagnostics::Diagnostics;
use crate::validate::Context;
use std::collections::HashMap;

/// No two registers share an address.
pub fn register_addresses_are_unique(drive: &Context, out: &mut Diagnostics) {
    let mut seen: HashMap<u32, usize> = HashMap::new();
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
        if let Some(first) = seen.insert(register.address, index) {
            let other = &drive.model.registers[first];
            out.push(
                drive
                    .source
                    .error(&path, format!("duplicate register address {:04X}h: `{}` (registers[{first}]) already uses it", register.address, other.id))
                    .hint("each communication number may be described once; check the manual's table for a typo"),
            );
        }
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
