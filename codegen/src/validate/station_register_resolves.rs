//! Check: the register said to hold the station number (`addressing.register`) is a
//! described register that can be written and holds station numbers: a plain number (no
//! bit field, no code table, no scale) whose range, where it gives one, lies within the
//! drive's `addressing`.

use crate::diagnostics::Diagnostics;
use crate::parse::model::BoundModel;
use crate::validate::ranges::RegisterIndex;
use crate::validate::Context;
use vfd_runtime::Access;

/// `addressing.register` names a writable register of station numbers.
pub fn station_register_resolves(drive: &Context, out: &mut Diagnostics) {
    let addressing = &drive.model.addressing;
    let Some(name) = &addressing.register else {
        return;
    };
    let path = "addressing.register";
    let mut problem = |message: String, hint: &str| {
        out.push(drive.source.error(path, message).hint(hint));
    };
    let index = RegisterIndex::new(&drive.model);
    let Some(register) = index.find(name) else {
        problem(
            format!("no register `{name}`"),
            "name the register holding the station number by its code or id",
        );
        return;
    };
    if register.access == Some(Access::ReadOnly) {
        problem(
            format!("register {} is read-only: the station could not be set over the link", register.code),
            "name the station-number parameter, or leave `register` out when the station is set on the panel only",
        );
    }
    if register.bitfield.is_some()
        || register.code_table.is_some()
        || register.scale.is_some_and(|s| s != 1.0)
    {
        problem(
            format!(
                "register {} does not hold a plain station number",
                register.code
            ),
            "a station-number register holds the number itself: no bit field, code table or scale",
        );
    }
    if let Some(range) = &register.range {
        let outside = |bound: &BoundModel| match bound {
            BoundModel::Number(value) => {
                *value < f64::from(addressing.min) || *value > f64::from(addressing.max)
            }
            BoundModel::Register(_) => false,
        };
        if outside(&range.min) || outside(&range.max) {
            problem(
                format!(
                    "register {}'s range reaches beyond the station numbers {}-{} (`addressing`)",
                    register.code, addressing.min, addressing.max
                ),
                "the register's range and `addressing` are the same station numbers: check both against the manual",
            );
        }
    }
}

#[cfg(test)]
mod tests {
    use super::station_register_resolves as check;
    use crate::validate::testing::{check_yaml, only, valid_with};

    const STATION: &str = "  - { address: 0x0802, id: station, code: F802, name: Station, range: { min: 0, max: 31 }, default: 1, source: \"6\" }\n";

    fn drive(register: &str, station: &str) -> String {
        valid_with(&[
            (
                "  max: 31\n",
                &format!("  max: 31\n  register: {register}\n"),
            ),
            ("registers:\n", &format!("registers:\n{station}")),
        ])
    }

    #[test]
    fn accepts_a_writable_register_of_station_numbers() {
        assert!(check_yaml(check, &drive("F802", STATION)).is_empty());
    }

    #[test]
    fn reports_what_cannot_hold_the_station() {
        let found = check_yaml(check, &drive("F803", STATION));
        assert_eq!(only(&found).message, "no register `F803`");
        assert_eq!(only(&found).path, "addressing.register");
        let found = check_yaml(
            check,
            &drive("F802", &STATION.replace("max: 31 }", "max: 99 }")),
        );
        assert_eq!(
            only(&found).message,
            "register F802's range reaches beyond the station numbers 0-31 (`addressing`)"
        );
        let found = check_yaml(check, &drive("F601", STATION));
        assert_eq!(
            only(&found).message,
            "register F601 does not hold a plain station number"
        );
    }
}
