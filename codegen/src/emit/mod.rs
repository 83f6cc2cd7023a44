//! Stage 6: emitters. Each reads only the IR ([`crate::ir::DriveIr`]): Rust with `quote!`
//! and prettyplease ([`rust`]), the same drive as run-time values ([`live`]), Markdown with
//! minijinja ([`markdown`]), golden-frame tests ([`tests`]).

pub mod live;
pub mod markdown;
pub mod rust;
pub mod tests;
pub mod words;
pub mod wrap;
