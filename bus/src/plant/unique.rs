//! What must be unique: bus names and ports in the plant, drive names and station
//! addresses on a bus. Each repeat is reported where it is, naming the line of the first.

use super::problems::Problems;

/// What is compared, for the message: `("bus name", "buses[1].name", "line1")`.
pub struct Keyed<'k> {
    /// The YAML path of the value.
    pub path: String,
    /// The value, as compared.
    pub key: &'k str,
}

/// Reports every value of `items` that an earlier one already has. `what` names the value
/// (`bus name`), `hint` says what to do.
pub fn check(what: &str, items: &[Keyed<'_>], hint: &str, problems: &mut Problems<'_>) {
    for (index, item) in items.iter().enumerate() {
        if let Some(first) = items[..index]
            .iter()
            .find(|earlier| earlier.key == item.key)
        {
            let line = problems.line(&first.path);
            problems.error(
                &item.path,
                format!("{what} `{}` is used twice (first at line {line})", item.key),
                hint,
            );
        }
    }
}
