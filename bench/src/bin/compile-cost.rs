//! Compile cost of generated APIs: clean, no-op and after-one-edit build times of a crate
//! that generates drives from YAML in its build script, with lines of generated code.
//!
//! `cargo run --release -p vfd-bench --bin compile-cost [-- all|described|1000|10000]`
//! (run from the workspace root). Scratch crates live in `target/compile-cost/`.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::{Duration, Instant};

struct Case {
    name: &'static str,
    drives: Vec<(String, String)>,
}

fn main() {
    let which = std::env::args().nth(1).unwrap_or_else(|| "all".to_owned());
    let root = std::env::current_dir().expect("current dir");
    if !root.join("drives/protocols").is_dir() {
        eprintln!("compile-cost: run from the workspace root");
        std::process::exit(1);
    }
    let described: Vec<(String, String)> = ["yd1000", "fc51"]
        .iter()
        .map(|id| {
            (
                id.to_string(),
                std::fs::read_to_string(root.join(format!("drives/{id}.yaml")))
                    .expect("drive file"),
            )
        })
        .collect();
    let mut cases = Vec::new();
    if matches!(which.as_str(), "all" | "described") {
        cases.push(Case {
            name: "described",
            drives: described,
        });
    }
    for size in [1_000usize, 10_000] {
        if which == "all" || which == size.to_string() {
            let id = format!("synthetic_{size}");
            cases.push(Case {
                name: if size == 1_000 {
                    "synthetic-1000"
                } else {
                    "synthetic-10000"
                },
                drives: vec![(id.clone(), vfd_bench::synthetic_drive(&id, size))],
            });
        }
    }
    let scratch = root.join("target/compile-cost");
    let target = scratch.join("target");
    println!("| crate | registers | generated Rust lines | lines per register (all / `registers` module) | clean build | no-op build | rebuild after editing one YAML | rebuilt after the edit |");
    println!("|---|---|---|---|---|---|---|---|");
    for case in cases {
        match measure(&root, &scratch, &target, &case) {
            Ok(row) => println!("{row}"),
            Err(message) => println!("| {} | failed: {message} |", case.name),
        }
    }
}

fn cargo(crate_dir: &Path, target: &Path, args: &[&str]) -> Result<(Duration, String), String> {
    let start = Instant::now();
    let output = Command::new(env!("CARGO"))
        .args(args)
        .current_dir(crate_dir)
        .env("CARGO_TARGET_DIR", target)
        .env_remove("CARGO_ENCODED_RUSTFLAGS")
        .output()
        .map_err(|e| e.to_string())?;
    let elapsed = start.elapsed();
    let log = String::from_utf8_lossy(&output.stderr).into_owned();
    if !output.status.success() {
        return Err(log.lines().rev().take(15).collect::<Vec<_>>().join(" / "));
    }
    Ok((elapsed, log))
}

fn measure(root: &Path, scratch: &Path, target: &Path, case: &Case) -> Result<String, String> {
    let dir = scratch.join(case.name);
    let crate_name = format!("drives_{}", case.name.replace('-', "_"));
    std::fs::create_dir_all(dir.join("src")).map_err(|e| e.to_string())?;
    std::fs::create_dir_all(dir.join("drives")).map_err(|e| e.to_string())?;
    let runtime = root.join("runtime");
    let codegen = root.join("codegen");
    std::fs::write(
        dir.join("Cargo.toml"),
        format!(
            "[package]\nname = \"{crate_name}\"\nversion = \"0.0.0\"\nedition = \"2021\"\npublish = false\n\n[workspace]\n\n[dependencies]\nvfd-runtime = {{ path = {runtime:?} }}\n\n[build-dependencies]\nvfd-codegen = {{ path = {codegen:?} }}\n"
        ),
    )
    .map_err(|e| e.to_string())?;
    let protocols = root.join("drives/protocols");
    std::fs::write(
        dir.join("build.rs"),
        format!(
            "fn main() {{\n    let out = std::path::PathBuf::from(std::env::var_os(\"OUT_DIR\").unwrap());\n    let builder = vfd_codegen::Builder::new().drives_in(\"drives\").unwrap().protocols_dir({protocols:?}).out_dir(&out).cargo_metadata(true);\n    if let Err(e) = builder.generate() {{ vfd_codegen::fail_build(&e); }}\n}}\n"
        ),
    )
    .map_err(|e| e.to_string())?;
    std::fs::write(
        dir.join("src/lib.rs"),
        "//! Generated drives.\ninclude!(concat!(env!(\"OUT_DIR\"), \"/drives.rs\"));\n",
    )
    .map_err(|e| e.to_string())?;
    let mut registers = 0;
    for (id, text) in &case.drives {
        vfd_codegen::write_if_changed(&dir.join(format!("drives/{id}.yaml")), text)
            .map_err(|e| e.to_string())?;
        registers +=
            text.matches("\n  - { address:").count() + text.matches("\n  - { space:").count();
    }
    // Dependencies first, so the clean build below measures this crate alone.
    cargo(&dir, target, &["build"])?;
    cargo(&dir, target, &["clean", "-p", &crate_name])?;
    let (clean, _) = cargo(&dir, target, &["build"])?;
    let (noop, noop_log) = cargo(&dir, target, &["build"])?;
    let noop_rebuilt = noop_log.contains("Compiling");
    let (first_id, first_text) = &case.drives[0];
    let edited = first_text.replacen("name: ", "name: Edited ", 1);
    std::fs::write(dir.join(format!("drives/{first_id}.yaml")), &edited)
        .map_err(|e| e.to_string())?;
    let (after_edit, edit_log) = cargo(&dir, target, &["build", "-v"])?;
    std::fs::write(dir.join(format!("drives/{first_id}.yaml")), first_text)
        .map_err(|e| e.to_string())?;
    let rebuilt: Vec<&str> = edit_log
        .lines()
        .filter_map(|line| line.trim().strip_prefix("Compiling "))
        .map(|rest| rest.split_whitespace().next().unwrap_or(""))
        .collect();
    let (lines, register_lines) = sum_lines(target, &crate_name);
    let per_register = |lines: usize| lines as f64 / registers.max(1) as f64;
    Ok(format!(
        "| {} | {registers} | {lines} | {:.1} / {:.1} | {:.1} s | {:.2} s{} | {:.1} s (edited `{first_id}.yaml`) | {} |",
        case.name,
        per_register(lines),
        per_register(register_lines),
        clean.as_secs_f64(),
        noop.as_secs_f64(),
        if noop_rebuilt { " (rebuilt!)" } else { ", nothing rebuilt" },
        after_edit.as_secs_f64(),
        rebuilt.join(", ")
    ))
}

/// Lines of Rust the build script generated for `crate_name` (its newest build output):
/// in all, and in the drives' `registers` modules alone.
fn sum_lines(target: &Path, crate_name: &str) -> (usize, usize) {
    let build = target.join("debug/build");
    let prefix = format!("{crate_name}-");
    let mut newest: Option<(std::time::SystemTime, PathBuf)> = None;
    for entry in std::fs::read_dir(&build).into_iter().flatten().flatten() {
        let path = entry.path();
        let name = path
            .file_name()
            .and_then(|n| n.to_str())
            .unwrap_or("")
            .to_owned();
        let out = path.join("out");
        if name.starts_with(&prefix) && out.join("drives.rs").is_file() {
            let modified = std::fs::metadata(out.join("drives.rs"))
                .and_then(|m| m.modified())
                .ok();
            if let Some(modified) = modified {
                if newest.as_ref().is_none_or(|(time, _)| modified > *time) {
                    newest = Some((modified, out));
                }
            }
        }
    }
    let Some((_, out)) = newest else {
        return (0, 0);
    };
    let texts: Vec<String> = std::fs::read_dir(out)
        .into_iter()
        .flatten()
        .flatten()
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|ext| ext == "rs"))
        .filter_map(|p| std::fs::read_to_string(p).ok())
        .collect();
    let all = texts.iter().map(|t| t.lines().count()).sum();
    let registers = texts.iter().map(|t| registers_module_lines(t)).sum();
    (all, registers)
}

/// Lines of each `pub mod registers { .. }` in a formatted file, from its opening line to
/// the closing brace at the same indentation, both included.
fn registers_module_lines(text: &str) -> usize {
    let mut count = 0;
    let mut closing: Option<String> = None;
    for line in text.lines() {
        match &closing {
            Some(end) => {
                count += 1;
                if line == end {
                    closing = None;
                }
            }
            None => {
                let trimmed = line.trim_start();
                if trimmed == "pub mod registers {" {
                    count += 1;
                    let indent = &line[..line.len() - trimmed.len()];
                    closing = Some(format!("{indent}}}"));
                }
            }
        }
    }
    count
}
