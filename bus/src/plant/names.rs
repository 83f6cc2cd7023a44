//! Bus and drive names: they become MQTT topic segments (`vfd/BUS/DRIVE/CODE`) and JSON
//! record fields, so they are lower-case letters, digits, `_` and `-` only: no `/`, `+` or
//! `#` (topic separators and wildcards), no spaces, no upper case (topics are
//! case-sensitive; two names differing in case only would confuse their readers).

/// The longest name.
pub const LONGEST: usize = 64;

/// What is wrong with `name` as a topic segment, and a hint; `None` when it is fine.
pub fn problem(name: &str) -> Option<(String, String)> {
    let rule = "names become MQTT topic segments: lower-case letters, digits, `_` and `-`";
    if name.is_empty() {
        return Some(("the name is empty".to_owned(), rule.to_owned()));
    }
    if name.chars().count() > LONGEST {
        return Some((
            format!("the name `{name}` is longer than {LONGEST} characters"),
            "shorten it".to_owned(),
        ));
    }
    let bad: Vec<char> = name
        .chars()
        .filter(|c| !(c.is_ascii_lowercase() || c.is_ascii_digit() || matches!(c, '_' | '-')))
        .collect();
    if bad.is_empty() {
        return None;
    }
    let shown: Vec<String> = bad.iter().map(|c| format!("`{c}`")).collect();
    let mut seen = shown.clone();
    seen.dedup();
    let suggestion: String = name
        .to_lowercase()
        .chars()
        .map(|c| {
            if c.is_ascii_lowercase() || c.is_ascii_digit() || c == '-' {
                c
            } else {
                '_'
            }
        })
        .collect();
    Some((
        format!(
            "the name `{name}` has {} {}",
            if seen.len() == 1 {
                "the character"
            } else {
                "the characters"
            },
            seen.join(", ")
        ),
        format!("{rule}; e.g. `{suggestion}`"),
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn topic_safe_names_pass() {
        for name in ["line1", "pump-2", "hall_a", "0"] {
            assert_eq!(problem(name), None, "{name}");
        }
    }

    #[test]
    fn wildcards_separators_case_and_empty_are_refused() {
        for (name, says) in [
            ("", "empty"),
            ("a/b", "`/`"),
            ("a+", "`+`"),
            ("#", "`#`"),
            ("Pump1", "`P`"),
            ("pump 1", "` `"),
        ] {
            let (message, hint) = problem(name).unwrap();
            assert!(message.contains(says), "{name}: {message}");
            assert!(hint.contains("topic"), "{hint}");
        }
        assert!(problem(&"a".repeat(65)).is_some());
        assert!(problem("Pump 1").unwrap().1.contains("`pump_1`"));
    }
}
