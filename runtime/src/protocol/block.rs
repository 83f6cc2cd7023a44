//! Block transfers: the selectors, code tables and modes choosing the registers they carry.

use crate::layout::List;

/// One selector of a block transfer: a register whose value chooses the register one word
/// of the transfer goes to (or comes from), through a code table.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct BlockSelector {
    /// The selector register's number.
    pub register: u16,
    /// Its default (factory) value.
    pub default: u16,
}

/// One code of a selector's code table: the register the value selects, `None` for "no
/// selection".
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct BlockChoice {
    /// The selector value.
    pub value: u16,
    /// The register it selects.
    pub register: Option<u16>,
}

/// Another selection of a block transfer, in force while a mode register holds a value:
/// fixed registers instead of the selectors' (see `protocols[].block.modes` in
/// `drives/README.md`).
#[derive(Debug, Clone, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct BlockMode {
    /// The register that turns the mode on.
    pub register: u16,
    /// The value that turns it on.
    pub value: u16,
    /// The register's default value.
    pub default: u16,
    /// The registers written, in word order.
    pub write: List<u16>,
    /// The registers read, in word order.
    pub read: List<u16>,
}

/// What a drive's block transfer writes and reads: selector registers whose values pick
/// the registers through code tables, and modes that replace the selection. The drive
/// reads the selectors at a reset (parameters that `take effect after reset`), so the
/// selection in force is the one at the last reset.
#[derive(Debug, Clone, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct BlockSpec {
    /// Selectors of the words written, in word order.
    pub write: List<BlockSelector>,
    /// Selectors of the words read, in word order.
    pub read: List<BlockSelector>,
    /// The write selectors' code table.
    pub write_choices: List<BlockChoice>,
    /// The read selectors' code table.
    pub read_choices: List<BlockChoice>,
    /// Modes that replace the selection; the first in force wins.
    pub modes: List<BlockMode>,
}

/// The registers a block transfer writes and reads, position by position (`None`: the
/// position selects nothing: a word written there is not written, a word read there is 0).
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct BlockSelection {
    /// Registers written, in word order.
    pub write: Vec<Option<u16>>,
    /// Registers read, in word order.
    pub read: Vec<Option<u16>>,
}

impl BlockSpec {
    /// The selection given the drive's current values: `value_of(register)` returns a
    /// selector's or mode register's value, `None` for its default.
    pub fn selection(&self, value_of: impl Fn(u16) -> Option<u32>) -> BlockSelection {
        let value = |register: u16, default: u16| value_of(register).unwrap_or(u32::from(default));
        if let Some(mode) = self
            .modes
            .iter()
            .find(|mode| value(mode.register, mode.default) == u32::from(mode.value))
        {
            return BlockSelection {
                write: mode.write.iter().map(|r| Some(*r)).collect(),
                read: mode.read.iter().map(|r| Some(*r)).collect(),
            };
        }
        let pick = |selectors: &[BlockSelector], choices: &[BlockChoice]| {
            selectors
                .iter()
                .map(|selector| {
                    let chosen = value(selector.register, selector.default);
                    choices
                        .iter()
                        .find(|choice| u32::from(choice.value) == chosen)
                        .and_then(|choice| choice.register)
                })
                .collect()
        };
        BlockSelection {
            write: pick(&self.write, &self.write_choices),
            read: pick(&self.read, &self.read_choices),
        }
    }

    /// The selection with every selector and mode register at its default (a drive in its
    /// factory state).
    pub fn default_selection(&self) -> BlockSelection {
        self.selection(|_| None)
    }

    /// Every register whose value the selection depends on: selectors, then mode registers.
    pub fn selector_registers(&self) -> Vec<u16> {
        self.write
            .iter()
            .chain(self.read.iter())
            .map(|s| s.register)
            .chain(self.modes.iter().map(|m| m.register))
            .collect()
    }
}
