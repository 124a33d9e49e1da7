//! Blend shapes (morph targets) with Maya semantics: sparse per-target deltas, in-between
//! targets, optional per-vertex weight maps and a deformer envelope.
//!
//! For a target with weight `x`, the *keys* are the base (weight 0, zero delta), the full
//! target (weight 1) and each in-between (its own weight). The delta applied is the
//! piecewise-linear interpolation of the keys' deltas at `x`, keys sorted by weight; beyond
//! the first or last key it extrapolates along the end segment (so without in-betweens the
//! delta is simply `x · full`, for any `x`, negative or above 1).
//!
//! Output: `out[v] = base[v] + envelope · Σ_targets mapᵗ[v] · deltaᵗ(xᵗ)[v]`.
//!
//! Bad data is skipped, never a panic: delta entries whose vertex index is out of range (or
//! beyond the shorter of `indices`/`deltas`), in-betweens whose weight is not finite or is
//! exactly 0 or 1 (and later duplicates of an earlier in-between's weight), target weights
//! that are not finite (treated as 0), a non-finite envelope (treated as 0). A weight map
//! shorter than the mesh counts as 1 for the missing vertices. [`Target::validate`] reports
//! such problems for authoring tools.

use glam::Vec3;

/// Sparse vertex offsets: `deltas[k]` moves vertex `indices[k]`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SparseDelta {
    /// Vertex indices (need not be sorted; repeats add up).
    pub indices: Vec<u32>,
    /// Offsets, parallel to `indices`.
    pub deltas: Vec<Vec3>,
}

impl SparseDelta {
    /// Builds a sparse delta from a target shape, keeping vertices that move by more than
    /// `tolerance` (compared per axis). Lengths beyond the shorter slice are ignored.
    pub fn from_shapes(base: &[Vec3], target: &[Vec3], tolerance: f32) -> Self {
        let mut d = SparseDelta::default();
        for (i, (b, t)) in base.iter().zip(target).enumerate() {
            let delta = *t - *b;
            if delta.abs().max_element() > tolerance {
                d.indices.push(i as u32);
                d.deltas.push(delta);
            }
        }
        d
    }
}

/// An intermediate shape reached at `weight` (Maya's in-between target, e.g. 0.5).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct InBetween {
    /// Target weight at which this shape is reached exactly; not 0 or 1.
    pub weight: f32,
    /// Offsets of the shape at that weight, relative to the base.
    pub delta: SparseDelta,
}

/// One blend shape target.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Target {
    /// Offsets of the full target (reached at weight 1).
    pub delta: SparseDelta,
    /// In-between shapes, in any order.
    pub in_betweens: Vec<InBetween>,
    /// Per-vertex multiplier (Maya's target weight map); empty means 1 everywhere.
    pub vertex_weights: Vec<f32>,
}

/// Why blend shapes could not be applied, or what [`Target::validate`] found.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum BlendShapeError {
    /// Output buffer length differs from the base.
    #[error("blendShape output has {out} points but the base mesh has {base}")]
    OutputLength {
        /// Output length.
        out: usize,
        /// Base length.
        base: usize,
    },
    /// A delta names a vertex the mesh does not have, or its two lists differ in length.
    #[error("blendShape target {target}: {problem}")]
    BadDelta {
        /// Target index.
        target: usize,
        /// Description.
        problem: String,
    },
    /// An in-between with an unusable weight.
    #[error("blendShape target {target} has an in-between at weight {weight}; in-between weights must be finite, distinct, and not 0 or 1")]
    BadInBetween {
        /// Target index.
        target: usize,
        /// The weight.
        weight: f32,
    },
}

/// Which key of a target: the base, the full target or an in-between.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Key {
    /// The base (weight 0, no delta).
    Base,
    /// The full target (weight 1).
    Full,
    /// In-between `i` of [`Target::in_betweens`].
    Between(usize),
}

impl Target {
    fn usable_between(&self, i: usize) -> bool {
        let w = self.in_betweens[i].weight;
        w.is_finite() && w != 0.0 && w != 1.0 && !self.in_betweens[..i].iter().any(|o| o.weight == w)
    }

    /// The keys [`apply`] uses, with their weights: the base, the full target and every
    /// usable in-between (in no particular order).
    pub fn keys(&self) -> impl Iterator<Item = (f32, Key)> + '_ {
        [(0.0, Key::Base), (1.0, Key::Full)].into_iter().chain(
            (0..self.in_betweens.len())
                .filter(|&i| self.usable_between(i))
                .map(|i| (self.in_betweens[i].weight, Key::Between(i))),
        )
    }

    /// The two keys bracketing `x` (or the end segment when outside) and the blend `t`: the
    /// delta at `x` is `(1 − t)·delta(lo) + t·delta(hi)`, exactly as [`apply`] sums it. As a
    /// function of `x`, each key's share is a hat function of the driving weight (1 at its
    /// own weight, 0 at the other keys, linear in between and extended linearly past the
    /// ends), which is how `sinew bake` exports in-betweens to glTF.
    pub fn bracket(&self, x: f32) -> ((f32, Key), (f32, Key), f32) {
        let pick = |better: &dyn Fn(f32, f32) -> bool, ok: &dyn Fn(f32) -> bool| {
            self.keys()
                .filter(|k| ok(k.0))
                .fold(None, |b: Option<(f32, Key)>, k| match b {
                    Some(b) if !better(k.0, b.0) => Some(b),
                    _ => Some(k),
                })
        };
        let lo = pick(&|a, b| a > b, &|w| w <= x);
        let (lo, hi) = match lo {
            None => {
                // Below every key: the first segment.
                let lo = pick(&|a, b| a < b, &|_| true).unwrap_or((0.0, Key::Base));
                (lo, pick(&|a, b| a < b, &|w| w > lo.0))
            }
            Some(lo) => match pick(&|a, b| a < b, &|w| w > x) {
                Some(hi) => (lo, Some(hi)),
                None => {
                    // At or above the last key: the last segment.
                    let hi = lo;
                    (pick(&|a, b| a > b, &|w| w < hi.0).unwrap_or(hi), Some(hi))
                }
            },
        };
        let hi = hi.unwrap_or(lo);
        let span = hi.0 - lo.0;
        let t = if span != 0.0 { (x - lo.0) / span } else { 0.0 };
        (lo, hi, t)
    }

    /// The offsets of key `k` (`None` for the base).
    pub fn key_delta(&self, k: Key) -> Option<&SparseDelta> {
        match k {
            Key::Base => None,
            Key::Full => Some(&self.delta),
            Key::Between(i) => self.in_betweens.get(i).map(|b| &b.delta),
        }
    }

    /// Reports the first problem that [`apply`] would silently skip.
    pub fn validate(&self, target: usize, vertex_count: usize) -> Result<(), BlendShapeError> {
        for (i, b) in self.in_betweens.iter().enumerate() {
            if !self.usable_between(i) {
                return Err(BlendShapeError::BadInBetween {
                    target,
                    weight: b.weight,
                });
            }
        }
        let deltas = std::iter::once(&self.delta).chain(self.in_betweens.iter().map(|b| &b.delta));
        for d in deltas {
            if d.indices.len() != d.deltas.len() {
                let problem = format!("{} indices but {} deltas", d.indices.len(), d.deltas.len());
                return Err(BlendShapeError::BadDelta { target, problem });
            }
            if let Some(&i) = d.indices.iter().find(|&&i| i as usize >= vertex_count) {
                let problem = format!("moves vertex {i} but the mesh has {vertex_count} vertices");
                return Err(BlendShapeError::BadDelta { target, problem });
            }
            if d.deltas.iter().any(|v| !v.is_finite()) {
                let problem = "has a non-finite delta".to_string();
                return Err(BlendShapeError::BadDelta { target, problem });
            }
        }
        Ok(())
    }
}

/// Adds `scale · map[v] · delta` for every entry of `d` into `out`.
fn accumulate(out: &mut [Vec3], d: &SparseDelta, map: &[f32], scale: f32) {
    for (&i, &delta) in d.indices.iter().zip(&d.deltas) {
        let i = i as usize;
        let m = map.get(i).copied().unwrap_or(1.0);
        if let Some(o) = out.get_mut(i) {
            *o += delta * (scale * m);
        }
    }
}

/// Writes `base` deformed by `targets` at `weights` (missing weights are 0) into `out`.
///
/// Allocation-free; cost is proportional to the non-zero delta entries of the active keys.
pub fn apply(
    base: &[Vec3],
    targets: &[Target],
    weights: &[f32],
    envelope: f32,
    out: &mut [Vec3],
) -> Result<(), BlendShapeError> {
    if out.len() != base.len() {
        return Err(BlendShapeError::OutputLength {
            out: out.len(),
            base: base.len(),
        });
    }
    out.copy_from_slice(base);
    if !envelope.is_finite() || envelope == 0.0 {
        return Ok(());
    }
    for (target, &x) in targets.iter().zip(weights) {
        add_target(out, target, x, envelope);
    }
    Ok(())
}

/// Adds `target` at weight `x` (its in-betweens interpolated, its weight map applied) scaled
/// by `envelope` into `out`; a non-finite or zero weight adds nothing. Entries beyond `out`
/// are skipped. Allocation-free.
pub fn add_target(out: &mut [Vec3], target: &Target, x: f32, envelope: f32) {
    if !x.is_finite() || x == 0.0 {
        return;
    }
    let ((_, lo), (_, hi), t) = target.bracket(x);
    let map = &target.vertex_weights[..];
    if let Some(d) = target.key_delta(lo) {
        if t != 1.0 {
            accumulate(out, d, map, envelope * (1.0 - t));
        }
    }
    if let Some(d) = target.key_delta(hi) {
        if t != 0.0 {
            accumulate(out, d, map, envelope * t);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn one(i: u32, d: Vec3) -> SparseDelta {
        SparseDelta {
            indices: vec![i],
            deltas: vec![d],
        }
    }

    fn run(targets: &[Target], w: &[f32], env: f32) -> Vec<Vec3> {
        let base = vec![Vec3::new(1.0, 2.0, 3.0), Vec3::ZERO];
        let mut out = vec![Vec3::NAN; 2];
        apply(&base, targets, w, env, &mut out).unwrap();
        out
    }

    #[test]
    fn linear_in_weight_and_envelope() {
        let t = Target {
            delta: one(0, Vec3::new(2.0, 0.0, -4.0)),
            ..Default::default()
        };
        let ts = [t];
        assert_eq!(run(&ts, &[0.5], 1.0)[0], Vec3::new(2.0, 2.0, 1.0));
        assert_eq!(run(&ts, &[1.0], 1.0)[0], Vec3::new(3.0, 2.0, -1.0));
        assert_eq!(run(&ts, &[1.0], 0.5)[0], Vec3::new(2.0, 2.0, 1.0));
        // Extrapolation without in-betweens: weight 2 doubles the delta, -1 reverses it.
        assert_eq!(run(&ts, &[2.0], 1.0)[0], Vec3::new(5.0, 2.0, -5.0));
        assert_eq!(run(&ts, &[-1.0], 1.0)[0], Vec3::new(-1.0, 2.0, 7.0));
        assert_eq!(run(&ts, &[0.0], 1.0)[0], Vec3::new(1.0, 2.0, 3.0));
        assert_eq!(run(&ts, &[f32::NAN], 1.0)[0], Vec3::new(1.0, 2.0, 3.0));
    }

    #[test]
    fn in_between_interpolation() {
        // Full target +4 in x; in-between at 0.5 is +8 in y (not on the straight line).
        let t = Target {
            delta: one(0, Vec3::new(4.0, 0.0, 0.0)),
            in_betweens: vec![InBetween {
                weight: 0.5,
                delta: one(0, Vec3::new(0.0, 8.0, 0.0)),
            }],
            ..Default::default()
        };
        let ts = [t];
        let base = Vec3::new(1.0, 2.0, 3.0);
        // 0.25 is half-way from the base to the in-between.
        assert_eq!(run(&ts, &[0.25], 1.0)[0], base + Vec3::new(0.0, 4.0, 0.0));
        assert_eq!(run(&ts, &[0.5], 1.0)[0], base + Vec3::new(0.0, 8.0, 0.0));
        // 0.75 is half-way from the in-between to the full target.
        assert_eq!(run(&ts, &[0.75], 1.0)[0], base + Vec3::new(2.0, 4.0, 0.0));
        assert_eq!(run(&ts, &[1.0], 1.0)[0], base + Vec3::new(4.0, 0.0, 0.0));
        // Beyond 1 it follows the last segment (length 0.5): 1.5 = full + (full − in-between).
        assert_eq!(run(&ts, &[1.5], 1.0)[0], base + Vec3::new(8.0, -8.0, 0.0));
    }

    #[test]
    fn weight_map_and_bad_entries() {
        let t = Target {
            delta: SparseDelta {
                indices: vec![0, 1, 7],
                deltas: vec![Vec3::X, Vec3::Y, Vec3::Z],
            },
            vertex_weights: vec![0.25],
            in_betweens: vec![InBetween {
                weight: 1.0,
                delta: one(0, Vec3::splat(100.0)),
            }],
        };
        let out = run(std::slice::from_ref(&t), &[1.0], 1.0);
        assert_eq!(out[0], Vec3::new(1.25, 2.0, 3.0));
        assert_eq!(out[1], Vec3::Y);
        assert!(t.validate(0, 2).is_err());
        let mut out = vec![Vec3::ZERO; 3];
        assert!(apply(&[Vec3::ZERO; 2], &[t], &[1.0], 1.0, &mut out).is_err());
    }

    #[test]
    fn sparse_from_shapes() {
        let d = SparseDelta::from_shapes(&[Vec3::ZERO, Vec3::ONE], &[Vec3::ZERO, Vec3::new(1.0, 3.0, 1.0)], 1e-6);
        assert_eq!(d.indices, vec![1]);
        assert_eq!(d.deltas, vec![Vec3::new(0.0, 2.0, 0.0)]);
    }
}
