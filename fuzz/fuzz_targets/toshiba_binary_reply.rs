//! The reply decoders of the `toshiba-binary` protocol file, as `vfd_drives::yd1000::protocols::BINARY` uses it.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    vfd_fuzz::replies(vfd_drives::yd1000::protocols::BINARY.protocol(), data);
});
