//! The spring IK solve (Maya's ikSpringSolver): a planar chain whose interior joints bend by
//! angles proportional to per-joint bias values, so the bend is spread over the whole chain
//! ("the spring IK solver keeps the angles between joints in its joint chain proportional by
//! applying bias values to those angles ... the angles between all joints are always evenly
//! distributed", Maya's Spring IK solver documentation).
//!
//! sinew's model: joint `i` (1 ..= n − 2) turns by `θᵢ = bᵢ · k` towards the pole side, one
//! common factor `k ≥ 0` chosen so the chord from the start joint to the end reaches the goal
//! distance; then the whole chain is turned in the plane so the chord points at the goal.
//! Maya also weighs the rest pose (flexed or extended) into its bias; sinew uses the bias
//! values alone (`springAngleBias[i]`, default 1: evenly distributed angles). Maya does not
//! publish its exact formula; this one reproduces the documented behaviour.

use glam::DVec3;

/// Samples of `k` scanned for the first crossing before bisection.
const SCAN: usize = 64;

/// The chord `(x, y)` of a planar chain with bone `lengths` whose joint `i` bends by
/// `bias(i) · k` (clockwise, so the chain arcs towards `+y` once turned to `+x`).
fn chord(lengths: &[f64], bias: &dyn Fn(usize) -> f64, k: f64) -> (f64, f64) {
    let (mut x, mut y, mut beta) = (0.0, 0.0, 0.0);
    for (i, &l) in lengths.iter().enumerate() {
        if i > 0 {
            beta -= bias(i) * k;
        }
        x += l * beta.cos();
        y += l * beta.sin();
    }
    (x, y)
}

/// The non-negative bias of joint `i`; when every interior joint's bias is zero (or not
/// finite) every one counts as 1.
fn bias_of(raw: &dyn Fn(usize) -> f64, n_bones: usize) -> impl Fn(usize) -> f64 + '_ {
    let clean = move |i: usize| {
        let b = raw(i);
        if b.is_finite() && b > 0.0 {
            b
        } else {
            0.0
        }
    };
    let any = (1..n_bones).any(|i| clean(i) > 0.0);
    move |i| if any { clean(i) } else { 1.0 }
}

/// Joint positions of the spring solve into `out`: from `p0`, in the plane of unit `u`
/// (towards the goal) and unit `w` (towards the pole, orthogonal to `u`), with the end at
/// `p0 + u · d` when the bends can bring it there (`d` below the chain's length). A goal
/// nearer than the most folded chord (joints bend at most a full turn each) gets that chord.
pub(super) fn spring_positions_into(
    p0: DVec3,
    u: DVec3,
    w: DVec3,
    lengths: &[f64],
    d: f64,
    raw_bias: &dyn Fn(usize) -> f64,
    out: &mut Vec<DVec3>,
) {
    let bias = bias_of(raw_bias, lengths.len());
    let max_b = (1..lengths.len()).map(&bias).fold(0.0, f64::max);
    let len = |k: f64| {
        let (x, y) = chord(lengths, &bias, k);
        x.hypot(y)
    };
    let k_max = if max_b > 0.0 {
        std::f64::consts::TAU / max_b
    } else {
        0.0
    };
    // First sample whose chord is at most d; else the shortest chord seen.
    let (mut lo, mut hi, mut best) = (0.0, None, (len(0.0), 0.0));
    for s in 1..=SCAN {
        let k = k_max * s as f64 / SCAN as f64;
        let c = len(k);
        if c < best.0 {
            best = (c, k);
        }
        if c <= d {
            hi = Some(k);
            break;
        }
        lo = k;
    }
    let k = match hi {
        Some(mut hi) => {
            for _ in 0..64 {
                let mid = 0.5 * (lo + hi);
                if len(mid) > d {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            0.5 * (lo + hi)
        }
        None => best.1,
    };
    let (cx, cy) = chord(lengths, &bias, k);
    let gamma = cy.atan2(cx);
    out.clear();
    out.push(p0);
    let (mut p, mut beta) = (p0, 0.0);
    for (i, &l) in lengths.iter().enumerate() {
        if i > 0 {
            beta -= bias(i) * k;
        }
        let a = beta - gamma;
        p += (u * a.cos() + w * a.sin()) * l;
        out.push(p);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Four equal bones with equal bias: the joints lie on a circular arc, every bend the same,
    /// the end at the goal distance.
    #[test]
    fn equal_bias_bends_evenly() {
        let mut out = Vec::new();
        spring_positions_into(DVec3::ZERO, DVec3::X, DVec3::Y, &[1.0; 4], 3.0, &|_| 1.0, &mut out);
        assert_eq!(out.len(), 5);
        assert!((out[4] - DVec3::new(3.0, 0.0, 0.0)).length() < 1e-12, "{out:?}");
        let dirs: Vec<DVec3> = out.windows(2).map(|p| p[1] - p[0]).collect();
        let bends: Vec<f64> = dirs.windows(2).map(|d| d[0].angle_between(d[1])).collect();
        for b in &bends {
            assert!((b - bends[0]).abs() < 1e-12, "{bends:?}");
        }
        assert!(out[2].y > 0.0, "bends towards +w");
        // Symmetric about the middle: the middle joint above the chord's midpoint.
        assert!((out[2].x - 1.5).abs() < 1e-12);
    }

    /// Bias 2 on joint 1, 1 on joints 2 and 3: joint 1 bends twice as much.
    #[test]
    fn bends_are_proportional_to_bias() {
        let mut out = Vec::new();
        let bias = |i: usize| if i == 1 { 2.0 } else { 1.0 };
        spring_positions_into(
            DVec3::ZERO,
            DVec3::X,
            DVec3::Z,
            &[1.0, 1.5, 1.0, 0.5],
            2.5,
            &bias,
            &mut out,
        );
        assert!((out[4] - DVec3::new(2.5, 0.0, 0.0)).length() < 1e-12);
        let dirs: Vec<DVec3> = out.windows(2).map(|p| p[1] - p[0]).collect();
        let bends: Vec<f64> = dirs.windows(2).map(|d| d[0].angle_between(d[1])).collect();
        assert!(
            (bends[0] - 2.0 * bends[1]).abs() < 1e-12 && (bends[1] - bends[2]).abs() < 1e-12,
            "{bends:?}"
        );
        // zero biases everywhere count as even
        spring_positions_into(DVec3::ZERO, DVec3::X, DVec3::Z, &[1.0; 3], 2.0, &|_| 0.0, &mut out);
        assert!((out[3] - DVec3::new(2.0, 0.0, 0.0)).length() < 1e-12);
    }
}
