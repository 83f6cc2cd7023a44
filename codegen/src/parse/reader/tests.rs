//! Reading whole files: every problem reported in one read, with its place and hint.

use super::*;
use crate::parse::tree;
use serde::Deserialize;

#[derive(Debug, Deserialize, JsonSchema, PartialEq)]
#[serde(deny_unknown_fields)]
struct Range {
    min: f64,
    max: f64,
}

#[derive(Debug, Deserialize, JsonSchema, PartialEq)]
#[serde(deny_unknown_fields, rename_all = "kebab-case")]
enum Access {
    ReadOnly,
    ReadWrite,
}

#[derive(Debug, Deserialize, JsonSchema, PartialEq)]
#[serde(deny_unknown_fields)]
struct Item {
    address: u16,
    name: String,
    range: Option<Range>,
    access: Option<Access>,
    #[serde(default)]
    tags: Vec<String>,
}

#[derive(Debug, Deserialize, JsonSchema, PartialEq)]
#[serde(deny_unknown_fields)]
struct File {
    items: Vec<Item>,
    pair: Option<[u16; 2]>,
}

fn read_text(text: &str) -> Outcome<File> {
    read(&tree::read(text).unwrap())
}

fn messages(outcome: &Outcome<File>) -> Vec<String> {
    outcome
        .problems
        .iter()
        .map(|p| {
            format!(
                "{}:{} {} | {} | {}",
                p.position.line,
                p.position.column,
                p.path,
                p.message,
                p.hint.as_deref().unwrap_or("")
            )
        })
        .collect()
}

#[test]
fn a_valid_file_reads_plainly() {
    let outcome = read_text(
        "items:\n  - { address: 0x10, name: a, range: { min: 0, max: 1.5 }, access: read-only }\npair: [1, 2]\n",
    );
    assert!(outcome.problems.is_empty(), "{:?}", outcome.problems);
    let file = outcome.value.unwrap();
    assert_eq!(file.items[0].address, 16);
    assert_eq!(file.items[0].range, Some(Range { min: 0.0, max: 1.5 }));
    assert_eq!(file.items[0].access, Some(Access::ReadOnly));
    assert_eq!(file.pair, Some([1, 2]));
}

#[test]
fn every_problem_is_reported_in_one_read() {
    let outcome = read_text(concat!(
        "items:\n",
        "  - { address: twelve, name: a }\n",
        "  - { adress: 3, name: b }\n",
        "  - { address: 4, name: c, access: readonly }\n",
        "  - { address: 70000, name: d, colour: red }\n",
        "pair: [1]\n",
    ));
    assert_eq!(
        messages(&outcome),
        [
            "2:16 items[0].address | expected a whole number from 0 to 65535, found the text `twelve` | numbers may be decimal or 0x-hex; text in quotes is text",
            "3:7 items[1].adress | unknown key `adress` | did you mean `address`?",
            "4:36 items[2].access | unknown value `readonly` | did you mean `read-only`?",
            "5:16 items[3].address | 70000 is out of range: expected a whole number from 0 to 65535 | ",
            "5:32 items[3].colour | unknown key `colour` | the keys allowed here are `address`, `name`, `range`, `access`, `tags`; drives/README.md says what each means",
            "6:1 pair | expected a list of 2 values, found 1 | ",
        ]
    );
    assert!(
        outcome.value.is_some(),
        "placeholders keep the file readable"
    );
    assert_eq!(
        outcome.incomplete,
        ["items[0]", "items[1]", "items[2]", "items[3]", "pair"]
    );
}

#[test]
fn missing_keys_are_all_reported() {
    let outcome = read_text("items:\n  - { tags: [] }\n");
    assert_eq!(
        messages(&outcome),
        [
            "2:7 items[0] | missing key `address` | add `address`; drives/README.md says what it holds",
            "2:7 items[0] | missing key `name` | add `name`; drives/README.md says what it holds",
        ]
    );
}

#[test]
fn a_key_indented_too_little_is_reported_where_it_is() {
    let outcome = read_text(concat!(
        "items:\n",
        "  - address: 1\n",
        "    name: a\n",
        "    range:\n",
        "      min: 0\n",
        "    max: 10\n",
    ));
    assert_eq!(
        messages(&outcome),
        ["6:5 items[0].max | `max` is not a key here: it belongs to `range` (line 4), and is indented too little | indent `max` like the other keys under `range`"]
    );
}

#[test]
fn a_key_indented_too_far_is_reported_where_it_is() {
    let outcome = read_text(concat!(
        "items:\n",
        "  - address: 1\n",
        "    range:\n",
        "      min: 0\n",
        "      max: 10\n",
        "      name: a\n",
    ));
    assert_eq!(
        messages(&outcome),
        ["6:7 items[0].range.name | `name` is not a key of `range`: it is indented too far | indent `name` like the keys of the mapping around it"]
    );
}

#[test]
fn a_key_the_enclosing_mapping_already_has_is_just_unknown() {
    let outcome = read_text(concat!(
        "items:\n",
        "  - address: 1\n",
        "    name: a\n",
        "    range:\n",
        "      min: 0\n",
        "      max: 10\n",
        "      name: b\n",
    ));
    assert_eq!(
        messages(&outcome),
        ["7:7 items[0].range.name | unknown key `name` | the keys allowed here are `min`, `max`; drives/README.md says what each means"]
    );
}

#[test]
fn a_duplicate_key_is_reported() {
    let outcome = read_text("items:\n  - { address: 1, name: a, name: b }\n");
    assert_eq!(
        messages(&outcome),
        ["2:28 items[0].name | key `name` appears twice in this mapping (first at line 2) | keep one of them"]
    );
}
