//! Engineering units and the quantity types typed register APIs take and return.

use crate::error::ValueError;
pub use crate::info::decimals_of;
use crate::info::RegisterInfo;
use crate::kinds::DataType;
pub use crate::kinds::Unit;
use crate::register::RegisterValue;

/// Converts an engineering value to the raw value, checking finiteness and the register's range.
pub fn scaled_to_raw(value: f64, info: &'static RegisterInfo) -> Result<u32, ValueError> {
    if !value.is_finite() {
        return Err(ValueError::NotFinite {
            register: info,
            value,
        });
    }
    // A value taken besides the range (99999) has its own raw word (FFFFh).
    if let Some(special) = info.special_value(value) {
        return Ok(special.raw);
    }
    let raw = (value / info.scale).round();
    if raw < info.raw_min as f64 || raw > info.raw_max as f64 {
        return Err(ValueError::OutOfRange {
            register: info,
            value,
            min: rounded(info.raw_min as f64 * info.scale, info),
            max: rounded(info.raw_max as f64 * info.scale, info),
        });
    }
    // The range check above keeps `raw` within the register's byte, word or double word.
    let raw = raw as i64;
    Ok(match (info.signed, info.data_type) {
        (true, DataType::DoubleWord) => raw as i32 as u32,
        (true, DataType::Byte) => u32::from(raw as i8 as u8),
        (true, _) => u32::from(raw as i16 as u16),
        (false, _) => raw as u32,
    })
}

fn rounded(value: f64, info: &RegisterInfo) -> f64 {
    let factor = 10f64.powi(i32::from(info.decimals()));
    (value * factor).round() / factor
}

/// A raw value as a number: two's complement when `signed`, over 32 bits for double
/// words, 8 bits for bytes and 16 bits otherwise.
pub fn raw_to_number(raw: u32, signed: bool, data_type: DataType) -> f64 {
    match (signed, data_type) {
        (true, DataType::DoubleWord) => f64::from(raw as i32),
        (true, DataType::Byte) => f64::from(raw as u8 as i8),
        (true, _) => f64::from(raw as u16 as i16),
        (false, _) => f64::from(raw),
    }
}

/// Converts a raw value to its engineering value (the raw word of a special value, such as
/// FFFFh for 99999, to that value).
pub fn raw_to_scaled(raw: u32, info: &RegisterInfo) -> f64 {
    if let Some(special) = info.special_raw(raw) {
        return special.value;
    }
    let raw = raw_to_number(raw, info.signed, info.data_type);
    // Round away binary noise such as 0.1 * 3 = 0.30000000000000004.
    rounded(raw * info.scale, info)
}

macro_rules! quantity {
    ($(#[$doc:meta])* $name:ident, $unit:expr) => {
        $(#[$doc])*
        #[derive(Debug, Clone, Copy, PartialEq, PartialOrd, Default)]
        pub struct $name(pub f64);

        impl $name {
            /// The unit of this quantity.
            pub const UNIT: Unit = $unit;
        }

        impl std::fmt::Display for $name {
            fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                write!(f, "{} {}", self.0, $unit.symbol())
            }
        }

        impl RegisterValue for $name {
            fn to_raw(&self, info: &'static RegisterInfo) -> Result<u32, ValueError> {
                scaled_to_raw(self.0, info)
            }
            fn from_raw(raw: u32, info: &'static RegisterInfo) -> Result<Self, ValueError> {
                Ok($name(raw_to_scaled(raw, info)))
            }
        }
    };
}

quantity!(
    /// A frequency in hertz.
    Hertz,
    Unit::Hertz
);
quantity!(
    /// A time in seconds.
    Seconds,
    Unit::Second
);
quantity!(
    /// A ratio in percent.
    Percent,
    Unit::Percent
);
quantity!(
    /// A current in amperes.
    Amperes,
    Unit::Ampere
);
quantity!(
    /// A voltage in volts.
    Volts,
    Unit::Volt
);
quantity!(
    /// A time in hours.
    Hours,
    Unit::Hour
);
quantity!(
    /// A power in kilowatts.
    Kilowatts,
    Unit::Kilowatt
);
quantity!(
    /// A speed in revolutions per minute.
    Rpm,
    Unit::Rpm
);

/// Plain scaled numbers (no unit, scale other than 1).
impl RegisterValue for f64 {
    fn to_raw(&self, info: &'static RegisterInfo) -> Result<u32, ValueError> {
        scaled_to_raw(*self, info)
    }
    fn from_raw(raw: u32, info: &'static RegisterInfo) -> Result<Self, ValueError> {
        Ok(raw_to_scaled(raw, info))
    }
}

/// Raw words (no unit, scale 1), range-checked.
impl RegisterValue for u16 {
    fn to_raw(&self, info: &'static RegisterInfo) -> Result<u32, ValueError> {
        scaled_to_raw(f64::from(*self), info)
    }
    fn from_raw(raw: u32, _info: &'static RegisterInfo) -> Result<Self, ValueError> {
        Ok(raw as u16)
    }
}

/// Signed raw words (no unit, scale 1), range-checked.
impl RegisterValue for i16 {
    fn to_raw(&self, info: &'static RegisterInfo) -> Result<u32, ValueError> {
        scaled_to_raw(f64::from(*self), info)
    }
    fn from_raw(raw: u32, _info: &'static RegisterInfo) -> Result<Self, ValueError> {
        Ok(raw as u16 as i16)
    }
}

/// Raw double words (no unit, scale 1), range-checked.
impl RegisterValue for u32 {
    fn to_raw(&self, info: &'static RegisterInfo) -> Result<u32, ValueError> {
        scaled_to_raw(f64::from(*self), info)
    }
    fn from_raw(raw: u32, _info: &'static RegisterInfo) -> Result<Self, ValueError> {
        Ok(raw)
    }
}

/// Signed raw double words (no unit, scale 1), range-checked.
impl RegisterValue for i32 {
    fn to_raw(&self, info: &'static RegisterInfo) -> Result<u32, ValueError> {
        scaled_to_raw(f64::from(*self), info)
    }
    fn from_raw(raw: u32, _info: &'static RegisterInfo) -> Result<Self, ValueError> {
        Ok(raw as i32)
    }
}

/// Text parameters: read as text; writing text is not supported by the runtime.
impl RegisterValue for String {
    fn to_raw(&self, info: &'static RegisterInfo) -> Result<u32, ValueError> {
        Err(ValueError::NotWritable { register: info })
    }
    fn from_raw(_raw: u32, info: &'static RegisterInfo) -> Result<Self, ValueError> {
        Err(ValueError::NotWritable { register: info })
    }
}

#[cfg(test)]
mod special_value_tests {
    use super::*;
    use crate::info::SpecialValue;

    /// A time-out of 0-999.8 s in 0.1 s steps that also takes 99999 ("no check") as FFFFh.
    static INTERVAL: RegisterInfo = RegisterInfo::new(0x0035, "07-09", "interval")
        .with_unit(Unit::Second, 0.1)
        .with_raw_range(0, 9998)
        .with_special_values(&[SpecialValue {
            value: 99999.0,
            raw: 0xFFFF,
            id: "no_check",
            name: "No time-out check",
        }]);

    #[test]
    fn a_special_value_has_its_own_raw_word_besides_the_range() {
        assert_eq!(Seconds(99999.0).to_raw(&INTERVAL).unwrap(), 0xFFFF);
        assert_eq!(
            Seconds::from_raw(0xFFFF, &INTERVAL).unwrap(),
            Seconds(99999.0)
        );
        assert_eq!(Seconds(999.8).to_raw(&INTERVAL).unwrap(), 9998);
        assert_eq!(Seconds::from_raw(9998, &INTERVAL).unwrap(), Seconds(999.8));
        // Values between the range and the special value are still refused.
        assert!(matches!(
            Seconds(1000.0).to_raw(&INTERVAL),
            Err(ValueError::OutOfRange { .. })
        ));
        assert_eq!(INTERVAL.special_raw(0xFFFF).map(|s| s.id), Some("no_check"));
        assert!(INTERVAL.special_raw(0xFFFE).is_none());
    }
}
