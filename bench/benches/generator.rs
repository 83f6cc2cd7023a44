//! Generator speed: read, validate, lower and emit Rust + Markdown for the described drives
//! and for synthetic drives of 1,000 and 10,000 registers made on the fly
//! (`cargo bench -p vfd-bench --bench generator`).

use criterion::{black_box, criterion_group, criterion_main, BenchmarkId, Criterion};
use std::path::Path;
use vfd_bench::synthetic_drive;
use vfd_codegen::OutputNames;

fn generate(path: &Path, text: &str) -> (usize, usize) {
    let drive = vfd_codegen::compile_text(
        path,
        text.to_owned(),
        Some(Path::new("../drives/protocols")),
    )
    .expect("valid");
    let names = OutputNames::default();
    let rust = vfd_codegen::rust_file(&drive, &names).expect("formats");
    let markdown = vfd_codegen::markdown_page(&drive, &names).expect("renders");
    (rust.len(), markdown.len())
}

fn generator(c: &mut Criterion) {
    let mut group = c.benchmark_group("generator: read + validate + Rust + Markdown");
    group.sample_size(10);
    let mut inputs: Vec<(String, String)> = ["yd1000", "fc51"]
        .iter()
        .map(|id| {
            (
                id.to_string(),
                std::fs::read_to_string(format!("../drives/{id}.yaml")).expect("drive file"),
            )
        })
        .collect();
    for size in [1_000usize, 10_000] {
        inputs.push((
            format!("synthetic {size}"),
            synthetic_drive(&format!("synthetic_{size}"), size),
        ));
    }
    for (name, text) in &inputs {
        let path = Path::new("../drives").join(format!("{}.yaml", name.replace(' ', "_")));
        group.bench_with_input(BenchmarkId::from_parameter(name), text, |b, text| {
            b.iter(|| generate(&path, black_box(text)))
        });
    }
    group.finish();
}

criterion_group!(benches, generator);
criterion_main!(benches);
