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
