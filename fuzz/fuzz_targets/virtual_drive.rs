//! The virtual drive's request handling: arbitrary line input for every described drive
//! and protocol (the first byte picks them).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    vfd_fuzz::virtual_drive(data);
});
