//! Times each public stage of the generator on a synthetic drive, for profiling
//! (`cargo run --release -p vfd-bench --example profile_generator -- 10000`, from `bench/`;
//! or under `perf record` / `valgrind --tool=callgrind`).

use std::path::Path;
use std::time::Instant;
use vfd_codegen::OutputNames;

fn main() {
    let size: usize = std::env::args()
        .nth(1)
        .and_then(|arg| arg.parse().ok())
        .unwrap_or(10_000);
    let id = format!("synthetic_{size}");
    let text = vfd_bench::synthetic_drive(&id, size);
    let path = Path::new("../drives").join(format!("{id}.yaml"));
    let protocols = Path::new(env!("CARGO_MANIFEST_DIR")).join("../drives/protocols");
    let names = OutputNames::default();

    let start = Instant::now();
    let drive = vfd_codegen::compile_text(&path, text, Some(&protocols)).expect("valid");
    let compiled = start.elapsed();
    let start = Instant::now();
    let tokens = vfd_codegen::rust_tokens(&drive);
    let tokens_time = start.elapsed();
    drop(tokens);
    let start = Instant::now();
    let rust = vfd_codegen::rust_file(&drive, &names).expect("formats");
    let rust_time = start.elapsed();
    let start = Instant::now();
    let markdown = vfd_codegen::markdown_page(&drive, &names).expect("renders");
    let markdown_time = start.elapsed();
    println!("{size} registers");
    println!("  read + validate + IR: {compiled:?}");
    println!("  Rust tokens:          {tokens_time:?}");
    println!(
        "  Rust file (tokens + prettyplease): {rust_time:?} ({} lines)",
        rust.lines().count()
    );
    println!(
        "  Markdown:             {markdown_time:?} ({} lines)",
        markdown.lines().count()
    );
}
