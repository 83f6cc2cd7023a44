//! Untyped masters on a virtual drive, for tests that go through every described drive
//! and protocol.

use vfd_runtime::transaction::Master;
use vfd_runtime::virtual_drive::{SimLink, Simulator};
use vfd_runtime::{DriveInfo, Protocol};

/// A master for `protocol` of `drive`, on `sim`'s line, at the drive's default serial
/// settings and addressed to the station `sim` answers.
pub fn untyped(sim: &Simulator, drive: &DriveInfo, protocol: &'static Protocol) -> Master<SimLink> {
    let address = sim.lock().address();
    Master::for_protocol(
        sim.link(protocol),
        protocol,
        drive.serial.default,
        drive.serial.timing,
    )
    .with_address(Some(address))
}
