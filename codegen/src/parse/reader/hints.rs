//! Hints for problems: the known name closest to a misspelt one, and what to write
//! instead.

/// Levenshtein distance between two short names.
pub(crate) fn edit_distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut previous: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut current = vec![i + 1];
        for (j, cb) in b.iter().enumerate() {
            let substitution = previous[j] + usize::from(ca != *cb);
            current.push(substitution.min(previous[j + 1] + 1).min(current[j] + 1));
        }
        previous = current;
    }
    previous[b.len()]
}

/// The known name closest to `written`, when at most a third of its letters differ (or it
/// differs only in case, `-` and `_`).
pub fn closest<'k>(written: &str, known: &[&'k str]) -> Option<&'k str> {
    let folded = |s: &str| s.to_lowercase().replace('-', "_");
    if let Some(same) = known.iter().find(|k| folded(k) == folded(written)) {
        return Some(same);
    }
    let (distance, best) = known
        .iter()
        .map(|candidate| (edit_distance(written, candidate), *candidate))
        .min_by_key(|(distance, _)| *distance)?;
    (distance <= (written.chars().count() / 3).max(1)).then_some(best)
}

pub(super) fn list(names: &[&str]) -> String {
    names
        .iter()
        .map(|name| format!("`{name}`"))
        .collect::<Vec<_>>()
        .join(", ")
}

/// "did you mean `x`?", or the list of what is allowed.
pub(super) fn unknown_hint(written: &str, known: &[&str], what: &str) -> String {
    if written.contains(' ') && what == "key" {
        return "inside `{ ... }` an unquoted comma ends the value: put text containing commas in quotes".to_owned();
    }
    match closest(written, known) {
        Some(best) => format!("did you mean `{best}`?"),
        None if known.is_empty() => format!("no {what} is allowed here"),
        None => format!(
            "the {what}s allowed here are {}; drives/README.md says what each means",
            list(known)
        ),
    }
}

pub(super) fn hint_for_type(expected: &str) -> &'static str {
    if expected.starts_with("a whole number") || expected == "a number" {
        "numbers may be decimal or 0x-hex; text in quotes is text"
    } else if expected.starts_with("a mapping") {
        "write `key: value` lines indented under the key, or `{ key: value, ... }`"
    } else if expected.starts_with("a list") {
        "write `- item` lines indented under the key, or `[a, b]`"
    } else {
        "check the value against drives/README.md"
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn close_names_are_suggested() {
        assert_eq!(closest("fromat", &["literal", "format"]), Some("format"));
        assert_eq!(
            closest("readonly", &["read-only", "read-write"]),
            Some("read-only")
        );
        assert_eq!(closest("register", &["parameter", "coil"]), None);
    }
}
