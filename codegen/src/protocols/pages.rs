//! A drive's parameter pages on one protocol (`protocols[].pages`): the page register's
//! wire numbers, the ranges of register numbers laid out on pages, and the registers whose
//! write resets the page. Checked here: ranges that are well formed and do not overlap,
//! every paged offset within what the commands' register field carries, and registers that
//! exist.

use super::lowered_command::LoweredCommand;
use super::Input;
use crate::diagnostics::Diagnostics;
use std::borrow::Cow;
use vfd_runtime::protocol::{PageRange, Paging};
use vfd_runtime::{DataType, Role};

/// The protocol's pages, or `None` when the drive gives none (or they have problems,
/// reported to `out`).
pub(super) fn paging(
    input: &Input<'_>,
    commands: &[LoweredCommand],
    out: &mut Diagnostics,
) -> Option<Paging> {
    let model = input.reference.pages.as_ref()?;
    let base = format!("{}.pages", input.reference_path);
    let before = out.items.len();
    let error = |out: &mut Diagnostics, path: String, message: String, hint: &str| {
        out.push(input.drive_source.error(&path, message).hint(hint));
    };
    let number = |out: &mut Diagnostics, key: &str, value: Option<u32>| -> Option<u16> {
        let value = value?;
        match u16::try_from(value) {
            Ok(n) => Some(n),
            Err(_) => {
                error(
                    out,
                    format!("{base}.select.{key}"),
                    format!("{value:#X} does not fit the 16 bits of a register number"),
                    "give the page register's number as the protocol carries it",
                );
                None
            }
        }
    };
    let select_read = number(out, "read", model.select.read);
    let select_write = number(out, "write", model.select.write);
    if model.select.write.is_none() {
        error(
            out,
            format!("{base}.select"),
            "the page register has no write number".into(),
            "pages are switched by writing the page register: select: { read: 0x7F, write: 0xFF }",
        );
    }
    // The page switch goes out with a write command that carries the page register's type.
    let select_data_type = model.data_type.unwrap_or(DataType::Word);
    let carries = |write: bool| {
        commands.iter().any(|c| {
            c.spec.kind.is_write() == write
                && c.spec.space == vfd_runtime::Space::Parameter
                && c.spec.carries(select_data_type)
        })
    };
    if !carries(true) || (model.select.read.is_some() && !carries(false)) {
        error(
            out,
            format!("{base}.data_type"),
            format!(
                "no command of the protocol carries a page register of type `{}`",
                select_data_type.as_str()
            ),
            "list the type in the `data_types` of a write command (and of a read, where the page can be read back), or leave `data_type` out for a word",
        );
    }
    let capacity = page_capacity(commands, select_data_type);
    if model.ranges.is_empty() {
        error(
            out,
            format!("{base}.ranges"),
            "no page ranges".into(),
            "e.g. ranges: [{ name: P mode, registers: [0, 499], size: 100, first_page: 0 }]",
        );
    }
    let mut ranges: Vec<PageRange> = Vec::new();
    // The YAML index of each range kept (a range with problems is left out).
    let mut indexes: Vec<usize> = Vec::new();
    for (index, range) in model.ranges.iter().enumerate() {
        let path = format!("{base}.ranges[{index}]");
        let [first, last] = range.registers;
        if first > last || last > u32::from(u16::MAX) {
            error(
                out,
                format!("{path}.registers"),
                format!("[{first:#X}, {last:#X}] is not a range of 16-bit register numbers"),
                "give the lowest and the highest register number, lowest first",
            );
            continue;
        }
        if range.size == 0 {
            error(
                out,
                format!("{path}.size"),
                "a page of size 0".into(),
                "the number of registers on one page (DV1: 100)",
            );
            continue;
        }
        let pages = (last - first) / u32::from(range.size);
        if u32::from(range.first_page) + pages > u32::from(u16::MAX) {
            error(
                out,
                format!("{path}.first_page"),
                "the range's last page does not fit 16 bits".into(),
                "check first_page and size",
            );
            continue;
        }
        let last_page = u32::from(range.first_page) + pages;
        if let Some((max, why)) = capacity.as_ref().filter(|(max, _)| last_page > *max) {
            error(
                out,
                format!("{path}.first_page"),
                format!(
                    "the range's last page, {last_page}, does not fit the page register: {why} carries pages 0-{max}"
                ),
                "check first_page and size against the manual's page table, or the page register's `data_type` (a byte carries 0-255)",
            );
            continue;
        }
        for (at, page) in range.missing_pages.iter().enumerate() {
            if *page < range.first_page || u32::from(*page) > u32::from(range.first_page) + pages {
                error(
                    out,
                    format!("{path}.missing_pages[{at}]"),
                    format!("page {page} is not one of the range's pages"),
                    "list only pages the range would otherwise lay registers on",
                );
            }
        }
        let built = PageRange {
            first: first as u16,
            last: last as u16,
            size: range.size,
            first_page: range.first_page,
            missing: Cow::Owned(range.missing_pages.clone()),
        };
        if let Some(other) = ranges
            .iter()
            .position(|r| r.first <= built.last && built.first <= r.last)
            .map(|at| indexes[at])
        {
            error(
                out,
                format!("{path}.registers"),
                format!("the range overlaps ranges[{other}]"),
                "each register number lies on one page at most",
            );
        }
        let pages_of = |r: &PageRange| {
            let count = (r.last - r.first) / r.size;
            r.first_page..=r.first_page + count
        };
        if let Some(other) = ranges
            .iter()
            .position(|r| {
                let (a, b) = (pages_of(r), pages_of(&built));
                a.start() <= b.end() && b.start() <= a.end()
            })
            .map(|at| indexes[at])
        {
            error(
                out,
                format!("{path}.first_page"),
                format!("the range's pages overlap those of ranges[{other}]"),
                "each page belongs to one range",
            );
        }
        ranges.push(built);
        indexes.push(index);
    }
    // The offset goes in the register field of every command that addresses parameters.
    let largest = model.ranges.iter().map(|r| r.size).max().unwrap_or(0);
    for command in commands {
        let spec = &command.spec;
        let Some(field) = spec.request.field(Role::Register) else {
            continue;
        };
        let highest = spec.address_map.to_wire(largest.saturating_sub(1));
        if highest.is_none_or(|wire| u32::from(wire) > field.format.max_value(field.width)) {
            error(
                out,
                format!("{base}.ranges"),
                format!(
                    "an offset of {} does not fit the register field of command {}",
                    largest.saturating_sub(1),
                    spec.code_label()
                ),
                "a page's size must fit what a request's register field carries",
            );
        }
    }
    if !ranges.is_empty() {
        let paging = Paging {
            select_read,
            select_write: select_write.unwrap_or(0),
            select_data_type,
            ranges: Cow::Owned(ranges.clone()),
            forgotten_after: Cow::Owned(Vec::new()),
            initial: 0,
        };
        if !paging.has_page(model.initial) {
            error(
                out,
                format!("{base}.initial"),
                format!("page {} is not one of the pages", model.initial),
                "the page a drive starts on is one the ranges lay registers on",
            );
        }
    }
    let mut forgotten_after = Vec::new();
    for (index, name) in model.forgotten_after.iter().enumerate() {
        match super::link::find_register(input, name) {
            Some(register) => forgotten_after.push(register.address as u16),
            None => error(
                out,
                format!("{base}.forgotten_after[{index}]"),
                format!("no register `{name}`"),
                "name a described register by its code or id",
            ),
        }
    }
    for (index, key) in model.assumed.iter().enumerate() {
        if key != "initial" {
            error(
                out,
                format!("{base}.assumed[{index}]"),
                format!("`{key}` is not a key of pages that can be assumed"),
                "assumed: [initial]",
            );
        }
    }
    if out.items.len() > before {
        return None;
    }
    Some(Paging {
        select_read,
        select_write: select_write?,
        select_data_type,
        ranges: Cow::Owned(ranges),
        forgotten_after: Cow::Owned(forgotten_after),
        initial: model.initial,
    })
}

/// The highest page the page register carries and what it is (a byte carries 255, a word
/// 65535); `None` when no write command carries it (reported on its own).
fn page_capacity(commands: &[LoweredCommand], data_type: DataType) -> Option<(u32, &'static str)> {
    commands
        .iter()
        .any(|c| {
            c.spec.kind.is_write()
                && c.spec.space == vfd_runtime::Space::Parameter
                && c.spec.carries(data_type)
        })
        .then_some(match data_type {
            DataType::Byte => (0xFF, "a byte"),
            DataType::DoubleWord => (u32::MAX, "a double word"),
            _ => (0xFFFF, "a word"),
        })
}
