//! The reply decoders of the `fc-telegram` protocol file, as `vfd_drives::fc51::protocols::FC` uses it.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    vfd_fuzz::replies(vfd_drives::fc51::protocols::FC.protocol(), data);
});
