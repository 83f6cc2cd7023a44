//! Combinations of register values a manual forbids (the DV1: two stop bits with parity in
//! the Eaton protocol), as data the code generator builds from the description's
//! `forbidden_combinations:`, checked by `DriveInfo::check_combinations`. The virtual drive
//! refuses a write that would make one, and tools check a write against the values they
//! read first. Nothing here names a drive or a register.

use crate::info::RegisterInfo;

/// One condition of a forbidden combination: the register holds one of these raw words.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct Condition {
    /// The register's code.
    pub register: &'static str,
    /// The raw words that fulfil the condition.
    pub raw: &'static [u32],
}

/// Values of several registers that must not hold together.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct ForbiddenCombination {
    /// Identifier in the drive file (`two_stop_bits_with_parity`).
    pub id: &'static str,
    /// The manual's rule, in its words.
    pub rule: &'static str,
    /// What the rule says, in English.
    pub meaning: &'static str,
    /// Where the manual says it.
    pub source: &'static str,
    /// Every condition holds at once: the combination is forbidden.
    pub when: &'static [Condition],
}

impl ForbiddenCombination {
    /// Whether one of its conditions is about `register` (by code).
    pub fn involves(&self, register: &RegisterInfo) -> bool {
        self.when.iter().any(|c| c.register == register.code)
    }

    /// Whether every condition holds for the raw words `raw_of` gives (by register code);
    /// a register it gives no word for fulfils no condition.
    pub fn holds(&self, raw_of: impl Fn(&str) -> Option<u32>) -> bool {
        self.when
            .iter()
            .all(|c| raw_of(c.register).is_some_and(|raw| c.raw.contains(&raw)))
    }
}

/// A write that would make a combination of values the manual forbids.
#[derive(Debug, Clone, Copy, thiserror::Error)]
#[error(
    "writing {raw} to {} would make a combination the manual forbids ({}): {} The manual: \"{}\" ({})",
    register.label(), combination.id, combination.meaning, combination.rule, combination.source
)]
pub struct CombinationError {
    /// The register written.
    pub register: &'static RegisterInfo,
    /// The raw word that would be written.
    pub raw: u32,
    /// The rule it breaks.
    pub combination: &'static ForbiddenCombination,
}

#[cfg(test)]
mod tests {
    use super::*;

    static RULE: ForbiddenCombination = ForbiddenCombination {
        id: "two_stop_bits_with_parity",
        rule: "如果 07-04 设定为 1 选择两位停止位，请务必把 07-05 设定为 0",
        meaning: "Two stop bits need no parity.",
        source: "note 4",
        when: &[
            Condition {
                register: "07-04",
                raw: &[1],
            },
            Condition {
                register: "07-05",
                raw: &[1, 2],
            },
        ],
    };

    #[test]
    fn a_combination_holds_only_when_every_condition_does() {
        let values = |stop: u32, parity: u32| {
            move |code: &str| match code {
                "07-04" => Some(stop),
                "07-05" => Some(parity),
                _ => None,
            }
        };
        assert!(RULE.holds(values(1, 2)));
        assert!(!RULE.holds(values(1, 0)));
        assert!(!RULE.holds(values(0, 2)));
        assert!(!RULE.holds(|_| None));
    }
}
