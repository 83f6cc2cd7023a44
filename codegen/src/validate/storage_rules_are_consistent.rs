//! Check: a register's storage rule is one rule: `ram_only` (the persistent command is
//! refused) or `persistent_write_to_ram` (it is accepted, the value kept in RAM), on a
//! register that can be written.

use crate::diagnostics::Diagnostics;
use crate::validate::Context;
use vfd_runtime::Access;

/// `persistent_write_to_ram` is neither combined with `ram_only` nor put on a register that
/// cannot be written.
pub fn storage_rules_are_consistent(drive: &Context, out: &mut Diagnostics) {
    for (index, register) in drive.model.registers.iter().enumerate() {
        if !register.persistent_write_to_ram {
            continue;
        }
        let path = format!("registers[{index}].persistent_write_to_ram");
        if register.ram_only {
            out.push(
                drive
                    .source
                    .error(
                        &path,
                        format!(
                            "register {} is both `ram_only` (the persistent command is refused) and `persistent_write_to_ram` (it is accepted, the value kept in RAM)",
                            register.code
                        ),
                    )
                    .hint("keep the one the manual shows: `persistent_write_to_ram` when its example shows the persistent write accepted, `ram_only` when the drive refuses it"),
            );
        }
        if register.access == Some(Access::ReadOnly) {
            out.push(
                drive
                    .source
                    .error(
                        &path,
                        format!(
                            "register {} is read-only: no write is stored",
                            register.code
                        ),
                    )
                    .hint("leave `persistent_write_to_ram` out, or correct `access`"),
            );
        }
    }
}

#[cfg(test)]
mod tests {
    use super::storage_rules_are_consistent as check;
    use crate::validate::testing::{check_yaml, valid_with, VALID};

    #[test]
    fn accepts_a_drive_without_the_rule() {
        assert!(check_yaml(check, VALID).is_empty());
    }

    #[test]
    fn reports_the_rule_with_ram_only() {
        let yaml = valid_with(&[(
            "ram_only: true,",
            "ram_only: true, persistent_write_to_ram: true,",
        )]);
        let found = check_yaml(check, &yaml);
        assert_eq!(found.len(), 1, "{found:#?}");
        assert!(found[0].message.contains("both `ram_only`"), "{found:#?}");
    }
}
