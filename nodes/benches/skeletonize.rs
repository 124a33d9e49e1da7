//! Skeleton extraction and bone-heat weights on capsule humanoids of ~300 to ~200k vertices,
//! against a baseline measured in the same run: one pass over every vertex computing the
//! bounding box and the covariance (the principal axes the silhouette view starts from).
//!
//! Run: `cargo bench -p sinew-nodes --bench skeletonize`.

use std::hint::black_box;
use std::time::Duration;

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use glam::{DMat3, DVec3};
use sinew_core::Mesh;
use sinew_nodes::skeletonize::{bone_heat_weights, shapes, skeletonize, SkeletonizeParams, WeightParams};

/// The baseline: bounding box, centroid and covariance, reading every vertex once.
fn bounds_and_covariance(m: &Mesh) -> (DVec3, DVec3, DMat3) {
    let (mut lo, mut hi) = (DVec3::INFINITY, DVec3::NEG_INFINITY);
    let (mut s, mut xx, mut yy, mut zz, mut xy, mut xz, mut yz) = (DVec3::ZERO, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
    for p in &m.positions {
        let p = p.as_dvec3();
        lo = lo.min(p);
        hi = hi.max(p);
        s += p;
        xx += p.x * p.x;
        yy += p.y * p.y;
        zz += p.z * p.z;
        xy += p.x * p.y;
        xz += p.x * p.z;
        yz += p.y * p.z;
    }
    let n = m.positions.len().max(1) as f64;
    let c = s / n;
    let cov = DMat3::from_cols_array(&[
        xx / n - c.x * c.x,
        xy / n - c.x * c.y,
        xz / n - c.x * c.z,
        xy / n - c.x * c.y,
        yy / n - c.y * c.y,
        yz / n - c.y * c.z,
        xz / n - c.x * c.z,
        yz / n - c.y * c.z,
        zz / n - c.z * c.z,
    ]);
    (lo, hi, cov)
}

fn bench(c: &mut Criterion) {
    let params = SkeletonizeParams::default();
    let meshes: Vec<Mesh> = [300, 2_000, 20_000, 200_000]
        .iter()
        .map(|&n| shapes::humanoid_near(n))
        .collect();
    let mut g = c.benchmark_group("baseline_bounds_pca");
    g.sample_size(20)
        .warm_up_time(Duration::from_millis(300))
        .measurement_time(Duration::from_secs(1));
    for m in &meshes {
        g.bench_with_input(BenchmarkId::from_parameter(m.positions.len()), m, |b, m| {
            b.iter(|| bounds_and_covariance(black_box(m)))
        });
    }
    g.finish();
    let mut g = c.benchmark_group("skeleton");
    g.sample_size(10)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(2));
    for m in &meshes {
        g.bench_with_input(BenchmarkId::from_parameter(m.positions.len()), m, |b, m| {
            b.iter(|| skeletonize(black_box(m), &params).unwrap())
        });
    }
    g.finish();
    let mut g = c.benchmark_group("weights");
    g.sample_size(10)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(3));
    let wp = WeightParams::default();
    for m in &meshes {
        let sk = skeletonize(
            m,
            &SkeletonizeParams {
                bones_per_branch: Some(3),
                ..params
            },
        )
        .unwrap();
        // A fixed id (the bone count goes to stderr): criterion compares runs by id, and
        // an id carrying the bone count changed whenever the skeleton did.
        eprintln!(
            "weights/3_bones_per_branch/{}: {} bones",
            m.positions.len(),
            sk.len() - 1
        );
        g.bench_with_input(BenchmarkId::new("3_bones_per_branch", m.positions.len()), m, |b, m| {
            b.iter(|| bone_heat_weights(black_box(m), &sk, &wp).unwrap())
        });
    }
    g.finish();
    // What a user runs: the default skeleton, then its weights.
    let mut g = c.benchmark_group("skeleton_and_weights");
    g.sample_size(10)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(3));
    for m in &meshes {
        g.bench_with_input(BenchmarkId::from_parameter(m.positions.len()), m, |b, m| {
            b.iter(|| {
                let sk = skeletonize(black_box(m), &params).unwrap();
                bone_heat_weights(m, &sk, &wp).unwrap()
            })
        });
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
