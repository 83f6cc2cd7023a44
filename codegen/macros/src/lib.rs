//! Proc macro (being written).
