//! The state an example's frames imply, set on the virtual drive before its request is
//! played, so that the rehearsal compares frames rather than state: what the reply shows
//! of the register it reads (a running drive's output frequency and status word, a
//! parameter set otherwise than its default), the process words the reply carries, and,
//! for a write the reply accepts, the settings the drive needs to take it (the operation
//! mode its behaviour requires, a bound the value needs). A value outside what its register
//! can hold is left alone: the drive could not show it, and the rehearsal says so.

use crate::ir::{ExampleIr, FrameIr};
use vfd_runtime::virtual_drive::VirtualDrive;
use vfd_runtime::{CommandKind, DriveInfo, RegisterInfo};

/// Sets on `virtual_drive` what `example` states beyond its `settings:` (which are set
/// already and win).
pub(super) fn prepare(
    virtual_drive: &mut VirtualDrive,
    drive: &'static DriveInfo,
    example: &ExampleIr,
    request: &FrameIr,
    reply: &FrameIr,
) {
    if reply.meaning.error_code.is_some() {
        return;
    }
    let register = example
        .register
        .as_deref()
        .and_then(|id| drive.register(id))
        .filter(|info| !example.settings.iter().any(|(code, _)| code == info.code));
    match request.meaning.kind {
        Some(CommandKind::Read) => {
            let first_element = request.meaning.index.unwrap_or(0) == 0;
            if let (Some(info), Some(data), true) = (register, reply.meaning.data, first_element) {
                if holds(info, data) {
                    virtual_drive.hold(info.id, data);
                }
            }
        }
        Some(kind) if kind.is_write() => {
            if let (Some(info), Some(data)) = (register, request.meaning.data) {
                accept_write(virtual_drive, drive, info, data);
            }
        }
        _ => {}
    }
    // The status word and output a reply's process words show.
    let process = drive.behaviour.and_then(|b| b.process.as_ref());
    if let (Some(process), Some(words)) = (process, reply.meaning.process) {
        for (id, word) in [(process.status, words[0]), (process.output, words[1])] {
            if drive
                .register(id)
                .is_some_and(|info| holds(info, u32::from(word)))
            {
                virtual_drive.hold(id, u32::from(word));
            }
        }
    }
}

/// Puts the drive where it takes a write of `raw` to `info`, as far as the description
/// says what that needs: the operation mode its commands require, and the registers
/// bounding `info`'s range moved to let the value in (where they can hold it).
fn accept_write(
    virtual_drive: &mut VirtualDrive,
    drive: &'static DriveInfo,
    info: &'static RegisterInfo,
    raw: u32,
) {
    if let Some(behaviour) = drive.behaviour {
        let commanded = [behaviour.command.register, behaviour.frequency.command];
        if let Some(mode) = behaviour.command.require_mode {
            let in_mode = virtual_drive
                .raw_in_effect(mode.register)
                .is_some_and(|now| mode.values.contains(&now));
            if commanded.contains(&info.id) && !in_mode {
                if let Some(&value) = mode.values.first() {
                    virtual_drive.preset(mode.register, value);
                }
            }
        }
    }
    let value = engineering(info, raw);
    for (bound, above) in [(info.max_bound, false), (info.min_bound, true)] {
        let Some(bound) = bound.and_then(|code| drive.register(code)) else {
            continue;
        };
        let Some(now) = virtual_drive.raw_in_effect(bound.id) else {
            continue;
        };
        let limit = engineering(bound, now);
        let blocks = if above {
            value < limit - 1e-9
        } else {
            value > limit + 1e-9
        };
        let wanted = (value / bound.scale).round();
        if blocks && wanted >= 0.0 && holds(bound, wanted as u32) {
            virtual_drive.preset(bound.id, wanted as u32);
        }
    }
}

/// Whether `raw` is a value `info` can hold: a code of its table, a value taken besides
/// its range, or a raw value in its range.
fn holds(info: &RegisterInfo, raw: u32) -> bool {
    if let Some(codes) = info.codes {
        return u16::try_from(raw).is_ok_and(|value| codes.find(value).is_some())
            || !codes.exhaustive && in_range(info, raw);
    }
    info.special_raw(raw).is_some() || in_range(info, raw)
}

/// Whether `raw`, read as `info` reads it (signed or not), lies in its static range.
fn in_range(info: &RegisterInfo, raw: u32) -> bool {
    let value = signed(info, raw);
    (info.raw_min..=info.raw_max).contains(&value)
}

/// `raw` as a number, in two's complement for a signed register.
fn signed(info: &RegisterInfo, raw: u32) -> i64 {
    match (info.signed, info.data_type.size()) {
        (true, 4) => i64::from(raw as i32),
        (true, _) => i64::from(raw as u16 as i16),
        (false, _) => i64::from(raw),
    }
}

/// `raw` in `info`'s unit.
fn engineering(info: &RegisterInfo, raw: u32) -> f64 {
    signed(info, raw) as f64 * info.scale
}
