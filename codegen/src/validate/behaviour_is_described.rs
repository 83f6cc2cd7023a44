//! Warning: the drive has no `behaviour:` section, so the virtual drive built from it never
//! answers a refusal and never runs its motor.

use crate::diagnostics::Diagnostics;
use crate::validate::Context;

/// A drive without `behaviour:` is valid, but its virtual drive (`vfd sim`, the tests'
/// `VirtualDrive`) is silent on every refusal and never runs.
pub fn behaviour_is_described(drive: &Context, out: &mut Diagnostics) {
    if drive.model.behaviour.is_some() {
        return;
    }
    out.push(
        drive
            .source
            .warning("drive", "the drive has no `behaviour:` section")
            .hint("without it the virtual drive built from this file (`vfd sim`, `VirtualDrive`) stays silent on every request it refuses (no error reply: it knows no error code for a refusal) and its motor never runs (no command word, no frequency command, no status bits); describe them under `behaviour:` (drives/README.md, \"The behaviour model\")"),
    );
}

#[cfg(test)]
mod tests {
    use super::behaviour_is_described as check;
    use crate::validate::testing::{assert_at, check_yaml, only, VALID};

    #[test]
    fn a_drive_without_behaviour_is_warned_about_at_its_drive_key() {
        let found = check_yaml(check, VALID);
        let warning = only(&found);
        assert!(warning.is_warning());
        assert_at(
            warning,
            VALID,
            "drive",
            "the drive has no `behaviour:` section",
            "drive:",
        );
        assert!(warning.hint.as_deref().unwrap().contains("silent"));
    }
}
