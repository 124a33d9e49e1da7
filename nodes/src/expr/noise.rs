//! `noise()` for expressions: Perlin's improved gradient noise (2002) in 3D,
//! with lattice gradients chosen by an integer hash instead of a permutation
//! table. Deterministic, smooth (C2 fade), 0 at lattice points, in [-1, 1].
//! Not Maya's noise bit for bit (Maya does not document its table); the same
//! character: smooth pseudo-random values around 0.

use glam::DVec3;

/// The 12 edge directions of a cube, Perlin's gradient set.
const GRADS: [[f64; 3]; 12] = [
    [1.0, 1.0, 0.0],
    [-1.0, 1.0, 0.0],
    [1.0, -1.0, 0.0],
    [-1.0, -1.0, 0.0],
    [1.0, 0.0, 1.0],
    [-1.0, 0.0, 1.0],
    [1.0, 0.0, -1.0],
    [-1.0, 0.0, -1.0],
    [0.0, 1.0, 1.0],
    [0.0, -1.0, 1.0],
    [0.0, 1.0, -1.0],
    [0.0, -1.0, -1.0],
];

/// A well-mixed hash of a lattice point (splitmix64 finalizer over the coordinates).
fn hash(x: i64, y: i64, z: i64) -> u64 {
    let mut h = (x as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15)
        ^ (y as u64).wrapping_mul(0xC2B2_AE3D_27D4_EB4F)
        ^ (z as u64).wrapping_mul(0x1656_67B1_9E37_79F9);
    h ^= h >> 30;
    h = h.wrapping_mul(0xBF58_476D_1CE4_E5B9);
    h ^= h >> 27;
    h = h.wrapping_mul(0x94D0_49BB_1331_11EB);
    h ^ (h >> 31)
}

fn grad(h: u64, d: DVec3) -> f64 {
    let g = GRADS[(h % 12) as usize];
    g[0] * d.x + g[1] * d.y + g[2] * d.z
}

fn fade(t: f64) -> f64 {
    t * t * t * (t * (t * 6.0 - 15.0) + 10.0)
}

/// Gradient noise at `p`, in [-1, 1]; non-finite or huge coordinates (beyond
/// ±2^52, where the lattice cell is no longer resolved) give 0.
pub fn noise3(p: DVec3) -> f64 {
    const LIMIT: f64 = 4_503_599_627_370_496.0; // 2^52
    let m = p.abs().max_element();
    if m.is_nan() || m >= LIMIT {
        return 0.0;
    }
    let c = p.floor();
    let f = p - c;
    let (x, y, z) = (c.x as i64, c.y as i64, c.z as i64);
    let (u, v, w) = (fade(f.x), fade(f.y), fade(f.z));
    let lerp = |a: f64, b: f64, t: f64| a + t * (b - a);
    let corner = |dx: i64, dy: i64, dz: i64| {
        grad(
            hash(x + dx, y + dy, z + dz),
            f - DVec3::new(dx as f64, dy as f64, dz as f64),
        )
    };
    let x00 = lerp(corner(0, 0, 0), corner(1, 0, 0), u);
    let x10 = lerp(corner(0, 1, 0), corner(1, 1, 0), u);
    let x01 = lerp(corner(0, 0, 1), corner(1, 0, 1), u);
    let x11 = lerp(corner(0, 1, 1), corner(1, 1, 1), u);
    let r = lerp(lerp(x00, x10, v), lerp(x01, x11, v), w);
    // The 12-gradient set bounds |r| by 1 in theory; clamp rounding.
    r.clamp(-1.0, 1.0)
}
