//! Plain scalars as YAML 1.2's core schema reads them: null, booleans, integers (decimal,
//! 0x-hex, 0o-octal), floats and text.

use crate::parse::tree::{Node, Value};

/// A scalar as YAML 1.2's core schema reads a plain one.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Scalar<'t> {
    Null,
    Bool(bool),
    Int(i128),
    Float(f64),
    Text(&'t str),
}

pub(super) fn resolve(node: &Node) -> Option<Scalar<'_>> {
    let Value::Scalar { text, plain } = &node.value else {
        return None;
    };
    if !plain {
        return Some(Scalar::Text(text));
    }
    Some(match text.as_str() {
        "" | "~" | "null" | "Null" | "NULL" => Scalar::Null,
        "true" | "True" | "TRUE" => Scalar::Bool(true),
        "false" | "False" | "FALSE" => Scalar::Bool(false),
        ".inf" | ".Inf" | ".INF" | "+.inf" | "+.Inf" | "+.INF" => Scalar::Float(f64::INFINITY),
        "-.inf" | "-.Inf" | "-.INF" => Scalar::Float(f64::NEG_INFINITY),
        ".nan" | ".NaN" | ".NAN" => Scalar::Float(f64::NAN),
        other => integer(other)
            .map(Scalar::Int)
            .or_else(|| float(other).map(Scalar::Float))
            .unwrap_or(Scalar::Text(other)),
    })
}

fn integer(text: &str) -> Option<i128> {
    let (negative, digits) = match text.as_bytes().first()? {
        b'-' => (true, &text[1..]),
        b'+' => (false, &text[1..]),
        _ => (false, text),
    };
    let (radix, digits) = if let Some(hex) = digits.strip_prefix("0x") {
        (16, hex)
    } else if let Some(octal) = digits.strip_prefix("0o") {
        (8, octal)
    } else {
        (10, digits)
    };
    if digits.is_empty() || !digits.chars().all(|c| c.is_digit(radix)) {
        return None;
    }
    let value = i128::from_str_radix(digits, radix).ok()?;
    Some(if negative { -value } else { value })
}

fn float(text: &str) -> Option<f64> {
    let digits = text.trim_start_matches(['-', '+']);
    let numeric = digits.starts_with(|c: char| c.is_ascii_digit() || c == '.')
        && digits.chars().any(|c| c.is_ascii_digit())
        && digits
            .chars()
            .all(|c| c.is_ascii_digit() || matches!(c, '.' | 'e' | 'E' | '-' | '+'));
    numeric.then(|| text.parse().ok()).flatten()
}

/// How a node is named in "found ..." messages.
pub(super) fn found(node: &Node) -> String {
    match resolve(node) {
        Some(Scalar::Null) => "nothing".to_owned(),
        Some(Scalar::Bool(value)) => format!("`{value}`"),
        Some(Scalar::Int(_) | Scalar::Float(_)) => {
            format!("the number {}", node.text().unwrap_or(""))
        }
        Some(Scalar::Text(text)) => format!("the text `{text}`"),
        None => match node.value {
            Value::Sequence(_) => "a list".to_owned(),
            _ => "a mapping (keys with values)".to_owned(),
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::parse::tree;

    #[test]
    fn plain_scalars_follow_the_core_schema() {
        let node = |text: &str| tree::read(text).unwrap();
        assert_eq!(resolve(&node("0x1F")), Some(Scalar::Int(31)));
        assert_eq!(resolve(&node("-12")), Some(Scalar::Int(-12)));
        assert_eq!(resolve(&node("0o17")), Some(Scalar::Int(15)));
        assert_eq!(resolve(&node("1.5e3")), Some(Scalar::Float(1500.0)));
        assert_eq!(resolve(&node("'12'")), Some(Scalar::Text("12")));
        assert_eq!(resolve(&node("~")), Some(Scalar::Null));
        assert_eq!(resolve(&node("inf")), Some(Scalar::Text("inf")));
        assert_eq!(resolve(&node("FH")), Some(Scalar::Text("FH")));
        assert_eq!(resolve(&node("1e")), Some(Scalar::Text("1e")));
    }
}
