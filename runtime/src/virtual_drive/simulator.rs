//! A virtual drive shared, behind a lock, between a test (or a server) and the masters
//! talking to it.

use super::faults::Fault;
use super::tally::Tally;
use super::VirtualDrive;
use crate::drive::DriveInfo;
use std::sync::{Arc, Mutex, MutexGuard, PoisonError};
use std::time::Duration;

/// A virtual drive shared between a test (or a server) and the masters talking to it.
/// Cloning it shares the same drive.
#[derive(Debug, Clone)]
pub struct Simulator {
    drive: Arc<Mutex<VirtualDrive>>,
}

impl Simulator {
    /// A drive in its factory state (see [`VirtualDrive::new`]).
    pub fn new(drive: &'static DriveInfo) -> Simulator {
        Simulator::from_drive(VirtualDrive::new(drive))
    }

    /// Shares `drive`.
    pub fn from_drive(drive: VirtualDrive) -> Simulator {
        Simulator {
            drive: Arc::new(Mutex::new(drive)),
        }
    }

    /// The drive, locked. A poisoned lock only means a thread panicked while holding it;
    /// the drive's state is still usable.
    pub fn lock(&self) -> MutexGuard<'_, VirtualDrive> {
        self.drive.lock().unwrap_or_else(PoisonError::into_inner)
    }

    /// Advances the simulated clock (see [`VirtualDrive::advance`]).
    pub fn advance(&self, elapsed: Duration) {
        self.lock().advance(elapsed);
    }

    /// Commits `fault` (see [`VirtualDrive::inject`]).
    pub fn inject(&self, fault: Fault) {
        self.lock().inject(fault);
    }

    /// Whether `fault` is pending or in force.
    pub fn has_fault(&self, fault: &Fault) -> bool {
        self.lock().has_fault(fault)
    }

    /// Stops every fault (see [`VirtualDrive::clear_faults`]).
    pub fn clear_faults(&self) {
        self.lock().clear_faults();
    }

    /// Request frames received so far (see [`VirtualDrive::requests`]).
    pub fn requests(&self) -> u64 {
        self.lock().requests()
    }

    /// What the station saw so far (see [`VirtualDrive::tally`]).
    pub fn tally(&self) -> Tally {
        self.lock().tally()
    }

    /// Requests addressed to this station so far, answered or not (see
    /// [`Tally::addressed`]).
    pub fn requests_received(&self) -> u64 {
        self.lock().tally().addressed
    }

    /// Unplugs the drive or plugs it back (see [`VirtualDrive::set_unplugged`]).
    pub fn set_unplugged(&self, unplugged: bool) {
        self.lock().set_unplugged(unplugged);
    }

    /// Trips the drive (see [`VirtualDrive::inject_trip`]).
    pub fn inject_trip(&self, code: u16) {
        self.lock().inject_trip(code);
    }

    /// Powers the drive off and on (see [`VirtualDrive::power_cycle`]).
    pub fn power_cycle(&self) {
        self.lock().power_cycle();
    }
}
