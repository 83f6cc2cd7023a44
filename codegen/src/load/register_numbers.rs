//! Register numbers for registers the manual gives no `address` of its own: one whose place
//! on a page is given (`on_page`) takes the number the protocol's page ranges lay there; one
//! known only by its own numbers on the wire (`wire_numbers`: an instruction code) takes a
//! number of its own that no frame carries and no page range lays out, counted down from
//! FFFFh, so that tools and the virtual drive can tell it from every other register. A
//! register with an `address` and an `on_page` must agree with it.

use crate::diagnostics::Diagnostics;
use crate::parse::model::{DriveFile, PageRangeModel, PagesModel};
use crate::parse::SourceFile;
use std::collections::HashSet;
use std::path::PathBuf;
use vfd_runtime::Space;

/// Sets every register's number (`RegisterModel::address`); problems go to `out`. Registers
/// holding a placeholder from reading (`incomplete`) are left out: their problem is reported.
/// A register left without a number joins `incomplete`, so that what would follow from its
/// placeholder number (a duplicate address) is left out.
pub(crate) fn resolve(
    source: &SourceFile,
    model: &mut DriveFile,
    incomplete: &mut Vec<(PathBuf, String)>,
    out: &mut Diagnostics,
) {
    let read_incomplete = incomplete.clone();
    let placeholder = |index: usize| {
        let element = format!("registers[{index}]");
        read_incomplete
            .iter()
            .any(|(file, path)| *file == source.path && *path == element)
    };
    let mut unresolved = Vec::new();
    let mut wire_only = Vec::new();
    for index in 0..model.registers.len() {
        let register = &model.registers[index];
        let mut number = register.given_address;
        for (protocol, place) in &register.on_page {
            let path = format!("registers[{index}].on_page.{protocol}");
            let pages = model
                .protocols
                .iter()
                .find(|p| &p.id == protocol)
                .map(|p| p.pages.as_ref());
            let laid = match pages {
                None => Err(format!("no protocol `{protocol}`")),
                Some(None) => Err(format!("protocol `{protocol}` has no pages")),
                Some(Some(_)) if register.wire_numbers.contains_key(protocol) => Err(format!(
                    "the register has its own numbers on protocol `{protocol}` (wire_numbers), so it lies on no page there"
                )),
                Some(Some(pages)) => register_at(pages, place.page, place.offset).ok_or_else(|| {
                    format!(
                        "page {}, offset {:02X}h lies in none of protocol `{protocol}`'s page ranges",
                        place.page, place.offset
                    )
                }),
            };
            match laid {
                Err(message) => {
                    unresolved.push(index);
                    if !placeholder(index) {
                        out.push(source.error(&path, message).hint(
                            "give the page and the offset (the read code on the page) as the manual's page table lays the register, on a protocol with `pages`",
                        ));
                    }
                }
                Ok(laid) => match number {
                    Some(given) if given != u32::from(laid) => out.push(
                        source
                            .error(
                                &path,
                                format!(
                                    "page {}, offset {:02X}h is register {laid:04X}h on protocol `{protocol}`, not the register's address {given:04X}h",
                                    place.page, place.offset
                                ),
                            )
                            .hint("check the page and the offset, or the address, against the manual; or leave `address` out"),
                    ),
                    Some(_) => {}
                    None => number = Some(u32::from(laid)),
                },
            }
        }
        match number {
            Some(number) => model.registers[index].address = number,
            None if register
                .wire_numbers
                .values()
                .any(|w| w.read.is_some() || w.write.is_some()) =>
            {
                wire_only.push(index);
            }
            None if register.on_page.is_empty() && !placeholder(index) => {
                unresolved.push(index);
                out.push(
                source
                    .error(
                        &format!("registers[{index}]"),
                        format!(
                            "register {} has no `address`, and no protocol reaches it by its own numbers or a place on a page",
                            register.code
                        ),
                    )
                    .hint("give its `address`; where the manual gives none, its numbers on the wire (`wire_numbers: { link: { read: 0x7A } }`) or its place on a page (`on_page: { link: { page: 1, offset: 0x5F } }`)"),
            );
            }
            None => unresolved.push(index),
        }
    }
    incomplete.extend(
        unresolved
            .into_iter()
            .map(|index| (source.path.clone(), format!("registers[{index}]"))),
    );
    // Numbers no frame carries: none of another register of the space, none a page range
    // lays out (a paged offset reaches those), counted down from FFFFh.
    let mut taken: HashSet<(Space, u32)> = model
        .registers
        .iter()
        .enumerate()
        .filter(|(index, _)| !wire_only.contains(index))
        .map(|(_, r)| (r.space.unwrap_or(Space::Parameter), r.address))
        .collect();
    let ranges: Vec<&PageRangeModel> = model
        .protocols
        .iter()
        .filter_map(|p| p.pages.as_ref())
        .flat_map(|pages| pages.ranges.iter())
        .collect();
    let paged = |number: u32| {
        ranges
            .iter()
            .any(|r| (r.registers[0]..=r.registers[1]).contains(&number))
    };
    let mut next = u32::from(u16::MAX);
    for index in wire_only {
        let space = model.registers[index].space.unwrap_or(Space::Parameter);
        while taken.contains(&(space, next)) || paged(next) {
            next -= 1;
        }
        model.registers[index].address = next;
        taken.insert((space, next));
        next -= 1;
    }
}

/// The register number `pages` lay at `offset` of `page`, if a range lays one there.
fn register_at(pages: &PagesModel, page: u16, offset: u16) -> Option<u16> {
    pages.ranges.iter().find_map(|range| {
        let [first, last] = range.registers;
        let size = u32::from(range.size);
        if size == 0
            || u32::from(offset) >= size
            || page < range.first_page
            || range.missing_pages.contains(&page)
        {
            return None;
        }
        let number = first + u32::from(page - range.first_page) * size + u32::from(offset);
        (number <= last)
            .then(|| u16::try_from(number).ok())
            .flatten()
    })
}
