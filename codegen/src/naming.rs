//! Turns description identifiers into Rust names.

/// `deceleration_time_1` -> `DecelerationTime1`.
pub fn type_name(id: &str) -> String {
    id.split('_')
        .filter(|part| !part.is_empty())
        .map(|part| {
            let mut chars = part.chars();
            match chars.next() {
                Some(first) => first.to_ascii_uppercase().to_string() + chars.as_str(),
                None => String::new(),
            }
        })
        .collect()
}

/// `P.195` -> `P195`: the Rust type name a register alias gives, its ASCII letters and
/// digits with the first in upper case; `None` when they do not begin with a letter.
pub fn alias_type_name(alias: &str) -> Option<String> {
    let kept: String = alias.chars().filter(char::is_ascii_alphanumeric).collect();
    let mut chars = kept.chars();
    let first = chars.next().filter(char::is_ascii_alphabetic)?;
    Some(first.to_ascii_uppercase().to_string() + chars.as_str())
}

/// `vf-as1` -> `vf_as1`: a drive or protocol-file id as a Rust module name.
pub fn module_name(id: &str) -> String {
    id.replace('-', "_")
}

/// `toshiba-ascii` or `ascii` -> `ASCII` / `TOSHIBA_ASCII`.
pub fn const_name(id: &str) -> String {
    id.replace('-', "_").to_ascii_uppercase()
}

/// Rust keywords cannot be field or method names without `r#`.
pub fn method_name(id: &str) -> String {
    const KEYWORDS: &[&str] = &[
        "as", "break", "const", "continue", "crate", "else", "enum", "extern", "false", "fn",
        "for", "if", "impl", "in", "let", "loop", "match", "mod", "move", "mut", "pub", "ref",
        "return", "self", "static", "struct", "super", "trait", "true", "type", "unsafe", "use",
        "where", "while", "async", "await", "dyn", "try", "gen",
    ];
    if KEYWORDS.contains(&id) {
        format!("{id}_")
    } else {
        id.to_owned()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names() {
        assert_eq!(type_name("deceleration_time_1"), "DecelerationTime1");
        assert_eq!(type_name("bps_1200"), "Bps1200");
        assert_eq!(const_name("ascii"), "ASCII");
        assert_eq!(module_name("vf-as1"), "vf_as1");
        assert_eq!(method_name("run"), "run");
        assert_eq!(method_name("type"), "type_");
        assert_eq!(alias_type_name("P.195").as_deref(), Some("P195"));
        assert_eq!(alias_type_name("p.33").as_deref(), Some("P33"));
        assert_eq!(alias_type_name("10700"), None);
    }
}
