//! The reply decoders of the `eaton-ascii` protocol file, as `vfd_drives::dv1::protocols::EATON` uses it.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    vfd_fuzz::replies(vfd_drives::dv1::protocols::EATON.protocol(), data);
});
