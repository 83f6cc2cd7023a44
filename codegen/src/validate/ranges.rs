//! Resolves register ranges: bounds that are numbers or that name another register
//! ("0.5~FH"), turned into static raw bounds the generated code checks before sending.

use crate::parse::model::{BoundModel, DriveFile, RegisterModel};
use std::collections::HashMap;

/// Which end of a range.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum End {
    /// Lower bound.
    Min,
    /// Upper bound.
    Max,
}

/// Why a bound cannot be resolved.
#[derive(Debug, Clone, PartialEq)]
pub enum BoundProblem {
    /// No register has that code or id.
    Unknown(String),
    /// The named register has no range of its own to take a static bound from.
    Unbounded(String),
    /// Bounds refer to each other in a circle.
    Cycle(String),
}

/// Finds a register by code (`FH`) or id (`maximum_frequency`): a one-off look-up, as
/// the tests make. A pass over every register builds one [`RegisterIndex`] instead.
#[cfg(test)]
pub fn find_register<'a>(drive: &'a DriveFile, name: &str) -> Option<&'a RegisterModel> {
    RegisterIndex::new(drive).find(name)
}

/// [`RegisterIndex::resolve_bound`] as a one-off.
#[cfg(test)]
pub fn resolve_bound(drive: &DriveFile, bound: &BoundModel, end: End) -> Result<f64, BoundProblem> {
    RegisterIndex::new(drive).resolve_bound(bound, end)
}

/// [`RegisterIndex::raw_range`] as a one-off.
#[cfg(test)]
pub fn raw_range(drive: &DriveFile, register: &RegisterModel) -> (i64, i64) {
    RegisterIndex::new(drive).raw_range(register)
}

/// Registers by code (`FH`) and by id (`maximum_frequency`), built once so that a pass over
/// every register looks names up in constant time.
pub struct RegisterIndex<'a> {
    registers: &'a [RegisterModel],
    code_tables: &'a [crate::parse::model::CodeTableModel],
    by_code: HashMap<&'a str, usize>,
    by_id: HashMap<&'a str, usize>,
    by_alias: HashMap<&'a str, usize>,
}

impl<'a> RegisterIndex<'a> {
    /// Indexes the drive's registers.
    pub fn new(drive: &'a DriveFile) -> RegisterIndex<'a> {
        let registers = drive.registers.as_slice();
        let mut by_code = HashMap::with_capacity(registers.len());
        let mut by_id = HashMap::with_capacity(registers.len());
        let mut by_alias = HashMap::new();
        for (index, register) in registers.iter().enumerate() {
            by_code.entry(register.code.as_str()).or_insert(index);
            by_id.entry(register.id.as_str()).or_insert(index);
            for alias in &register.aliases {
                by_alias.entry(alias.as_str()).or_insert(index);
            }
        }
        RegisterIndex {
            registers,
            code_tables: &drive.codes,
            by_code,
            by_id,
            by_alias,
        }
    }

    /// The first register with this code, else the first with this id, else the one with
    /// this alias (`P.195`).
    pub fn find(&self, name: &str) -> Option<&'a RegisterModel> {
        self.by_code
            .get(name)
            .or_else(|| self.by_id.get(name))
            .or_else(|| self.by_alias.get(name))
            .map(|&index| &self.registers[index])
    }

    /// The static value of a bound, in engineering units: a named register contributes its
    /// own static bound at the same end (the widest value it can take).
    pub fn resolve_bound(&self, bound: &BoundModel, end: End) -> Result<f64, BoundProblem> {
        self.resolve_at_depth(bound, end, 0)
    }

    fn resolve_at_depth(
        &self,
        bound: &BoundModel,
        end: End,
        depth: usize,
    ) -> Result<f64, BoundProblem> {
        match bound {
            BoundModel::Number(value) => Ok(*value),
            BoundModel::Register(name) => {
                if depth > 8 {
                    return Err(BoundProblem::Cycle(name.clone()));
                }
                let register = self
                    .find(name)
                    .ok_or_else(|| BoundProblem::Unknown(name.clone()))?;
                let range = register
                    .range
                    .as_ref()
                    .ok_or_else(|| BoundProblem::Unbounded(name.clone()))?;
                let next = match end {
                    End::Min => &range.min,
                    End::Max => &range.max,
                };
                self.resolve_at_depth(next, end, depth + 1)
            }
        }
    }

    /// Static raw bounds: the range's; without a range, the lowest and highest value of an
    /// exhaustive code table the register uses; else the whole word.
    pub fn raw_range(&self, register: &RegisterModel) -> (i64, i64) {
        let (word_min, word_max) = word_limits(register);
        let Some(range) = &register.range else {
            let table = register
                .code_table
                .as_ref()
                .and_then(|id| self.code_tables.iter().find(|t| &t.id == id))
                .filter(|table| table.exhaustive && !table.values.is_empty());
            return match table {
                Some(table) => {
                    let values = table.values.iter().map(|v| i64::from(v.value));
                    let low = values.clone().min().unwrap_or(word_min);
                    let high = values.max().unwrap_or(word_max);
                    (low.max(word_min), high.min(word_max))
                }
                None => (word_min, word_max),
            };
        };
        let min = self
            .resolve_bound(&range.min, End::Min)
            .ok()
            .and_then(|v| to_raw(register, v))
            .unwrap_or(word_min)
            .max(word_min);
        let max = self
            .resolve_bound(&range.max, End::Max)
            .ok()
            .and_then(|v| to_raw(register, v))
            .unwrap_or(word_max)
            .min(word_max);
        (min, max)
    }
}

/// The engineering step of one raw count.
pub fn scale_of(register: &RegisterModel) -> f64 {
    register.scale.unwrap_or(1.0)
}

/// Whether the register's scale is a positive number, so that its values can be judged in
/// steps. A scale that is not is reported once, by `scales_are_positive`; the checks of the
/// register's bounds, default and example values leave the register out rather than report
/// the same cause again for each value.
pub fn has_sound_scale(register: &RegisterModel) -> bool {
    let scale = scale_of(register);
    scale.is_finite() && scale > 0.0
}

/// Converts an engineering value to raw counts, if it is a whole number of steps.
pub fn to_raw(register: &RegisterModel, value: f64) -> Option<i64> {
    let raw = value / scale_of(register);
    let rounded = raw.round();
    ((raw - rounded).abs() < 1e-6 && rounded.abs() < 1e12).then_some(rounded as i64)
}

/// The widest raw range the register's word or double word can hold.
pub fn word_limits(register: &RegisterModel) -> (i64, i64) {
    register
        .data_type
        .unwrap_or(vfd_runtime::DataType::Word)
        .raw_limits(register.signed)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::validate::testing::{context, valid_with, VALID};

    fn named(name: &str) -> BoundModel {
        BoundModel::Register(name.to_owned())
    }

    #[test]
    fn finds_registers_by_code_before_id() {
        let drive = context(VALID).model;
        assert_eq!(find_register(&drive, "FH").map(|r| r.address), Some(0x11));
        assert_eq!(
            find_register(&drive, "maximum_frequency").map(|r| r.address),
            Some(0x11)
        );
        assert!(find_register(&drive, "fh").is_none());
        // A code wins over another register's id.
        let drive = context(&valid_with(&[("code: Acc,", "code: command,")])).model;
        assert_eq!(
            find_register(&drive, "command").map(|r| r.address),
            Some(0x09)
        );
    }

    #[test]
    fn resolves_numbers_and_named_bounds() {
        let drive = context(VALID).model;
        assert_eq!(
            resolve_bound(&drive, &BoundModel::Number(2.5), End::Min),
            Ok(2.5)
        );
        assert_eq!(resolve_bound(&drive, &named("FH"), End::Max), Ok(320.0));
        assert_eq!(resolve_bound(&drive, &named("FH"), End::Min), Ok(30.0));
        // Through UL (max: FH) to FH's maximum; UL's own minimum is a number.
        assert_eq!(resolve_bound(&drive, &named("UL"), End::Max), Ok(320.0));
        assert_eq!(
            resolve_bound(&drive, &named("upper_limit_frequency"), End::Min),
            Ok(0.5)
        );
    }

    #[test]
    fn reports_unknown_unbounded_and_circular_bounds() {
        let drive = context(VALID).model;
        assert_eq!(
            resolve_bound(&drive, &named("XX"), End::Max),
            Err(BoundProblem::Unknown("XX".to_owned()))
        );
        assert_eq!(
            resolve_bound(&drive, &named("F601"), End::Max),
            Err(BoundProblem::Unbounded("F601".to_owned()))
        );
        let drive = context(&valid_with(&[(
            "min: 30.0, max: 320.0",
            "min: 30.0, max: UL",
        )]))
        .model;
        assert!(matches!(
            resolve_bound(&drive, &named("UL"), End::Max),
            Err(BoundProblem::Cycle(_))
        ));
        // The other end of the same registers is numeric, so it still resolves.
        assert_eq!(resolve_bound(&drive, &named("UL"), End::Min), Ok(0.5));
    }

    #[test]
    fn converts_to_whole_raw_steps() {
        let drive = context(VALID).model;
        let frequency = &drive.registers[1];
        assert_eq!(scale_of(frequency), 0.01);
        assert_eq!(to_raw(frequency, 80.0), Some(8000));
        assert_eq!(to_raw(frequency, 0.29), Some(29));
        assert_eq!(to_raw(frequency, 0.005), None);
        assert_eq!(to_raw(frequency, 1e20), None);
        assert_eq!(scale_of(&drive.registers[3]), 1.0);
    }

    #[test]
    fn word_limits_follow_sign_and_width() {
        let yaml = valid_with(&[(
            "code: F601, name: Parity,",
            "code: F601, name: Parity, signed: true,",
        )]);
        let drive = context(&yaml).model;
        assert_eq!(word_limits(&drive.registers[1]), (0, 65535));
        assert_eq!(word_limits(&drive.registers[3]), (-32768, 32767));
        let yaml = valid_with(&[(
            "code: F601, name: Parity,",
            "code: F601, name: Parity, data_type: double_word,",
        )]);
        let drive = context(&yaml).model;
        assert_eq!(word_limits(&drive.registers[3]), (0, i64::from(u32::MAX)));
    }

    #[test]
    fn raw_ranges_take_static_bounds() {
        let drive = context(VALID).model;
        assert_eq!(raw_range(&drive, &drive.registers[2]), (50, 32000));
        // No range, but an exhaustive code table (parity: 0 to 2).
        let (low, high) = raw_range(&drive, &drive.registers[3]);
        assert_eq!(low, 0);
        assert!(high < 65535, "{high}");
        // An unresolvable bound falls back to the word's limit.
        let drive = context(&valid_with(&[("max: FH }", "max: XX }")])).model;
        assert_eq!(raw_range(&drive, &drive.registers[2]), (50, 65535));
    }
}
