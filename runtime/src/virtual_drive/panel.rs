//! What the operator panel sets and shows, for tests and tools: the station number, the
//! serial port served, registers' raw values in RAM, in EEPROM and in effect, settings made
//! before power-on, and the protocol variant selected; and the register a name means on the
//! port served, at its present scale.

use super::VirtualDrive;
use crate::drive::DriveInfo;
use crate::info::RegisterInfo;
use crate::protocol::Protocol;

impl VirtualDrive {
    /// The described drive.
    pub fn drive(&self) -> &'static DriveInfo {
        self.drive
    }

    /// Its station number.
    pub fn address(&self) -> u8 {
        self.address
    }

    /// Sets its station number (and the register holding it, where the description names
    /// one: `addressing.register`, as if set on the panel before power-on).
    pub fn set_address(&mut self, address: u8) {
        self.address = address;
        self.set_station_register(address);
    }

    /// The serial port it serves, for a drive with several (`None`: not chosen).
    pub fn port(&self) -> Option<&'static str> {
        self.port
    }

    /// Serves the port `name` (an id or English name of the description's `ports`): the
    /// command word and frequency command of that port act. Returns false, changing
    /// nothing, when the drive has no such port.
    pub fn set_port(&mut self, name: &str) -> bool {
        match self.drive.ports.and_then(|ports| ports.port(name)) {
            Some(port) => {
                self.port = Some(port.id);
                self.refresh();
                true
            }
            None => false,
        }
    }

    /// The id of the register `id` names on the port served (its port's copy).
    pub(crate) fn served(&self, id: &'static str) -> &'static str {
        match (self.port, self.drive.register(id)) {
            (Some(port), Some(info)) => self.drive.on_port(info, port).id,
            _ => id,
        }
    }

    /// `info` as it is with its scale selector's present value (itself when its scale is
    /// fixed).
    pub(crate) fn scaled(&self, info: &'static RegisterInfo) -> &'static RegisterInfo {
        let Some(scale_by) = info.scale_by else {
            return info;
        };
        let selector = self
            .drive
            .register(scale_by.register)
            .map(|selector| self.storage.in_effect(selector, 0));
        info.scaled_for(selector)
    }

    /// The raw value in RAM of the register with this code or id (element 0 of arrays).
    pub fn raw(&self, name: &str) -> Option<u32> {
        let info = self.drive.register(name)?;
        Some(self.storage.get(info, 0))
    }

    /// The raw value in EEPROM of the register with this code or id (element 0 of arrays):
    /// what RAM holds after a power cycle. Writes go there when they are persistent (a
    /// persistent command, or the drive's persistence selector choosing RAM and EEPROM).
    pub fn eeprom_raw(&self, name: &str) -> Option<u32> {
        let info = self.drive.register(name)?;
        Some(self.storage.get_eeprom(info, 0))
    }

    /// The raw value the drive acts on: for parameters that take effect after a reset, the
    /// value at the last reset.
    pub fn raw_in_effect(&self, name: &str) -> Option<u32> {
        let info = self.drive.register(name)?;
        Some(self.storage.in_effect(info, 0))
    }

    /// Sets a register as the operator panel would (no checks, RAM only). Returns false
    /// when there is no such register.
    pub fn set_raw(&mut self, name: &str, raw: u32) -> bool {
        let Some(info) = self.drive.register(name) else {
            return false;
        };
        self.storage.set(info, 0, raw, false);
        self.refresh();
        true
    }

    /// Sets a register as it stood at power-on (no checks): in RAM and EEPROM and in effect
    /// at once, as a setting made on the panel before the drive was switched on (a setting
    /// that takes effect after a reset has taken it). Returns false when there is no such
    /// register.
    pub fn preset(&mut self, name: &str, raw: u32) -> bool {
        let Some(info) = self.drive.register(name) else {
            return false;
        };
        self.storage.set(info, 0, raw, true);
        self.storage.take_effect(std::slice::from_ref(&info));
        self.refresh();
        true
    }

    /// Sets the register that selects `variant`'s variant of its protocol (the one it is
    /// in, [`Protocol::variant`]) to the value that selects it, in RAM and EEPROM and in
    /// effect at once, as if set on the panel before power-on. Returns false, changing
    /// nothing, when no register of the drive selects it.
    pub fn select_variant(&mut self, variant: &Protocol) -> bool {
        let Some(variants) = &variant.variants else {
            return false;
        };
        let (Some(selector), Some(value)) = (
            &variants.selected_by,
            variants.value_selecting(usize::from(variants.current)),
        ) else {
            return false;
        };
        let Some(info) = self
            .drive
            .register_at(crate::kinds::Space::Parameter, selector.register)
        else {
            return false;
        };
        self.storage.set(info, 0, value, true);
        self.storage.take_effect(std::slice::from_ref(&info));
        self.refresh();
        true
    }
}
