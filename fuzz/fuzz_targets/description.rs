//! The description reader (YAML tree, model, protocols, checks, IR, Rust emitter) on
//! arbitrary text as a drive file.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    vfd_fuzz::description(data);
});
