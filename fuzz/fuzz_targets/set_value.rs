//! The reader of `vfd serve --mqtt`'s `set` messages (cli/src/service/serve/mqtt/set_value.rs,
//! compiled here on its own) on arbitrary bytes: it must never panic, a value it takes is
//! non-empty trimmed text no longer than the limit, and a refusal's reason stays short
//! whatever was sent (it never repeats the message).
#![no_main]

#[path = "../../cli/src/service/serve/mqtt/set_value.rs"]
mod set_value;

/// The service's limit (`MAX_VALUE_BYTES` in cli/src/service/serve/request_text.rs).
const MAX: usize = 1024;

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    match set_value::set_value(data, MAX) {
        Ok(value) => {
            assert!(!value.is_empty());
            assert_eq!(value.trim(), value);
            assert!(value.len() <= MAX, "{} bytes taken", value.len());
        }
        Err(reason) => assert!(reason.len() < 256, "a reason of {} bytes", reason.len()),
    }
});
