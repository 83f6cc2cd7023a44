//! The reply decoders of the `modbus-rtu` protocol file, as `vfd_drives::fc51::protocols::MODBUS` uses it.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    vfd_fuzz::replies(vfd_drives::fc51::protocols::MODBUS.protocol(), data);
});
