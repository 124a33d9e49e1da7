//! Exact Euclidean distance transform of a solid: for every inside cell, the squared
//! distance (in cells) from its centre to the nearest outside cell's centre, by the
//! separable lower-envelope-of-parabolas algorithm of Felzenszwalb & Huttenlocher
//! ("Distance Transforms of Sampled Functions", Theory of Computing 8, 2012): one
//! linear pass along each axis. Lines with no inside cell are skipped, and each other
//! line is transformed only from just before its first inside cell to just after its last.
//!
//! The surface passes through the solid's outermost (shell) cells, so it lies about a
//! cell inside the nearest outside cell's centre: the local radius at a cell is about
//! `sqrt(d²) - 1` cells ([`radius_cells`]).

use super::voxel::Grid;

/// A value larger than any squared distance in a grid of at most 2²⁴ cells.
const FAR: f32 = 1e20;

/// Squared distance to the nearest outside cell, per cell (0 outside).
pub fn squared_distances(grid: &Grid, inside: &[bool]) -> Vec<f32> {
    let [nx, ny, nz] = grid.dims;
    let mut d: Vec<f32> = inside.iter().map(|&i| if i { FAR } else { 0.0 }).collect();
    let n = nx.max(ny).max(nz);
    let mut line = vec![0f32; n];
    let mut out = vec![0f32; n];
    let mut v = vec![0usize; n];
    let mut z = vec![0f32; n + 1];
    let strides = [1, nx, nx * ny];
    // Per axis and line (indexed `ia + dims[a] * ib` as below), the first and last
    // inside cell along the line (`u32::MAX, 0` for a line without one), from one pass
    // in memory order instead of a strided search along every line. A cell stays
    // positive exactly when it is inside through all passes (its nearest outside cell
    // is at least one cell away), so these hold for every pass.
    let mut spans: [Vec<(u32, u32)>; 3] = [ny * nz, nz * nx, nx * ny].map(|n| vec![(u32::MAX, 0u32); n]);
    let mut c = 0;
    for k in 0..nz {
        for j in 0..ny {
            for i in 0..nx {
                if inside[c] {
                    for (span, line, q) in [(0, j + ny * k, i), (1, k + nz * i, j), (2, i + nx * j, k)] {
                        let s = &mut spans[span][line];
                        s.0 = s.0.min(q as u32);
                        s.1 = s.1.max(q as u32);
                    }
                }
                c += 1;
            }
        }
    }
    for axis in 0..3 {
        let len = grid.dims[axis];
        let stride = strides[axis];
        let (a, b) = ((axis + 1) % 3, (axis + 2) % 3);
        for ib in 0..grid.dims[b] {
            for ia in 0..grid.dims[a] {
                let base = ia * strides[a] + ib * strides[b];
                // Only the stretch from the cell before the first inside cell to the
                // cell after the last one changes: the outside cells around it are
                // zeros (sources) nearer than any beyond them.
                let (first, last) = spans[axis][ia + grid.dims[a] * ib];
                if first == u32::MAX {
                    continue;
                }
                let (first, last) = (first as usize, last as usize);
                let (from, to) = (first.saturating_sub(1), (last + 2).min(len));
                let span = to - from;
                if axis == 0 && span <= EXACT && d[base + from] == 0.0 && d[base + to - 1] == 0.0 {
                    // The first pass's line holds only zeros and FAR: the distance to
                    // the nearest zero, in place (the line is contiguous).
                    let row = &mut d[base + from..base + to];
                    line[..span].copy_from_slice(row);
                    nearest_zero_squared(&line[..span], row);
                    continue;
                }
                for (q, x) in line[..span].iter_mut().enumerate() {
                    *x = d[base + (from + q) * stride];
                }
                envelope(&line[..span], &mut out[..span], &mut v, &mut z);
                for (q, x) in out[..span].iter().enumerate() {
                    d[base + (from + q) * stride] = *x;
                }
            }
        }
    }
    d
}

/// The local radius in cells of an inside cell with squared distance `d2` (at least
/// half a cell).
pub fn radius_cells(d2: f32) -> f64 {
    ((d2 as f64).sqrt() - 1.0).max(0.5)
}

/// Longest line on which [`envelope`]'s sums of squares and intersections are exact in
/// `f32` (squares of indices up to 2¹²).
const EXACT: usize = 4096;

/// `out[q] = min_p (q - p)²` over the zeros `p` of `f`, a line of zeros and `FAR`s
/// that starts and ends with a zero: by two scans, the same numbers [`envelope`] gives
/// such a line of at most [`EXACT`] cells (where its arithmetic is exact; tested).
fn nearest_zero_squared(f: &[f32], out: &mut [f32]) {
    let mut last = 0usize;
    for (q, (o, &x)) in out.iter_mut().zip(f).enumerate() {
        if x == 0.0 {
            last = q;
        }
        *o = (q - last) as f32;
    }
    let mut next = f.len().saturating_sub(1);
    for (q, (o, &x)) in out.iter_mut().zip(f).enumerate().rev() {
        if x == 0.0 {
            next = q;
        }
        let dq = o.min((next - q) as f32);
        *o = dq * dq;
    }
}

/// One dimension: `out[q] = min_p (q - p)² + f[p]` (the lower envelope of parabolas).
fn envelope(f: &[f32], out: &mut [f32], v: &mut [usize], z: &mut [f32]) {
    let n = f.len();
    if n == 0 {
        return;
    }
    let mut k = 0usize;
    v[0] = 0;
    z[0] = f32::NEG_INFINITY;
    z[1] = f32::INFINITY;
    for q in 1..n {
        let fq = f[q] + (q * q) as f32;
        // z[0] is -inf, so the search stops at k = 0 at the latest.
        let mut s;
        loop {
            let p = v[k];
            s = (fq - (f[p] + (p * p) as f32)) / (2.0 * (q as f32 - p as f32));
            if s > z[k] || k == 0 {
                break;
            }
            k -= 1;
        }
        k += 1;
        v[k] = q;
        z[k] = s;
        z[k + 1] = f32::INFINITY;
    }
    k = 0;
    for (q, o) in out.iter_mut().enumerate() {
        while z[k + 1] < q as f32 {
            k += 1;
        }
        let p = v[k];
        let dq = q as f32 - p as f32;
        *o = (dq * dq + f[p]).min(FAR);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;

    #[test]
    fn nearest_zero_scans_match_the_envelope_on_lines_of_zeros_and_far() {
        // Pseudo-random lines of zeros and FARs with zeros at both ends, lengths 2..400,
        // sparse and dense zeros; the two scans must give the envelope's bits, and
        // the distance to the nearest zero squared (brute force).
        let mut state = 0x9e37_79b9_7f4a_7c15u64;
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            state
        };
        for len in 2..400usize {
            for density in [2u64, 8, 64] {
                let mut f: Vec<f32> = (0..len)
                    .map(|_| if next() % density == 0 { 0.0 } else { FAR })
                    .collect();
                f[0] = 0.0;
                f[len - 1] = 0.0;
                let (mut a, mut b) = (vec![0f32; len], vec![0f32; len]);
                let (mut v, mut z) = (vec![0usize; len], vec![0f32; len + 1]);
                envelope(&f, &mut a, &mut v, &mut z);
                nearest_zero_squared(&f, &mut b);
                for q in 0..len {
                    let near = (0..len)
                        .filter(|&p| f[p] == 0.0)
                        .map(|p| q.abs_diff(p))
                        .min()
                        .unwrap_or(0);
                    assert_eq!(a[q].to_bits(), b[q].to_bits(), "len {len} cell {q}");
                    assert_eq!(b[q], (near * near) as f32, "len {len} cell {q}");
                }
            }
        }
    }

    #[test]
    fn a_ball_matches_brute_force() {
        // Cells whose centre lies within 6.5 of the centre cell's are inside. The nearest
        // outside cell to the centre is the integer offset with the least squared length
        // above 6.5² = 42.25: 43 = 5² + 3² + 3².
        let grid = Grid {
            origin: DVec3::ZERO,
            h: 1.0,
            dims: [17, 17, 17],
        };
        let c = DVec3::splat(8.5);
        let inside: Vec<bool> = (0..grid.len()).map(|i| grid.center(i).distance(c) <= 6.5).collect();
        let d = squared_distances(&grid, &inside);
        let centre = grid.index(8, 8, 8);
        assert_eq!(d[centre], 43.0);
        // Brute force on every cell.
        let outside: Vec<DVec3> = (0..grid.len())
            .filter(|&i| !inside[i])
            .map(|i| grid.center(i))
            .collect();
        for i in (0..grid.len()).filter(|&i| inside[i]) {
            let p = grid.center(i);
            let best = outside
                .iter()
                .map(|q| q.distance_squared(p))
                .fold(f64::INFINITY, f64::min);
            assert_eq!(d[i] as f64, best, "cell {i}");
        }
        assert!(d.iter().zip(&inside).all(|(x, &i)| i || *x == 0.0));
    }
}
