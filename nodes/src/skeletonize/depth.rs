//! Depth: lifts the planar chordal axis into 3D by placing every axis point at the
//! mid-depth of the surface under it (the mean of the nearest and farthest surface
//! depth in the silhouette raster), so joints sit inside the volume.
//!
//! A single view cannot separate parts that overlap in projection (an arm in front
//! of the torso): there the mid-depth lies between them.

use glam::DVec3;

use super::chordal_axis::Axis2;
use super::raster::{Frame, Raster};

/// A 3D axis graph with the same layout as [`Axis2`]: branches of point indices whose
/// first and last entries are key points (branch ends and junctions).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Axis3 {
    /// Axis points in world space.
    pub points: Vec<DVec3>,
    /// Local half-width of the silhouette at each point (0 at tips).
    pub radius: Vec<f64>,
    /// Branches as point indices; the first and last are key points.
    pub branches: Vec<Vec<u32>>,
}

impl Axis3 {
    /// Appends `other`, renumbering its points.
    pub fn append(&mut self, other: Axis3) {
        let base = self.points.len() as u32;
        self.points.extend(other.points);
        self.radius.extend(other.radius);
        self.branches.extend(
            other
                .branches
                .into_iter()
                .map(|b| b.into_iter().map(|i| i + base).collect()),
        );
    }

    /// Length of branch `b`.
    pub fn branch_length(&self, b: usize) -> f64 {
        self.branches[b]
            .windows(2)
            .map(|w| self.points[w[0] as usize].distance(self.points[w[1] as usize]))
            .sum()
    }
}

/// How many pixels around a point the depth lookup may search for drawn pixels.
const SEARCH_RING: usize = 6;

/// Lifts `axis` into world space with mid-depths from `raster`; depths along each
/// branch are smoothed with `smooth_iterations` passes (ends fixed).
pub fn lift(axis: &Axis2, raster: &Raster, frame: &Frame, smooth_iterations: usize) -> Axis3 {
    let mut depth: Vec<f64> = axis
        .points
        .iter()
        .map(|&q| raster.mid_depth(q, SEARCH_RING).unwrap_or(0.0))
        .collect();
    for br in &axis.branches {
        if br.len() < 3 {
            continue;
        }
        let mut d: Vec<f64> = br.iter().map(|&i| depth[i as usize]).collect();
        for _ in 0..smooth_iterations {
            let prev = d.clone();
            for k in 1..d.len() - 1 {
                d[k] = 0.5 * prev[k] + 0.25 * (prev[k - 1] + prev[k + 1]);
            }
        }
        for k in 1..br.len() - 1 {
            depth[br[k] as usize] = d[k];
        }
    }
    Axis3 {
        points: axis
            .points
            .iter()
            .zip(&depth)
            .map(|(&q, &d)| frame.to_world(q, d))
            .collect(),
        radius: axis.radius.clone(),
        branches: axis.branches.clone(),
    }
}
