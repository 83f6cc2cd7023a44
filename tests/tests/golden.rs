//! Golden-frame tests generated from every example in `drives/*.yaml` (see `build.rs`).

include!(concat!(env!("OUT_DIR"), "/golden.rs"));
