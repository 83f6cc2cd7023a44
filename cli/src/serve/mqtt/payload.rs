//! What goes on the wire: the JSON of a state and of a write outcome, and the value a `set`
//! message carries (plain text as `vfd write` takes it, a JSON string, or
//! `{"value": ...}`).

use crate::serve::event::{Reading, WriteOutcome};

/// A register's retained state: the reading's fields as JSON.
pub fn state(reading: &Reading) -> Vec<u8> {
    serde_json::to_vec(reading).unwrap_or_default()
}

/// A write's outcome as JSON.
pub fn outcome(outcome: &WriteOutcome) -> Vec<u8> {
    serde_json::to_vec(outcome).unwrap_or_default()
}

/// The value text of a `set` message: `50`, `50 Hz`, a code name, bit fields; or the same
/// as a JSON string (`"50 Hz"`), or an object `{"value": 50}` / `{"value": "50 Hz"}`.
pub fn set_value(payload: &[u8]) -> Result<String, String> {
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
            other => {
                return Err(format!(
                    "the set message's value must be text or a number, not {other}"
                ))
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

    #[test]
    fn set_values_are_taken_as_text_or_json() {
        assert_eq!(set_value(b"50").unwrap(), "50");
        assert_eq!(set_value(b" 50 Hz\n").unwrap(), "50 Hz");
        assert_eq!(set_value(b"\"run,forward\"").unwrap(), "run,forward");
        assert_eq!(set_value(br#"{"value": 42.5}"#).unwrap(), "42.5");
        assert_eq!(set_value(br#"{"value": "50 Hz"}"#).unwrap(), "50 Hz");
        assert!(set_value(br#"{"v": 1}"#).unwrap_err().contains("\"value\""));
        assert!(set_value(b"").unwrap_err().contains("empty"));
        assert!(set_value(b"{oops").unwrap_err().contains("not"));
        assert!(set_value(&[0xff, 0xfe]).unwrap_err().contains("UTF-8"));
    }
}
