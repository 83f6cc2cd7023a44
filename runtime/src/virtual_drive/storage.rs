//! Register memory of the virtual drive: RAM, EEPROM and the values in effect for
//! parameters that take effect only after a reset.

use crate::info::RegisterInfo;
use crate::kinds::{Space, TakesEffect};
use std::collections::HashMap;

/// A stored value's place: space, register number, register id, array index. The id
/// keeps apart two registers sharing a number (one read, the other written).
type Key = (Space, u16, &'static str, u16);

fn key(info: &RegisterInfo, index: u16) -> Key {
    (info.space, info.address, info.id, index)
}

/// Raw values in RAM and EEPROM, initialised from the description's defaults.
#[derive(Debug, Clone, Default)]
pub(crate) struct Storage {
    ram: HashMap<Key, u32>,
    eeprom: HashMap<Key, u32>,
    /// Values of `after_reset` parameters as they were at the last reset or power-up.
    in_effect: HashMap<Key, u32>,
}

/// The raw value a register holds in the virtual drive's factory state: its default, else
/// 0 when every range it can have (its own, and each scale another register may choose for
/// it) takes 0, else the lowest raw value all of them take (the VF-AS1's ACC, 0.1-6000 s
/// with no factory setting given, starts at 0.1 s), so that a fresh drive holds only values
/// it would accept and a backup of it restores onto it.
pub(crate) fn factory_raw(info: &RegisterInfo) -> u32 {
    if let Some(raw) = info.default_raw {
        return raw;
    }
    let mut ranges = vec![(info.raw_min, info.raw_max)];
    if let Some(by) = info.scale_by {
        ranges.extend(by.scales().map(|r| (r.raw_min, r.raw_max)));
    }
    let takes = |raw: i64| ranges.iter().all(|(min, max)| (*min..=*max).contains(&raw));
    let start = if takes(0) {
        0
    } else {
        ranges
            .iter()
            .map(|(min, _)| *min)
            .filter(|low| takes(*low))
            .min()
            .unwrap_or(info.raw_min.max(0))
    };
    // A negative start of a signed register is its two's complement in the register's width.
    let mask = if info.data_type.size() == 4 {
        u32::MAX
    } else {
        u32::from(u16::MAX)
    };
    (start as u32) & mask
}

impl Storage {
    /// Storage holding every register's factory value ([`factory_raw`]).
    pub(crate) fn new(registers: &[&RegisterInfo]) -> Storage {
        let mut eeprom = HashMap::new();
        for info in registers {
            for index in 0..u16::from(info.array_len.max(1)) {
                eeprom.insert(key(info, index), factory_raw(info));
            }
        }
        let mut storage = Storage {
            ram: eeprom.clone(),
            eeprom,
            in_effect: HashMap::new(),
        };
        storage.take_effect(registers);
        storage
    }

    /// The value in RAM (what a read returns).
    pub(crate) fn get(&self, info: &RegisterInfo, index: u16) -> u32 {
        self.ram.get(&key(info, index)).copied().unwrap_or(0)
    }

    /// The value in EEPROM (what RAM holds after a power cycle).
    pub(crate) fn get_eeprom(&self, info: &RegisterInfo, index: u16) -> u32 {
        self.eeprom.get(&key(info, index)).copied().unwrap_or(0)
    }

    /// The value the drive acts on: for `after_reset` parameters the value at the last
    /// reset, otherwise the value in RAM.
    pub(crate) fn in_effect(&self, info: &RegisterInfo, index: u16) -> u32 {
        match info.takes_effect {
            TakesEffect::AfterReset => self
                .in_effect
                .get(&key(info, index))
                .copied()
                .unwrap_or_else(|| self.get(info, index)),
            TakesEffect::Immediately => self.get(info, index),
        }
    }

    /// Stores `raw` in RAM, and in EEPROM too when `persistent`.
    pub(crate) fn set(&mut self, info: &RegisterInfo, index: u16, raw: u32, persistent: bool) {
        self.ram.insert(key(info, index), raw);
        if persistent {
            self.eeprom.insert(key(info, index), raw);
        }
    }

    /// A reset: `after_reset` parameters take their RAM values.
    pub(crate) fn take_effect(&mut self, registers: &[&RegisterInfo]) {
        for info in registers {
            if info.takes_effect == TakesEffect::AfterReset {
                for index in 0..u16::from(info.array_len.max(1)) {
                    let value = self.get(info, index);
                    self.in_effect.insert(key(info, index), value);
                }
            }
        }
    }

    /// Power off and on: RAM is reloaded from EEPROM.
    pub(crate) fn power_cycle(&mut self, registers: &[&RegisterInfo]) {
        self.ram = self.eeprom.clone();
        self.take_effect(registers);
    }
}
