//! A bus: one line and the stations on it, the line's timing kept by the bus itself. The
//! bus owns the line; a station's master holds [`Line::Away`] until the bus lends it the
//! line for its turn ([`Bus::speak`]). Lending, the bus tells the station's master when the
//! line was last busy (any station's frame), so the frame gap is kept across stations;
//! taking the line back, it notes when the station left it and that it spoke last. No
//! caller shares the line between masters or copies timing from one to another.

use crate::Line;
use std::time::Instant;
use vfd_runtime::transaction::Master;

/// A station as a bus drives it: anything that speaks through a master on a [`Line`].
pub trait OnLine {
    /// The master that speaks for the station.
    fn master(&mut self) -> &mut Master<Line>;
}

impl OnLine for Master<Line> {
    fn master(&mut self) -> &mut Master<Line> {
        self
    }
}

/// One line and the stations on it (see the module).
#[derive(Debug)]
pub struct Bus<S> {
    line: Line,
    stations: Vec<S>,
    /// When the line was last busy: the end of the last frame any station sent or got.
    last_busy: Option<Instant>,
    /// The station (its index) that used the line last.
    last_speaker: Option<usize>,
}

impl<S: OnLine> Bus<S> {
    /// A bus on `line` with `stations`, whose masters hold [`Line::Away`] (a line they
    /// hold is set aside while the bus lends them its own).
    pub fn new(line: Line, stations: Vec<S>) -> Bus<S> {
        Bus {
            line,
            stations,
            last_busy: None,
            last_speaker: None,
        }
    }

    /// The stations, in the order given.
    pub fn stations(&self) -> &[S] {
        &self.stations
    }

    /// Station `index`, to look at or change between turns (not to speak: see
    /// [`Bus::speak`]).
    pub fn station_mut(&mut self, index: usize) -> &mut S {
        &mut self.stations[index]
    }

    /// When the line was last busy (`None`: no station has used it yet).
    pub fn last_busy(&self) -> Option<Instant> {
        self.last_busy
    }

    /// The station (its index) that used the line last.
    pub fn last_speaker(&self) -> Option<usize> {
        self.last_speaker
    }

    /// Gives station `index` the line for `turn`: its master gets the line and knows when
    /// it was last busy; after the turn the line is the bus's again, and, when the station
    /// used it, the bus notes when it left it and that it spoke last.
    ///
    /// # Panics
    ///
    /// When there is no station `index`.
    pub fn speak<R>(&mut self, index: usize, turn: impl FnOnce(&mut S) -> R) -> R {
        let station = &mut self.stations[index];
        let master = station.master();
        std::mem::swap(master.transport_mut(), &mut self.line);
        if let Some(at) = self.last_busy {
            master.note_line_activity(at);
        }
        let before = master.line_activity();
        let result = turn(station);
        let master = station.master();
        std::mem::swap(master.transport_mut(), &mut self.line);
        let after = master.line_activity();
        if after != before {
            self.last_busy = after.max(self.last_busy);
            self.last_speaker = Some(index);
        }
        result
    }

    /// The line and the stations, taken apart (to close the line, and keep what the
    /// stations know for the next line).
    pub fn into_parts(self) -> (Line, Vec<S>) {
        (self.line, self.stations)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use vfd_runtime::transport::Transport;
    use vfd_runtime::virtual_drive::Simulator;
    use vfd_runtime::{CommandKind, Request};

    /// Two stations (each its own master) on one line to a virtual drive.
    fn two_stations() -> Bus<Master<Line>> {
        let drive = vfd_drives::ALL_DRIVES
            .iter()
            .copied()
            .find(|d| !d.protocols.is_empty() && d.registers.iter().any(|r| r.has_address))
            .expect("a drive compiled in");
        let protocol = drive.protocols[0];
        let simulator = Simulator::new(drive);
        let address = simulator.lock().address();
        let settings = drive.serial.default_for(&protocol.id);
        let line = Line::other(simulator.link(protocol));
        let master = || {
            Master::for_protocol(Line::Away, protocol, settings, drive.serial.timing)
                .with_address(Some(address))
        };
        Bus::new(line, vec![master(), master()])
    }

    fn read_something(master: &mut Master<Line>) {
        let drive = vfd_drives::ALL_DRIVES
            .iter()
            .copied()
            .find(|d| !d.protocols.is_empty() && d.registers.iter().any(|r| r.has_address))
            .unwrap();
        let register = drive
            .registers
            .iter()
            .find(|r| r.has_address && drive.protocols[0].can_read(r))
            .unwrap();
        let _ = master.transact(&Request::for_register(CommandKind::Read, register, 0));
    }

    #[test]
    fn the_bus_lends_its_line_for_a_turn_and_keeps_its_timing() {
        let mut bus = two_stations();
        assert_eq!(bus.last_speaker(), None);
        // A turn that does not use the line changes nothing.
        bus.speak(0, |master| assert!(master.transport().is_here()));
        assert_eq!((bus.last_speaker(), bus.last_busy()), (None, None));
        assert!(!bus.stations()[0].transport().is_here(), "the line is back");

        bus.speak(0, read_something);
        let first = bus.last_busy().expect("the line was busy");
        assert_eq!(bus.last_speaker(), Some(0));
        assert_eq!(bus.stations()[0].line_activity(), Some(first));
        assert!(bus.stations()[1].line_activity().is_none());

        // The next station is told when the line was last busy before it speaks.
        let seen = bus.speak(1, |master| master.line_activity());
        assert_eq!(seen, Some(first));
        bus.speak(1, read_something);
        assert_eq!(bus.last_speaker(), Some(1));
        assert!(bus.last_busy().unwrap() >= first);
        assert!(bus.stations().iter().all(|m| !m.transport().is_here()));
        let (mut line, _) = bus.into_parts();
        assert!(line.is_here());
        assert!(line.clear_input().is_ok());
    }
}
