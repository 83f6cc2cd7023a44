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

impl Storage {
    /// Storage holding every register's default (0 where the manual gives none).
    pub(crate) fn new(registers: &[&RegisterInfo]) -> Storage {
        let mut eeprom = HashMap::new();
        for info in registers {
            for index in 0..u16::from(info.array_len.max(1)) {
                eeprom.insert(key(info, index), info.default_raw.unwrap_or(0));
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
