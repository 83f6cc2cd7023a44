//! Typed register APIs for every drive described in this folder's YAML files.
//!
//! Each drive is a module (`vfd_drives::yd1000`) generated at build time from
//! `drives/<id>.yaml` and the protocol files in `drives/protocols/`. Its reference page is
//! `generated-docs/<id>.md`.
//!
//! ```
//! use vfd_drives::yd1000;
//! use vfd_runtime::prelude::*;
//!
//! // "Set 60 Hz in RAM", binary protocol, no station number.
//! let request = yd1000::registers::FrequencyCommand::write_ram(Hertz(60.0)).unwrap();
//! let mut frame = [0u8; 16];
//! let len = yd1000::protocols::BINARY.encode_request(&request, None, &mut frame).unwrap();
//! assert_eq!(&frame[..len], [0x2F, 0x50, 0xFA, 0x01, 0x17, 0x70, 0x01]);
//! ```
#![warn(missing_docs)]

include!(concat!(env!("OUT_DIR"), "/drives.rs"));
include!(concat!(env!("OUT_DIR"), "/shipped.rs"));

#[doc = include_str!("guide.md")]
#[doc = "```"]
#[doc = include_str!("../examples/fake_drive.rs")]
#[doc = "```"]
pub mod guide {}

/// The described drive with this id.
pub fn drive(id: &str) -> Option<&'static vfd_runtime::DriveInfo> {
    ALL_DRIVES.iter().copied().find(|drive| drive.id == id)
}

/// Writing a read-only register or writing a RAM-only register persistently does not compile:
///
/// ```compile_fail,E0599
/// use vfd_runtime::prelude::*;
/// use vfd_drives::yd1000::registers::OutputFrequency;
/// let _ = OutputFrequency::write_ram(vfd_runtime::units::Hertz(1.0));
/// ```
///
/// ```compile_fail,E0599
/// use vfd_runtime::prelude::*;
/// use vfd_drives::yd1000::registers::FrequencyCommand;
/// let _ = FrequencyCommand::write_persistent(vfd_runtime::units::Hertz(1.0));
/// ```
///
/// ```compile_fail,E0308
/// // Units are types: seconds are not hertz.
/// use vfd_runtime::prelude::*;
/// use vfd_drives::yd1000::registers::FrequencyCommand;
/// let _ = FrequencyCommand::write_ram(vfd_runtime::units::Seconds(1.0));
/// ```
///
/// A register of one drive does not compile with another drive's protocol or master (each
/// drive module has a `Drive` type; registers, protocols and masters name it):
///
/// ```compile_fail,E0308
/// use vfd_runtime::prelude::*;
/// let request = vfd_drives::fc51::registers::MaximumReference::read();
/// let mut frame = [0u8; 32];
/// let _ = vfd_drives::yd1000::protocols::BINARY.encode_request(&request, None, &mut frame);
/// ```
///
/// ```compile_fail,E0271
/// use vfd_drives::{fc51, yd1000};
/// use vfd_runtime::prelude::*;
/// let (line, _drive) = vfd_runtime::transport::memory_pair();
/// let mut master = Master::new(line, &yd1000::protocols::BINARY, yd1000::SERIAL.default, yd1000::SERIAL.timing);
/// let _ = master.read::<fc51::registers::MaximumReference>();
/// ```
///
/// The same calls with the drive's own registers compile:
///
/// ```
/// use vfd_drives::yd1000;
/// use vfd_runtime::prelude::*;
/// let request = yd1000::registers::MaximumFrequency::read();
/// let mut frame = [0u8; 32];
/// assert!(yd1000::protocols::BINARY.encode_request(&request, None, &mut frame).is_ok());
/// let (line, _drive) = vfd_runtime::transport::memory_pair();
/// let mut master = Master::new(line, &yd1000::protocols::BINARY, yd1000::SERIAL.default, yd1000::SERIAL.timing);
/// let _ = master.read::<yd1000::registers::MaximumFrequency>(); // no drive answers: a timeout
/// ```
pub mod compile_time_checks {}
