//! The drive's trip flag of one round of reads, from what the description says shows a
//! trip: the reply itself where the protocol marks a tripped drive's reply (a lower-case
//! command letter), else a status word among the registers read and its trip bits. `None`
//! when neither was read: no second read is made for it.

use crate::session::{Session, Value};
use vfd_runtime::RegisterInfo;

/// The trip flag of `values`, the reads of `registers` (failed reads count for nothing).
pub fn trip_flag<E>(
    session: &Session,
    registers: &[&'static RegisterInfo],
    values: &[Result<Value, E>],
) -> Option<bool> {
    let good = registers
        .iter()
        .zip(values)
        .filter_map(|(info, value)| value.as_ref().ok().map(|v| (info, v)));
    if session.protocol.lowercase_means_tripped {
        let mut any = None;
        for (_, value) in good {
            any = Some(any.unwrap_or(false) | value.tripped);
        }
        return any;
    }
    let status = session.drive.behaviour.map(|b| &b.status)?;
    if status.tripped.is_empty() {
        return None;
    }
    let mut flag = None;
    for (info, value) in good {
        if let (true, Some(raw)) = (status.registers.contains(&info.id), value.raw) {
            flag =
                Some(flag.unwrap_or(false) | status.tripped.iter().any(|bit| bit.is_active(raw)));
        }
    }
    flag
}
