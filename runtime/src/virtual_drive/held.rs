//! Registers held at a value: what a manual's example shows of a state the drive is not
//! in (a running drive's output frequency and status word), shown whatever the behaviour
//! model computes, so that `vfd check` can compare an example's frames without bringing
//! the virtual drive to that state.

use super::VirtualDrive;

impl VirtualDrive {
    /// Shows `raw` in the register with this code or id (RAM, element 0), whatever the
    /// behaviour model computes for it or a request writes, until a power cycle: a monitor
    /// or a status word as a manual's example prints it (the output frequency of a running
    /// drive), so that a read returns the printed value without the drive being brought to
    /// that state. No checks. Returns false when there is no such register.
    pub fn hold(&mut self, name: &str, raw: u32) -> bool {
        let Some(info) = self.drive.register(name) else {
            return false;
        };
        self.held.retain(|(held, _)| !std::ptr::eq(*held, info));
        self.held.push((info, raw));
        self.refresh();
        true
    }

    /// Puts the held registers' values back ([`VirtualDrive::hold`]).
    pub(crate) fn show_held(&mut self) {
        for (info, raw) in &self.held {
            self.storage.set(info, 0, *raw, false);
        }
    }
}
