//! Parameters reached through pages (`pages:`): which page and offset a register is at.

use crate::kinds::DataType;
use crate::layout::List;

/// Parameters reached through pages (`pages:` of a drive's protocol entry): a request
/// carries a parameter's offset within its page, and the page is chosen beforehand by
/// writing its number to a page register, which the drive keeps until it is changed or the
/// drive is reset. The DV1's Eaton protocol: P mode pages 0-4 of 100 parameters each, group
/// mode pages 100 + group.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct Paging {
    /// The page register's number in read requests (`None`: it cannot be read back).
    pub select_read: Option<u16>,
    /// The page register's number in write requests.
    pub select_write: u16,
    /// The page register's data type: the page switch goes out with the write command that
    /// carries it (a byte command's narrower layout where the drive takes two data digits),
    /// and the virtual drive answers a read of the page with the read that carries it.
    pub select_data_type: DataType,
    /// The ranges of register numbers laid out on pages.
    pub ranges: List<PageRange>,
    /// Registers whose write makes the drive forget its page (a reset): the master selects
    /// the page again before the next paged access.
    pub forgotten_after: List<u16>,
    /// The page a drive is on after power-on or a reset (the virtual drive's start).
    pub initial: u16,
}

/// Register numbers `first..=last`, laid out `size` to a page from page `first_page` on:
/// register `first + k` is at offset `k % size` of page `first_page + k / size`.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct PageRange {
    /// Lowest register number of the range.
    pub first: u16,
    /// Highest register number of the range.
    pub last: u16,
    /// Registers per page.
    pub size: u16,
    /// The page of `first`.
    pub first_page: u16,
    /// Pages the range skips: no register of the range lies on them (the DV1 has no pages
    /// for parameter groups 09, 12 and 14).
    pub missing: List<u16>,
}

impl PageRange {
    fn locate(&self, number: u16) -> Option<(u16, u16)> {
        if number < self.first || number > self.last || self.size == 0 {
            return None;
        }
        let k = number - self.first;
        let page = self.first_page.checked_add(k / self.size)?;
        (!self.missing.contains(&page)).then_some((page, k % self.size))
    }

    fn register(&self, page: u16, offset: u16) -> Option<u16> {
        if offset >= self.size || page < self.first_page || self.missing.contains(&page) {
            return None;
        }
        let k = u32::from(page - self.first_page) * u32::from(self.size) + u32::from(offset);
        let number = u32::from(self.first) + k;
        (number <= u32::from(self.last)).then_some(number as u16)
    }
}

impl Paging {
    /// The page and the offset within it of register `number`; `None`: it is not paged.
    pub fn locate(&self, number: u16) -> Option<(u16, u16)> {
        self.ranges.iter().find_map(|range| range.locate(number))
    }

    /// The register at `offset` of `page`, if one lies there.
    pub fn register(&self, page: u16, offset: u16) -> Option<u16> {
        self.ranges
            .iter()
            .find_map(|range| range.register(page, offset))
    }

    /// Whether `page` exists (some range lays registers on it).
    pub fn has_page(&self, page: u16) -> bool {
        self.ranges
            .iter()
            .any(|range| range.size > 0 && range.register(page, 0).is_some())
    }

    /// The most registers one page holds: the offsets a request can carry are below it.
    pub fn page_size(&self) -> u16 {
        self.ranges.iter().map(|r| r.size).max().unwrap_or(0)
    }
}
