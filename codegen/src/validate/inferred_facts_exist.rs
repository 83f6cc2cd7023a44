//! Check: a register marks as inferred only facts it states, each once.

use crate::diagnostics::Diagnostics;
use crate::parse::model::InferredFact;
use crate::validate::Context;

/// Every `inferred` entry names a fact the register has (a unit, scale, range or default
/// that is given, a while-running flag that is not `unknown`), and no entry is repeated.
pub fn inferred_facts_exist(drive: &Context, out: &mut Diagnostics) {
    for (index, register) in drive.model.registers.iter().enumerate() {
        for (position, fact) in register.inferred.iter().enumerate() {
            let path = format!("registers[{index}].inferred[{position}]");
            let missing = match fact {
                InferredFact::Unit => register.unit.is_none().then_some("unit"),
                InferredFact::Scale => register.scale.is_none().then_some("scale"),
                InferredFact::Range => register.range.is_none().then_some("range"),
                InferredFact::Default => register.default.is_none().then_some("default"),
                _ => None,
            };
            if *fact == InferredFact::WritableWhileRunning
                && register.writable_while_running.is_unknown()
            {
                out.push(
                    drive
                        .source
                        .error(
                            &path,
                            format!(
                                "`{}` marks writable_while_running as inferred but gives it as `unknown`",
                                register.code
                            ),
                        )
                        .hint("an unknown is not a reading: give `true` or `false` and keep the entry, or keep `unknown` and drop the entry"),
                );
            } else if let Some(key) = missing {
                out.push(
                    drive
                        .source
                        .error(
                            &path,
                            format!(
                                "`{}` marks its {key} as inferred but gives no `{key}`",
                                register.code
                            ),
                        )
                        .hint("mark only facts the register states; add the key or drop the entry"),
                );
            } else if register.inferred[..position].contains(fact) {
                out.push(
                    drive
                        .source
                        .error(
                            &path,
                            format!("`{}` lists an inferred fact twice", register.code),
                        )
                        .hint("list each inferred fact once"),
                );
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::inferred_facts_exist as check;
    use crate::validate::testing::{assert_at, check_yaml, only, valid_with, VALID};

    #[test]
    fn accepts_stated_facts() {
        assert!(check_yaml(check, VALID).is_empty());
        let yaml = valid_with(&[(
            "unit: s, scale: 0.1,",
            "unit: s, scale: 0.1, inferred: [unit, scale, writable_while_running],",
        )]);
        assert!(check_yaml(check, &yaml).is_empty());
    }

    #[test]
    fn reports_an_unknown_marked_as_inferred() {
        let yaml = valid_with(&[(
            "unit: s, scale: 0.1,",
            "unit: s, scale: 0.1, writable_while_running: unknown, inferred: [writable_while_running],",
        )]);
        let found = check_yaml(check, &yaml);
        assert_at(
            only(&found),
            &yaml,
            "registers[0].inferred[0]",
            "`Acc` marks writable_while_running as inferred but gives it as `unknown`",
            "code: Acc,",
        );
        let yaml = valid_with(&[(
            "unit: s, scale: 0.1,",
            "unit: s, scale: 0.1, writable_while_running: unknown,",
        )]);
        assert!(check_yaml(check, &yaml).is_empty());
    }

    #[test]
    fn reports_missing_and_repeated_facts() {
        let yaml = valid_with(&[("unit: s, scale: 0.1,", "inferred: [unit],")]);
        let found = check_yaml(check, &yaml);
        assert_at(
            only(&found),
            &yaml,
            "registers[0].inferred[0]",
            "`Acc` marks its unit as inferred but gives no `unit`",
            "code: Acc,",
        );
        let yaml = valid_with(&[(
            "unit: s, scale: 0.1,",
            "unit: s, scale: 0.1, inferred: [unit, unit],",
        )]);
        let found = check_yaml(check, &yaml);
        assert_at(
            only(&found),
            &yaml,
            "registers[0].inferred[1]",
            "`Acc` lists an inferred fact twice",
            "code: Acc,",
        );
    }
}
