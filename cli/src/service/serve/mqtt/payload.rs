//! What goes on the wire: the JSON of a state and of a write outcome. (The value a `set`
//! message carries is read by [`super::set_value`].)

use vfd_bus::service::event::{Reading, WriteOutcome};

/// A register's retained state: the reading's fields as JSON.
pub fn state(reading: &Reading) -> Vec<u8> {
    serde_json::to_vec(reading).unwrap_or_default()
}

/// A write's outcome as JSON.
pub fn outcome(outcome: &WriteOutcome) -> Vec<u8> {
    serde_json::to_vec(outcome).unwrap_or_default()
}
