//! The drive's station number held in a register (`addressing.register`, DV1 07-01): the
//! virtual drive answers at the station the register holds (its value in effect, so after
//! a reset for a register that takes effect then), and setting the station sets the
//! register.

use super::VirtualDrive;

impl VirtualDrive {
    /// The register holding the station number, when the description names one.
    fn station_register(&self) -> Option<&'static crate::info::RegisterInfo> {
        self.drive.register(self.drive.station_register?)
    }

    /// At power-on: the station the register's value sets, when it is one the first
    /// protocol answers at (at least 1, as without a register); else that lowest station,
    /// with the register set to it as if on the panel before power-on.
    pub(super) fn place_station(&mut self) {
        let Some(info) = self.station_register() else {
            return;
        };
        let (low, high) = self.drive.protocols.first().map_or((1, u8::MAX), |p| {
            (p.address_range.0.max(1), p.address_range.1)
        });
        let held = self.storage.in_effect(info, 0);
        match u8::try_from(held).ok().filter(|s| (low..=high).contains(s)) {
            Some(station) => self.address = station,
            None => self.storage_set_station(info, self.address),
        }
    }

    /// Moves the station to the one the register holds (in effect), when it holds a
    /// station number: after a write of it, a reset, a power cycle or a preset.
    pub(super) fn follow_station_register(&mut self) {
        let Some(info) = self.station_register() else {
            return;
        };
        if let Ok(station) = u8::try_from(self.storage.in_effect(info, 0)) {
            self.address = station;
        }
    }

    /// Sets the register to `station`, in RAM and EEPROM and in effect.
    pub(super) fn set_station_register(&mut self, station: u8) {
        if let Some(info) = self.station_register() {
            self.storage_set_station(info, station);
        }
    }

    fn storage_set_station(&mut self, info: &'static crate::info::RegisterInfo, station: u8) {
        self.storage.set(info, 0, u32::from(station), true);
        self.storage.take_effect(std::slice::from_ref(&info));
    }
}
