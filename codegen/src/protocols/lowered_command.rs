//! A command that lowered: the runtime command with its place in the protocol file. Made
//! by [`super::commands`], read by the layouts', blocks', link's and pages' checks.

use vfd_runtime::CommandSpec;

/// A command that lowered, with its index under `commands:`.
pub(super) struct LoweredCommand {
    /// Index in the protocol file's `commands:`.
    pub index: usize,
    /// The runtime command.
    pub spec: CommandSpec,
    /// Whether the file gives it a code (without one, `spec.code` is 0).
    pub has_code: bool,
}

impl LoweredCommand {
    /// Where it is in the protocol file: `commands[3]`.
    pub fn path(&self) -> String {
        format!("commands[{}]", self.index)
    }
}
