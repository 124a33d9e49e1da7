//! Skin weights as the skinning kernels take them: raw [`Weights`] checked on every call, or
//! [`PreparedWeights`] checked once when the weights change (what `skinCluster` caches).
//!
//! Preparing does two things, neither of which changes a single output bit:
//! - rows of fewer than four influences are padded to four with absent influences (joint
//!   `u32::MAX`, weight 0), exactly as the kernels pad them on the fly, so every vertex
//!   takes the uniform four-influence path;
//! - when every row then holds four *usable* influences (finite weights `≥ 0`, a positive
//!   weight in each row), the largest joint index is recorded. A call whose palette is
//!   longer than that index skips the per-vertex validation entirely: its result is the
//!   one the validation would have allowed anyway. Clean weights whose joints are all
//!   below 1,024 also keep each joint's byte offset in the palette (`64 · joint`) as a
//!   `u16` (8 bytes a vertex instead of 16): the AVX2 kernel then addresses the palette
//!   with no arithmetic.

use sinew_core::data::Weights;

use super::skinning_lbs::pad4;

/// Skin weights checked once for the linear blend kernel (see the module docs).
///
/// Immutable after construction, so the facts it records always describe its weights.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PreparedWeights {
    weights: Weights,
    padded: bool,
    clean_max_joint: Option<u32>,
    palette_offsets: Vec<u16>,
}

impl PreparedWeights {
    /// Prepares `w`: pads rows of at most four influences to exactly four (when some row is
    /// shorter and none is longer) and records whether every row is clean.
    pub fn new(w: &Weights) -> Self {
        let (weights, padded) = match pad_to_four(w) {
            Some(p) => (p, true),
            None => (w.clone(), false),
        };
        let clean_max_joint = clean_max_joint(&weights);
        let palette_offsets = match clean_max_joint {
            Some(m) if m < OFFSET_JOINTS => weights.joints.iter().map(|&j| (j * MATRIX_BYTES) as u16).collect(),
            _ => Vec::new(),
        };
        PreparedWeights {
            weights,
            padded,
            clean_max_joint,
            palette_offsets,
        }
    }

    /// The weights the kernels read: padded to four influences per vertex when
    /// [`PreparedWeights::is_padded`], else the weights given to [`PreparedWeights::new`].
    pub fn weights(&self) -> &Weights {
        &self.weights
    }

    /// Whether short rows were padded to four influences.
    pub fn is_padded(&self) -> bool {
        self.padded
    }

    /// The largest joint index when every vertex has exactly four influences stored back to
    /// back, every weight is finite and `≥ 0`, and every row has a positive weight; `None`
    /// otherwise (the kernels then validate each vertex as they do for raw weights).
    pub fn clean_max_joint(&self) -> Option<u32> {
        self.clean_max_joint
    }

    /// The byte offset (`64 · joint`) of each joint of [`PreparedWeights::weights`] in a
    /// `Mat4` palette when the weights are clean ([`PreparedWeights::clean_max_joint`])
    /// and every joint is below 1,024; empty otherwise.
    pub(super) fn palette_offsets(&self) -> &[u16] {
        &self.palette_offsets
    }
}

/// Bytes of one palette matrix (`Mat4`).
const MATRIX_BYTES: u32 = 64;

/// Joints below this have a palette byte offset that fits in a `u16`.
const OFFSET_JOINTS: u32 = (u16::MAX as u32 + 1) / MATRIX_BYTES;

/// Which weights a skinning call reads.
#[derive(Clone, Copy, Debug)]
pub enum SkinWeights<'a> {
    /// Weights as given, validated per vertex on every call.
    Raw(&'a Weights),
    /// Weights prepared once; the linear blend kernel skips per-vertex validation when
    /// they are clean and the palette covers every joint. DQS and weight-blended skinning
    /// read [`PreparedWeights::weights`] like raw weights.
    Prepared(&'a PreparedWeights),
}

impl<'a> SkinWeights<'a> {
    /// The weights the kernels read.
    pub fn weights(&self) -> &'a Weights {
        match *self {
            SkinWeights::Raw(w) => w,
            SkinWeights::Prepared(p) => &p.weights,
        }
    }

    /// Whether the linear blend kernel may skip per-vertex validation with `palette_len`
    /// matrices: the weights are prepared and clean, and every joint indexes the palette.
    pub(super) fn trusted(&self, palette_len: usize) -> bool {
        match self {
            SkinWeights::Raw(_) => false,
            SkinWeights::Prepared(p) => p.clean_max_joint.is_some_and(|m| (m as usize) < palette_len),
        }
    }

    /// [`PreparedWeights::palette_offsets`] of prepared weights; empty for raw ones.
    pub(super) fn palette_offsets(&self) -> &'a [u16] {
        match *self {
            SkinWeights::Raw(_) => &[],
            SkinWeights::Prepared(p) => p.palette_offsets(),
        }
    }
}

impl<'a> From<&'a Weights> for SkinWeights<'a> {
    fn from(w: &'a Weights) -> Self {
        SkinWeights::Raw(w)
    }
}

impl<'a> From<&'a PreparedWeights> for SkinWeights<'a> {
    fn from(p: &'a PreparedWeights) -> Self {
        SkinWeights::Prepared(p)
    }
}

/// `w` padded to exactly four influences per vertex; `None` when a vertex has more than
/// four or every vertex already has four.
pub fn pad_to_four(w: &Weights) -> Option<Weights> {
    let n = w.vertex_count();
    if (0..n).all(|v| w.influences(v).0.len() == 4) {
        return None;
    }
    let mut out = Weights {
        offsets: Vec::with_capacity(n + 1),
        joints: Vec::with_capacity(4 * n),
        weights: Vec::with_capacity(4 * n),
    };
    out.offsets.push(0);
    for v in 0..n {
        let (js, ws) = w.influences(v);
        // The kernels' own padding of short rows, so both paths agree bit for bit.
        let (j4, w4) = pad4(js, ws)?;
        out.joints.extend_from_slice(&j4);
        out.weights.extend_from_slice(&w4);
        out.offsets.push(u32::try_from(4 * (v + 1)).ok()?);
    }
    Some(out)
}

/// See [`PreparedWeights::clean_max_joint`].
fn clean_max_joint(w: &Weights) -> Option<u32> {
    let n = w.vertex_count();
    // `u32::MAX` marks a padded (absent) influence: no palette reaches it.
    if w.joints.contains(&u32::MAX) {
        return None;
    }
    let layout_ok = w.offsets.len() == n + 1
        && w.joints.len() == 4 * n
        && w.weights.len() == 4 * n
        && w.offsets.iter().enumerate().all(|(v, &o)| o as usize == 4 * v);
    if !layout_ok {
        return None;
    }
    let usable = |x: f32| (0.0..f32::INFINITY).contains(&x);
    let rows_ok = w
        .weights
        .chunks_exact(4)
        .all(|r| r.iter().all(|&x| usable(x)) && r.iter().any(|&x| x > 0.0));
    if !rows_ok {
        return None;
    }
    Some(w.joints.iter().copied().max().unwrap_or(0))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn clean_rows_record_the_largest_joint() {
        let w = Weights::from_lists([vec![(0, 0.25), (5, 0.25), (2, 0.25), (1, 0.25)], vec![(3, 1.0); 4]]);
        let p = PreparedWeights::new(&w);
        assert!(!p.is_padded());
        assert_eq!(p.weights(), &w);
        assert_eq!(p.clean_max_joint(), Some(5));
        assert!(SkinWeights::from(&p).trusted(6));
        assert!(
            !SkinWeights::from(&p).trusted(5),
            "joint 5 is outside a 5-matrix palette"
        );
        assert!(!SkinWeights::from(&w).trusted(100), "raw weights are never trusted");
        assert_eq!(p.palette_offsets(), &[0, 320, 128, 64, 192, 192, 192, 192]);
        assert_eq!(SkinWeights::from(&p).palette_offsets(), p.palette_offsets());
        assert!(SkinWeights::from(&w).palette_offsets().is_empty());
    }

    #[test]
    fn palette_offsets_only_for_clean_weights_that_fit() {
        assert_eq!(OFFSET_JOINTS, 1024);
        assert_eq!(std::mem::size_of::<glam::Mat4>() as u32, MATRIX_BYTES);
        let row = |j: u32| vec![(j, 0.25), (1, 0.25), (2, 0.25), (3, 0.25)];
        let fits = PreparedWeights::new(&Weights::from_lists([row(1023)]));
        assert_eq!(fits.palette_offsets(), &[65_472, 64, 128, 192]);
        let wide = PreparedWeights::new(&Weights::from_lists([row(1024)]));
        assert_eq!(wide.clean_max_joint(), Some(1024));
        assert!(
            wide.palette_offsets().is_empty(),
            "joint 1,024's offset does not fit in 16 bits"
        );
        let unclean = PreparedWeights::new(&Weights::from_lists([vec![(0, 1.0)]]));
        assert!(unclean.palette_offsets().is_empty(), "padded rows are not clean");
    }

    #[test]
    fn unusable_rows_are_not_clean() {
        let base = vec![(0, 0.5), (1, 0.5), (2, 0.0), (3, -0.0)];
        assert_eq!(
            PreparedWeights::new(&Weights::from_lists([base.clone()])).clean_max_joint(),
            Some(3),
            "zero weights (of either sign) are usable while the row has a positive one"
        );
        for bad in [f32::NAN, f32::INFINITY, -0.5] {
            let mut row = base.clone();
            row[1].1 = bad;
            let p = PreparedWeights::new(&Weights::from_lists([row]));
            assert_eq!(p.clean_max_joint(), None, "weight {bad}");
        }
        let all_zero = Weights::from_lists([vec![(0, 0.0); 4]]);
        assert_eq!(PreparedWeights::new(&all_zero).clean_max_joint(), None);
    }

    #[test]
    fn short_rows_pad_but_are_not_clean() {
        let w = Weights::from_lists([vec![(0, 1.0)], vec![(1, 0.5), (2, 0.5)]]);
        let p = PreparedWeights::new(&w);
        assert!(p.is_padded());
        assert_eq!(p.weights().influences(0).0, &[0, u32::MAX, u32::MAX, u32::MAX]);
        assert_eq!(p.clean_max_joint(), None, "padded influences are absent, not clean");
        let five = Weights::from_lists([vec![(0, 0.2); 5]]);
        let p = PreparedWeights::new(&five);
        assert!(!p.is_padded());
        assert_eq!(p.clean_max_joint(), None);
    }
}
