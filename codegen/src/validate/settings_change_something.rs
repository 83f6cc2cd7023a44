//! Warning: an example's `settings:` key that changes nothing: the register already holds
//! that value from the factory, or nothing the example's frames or the drive's models
//! depend on reads the register (the rehearsal against the virtual drive reads the
//! register the example's frames address).

use crate::diagnostics::Diagnostics;
use crate::frames::space_of;
use crate::parse::model::RegisterModel;
use crate::validate::{ranges, Context};
use vfd_runtime::Space;

/// Every assumed setting differs from the register's default and names a register
/// something reads: the register the example's frames address (the virtual drive's reply
/// reads it), a block-transfer selector or mode register of the example's protocol,
/// a register whose value chooses another's scale, the persistence selector, or the
/// register choosing the protocol's variant.
pub fn settings_change_something(drive: &Context, out: &mut Diagnostics) {
    let index = ranges::RegisterIndex::new(&drive.model);
    for (at, example) in drive.model.examples.iter().enumerate() {
        let mut read = read_registers(drive, &example.protocol);
        // The virtual drive answers the example's request from the register it addresses.
        let addressed = [&example.request, &example.reply]
            .into_iter()
            .flatten()
            .filter_map(|frame| frame.expect.register);
        for number in addressed {
            read.extend(drive.model.registers.iter().filter(|r| r.address == number));
        }
        for (name, value) in &example.settings {
            let Some(register) = index.find(name) else {
                continue; // Reported by examples_decode.
            };
            let path = format!("examples[{at}].settings.{name}");
            let code = &register.code;
            if register.default.is_some_and(|default| (default - value).abs() < 1e-9) {
                out.push(
                    drive
                        .source
                        .warning(&path, format!("{code} = {value} is its default: the setting changes nothing"))
                        .hint("a drive holds its default unless told otherwise; leave the key out (say in the description that the frames assume the factory setting, if that matters)"),
                );
                continue;
            }
            if !read.iter().any(|r| std::ptr::eq(*r, register)) {
                out.push(
                    drive
                        .source
                        .warning(&path, format!("nothing reads {code}: the setting changes nothing"))
                        .hint(format!("settings are read where they choose what the frames carry: the register the frames address, a block transfer's selectors and modes, a register's scale selector, the persistence selector, the protocol's variant register; {code} is none of these, so give the assumption in the description instead")),
                );
            }
        }
    }
}

/// The registers whose values the tools read for an example in `protocol`.
fn read_registers<'d>(drive: &'d Context, protocol: &str) -> Vec<&'d RegisterModel> {
    let index = ranges::RegisterIndex::new(&drive.model);
    let mut names: Vec<&str> = Vec::new();
    names.extend(
        drive
            .model
            .registers
            .iter()
            .filter_map(|r| r.scale_by.as_ref())
            .map(|s| s.register.as_str()),
    );
    names.extend(drive.model.persistence.as_ref().map(|p| p.selector.as_str()));
    names.extend(
        drive
            .model
            .protocols
            .iter()
            .filter(|p| p.id == protocol)
            .filter_map(|p| p.variant.as_ref())
            .map(|v| v.register.as_str()),
    );
    let mut read: Vec<&RegisterModel> = names.into_iter().filter_map(|n| index.find(n)).collect();
    let block = drive
        .protocols
        .iter()
        .find(|p| p.id == protocol)
        .and_then(|p| p.runtime.block.as_ref());
    if let Some(block) = block {
        let numbers = block
            .write
            .iter()
            .chain(block.read.iter())
            .map(|s| s.register)
            .chain(block.modes.iter().map(|m| m.register));
        for number in numbers {
            read.extend(drive.model.registers.iter().filter(|r| {
                r.address == u32::from(number) && space_of(r) == Space::Parameter
            }));
        }
    }
    read
}

#[cfg(test)]
mod tests {
    use super::settings_change_something as check;
    use crate::validate::testing::{assert_at, check_yaml, valid_with, VALID};

    fn with_settings(settings: &str) -> String {
        valid_with(&[(
            "    value: 80.0\n",
            &format!("    value: 80.0\n    settings: {{ {settings} }}\n"),
        )])
    }

    #[test]
    fn a_setting_at_its_default_is_warned_about() {
        let yaml = with_settings("F601: 1");
        let found = check_yaml(check, &yaml);
        assert_eq!(found.len(), 1, "{found:#?}");
        assert!(found[0].is_warning());
        assert_at(
            &found[0],
            &yaml,
            "examples[0].settings.F601",
            "F601 = 1 is its default: the setting changes nothing",
            "settings:",
        );
    }

    #[test]
    fn a_setting_nothing_reads_is_warned_about() {
        let yaml = with_settings("F601: 0");
        let found = check_yaml(check, &yaml);
        assert_eq!(found.len(), 1, "{found:#?}");
        assert_eq!(
            found[0].message,
            "nothing reads F601: the setting changes nothing"
        );
    }

    #[test]
    fn no_settings_no_warning() {
        assert!(check_yaml(check, VALID).is_empty());
    }
}
