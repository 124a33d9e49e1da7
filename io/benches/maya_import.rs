//! Maya ASCII import speed on the 929 KB digitigrade leg rig of the shared assets:
//! tokenizing, parsing into the scene model, and the whole import (mapping onto sinew
//! nodes and the check that the rig builds), against a baseline in the same run that only
//! splits the text into whitespace-separated words.
//!
//! `cargo bench -p sinew-io --bench maya_import`. Skips with a message when the assets
//! are absent.

use std::path::PathBuf;

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use sinew_io::maya::{decode_text, import_maya, lex::lex, parse::parse, MayaImportOptions};

fn leg_rig() -> Option<String> {
    let p = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../shared/assets/maya/digitigrade_leg_mod_example.ma");
    match std::fs::read(&p) {
        Ok(b) => Some(decode_text(&b)),
        Err(_) => {
            eprintln!("skipping: {} is absent", p.display());
            None
        }
    }
}

fn bench(c: &mut Criterion) {
    let Some(text) = leg_rig() else { return };
    let registry = sinew_nodes::registry().expect("registry");
    let opts = MayaImportOptions::default();
    let mut g = c.benchmark_group("maya_import_leg_rig");
    g.sample_size(30);
    g.bench_function("baseline: split into words", |b| {
        b.iter(|| black_box(&text).split_ascii_whitespace().count())
    });
    g.bench_function("tokenize", |b| b.iter(|| lex(black_box(&text)).map(|t| t.len())));
    g.bench_function("parse to the scene model", |b| {
        b.iter(|| parse(black_box(&text)).map(|s| s.nodes.len()))
    });
    g.bench_function("import (map and check)", |b| {
        b.iter(|| {
            import_maya(black_box(&text), "leg.ma", &registry, &opts)
                .map(|i| i.rig.nodes.len())
                .unwrap_or(0)
        })
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
