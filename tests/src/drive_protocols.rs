//! A drive's typed protocols as one list, for tests that run the same exchanges over each
//! of them.

use vfd_drives::yd1000;
use vfd_runtime::DriveProtocol;

/// YD1000's protocols: ASCII and binary.
pub const YD1000_PROTOCOLS: [&DriveProtocol<yd1000::Drive>; 2] =
    [&yd1000::protocols::ASCII, &yd1000::protocols::BINARY];
