//! The value a `set` message carries: plain text as `vfd write` takes it (`50`, `50 Hz`, a
//! code's name, bit fields by name), the same as a JSON string (`"50 Hz"`), or an object
//! `{"value": 50}` / `{"value": "50 Hz"}`. A message longer than the limit is refused
//! before a byte of it is looked at; a refusal never repeats the message, so its length is
//! bounded whatever was sent. This file depends on nothing of the crate but `serde_json`:
//! the fuzz target `set_value` (fuzz/) compiles it on its own.

/// The value text of a `set` message of at most `max_bytes` bytes, or why there is none.
pub fn set_value(payload: &[u8], max_bytes: usize) -> Result<String, String> {
    if payload.len() > max_bytes {
        return Err(format!(
            "the set message is {} bytes, more than any register's value ({max_bytes}); it was not read",
            payload.len()
        ));
    }
    let text = std::str::from_utf8(payload)
        .map_err(|_| "the set message is not UTF-8 text".to_string())?
        .trim();
    let value = if text.starts_with('{') || text.starts_with('"') {
        let json: serde_json::Value = serde_json::from_str(text)
            .map_err(|e| format!("the set message looks like JSON but is not: {e}"))?;
        let value = match json {
            serde_json::Value::Object(mut object) => object.remove("value").ok_or_else(|| {
                "the set message is a JSON object without a \"value\" field".to_string()
            })?,
            other => other,
        };
        match value {
            serde_json::Value::String(text) => text,
            serde_json::Value::Number(number) => number.to_string(),
            serde_json::Value::Bool(flag) => flag.to_string(),
            serde_json::Value::Null => {
                return Err("the set message's value must be text or a number, not null".into())
            }
            serde_json::Value::Array(_) => {
                return Err("the set message's value must be text or a number, not a list".into())
            }
            serde_json::Value::Object(_) => {
                return Err(
                    "the set message's value must be text or a number, not an object".into(),
                )
            }
        }
    } else {
        text.to_string()
    };
    let value = value.trim().to_string();
    if value.is_empty() {
        return Err("the set message is empty: send the value to write (e.g. 50 Hz)".into());
    }
    Ok(value)
}

#[cfg(test)]
mod tests {
    use super::*;

    const MAX: usize = 1024;

    #[test]
    fn set_values_are_taken_as_text_or_json() {
        let value = |payload: &[u8]| set_value(payload, MAX);
        assert_eq!(value(b"50").unwrap(), "50");
        assert_eq!(value(b" 50 Hz\n").unwrap(), "50 Hz");
        assert_eq!(
            value(b"\"command_enabled,frequency_enabled,run\"").unwrap(),
            "command_enabled,frequency_enabled,run"
        );
        assert_eq!(value(br#"{"value": 42.5}"#).unwrap(), "42.5");
        assert_eq!(value(br#"{"value": "50 Hz"}"#).unwrap(), "50 Hz");
        assert!(value(br#"{"v": 1}"#).unwrap_err().contains("\"value\""));
        assert!(value(b"").unwrap_err().contains("empty"));
        assert!(value(b"{oops").unwrap_err().contains("not"));
        assert!(value(&[0xff, 0xfe]).unwrap_err().contains("UTF-8"));
    }

    #[test]
    fn hostile_messages_are_refused_with_short_reasons() {
        let long = vec![b'5'; MAX + 1];
        assert!(set_value(&long, MAX)
            .unwrap_err()
            .contains("1025 bytes, more than any register's value (1024)"));
        let nested = format!("{}{}", "[".repeat(500), "]".repeat(500));
        let deep = format!("{{\"value\": {}{}}}", "[".repeat(400), "]".repeat(400));
        let list = format!("{{\"value\": [{}1]}}", "1,".repeat(300));
        for payload in [
            deep.as_str(),
            list.as_str(),
            "{\"value\": 1e999999}",
            "{\"value\": null}",
            "\"\"",
            "   ",
        ] {
            let error = set_value(payload.as_bytes(), MAX).unwrap_err();
            assert!(error.len() < 200, "{error}");
        }
        // Text that is not JSON's `{` or `"` is a value for the write's own checks (the
        // register's range, its codes) to refuse: a huge number, brackets.
        assert_eq!(set_value(b"1e999999", MAX).unwrap(), "1e999999");
        assert_eq!(set_value(nested.as_bytes(), MAX).unwrap(), nested);
    }
}
