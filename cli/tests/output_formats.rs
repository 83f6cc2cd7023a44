//! `--format text|json|jsonl|csv`: each format of each command parses (serde_json, the csv
//! crate), carries the fields docs/output.md documents, and the values are right.

mod common;

use common::Sim;
use std::process::{Command, Output};

/// The fields of a value record, in order (docs/output.md documents each).
const VALUE_FIELDS: [&str; 17] = [
    "drive",
    "code",
    "name",
    "name_zh",
    "value",
    "unit",
    "raw",
    "text",
    "time",
    "epoch_ms",
    "tripped",
    "stale",
    "error_kind",
    "error_code",
    "error_meaning",
    "errors",
    "sample",
];

/// The fields of a register record (`info`).
const REGISTER_FIELDS: [&str; 11] = [
    "drive", "code", "name", "name_zh", "address", "unit", "min", "max", "default", "access",
    "ram_only",
];

/// The fields of a drive record (`list`).
const DRIVE_FIELDS: [&str; 7] = [
    "drive",
    "vendor",
    "model",
    "name",
    "name_zh",
    "protocols",
    "file",
];

fn vfd(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_vfd"))
        .args(args)
        .output()
        .expect("vfd runs")
}

fn ok(output: &Output) -> String {
    assert!(
        output.status.success(),
        "{:?}\n{}",
        output.status,
        common::text(output)
    );
    String::from_utf8(output.stdout.clone()).expect("UTF-8")
}

/// The objects of a `json` document (an array).
fn json_records(text: &str) -> Vec<serde_json::Map<String, serde_json::Value>> {
    let document: serde_json::Value = serde_json::from_str(text).expect("one JSON document");
    document
        .as_array()
        .expect("an array")
        .iter()
        .map(|r| r.as_object().expect("objects").clone())
        .collect()
}

/// The objects of a `jsonl` output, one per line.
fn jsonl_records(text: &str) -> Vec<serde_json::Map<String, serde_json::Value>> {
    text.lines()
        .map(|line| {
            serde_json::from_str::<serde_json::Value>(line)
                .expect("a JSON object per line")
                .as_object()
                .expect("an object")
                .clone()
        })
        .collect()
}

/// The header and rows of a `csv` output.
fn csv_rows(text: &str) -> (Vec<String>, Vec<Vec<String>>) {
    let mut reader = csv::Reader::from_reader(text.as_bytes());
    let header = reader
        .headers()
        .expect("a header row")
        .iter()
        .map(str::to_owned)
        .collect();
    let rows = reader
        .records()
        .map(|r| {
            r.expect("an RFC 4180 row")
                .iter()
                .map(str::to_owned)
                .collect()
        })
        .collect();
    (header, rows)
}

/// The record's field names, sorted (serde_json's map does not keep the order; the CSV
/// header shows it).
fn keys(record: &serde_json::Map<String, serde_json::Value>) -> Vec<&str> {
    let mut keys: Vec<&str> = record.keys().map(String::as_str).collect();
    keys.sort_unstable();
    keys
}

/// `fields`, sorted.
fn sorted(fields: &[&'static str]) -> Vec<&'static str> {
    let mut fields = fields.to_vec();
    fields.sort_unstable();
    fields
}

/// FH (maximum frequency) read fresh from the virtual yd1000: 80.00 Hz, raw 8000.
fn assert_fh(record: &serde_json::Map<String, serde_json::Value>, tripped: bool) {
    assert_eq!(keys(record), sorted(&VALUE_FIELDS), "{record:?}");
    assert_eq!(record["drive"], "yd1000");
    assert_eq!(record["code"], "FH");
    assert_eq!(record["name"], "Maximum frequency");
    assert_eq!(record["name_zh"], "最高频率");
    assert_eq!(record["value"], 80.0);
    assert_eq!(record["unit"], "Hz");
    assert_eq!(record["raw"], 8000);
    assert_eq!(record["text"], "80.00 Hz");
    assert_eq!(record["tripped"], tripped);
    assert_eq!(record["stale"], false);
    assert!(record["error_kind"].is_null());
    let time = record["time"].as_str().expect("a time");
    assert!(
        time.len() == 24 && time.ends_with('Z') && time.as_bytes()[10] == b'T',
        "RFC 3339 UTC with milliseconds: {time}"
    );
    assert!(record["epoch_ms"].as_u64().expect("epoch ms") > 1_600_000_000_000);
}

#[test]
fn read_gives_every_format_with_the_documented_fields() {
    let sim = Sim::start("yd1000", "binary");
    let read = |format: &str| {
        ok(&sim.vfd(
            "yd1000",
            "binary",
            &["read", "FH", "FA01", "--format", format],
        ))
    };

    let records = json_records(&read("json"));
    assert_eq!(records.len(), 2);
    assert_fh(&records[0], false);
    assert_eq!(records[1]["code"], "FA01");
    assert_eq!(records[1]["sample"], 1);

    let records = jsonl_records(&read("jsonl"));
    assert_eq!(records.len(), 2);
    assert_fh(&records[0], false);

    let (header, rows) = csv_rows(&read("csv"));
    assert_eq!(header, VALUE_FIELDS);
    assert_eq!(rows.len(), 2);
    let row = |name: &str| &rows[0][header.iter().position(|h| h == name).unwrap()];
    assert_eq!(row("code"), "FH");
    assert_eq!(row("value"), "80.0");
    assert_eq!(row("unit"), "Hz");
    assert_eq!(row("raw"), "8000");
    assert_eq!(row("tripped"), "false");
    assert_eq!(row("error_kind"), "", "null is an empty field");

    // Text stays the default, for people.
    let text = read("text");
    assert!(
        text.starts_with("FH      Maximum frequency (最高频率) = 80.00 Hz"),
        "{text}"
    );
    assert_eq!(
        text,
        ok(&sim.vfd("yd1000", "binary", &["read", "FH", "FA01"]))
    );
}

#[test]
fn a_tripped_drive_says_so_in_the_records() {
    let sim = Sim::start_with("yd1000", "binary", &["--trip", "5"]);
    let out = ok(&sim.vfd("yd1000", "binary", &["read", "FH", "--format", "jsonl"]));
    let records = jsonl_records(&out);
    assert_fh(&records[0], true);
}

#[test]
fn watch_gives_every_format_one_record_per_sample_and_value() {
    let sim = Sim::start("yd1000", "binary");
    let watch = |format: &str| {
        ok(&sim.vfd(
            "yd1000",
            "binary",
            &[
                "watch",
                "FH",
                "FA01",
                "--count",
                "3",
                "--interval",
                "50",
                "--format",
                format,
            ],
        ))
    };
    let records = json_records(&watch("json"));
    assert_eq!(records.len(), 6);
    assert_fh(&records[4], false);
    assert_eq!(records[4]["sample"], 3);
    assert_eq!(records[5]["errors"], 0);

    let records = jsonl_records(&watch("jsonl"));
    assert_eq!(records.len(), 6);
    let samples: Vec<u64> = records
        .iter()
        .map(|r| r["sample"].as_u64().unwrap())
        .collect();
    assert_eq!(samples, [1, 1, 2, 2, 3, 3]);
    assert_fh(&records[2], false);

    let (header, rows) = csv_rows(&watch("csv"));
    assert_eq!(header, VALUE_FIELDS);
    assert_eq!(rows.len(), 6);
    assert!(rows.iter().all(|row| row.len() == VALUE_FIELDS.len()));
}

#[test]
fn info_and_list_give_every_format() {
    let records = json_records(&ok(&vfd(&["info", "yd1000", "FH", "--format", "json"])));
    assert_eq!(records.len(), 1);
    let fh = &records[0];
    assert_eq!(keys(fh), sorted(&REGISTER_FIELDS));
    assert_eq!(fh["code"], "FH");
    assert_eq!(fh["unit"], "Hz");
    assert_eq!(fh["default"], 80.0);
    assert_eq!(fh["access"], "read-write");

    let all = jsonl_records(&ok(&vfd(&["info", "yd1000", "--format", "jsonl"])));
    assert!(all.len() > 10, "every register: {}", all.len());
    assert!(all.iter().any(|r| r["code"] == "FA01"));

    let (header, rows) = csv_rows(&ok(&vfd(&["info", "yd1000", "--format", "csv"])));
    assert_eq!(header, REGISTER_FIELDS);
    assert_eq!(rows.len(), all.len());

    let drives = json_records(&ok(&vfd(&["list", "--format", "json"])));
    assert_eq!(keys(&drives[0]), sorted(&DRIVE_FIELDS));
    let yd1000 = drives
        .iter()
        .find(|d| d["drive"] == "yd1000")
        .expect("yd1000 listed");
    assert!(yd1000["protocols"].as_str().unwrap().contains("binary"));
    assert_eq!(
        jsonl_records(&ok(&vfd(&["list", "--format", "jsonl"]))).len(),
        drives.len()
    );
    let (header, rows) = csv_rows(&ok(&vfd(&["list", "--format", "csv"])));
    assert_eq!(header, DRIVE_FIELDS);
    assert_eq!(rows.len(), drives.len());
}

#[test]
fn decode_gives_every_format_and_json_stays_its_alias() {
    // A write of FA01 = 60.00 Hz (raw 6000 = 1770h).
    let frame = "2F 50 FA 01 17 70 01";
    let via_json = ok(&vfd(&["decode", "--json", frame]));
    let via_format = ok(&vfd(&["decode", "--format", "json", frame]));
    assert_eq!(via_json, via_format);
    let object: serde_json::Value = serde_json::from_str(&via_json).expect("one object");
    assert_eq!(object["valid"], true);
    let record = object["record"].as_object().expect("the value record");
    assert_eq!(keys(record), sorted(&VALUE_FIELDS));
    assert_eq!(record["code"], "FA01");
    assert_eq!(record["raw"], 6000);
    assert_eq!(record["value"], 60.0);

    let records = jsonl_records(&ok(&vfd(&["decode", "--format", "jsonl", frame])));
    assert_eq!(records.len(), 1);
    assert_eq!(keys(&records[0]), sorted(&VALUE_FIELDS));
    assert_eq!(records[0]["value"], 60.0);
    assert!(records[0]["time"].is_null(), "a captured frame has no time");

    let (header, rows) = csv_rows(&ok(&vfd(&["decode", "--format", "csv", frame])));
    assert_eq!(header, VALUE_FIELDS);
    assert_eq!(rows.len(), 1);

    // A value with commas (a command word's fields) is quoted, and parses back whole.
    let command_word = "2F 50 FA 00 C4 00 3D";
    let out = ok(&vfd(&[
        "decode",
        "--drive",
        "yd1000",
        "--format",
        "csv",
        command_word,
    ]));
    assert!(
        out.contains("\"C400h: command_enabled, frequency_enabled, run\""),
        "{out}"
    );
    let (header, rows) = csv_rows(&out);
    let text = header.iter().position(|h| h == "text").unwrap();
    assert_eq!(
        rows[0][text],
        "C400h: command_enabled, frequency_enabled, run"
    );
    assert_eq!(rows[0].len(), VALUE_FIELDS.len());
}

#[test]
fn backup_lists_what_it_read_in_every_format() {
    let sim = Sim::start("yd1000", "binary");
    let dir = std::env::temp_dir().join(format!("vfd-output-backup-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("b.yaml");
    let file = file.to_str().unwrap();
    let out = sim.vfd(
        "yd1000",
        "binary",
        &["backup", "--to", file, "--format", "jsonl"],
    );
    let records = jsonl_records(&ok(&out));
    assert!(records.len() > 10, "{}", records.len());
    let fh = records
        .iter()
        .find(|r| r["code"] == "FH")
        .expect("FH listed");
    assert_eq!(fh["value"], 80.0);
    assert_eq!(fh["tripped"], false, "the replies carry the trip flag");
    assert!(String::from_utf8_lossy(&out.stderr).contains("saved"));
    let (header, rows) = csv_rows(&ok(&sim.vfd(
        "yd1000",
        "binary",
        &["backup", "--to", file, "--format", "csv"],
    )));
    assert_eq!(header, VALUE_FIELDS);
    assert_eq!(rows.len(), records.len());
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn every_field_is_documented() {
    let doc = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../docs/output.md"))
        .expect("docs/output.md");
    for field in VALUE_FIELDS
        .iter()
        .chain(&REGISTER_FIELDS)
        .chain(&DRIVE_FIELDS)
    {
        assert!(
            doc.contains(&format!("| `{field}` |")),
            "docs/output.md lacks `{field}`"
        );
    }
    let readme = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../README.md"))
        .expect("README.md");
    assert!(
        readme.contains("docs/output.md"),
        "the README links the reference"
    );
}

#[test]
fn without_a_trip_flag_in_the_reply_the_status_word_tells_or_it_is_null() {
    // Modbus replies carry no trip flag: the FC 51's status word (its trip bit) does.
    let sim = Sim::start_with("fc51", "modbus", &["--trip", "5"]);
    let records = jsonl_records(&ok(&sim.vfd(
        "fc51",
        "modbus",
        &["read", "STW", "303", "--format", "jsonl"],
    )));
    assert_eq!(records.len(), 2);
    assert!(records.iter().all(|r| r["tripped"] == true), "{records:?}");
    // Without the status word no second read is made: unknown.
    let records = jsonl_records(&ok(&sim.vfd(
        "fc51",
        "modbus",
        &["read", "303", "--format", "jsonl"],
    )));
    assert!(records[0]["tripped"].is_null(), "{records:?}");
}
