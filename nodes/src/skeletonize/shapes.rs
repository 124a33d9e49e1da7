//! Procedural meshes with known skeletons (capsules, a plus, stars, a torus, a
//! capsule humanoid), for tests, benchmarks and demos of skeleton extraction.

use std::f32::consts::{FRAC_PI_2, TAU};

use glam::Vec3;

use sinew_core::data::Mesh;

/// A closed capsule (cylinder with hemispherical caps) from `a` to `b`.
///
/// `around` segments around the axis (at least 3); rings along the body are chosen
/// so that quads are roughly square. `a == b` gives a sphere.
pub fn capsule(a: Vec3, b: Vec3, radius: f32, around: usize) -> Mesh {
    let around = around.max(3);
    let len = a.distance(b);
    let d = (b - a).try_normalize().unwrap_or(Vec3::Y);
    let e1 = d.any_orthonormal_vector();
    let e2 = d.cross(e1);
    let cap = (around / 4).max(1);
    let step = TAU * radius / around as f32;
    let body = if step > 0.0 { (len / step).round() as usize } else { 0 };
    // Rings as (centre, radius), pole to pole, excluding the poles.
    let mut rings: Vec<(Vec3, f32)> = Vec::new();
    for k in 1..=cap {
        let phi = -FRAC_PI_2 + FRAC_PI_2 * k as f32 / cap as f32;
        rings.push((a + d * radius * phi.sin(), radius * phi.cos()));
    }
    for k in 1..=body {
        rings.push((a + d * len * k as f32 / (body + 1) as f32, radius));
    }
    for k in 0..cap {
        let phi = FRAC_PI_2 * k as f32 / cap as f32;
        rings.push((b + d * radius * phi.sin(), radius * phi.cos()));
    }
    let mut m = Mesh::default();
    m.positions.push(a - d * radius);
    for (c, r) in &rings {
        for s in 0..around {
            let t = TAU * s as f32 / around as f32;
            m.positions.push(*c + (e1 * t.cos() + e2 * t.sin()) * *r);
        }
    }
    m.positions.push(b + d * radius);
    let top = (m.positions.len() - 1) as u32;
    let ring = |k: usize, s: usize| (1 + k * around + s % around) as u32;
    for s in 0..around {
        m.triangles.push([0, ring(0, s + 1), ring(0, s)]);
    }
    for k in 0..rings.len() - 1 {
        for s in 0..around {
            let (p, q, r, t) = (ring(k, s), ring(k, s + 1), ring(k + 1, s + 1), ring(k + 1, s));
            m.triangles.push([p, q, r]);
            m.triangles.push([p, r, t]);
        }
    }
    let last = rings.len() - 1;
    for s in 0..around {
        m.triangles.push([top, ring(last, s), ring(last, s + 1)]);
    }
    m
}

/// A torus around the Z axis (major radius `major`, tube radius `minor`).
pub fn torus(major: f32, minor: f32, around: usize, tube: usize) -> Mesh {
    let (around, tube) = (around.max(3), tube.max(3));
    let mut m = Mesh::default();
    for i in 0..around {
        let t = TAU * i as f32 / around as f32;
        let c = Vec3::new(t.cos(), t.sin(), 0.0);
        for j in 0..tube {
            let s = TAU * j as f32 / tube as f32;
            m.positions
                .push(c * (major + minor * s.cos()) + Vec3::Z * minor * s.sin());
        }
    }
    let id = |i: usize, j: usize| ((i % around) * tube + j % tube) as u32;
    for i in 0..around {
        for j in 0..tube {
            m.triangles.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
            m.triangles.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    m
}

/// Concatenates meshes (no welding).
pub fn merge(parts: &[Mesh]) -> Mesh {
    let mut m = Mesh::default();
    for p in parts {
        let base = m.positions.len() as u32;
        m.positions.extend_from_slice(&p.positions);
        m.triangles.extend(p.triangles.iter().map(|t| t.map(|i| i + base)));
    }
    m
}

/// Two capsules crossed at the origin in the XY plane, arms reaching `arm` out.
pub fn plus(arm: f32, radius: f32, around: usize) -> Mesh {
    merge(&[
        capsule(Vec3::new(-arm, 0.0, 0.0), Vec3::new(arm, 0.0, 0.0), radius, around),
        capsule(Vec3::new(0.0, -arm, 0.0), Vec3::new(0.0, arm, 0.0), radius, around),
    ])
}

/// `n` capsule arms of length `arm` radiating from a ball at the origin in the XY plane.
pub fn star(n: usize, arm: f32, radius: f32, around: usize) -> Mesh {
    let mut parts = vec![capsule(Vec3::ZERO, Vec3::ZERO, radius * 1.6, around)];
    for k in 0..n {
        let t = TAU * k as f32 / n as f32 + 0.3;
        parts.push(capsule(
            Vec3::ZERO,
            Vec3::new(t.cos(), t.sin(), 0.0) * arm,
            radius,
            around,
        ));
    }
    merge(&parts)
}

/// The [`humanoid`] whose vertex count is the first at or above `target` (a bisection
/// over `around`, capped at `around = 1024`): the benchmark and profiling meshes.
pub fn humanoid_near(target: usize) -> Mesh {
    let (mut lo, mut hi) = (4usize, 1024usize);
    while lo + 1 < hi {
        let mid = (lo + hi) / 2;
        if humanoid(mid).positions.len() < target {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    humanoid(hi)
}

/// A T-pose humanoid about 1.8 units tall, facing +Z, built from overlapping
/// capsules: torso, neck, head, two arms, two legs. `around` sets the density
/// (vertex count grows roughly with `around²`).
pub fn humanoid(around: usize) -> Mesh {
    let v = |x: f32, y: f32| Vec3::new(x, y, 0.0);
    merge(&[
        capsule(v(0.0, 0.95), v(0.0, 1.35), 0.15, around),
        capsule(v(0.0, 1.4), v(0.0, 1.56), 0.05, around / 2),
        capsule(v(0.0, 1.65), v(0.0, 1.65), 0.11, around),
        capsule(v(0.15, 1.38), v(0.85, 1.38), 0.05, around / 2),
        capsule(v(-0.15, 1.38), v(-0.85, 1.38), 0.05, around / 2),
        capsule(v(0.09, 0.95), v(0.2, 0.08), 0.07, around / 2),
        capsule(v(-0.09, 0.95), v(-0.2, 0.08), 0.07, around / 2),
    ])
}
