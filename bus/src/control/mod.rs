//! The control profile: one way to run, stop, coast, reset, set the speed of and read the
//! state of every drive whose description has control roles, whatever its command word,
//! codes or protocol. The roles come from the drive's behaviour model ([`Roles`]); what
//! each operation writes is prepared without a line ([`steps()`]) and carried out through
//! a session ([`Control`]); the state is judged from what was read ([`DriveState`]).

pub mod error;
pub mod operate;
pub mod roles;
pub mod state;
pub mod steps;

pub use error::ControlError;
pub use operate::Control;
pub use roles::{MissingRoles, Roles};
pub use state::{DriveState, Trip};
pub use steps::{steps, Action, Direction, Step};
