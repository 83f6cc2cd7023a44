//! A drive's life on its simulated clock: made in its factory state at power-on, its clock
//! advanced (the motor model integrated in short steps), powered off and on, and silent
//! while it starts up again.

use super::motor::Motor;
use super::storage::Storage;
use super::tally::Tally;
use super::VirtualDrive;
use crate::drive::DriveInfo;
use std::collections::VecDeque;
use std::time::Duration;

/// The longest simulated step: ramps are integrated in steps no longer than this.
const MAX_STEP: Duration = Duration::from_millis(100);

impl VirtualDrive {
    /// A drive in its factory state: every register at its default, at the lowest station
    /// number its first protocol accepts (at least 1), motor stopped, clock at zero.
    pub fn new(drive: &'static DriveInfo) -> VirtualDrive {
        let address = drive
            .protocols
            .first()
            .map_or(1, |p| p.address_range.0.max(1));
        let mut virtual_drive = VirtualDrive {
            drive,
            address,
            storage: Storage::new(drive.registers),
            motor: Motor::default(),
            now: Duration::ZERO,
            selected_index: 0,
            persistent_writes: false,
            faults: VecDeque::new(),
            noise: false,
            echo: false,
            requests: 0,
            tally: Tally::default(),
            unplugged: false,
            silent_until: Duration::ZERO,
            sender_tripped: false,
            garbage: false,
            port: None,
            page: None,
            awaiting_follow_up: None,
            held: Vec::new(),
            unreadable_in_a_row: 0,
        };
        virtual_drive.place_station();
        virtual_drive.refresh();
        virtual_drive
    }

    /// Simulated time since power-up.
    pub fn now(&self) -> Duration {
        self.now
    }

    /// Advances the simulated clock: the output ramps, monitors follow.
    pub fn advance(&mut self, elapsed: Duration) {
        let mut left = elapsed;
        while !left.is_zero() {
            let step = left.min(MAX_STEP);
            self.step(step);
            left -= step;
        }
        self.now += elapsed;
    }

    /// Power off and on: values written to RAM only are lost, the motor stops, a trip is
    /// cleared and parameters that take effect after a reset take their stored values. The
    /// drive then stays silent for the start-up delay its manual gives
    /// (`serial.timing.startup_delay_ms`), on the simulated clock.
    pub fn power_cycle(&mut self) {
        self.silent_until = self.now + self.drive.serial.timing.startup_delay;
        self.storage.power_cycle(self.drive.registers);
        self.motor = Motor::default();
        self.selected_index = 0;
        self.persistent_writes = false;
        self.page = None;
        self.awaiting_follow_up = None;
        self.held.clear();
        self.refresh();
    }

    /// Whether it is still starting up after a power cycle (and answers nothing).
    pub fn starting_up(&self) -> bool {
        self.now < self.silent_until
    }
}
