//! Code tables: what every generated code-table enum shares. A generated enum holds its
//! `TABLE` of rows (value, code, English name, Chinese name); these const functions look
//! codes up in it, so the enum's methods are one call each.

/// One row of a generated code table: the value, its code, its English name and the
/// manual's Chinese name (empty when the manual gives none).
pub type CodeRow<T> = (T, u16, &'static str, &'static str);

/// The value whose code is `code`, if the table has it.
pub const fn find<T: Copy>(table: &[CodeRow<T>], code: u16) -> Option<T> {
    let mut index = 0;
    while index < table.len() {
        if table[index].1 == code {
            return Some(table[index].0);
        }
        index += 1;
    }
    None
}

/// The English and Chinese names of `code` (empty when the table does not have it).
pub const fn names<T>(table: &'static [CodeRow<T>], code: u16) -> (&'static str, &'static str) {
    let mut index = 0;
    while index < table.len() {
        if table[index].1 == code {
            return (table[index].2, table[index].3);
        }
        index += 1;
    }
    ("", "")
}

#[cfg(test)]
mod tests {
    use super::*;

    const TABLE: [CodeRow<char>; 2] = [('a', 1, "one", "一"), ('b', 7, "seven", "")];

    #[test]
    fn codes_are_found_by_their_number() {
        assert_eq!(find(&TABLE, 7), Some('b'));
        assert_eq!(find(&TABLE, 2), None);
        assert_eq!(names(&TABLE, 1), ("one", "一"));
        assert_eq!(names(&TABLE, 2), ("", ""));
    }
}
