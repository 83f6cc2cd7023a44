//! Resolves register ranges: bounds that are numbers or that name another register
//! ("0.5~FH"), turned into static raw bounds the generated code checks before sending.

use crate::parse::model::{BoundModel, DriveFile, RegisterModel};

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

/// Finds a register by code (`FH`) or id (`maximum_frequency`).
pub fn find_register<'a>(drive: &'a DriveFile, name: &str) -> Option<&'a RegisterModel> {
    drive
        .registers
        .iter()
        .find(|r| r.code == name)
        .or_else(|| drive.registers.iter().find(|r| r.id == name))
}

/// The static value of a bound, in engineering units: a named register contributes its own
/// static bound at the same end (the widest value it can take).
pub fn resolve_bound(drive: &DriveFile, bound: &BoundModel, end: End) -> Result<f64, BoundProblem> {
    resolve_at_depth(drive, bound, end, 0)
}

fn resolve_at_depth(
    drive: &DriveFile,
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
            let register =
                find_register(drive, name).ok_or_else(|| BoundProblem::Unknown(name.clone()))?;
            let range = register
                .range
                .as_ref()
                .ok_or_else(|| BoundProblem::Unbounded(name.clone()))?;
            let next = match end {
                End::Min => &range.min,
                End::Max => &range.max,
            };
            resolve_at_depth(drive, next, end, depth + 1)
        }
    }
}

/// The engineering step of one raw count.
pub fn scale_of(register: &RegisterModel) -> f64 {
    register.scale.unwrap_or(1.0)
}

/// Converts an engineering value to raw counts, if it is a whole number of steps.
pub fn to_raw(register: &RegisterModel, value: f64) -> Option<i64> {
    let raw = value / scale_of(register);
    let rounded = raw.round();
    ((raw - rounded).abs() < 1e-6 && rounded.abs() < 1e12).then_some(rounded as i64)
}

/// The widest raw range the register's word or double word can hold.
pub fn word_limits(register: &RegisterModel) -> (i64, i64) {
    let double = register.data_type.as_deref() == Some("double_word");
    match (register.signed, double) {
        (true, true) => (i64::from(i32::MIN), i64::from(i32::MAX)),
        (false, true) => (0, i64::from(u32::MAX)),
        (true, false) => (i64::from(i16::MIN), i64::from(i16::MAX)),
        (false, false) => (0, i64::from(u16::MAX)),
    }
}

/// Static raw bounds and the names of run-time bounds, falling back to the whole word.
pub fn raw_range(
    drive: &DriveFile,
    register: &RegisterModel,
) -> (i64, i64, Option<String>, Option<String>) {
    let (word_min, word_max) = word_limits(register);
    let Some(range) = &register.range else {
        return (word_min, word_max, None, None);
    };
    let name = |bound: &BoundModel| match bound {
        BoundModel::Register(name) => Some(name.clone()),
        BoundModel::Number(_) => None,
    };
    let min = resolve_bound(drive, &range.min, End::Min)
        .ok()
        .and_then(|v| to_raw(register, v))
        .unwrap_or(word_min)
        .max(word_min);
    let max = resolve_bound(drive, &range.max, End::Max)
        .ok()
        .and_then(|v| to_raw(register, v))
        .unwrap_or(word_max)
        .min(word_max);
    (min, max, name(&range.min), name(&range.max))
}
