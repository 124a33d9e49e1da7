//! Skin weight hygiene: normalize, prune to a maximum influence count, build from dense
//! rows, and validate against a skeleton. Authoring-time tools; they may allocate.
//!
//! Conventions:
//! - a *usable* weight is finite and `> 0`; normalization and pruning drop the others
//!   (negative, zero, NaN and infinite entries are removed from the rows);
//! - a vertex whose usable weights sum to 0 ("unweighted") is kept with **no influences**
//!   (an empty row); the skinning kernels leave such a vertex at its rest position;
//! - entries keep their order within a row, except that pruning orders them by decreasing
//!   weight (ties: lower joint index first).

use sinew_core::data::Weights;

/// Why weights do not fit a mesh or skeleton.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum WeightsError {
    /// The compressed-row structure is broken (see [`Weights::validate`]).
    #[error("{0}")]
    Structure(String),
    /// The weights cover a different number of vertices than the mesh.
    #[error("weights cover {weights} vertices but the mesh has {mesh}; rebind the skin or fix the weight list")]
    VertexCount {
        /// Vertices covered by the weights.
        weights: usize,
        /// Vertices in the mesh.
        mesh: usize,
    },
    /// An entry names a joint the skeleton does not have.
    #[error("vertex {vertex} is weighted to joint {joint} but the skin has only {joint_count} joints; add the joint or remove the influence")]
    JointOutOfRange {
        /// Vertex index.
        vertex: usize,
        /// Offending joint index.
        joint: u32,
        /// Number of joints in the palette.
        joint_count: usize,
    },
    /// A negative weight.
    #[error("vertex {vertex} has negative weight {weight} on joint {joint}; skin weights must be >= 0")]
    Negative {
        /// Vertex index.
        vertex: usize,
        /// Joint index.
        joint: u32,
        /// The weight.
        weight: f32,
    },
    /// Dense input whose length is not `vertex_count * joint_count`.
    #[error("dense weights have {len} values, which is not a multiple of the joint count {joint_count}")]
    DenseShape {
        /// Number of values given.
        len: usize,
        /// Joint count (row length).
        joint_count: usize,
    },
}

fn usable(w: f32) -> bool {
    w.is_finite() && w > 0.0
}

/// Normalizes every row so its weights sum to 1, dropping unusable entries (non-finite or
/// `<= 0`). Rows with no usable weight become empty (see the module docs).
///
/// The sum is accumulated in `f64`, so each row sums to 1 within a few `f32` ulps.
pub fn normalize(w: &Weights) -> Weights {
    let mut out = Weights::default();
    for v in 0..w.vertex_count() {
        let (joints, weights) = w.influences(v);
        let sum: f64 = weights.iter().filter(|x| usable(**x)).map(|&x| x as f64).sum();
        if sum > 0.0 && sum.is_finite() {
            for (&j, &x) in joints.iter().zip(weights).filter(|(_, x)| usable(**x)) {
                out.joints.push(j);
                out.weights.push((x as f64 / sum) as f32);
            }
        }
        out.offsets.push(out.joints.len() as u32);
    }
    out
}

/// Keeps at most `max_influences` usable influences per vertex (the largest, ties broken by
/// lower joint index), then renormalizes each row to sum to 1.
///
/// `max_influences = 0` yields all-empty rows.
pub fn prune(w: &Weights, max_influences: usize) -> Weights {
    let mut out = Weights::default();
    let mut row: Vec<(u32, f32)> = Vec::new();
    for v in 0..w.vertex_count() {
        let (joints, weights) = w.influences(v);
        row.clear();
        row.extend(
            joints
                .iter()
                .copied()
                .zip(weights.iter().copied())
                .filter(|(_, x)| usable(*x)),
        );
        row.sort_by(|a, b| b.1.total_cmp(&a.1).then(a.0.cmp(&b.0)));
        row.truncate(max_influences);
        let sum: f64 = row.iter().map(|(_, x)| *x as f64).sum();
        if sum > 0.0 && sum.is_finite() {
            for &(j, x) in &row {
                out.joints.push(j);
                out.weights.push((x as f64 / sum) as f32);
            }
        }
        out.offsets.push(out.joints.len() as u32);
    }
    out
}

/// Builds sparse weights from a dense row-major `vertex_count × joint_count` table, keeping
/// entries strictly greater than `threshold` (use 0 to keep every positive weight).
/// Rows are not normalized; call [`normalize`] if needed.
pub fn from_dense(dense: &[f32], joint_count: usize, threshold: f32) -> Result<Weights, WeightsError> {
    if joint_count == 0 || dense.len() % joint_count != 0 {
        return Err(WeightsError::DenseShape {
            len: dense.len(),
            joint_count,
        });
    }
    let mut out = Weights::default();
    for row in dense.chunks_exact(joint_count) {
        for (j, &x) in row.iter().enumerate() {
            if usable(x) && x > threshold {
                out.joints.push(j as u32);
                out.weights.push(x);
            }
        }
        out.offsets.push(out.joints.len() as u32);
    }
    Ok(out)
}

/// Checks that the weights are structurally sound, cover exactly `vertex_count` vertices,
/// name only joints below `joint_count`, and hold finite, non-negative weights.
///
/// Returns the first problem found. Rows need not sum to 1.
pub fn validate_for(w: &Weights, vertex_count: usize, joint_count: usize) -> Result<(), WeightsError> {
    w.validate().map_err(WeightsError::Structure)?;
    if w.vertex_count() != vertex_count {
        return Err(WeightsError::VertexCount {
            weights: w.vertex_count(),
            mesh: vertex_count,
        });
    }
    for v in 0..w.vertex_count() {
        let (joints, weights) = w.influences(v);
        for (&joint, &weight) in joints.iter().zip(weights) {
            if joint as usize >= joint_count {
                return Err(WeightsError::JointOutOfRange {
                    vertex: v,
                    joint,
                    joint_count,
                });
            }
            if weight < 0.0 {
                return Err(WeightsError::Negative {
                    vertex: v,
                    joint,
                    weight,
                });
            }
        }
    }
    Ok(())
}

/// The largest number of influences on any vertex.
pub fn max_influence_count(w: &Weights) -> usize {
    w.offsets
        .windows(2)
        .map(|p| p[1].saturating_sub(p[0]) as usize)
        .max()
        .unwrap_or(0)
}

/// Converts to fixed 4-wide rows (glTF `JOINTS_0`/`WEIGHTS_0` layout): rows are pruned to the
/// 4 largest influences and renormalized, then padded with joint 0 and weight 0.
pub fn to_fixed4(w: &Weights) -> (Vec<[u32; 4]>, Vec<[f32; 4]>) {
    let p = prune(w, 4);
    let mut joints = Vec::with_capacity(p.vertex_count());
    let mut weights = Vec::with_capacity(p.vertex_count());
    for v in 0..p.vertex_count() {
        let (js, ws) = p.influences(v);
        let (mut j4, mut w4) = ([0u32; 4], [0f32; 4]);
        for (k, (&j, &x)) in js.iter().zip(ws).enumerate().take(4) {
            j4[k] = j;
            w4[k] = x;
        }
        joints.push(j4);
        weights.push(w4);
    }
    (joints, weights)
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn normalize_sums_to_one_and_keeps_unweighted_empty() {
        let w = Weights::from_lists([
            vec![(0, 2.0), (1, 6.0)],
            vec![(0, 0.0), (3, -1.0)],
            vec![(2, f32::NAN), (1, 1.0)],
            vec![],
        ]);
        let n = normalize(&w);
        assert_eq!(n.influences(0), (&[0u32, 1][..], &[0.25f32, 0.75][..]));
        assert_eq!(n.influences(1), (&[][..], &[][..]));
        assert_eq!(n.influences(2), (&[1u32][..], &[1.0f32][..]));
        assert_eq!(n.vertex_count(), 4);
        n.validate().unwrap();
    }

    #[test]
    fn prune_keeps_the_largest() {
        let w = Weights::from_lists([vec![(0, 0.1), (1, 0.4), (2, 0.2), (3, 0.3)]]);
        let p = prune(&w, 2);
        let (j, x) = p.influences(0);
        assert_eq!(j, &[1, 3]);
        // 0.4 / 0.7 and 0.3 / 0.7.
        assert!((x[0] - 4.0 / 7.0).abs() < 1e-6 && (x[1] - 3.0 / 7.0).abs() < 1e-6);
    }

    #[test]
    fn dense_and_validation() {
        let w = from_dense(&[0.5, 0.0, 0.5, 1.0, 0.0, 0.0], 3, 0.0).unwrap();
        assert_eq!(w.joints, vec![0, 2, 0]);
        assert_eq!(w.offsets, vec![0, 2, 3]);
        assert!(from_dense(&[1.0; 5], 3, 0.0).is_err());
        validate_for(&w, 2, 3).unwrap();
        assert!(matches!(
            validate_for(&w, 2, 2),
            Err(WeightsError::JointOutOfRange {
                vertex: 0,
                joint: 2,
                ..
            })
        ));
        assert!(matches!(validate_for(&w, 3, 3), Err(WeightsError::VertexCount { .. })));
        let (j4, w4) = to_fixed4(&w);
        assert_eq!(j4[0], [0, 2, 0, 0]);
        assert_eq!(w4[1], [1.0, 0.0, 0.0, 0.0]);
        assert_eq!(max_influence_count(&w), 2);
    }

    proptest! {
        #[test]
        fn normalized_rows_sum_to_one(rows in prop::collection::vec(
            prop::collection::vec((0u32..64, 0.0f32..10.0), 0..9), 0..40)) {
            let n = normalize(&Weights::from_lists(rows.clone()));
            prop_assert_eq!(n.vertex_count(), rows.len());
            for v in 0..n.vertex_count() {
                let (_, x) = n.influences(v);
                if !x.is_empty() {
                    let s: f32 = x.iter().sum();
                    prop_assert!((s - 1.0).abs() < 1e-6, "row {} sums to {}", v, s);
                }
            }
            let p = prune(&n, 4);
            prop_assert!(max_influence_count(&p) <= 4);
        }
    }
}
