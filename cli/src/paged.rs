//! Wire numbers of a paged protocol as `vfd decode` names them: the page switch (a step of
//! the protocol, not a register), and an offset on a page, with the registers it is on
//! each page (the frame alone does not say which page is selected).

use vfd_runtime::{Protocol, Space};

/// Whether `wire` is the page register of `protocol` in `command`'s direction: `Some(true)`
/// written (the page switch), `Some(false)` read; `None`: it is not.
pub fn page_switch(
    protocol: &Protocol,
    command: Option<&vfd_runtime::protocol::CommandSpec>,
    wire: u16,
) -> Option<bool> {
    let (paging, command) = (protocol.paging.as_ref()?, command?);
    if command.kind.is_write() {
        (wire == paging.select_write).then_some(true)
    } else {
        (Some(wire) == paging.select_read).then_some(false)
    }
}

/// A wire number no register owns: on a protocol with pages, the offset it is and the
/// registers it is on each page (the frame alone does not say which page is selected);
/// the page register itself; else just the number.
pub fn paged_text(
    drive: &'static vfd_runtime::DriveInfo,
    protocol: &Protocol,
    command: Option<&vfd_runtime::protocol::CommandSpec>,
    wire: u16,
) -> String {
    let plain = format!("wire number {wire:04X}h");
    let (Some(paging), Some(command)) = (&protocol.paging, command) else {
        return plain;
    };
    let Some(offset) = command.address_map.from_wire(wire) else {
        return plain;
    };
    let on_pages: Vec<String> = paging
        .ranges
        .iter()
        .flat_map(|range| {
            let pages = range.last.saturating_sub(range.first) / range.size.max(1);
            let last = range.first_page.saturating_add(pages);
            range.first_page..=last
        })
        .filter_map(|page| {
            let number = paging.register(page, offset)?;
            let info = drive.register_at(Space::Parameter, number)?;
            Some(format!("page {page}: {}", info.label()))
        })
        .collect();
    let described = if on_pages.is_empty() {
        "no described register lies there on any page".to_owned()
    } else {
        on_pages.join("; ")
    };
    format!("{plain}: offset {offset} ({offset:02X}h) of the page selected before ({described})")
}
