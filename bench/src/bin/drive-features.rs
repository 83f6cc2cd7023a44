//! One drive, one compile: build time of `vfd-drives` and size of a program that embeds its
//! catalogue (`drives/examples/catalogue.rs`), with each drive's feature alone and with all.
//!
//! `cargo run --release -p vfd-bench --bin drive-features` (run from the workspace root).
//! Release profile, in `target/drive-features/`; the dependencies are built first, then each
//! case rebuilds `vfd-drives` (its build script, which generates the drives, and the crate)
//! and the example, twice, and reports the faster.

use std::path::Path;
use std::process::Command;
use std::time::{Duration, Instant};

fn main() {
    let root = std::env::current_dir().expect("current dir");
    if !root.join("drives/protocols").is_dir() {
        eprintln!("drive-features: run from the workspace root");
        std::process::exit(1);
    }
    let mut ids: Vec<String> = std::fs::read_dir(root.join("drives"))
        .expect("drives/ lists")
        .filter_map(|entry| entry.ok())
        .filter_map(|entry| {
            let name = entry.file_name().into_string().ok()?;
            name.strip_suffix(".yaml").map(str::to_owned)
        })
        .collect();
    ids.sort();
    let target = root.join("target/drive-features");
    let mut cases: Vec<(String, Vec<String>)> = ids
        .iter()
        .map(|id| {
            (
                id.clone(),
                vec![
                    "--no-default-features".into(),
                    "--features".into(),
                    id.clone(),
                ],
            )
        })
        .collect();
    cases.push((format!("all {} drives", ids.len()), Vec::new()));
    // Dependencies first, so each case times vfd-drives and the example alone.
    build(&target, &cases[cases.len() - 1].1).expect("the workspace builds");
    println!("| drives compiled | build of vfd-drives + example | libvfd_drives.rlib | example binary (stripped) |");
    println!("|---|---|---|---|");
    let mut rows = Vec::new();
    for (name, args) in &cases {
        let mut best = Duration::MAX;
        for _ in 0..2 {
            clean(&target);
            let started = Instant::now();
            build(&target, args).expect("the case builds");
            best = best.min(started.elapsed());
        }
        let rlib = rlib_size(&target.join("release/deps"));
        let example = target.join("release/examples/catalogue");
        let stripped = target.join("release/examples/catalogue.stripped");
        let size = match Command::new("strip")
            .arg("-o")
            .arg(&stripped)
            .arg(&example)
            .status()
        {
            Ok(status) if status.success() => file_size(&stripped),
            _ => file_size(&example),
        };
        let row = format!(
            "| {name} | {:.1} s | {} | {} |",
            best.as_secs_f64(),
            kib(rlib),
            kib(size)
        );
        println!("{row}");
        rows.push((name.clone(), best, size));
    }
    if let (Some(smallest), Some(all)) = (
        rows[..rows.len() - 1].iter().min_by_key(|r| r.1),
        rows.last(),
    ) {
        println!(
            "\none drive ({}) / all: build {:.2}, binary {:.2}",
            smallest.0,
            smallest.1.as_secs_f64() / all.1.as_secs_f64(),
            smallest.2 as f64 / all.2 as f64
        );
    }
}

fn build(target: &Path, args: &[String]) -> Result<(), String> {
    let status = Command::new(std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into()))
        .args([
            "build",
            "--quiet",
            "--release",
            "-p",
            "vfd-drives",
            "--example",
            "catalogue",
        ])
        .args(args)
        .env("CARGO_TARGET_DIR", target)
        .status()
        .map_err(|e| e.to_string())?;
    if status.success() {
        Ok(())
    } else {
        Err(format!("cargo build {args:?} failed"))
    }
}

/// Removes what the cases rebuild: vfd-drives (library, build script output) and the example.
fn clean(target: &Path) {
    let status = Command::new(std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into()))
        .args(["clean", "--quiet", "--release", "-p", "vfd-drives"])
        .env("CARGO_TARGET_DIR", target)
        .status()
        .expect("cargo clean runs");
    assert!(status.success(), "cargo clean -p vfd-drives failed");
}

fn rlib_size(deps: &Path) -> u64 {
    std::fs::read_dir(deps)
        .map(|entries| {
            entries
                .filter_map(|entry| entry.ok())
                .filter(|entry| {
                    let name = entry.file_name();
                    let name = name.to_string_lossy();
                    name.starts_with("libvfd_drives-") && name.ends_with(".rlib")
                })
                .filter_map(|entry| entry.metadata().ok().map(|m| m.len()))
                .max()
                .unwrap_or(0)
        })
        .unwrap_or(0)
}

fn file_size(path: &Path) -> u64 {
    std::fs::metadata(path).map(|m| m.len()).unwrap_or(0)
}

fn kib(bytes: u64) -> String {
    format!("{:.0} KiB", bytes as f64 / 1024.0)
}
