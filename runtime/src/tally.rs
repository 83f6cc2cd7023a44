//! Counts, on the current thread, of the work an exchange costs: command lookups
//! ([`crate::Protocol::command_for_request`]) and frame encodings (the codec's and the
//! compiled plans'). Counted with the `testing` feature only, for the test that pins one
//! lookup and one encoding per frame; without it the counting compiles to nothing.

#[cfg(feature = "testing")]
use std::cell::Cell;

#[cfg(feature = "testing")]
thread_local! {
    static LOOKUPS: Cell<u64> = const { Cell::new(0) };
    static ENCODINGS: Cell<u64> = const { Cell::new(0) };
}

/// Counts a command lookup.
#[inline(always)]
pub(crate) fn lookup() {
    #[cfg(feature = "testing")]
    LOOKUPS.with(|count| count.set(count.get() + 1));
}

/// Counts a frame encoding.
#[inline(always)]
pub(crate) fn encoding() {
    #[cfg(feature = "testing")]
    ENCODINGS.with(|count| count.set(count.get() + 1));
}

/// Command lookups and frame encodings on this thread so far.
#[cfg(feature = "testing")]
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Tally {
    /// Commands looked up for a request.
    pub lookups: u64,
    /// Frames encoded.
    pub encodings: u64,
}

#[cfg(feature = "testing")]
impl Tally {
    /// The counts so far on this thread.
    pub fn now() -> Tally {
        Tally {
            lookups: LOOKUPS.with(Cell::get),
            encodings: ENCODINGS.with(Cell::get),
        }
    }

    /// The counts since `earlier`.
    pub fn since(earlier: Tally) -> Tally {
        let now = Tally::now();
        Tally {
            lookups: now.lookups - earlier.lookups,
            encodings: now.encodings - earlier.encodings,
        }
    }
}
