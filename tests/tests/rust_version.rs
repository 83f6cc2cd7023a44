//! The declared `rust-version` is honest: no locked dependency of a published crate (its
//! normal and build dependencies, as `cargo metadata --locked` resolves them) declares a
//! newer Rust than the crate itself.
//!
//! The resolve is the workspace's (features unified over every member, and dependencies of
//! every platform where they can be had), so the walk can only see more than a user's
//! build, never less. A fresh clone has only this platform's crates on disk: the test then
//! lets cargo fetch the others, and without a network reads this platform's resolve alone
//! (said on stderr) instead of failing.

use std::collections::{BTreeSet, HashMap};
use std::path::Path;
use std::process::Command;

use serde_json::Value;

/// `"1.85"`, `"1.88.0"` as comparable numbers (missing parts are zero).
fn version(text: &str) -> Vec<u64> {
    let mut parts: Vec<u64> = text
        .split('.')
        .map(|part| part.trim().parse().unwrap_or(0))
        .collect();
    parts.resize(3, 0);
    parts
}

/// The workspace's resolve as `cargo metadata` prints it, read as widely as this machine
/// allows: every platform's dependencies from the local cache; failing that (a fresh clone
/// whose build fetched only this platform's crates), every platform's fetched from the
/// registry; failing that too (no network), this platform's alone, said on stderr.
fn metadata() -> Value {
    let host = host_triple();
    let attempts: [(&str, Vec<&str>); 3] = [
        ("every platform, offline", vec!["--offline"]),
        ("every platform, fetched", vec![]),
        (
            "this platform only, offline",
            vec!["--offline", "--filter-platform", host.as_str()],
        ),
    ];
    let mut failures = Vec::new();
    for (what, extra) in attempts {
        match cargo_metadata(&extra) {
            Ok(json) => {
                if !failures.is_empty() {
                    eprintln!(
                        "rust_version: read the resolve for {what}; before that:\n{}",
                        failures.join("\n")
                    );
                }
                return json;
            }
            Err(why) => failures.push(format!("  {what}: {why}")),
        }
    }
    panic!(
        "cargo metadata --locked failed every way (is Cargo.lock up to date?):\n{}",
        failures.join("\n")
    );
}

/// `cargo metadata --format-version 1 --locked` with `extra` arguments, at the workspace root.
fn cargo_metadata(extra: &[&str]) -> Result<Value, String> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let output = Command::new(cargo())
        .current_dir(&root)
        .args(["metadata", "--format-version", "1", "--locked"])
        .args(extra)
        .output()
        .map_err(|e| format!("cargo did not start: {e}"))?;
    if !output.status.success() {
        let stderr = String::from_utf8_lossy(&output.stderr);
        let last = stderr.lines().rev().find(|l| !l.trim().is_empty());
        return Err(last.unwrap_or("no message").trim().to_owned());
    }
    serde_json::from_slice(&output.stdout).map_err(|e| format!("not JSON: {e}"))
}

fn cargo() -> String {
    std::env::var("CARGO").unwrap_or_else(|_| "cargo".to_owned())
}

/// The host's target triple, from `rustc -vV` (the `host:` line).
fn host_triple() -> String {
    let rustc = std::env::var("RUSTC").unwrap_or_else(|_| "rustc".to_owned());
    let output = Command::new(rustc)
        .arg("-vV")
        .output()
        .expect("rustc -vV runs");
    String::from_utf8_lossy(&output.stdout)
        .lines()
        .find_map(|line| line.strip_prefix("host: "))
        .expect("rustc -vV names the host")
        .trim()
        .to_owned()
}

#[test]
fn no_locked_dependency_of_a_published_crate_needs_a_newer_rust() {
    let metadata = metadata();
    let packages: HashMap<&str, &Value> = metadata["packages"]
        .as_array()
        .expect("packages")
        .iter()
        .map(|p| (p["id"].as_str().expect("id"), p))
        .collect();
    let nodes: HashMap<&str, &Value> = metadata["resolve"]["nodes"]
        .as_array()
        .expect("resolve.nodes")
        .iter()
        .map(|n| (n["id"].as_str().expect("id"), n))
        .collect();
    // Published: workspace members without `publish = false` (cargo metadata: `publish: []`).
    let published: Vec<&str> = metadata["workspace_members"]
        .as_array()
        .expect("workspace_members")
        .iter()
        .filter_map(Value::as_str)
        .filter(|id| packages[id]["publish"] != serde_json::json!([]))
        .collect();
    let names: BTreeSet<&str> = published
        .iter()
        .map(|id| packages[id]["name"].as_str().expect("name"))
        .collect();
    for crate_name in [
        "vfd-runtime",
        "vfd-codegen",
        "vfd-macros",
        "vfd-drives",
        "vfd-cli",
    ] {
        assert!(
            names.contains(crate_name),
            "{crate_name} is not among the published crates {names:?}"
        );
    }

    let mut too_new = Vec::new();
    let mut walked = 0;
    for root in &published {
        let declared = packages[root]["rust_version"]
            .as_str()
            .unwrap_or_else(|| panic!("{root} declares no rust-version"));
        let mut seen = BTreeSet::new();
        let mut stack = vec![*root];
        while let Some(id) = stack.pop() {
            if !seen.insert(id) {
                continue;
            }
            let package = packages[id];
            if let Some(needs) = package["rust_version"].as_str() {
                if version(needs) > version(declared) {
                    too_new.push(format!(
                        "{} {} needs Rust {needs}, {} declares {declared}",
                        package["name"].as_str().unwrap_or("?"),
                        package["version"].as_str().unwrap_or("?"),
                        packages[root]["name"].as_str().unwrap_or("?"),
                    ));
                }
            }
            for dep in nodes[id]["deps"].as_array().into_iter().flatten() {
                let normal_or_build = dep["dep_kinds"]
                    .as_array()
                    .into_iter()
                    .flatten()
                    .any(|kind| kind["kind"].is_null() || kind["kind"] == "build");
                if normal_or_build {
                    stack.push(dep["pkg"].as_str().expect("pkg"));
                }
            }
        }
        walked += seen.len();
    }
    assert!(
        walked > 20,
        "the walk saw only {walked} packages: the dependency graph was not read"
    );
    too_new.sort();
    too_new.dedup();
    assert!(
        too_new.is_empty(),
        "locked dependencies need a newer Rust than declared (drop the feature that pulls \
         them in, or raise rust-version in Cargo.toml):\n{}",
        too_new.join("\n")
    );
}

#[test]
fn versions_compare_by_number() {
    assert!(version("1.88") > version("1.85"));
    assert!(version("1.85.1") > version("1.85"));
    assert!(version("1.100") > version("1.99.9"));
    assert_eq!(version("1.85"), version("1.85.0"));
}
