//! Default values serde fills in for keys a file leaves out.

pub(super) fn one() -> u8 {
    1
}

pub(super) fn yes() -> bool {
    true
}
