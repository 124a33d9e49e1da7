//! Skeleton extraction from a mesh, end to end: the public entry point
//! [`skeletonize`], its parameters, its result type and its errors.
//!
//! Pipeline: principal-axes view ([`Frame`]) → silhouette raster with front/back
//! depth ([`Raster`]) → outline loops grouped into parts ([`Part`]) → chordal axis
//! per part → mid-depth lift → joints. Every stage works on any input: the raster
//! absorbs holes, several parts, non-manifold edges and degenerate triangles, and
//! outline tracing visits each pixel edge once, so it always terminates.
//!
//! Several parts: by default only the largest silhouette part is skeletonized
//! (one root); with [`SkeletonizeParams::all_parts`] every part gets its own tree
//! (one root each, largest first).

use glam::{DQuat, DVec2, DVec3};

use super::chordal_axis::{chordal_axis, AxisParams};
use super::depth::{lift, Axis3};
use super::joints::{build, JointParams};
use super::outline::{parts, Part};
use super::raster::{Frame, Raster};
use sinew_core::data::Mesh;

/// A joint hierarchy in parent-first order with world-space placement.
///
/// Orientation convention: each joint's +X aims at its main child (the one with the
/// longest subtree), +Z is the silhouette's view axis made perpendicular to +X,
/// +Y = Z × X; leaves copy their parent's orientation.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Skeleton {
    /// Unique joint names (`root`, `branchN_K`, `junctionN`, `branchN_end`).
    pub names: Vec<String>,
    /// Parent of each joint; parents come before their children.
    pub parents: Vec<Option<usize>>,
    /// World-space joint positions.
    pub positions: Vec<DVec3>,
    /// World-space joint orientations (see the type docs for the convention).
    pub orientations: Vec<DQuat>,
}

impl Skeleton {
    /// Number of joints.
    pub fn len(&self) -> usize {
        self.names.len()
    }

    /// True when there are no joints.
    pub fn is_empty(&self) -> bool {
        self.names.is_empty()
    }

    /// Indices of joints without a parent.
    pub fn roots(&self) -> impl Iterator<Item = usize> + '_ {
        self.parents
            .iter()
            .enumerate()
            .filter(|(_, p)| p.is_none())
            .map(|(j, _)| j)
    }

    /// Children of joint `j`.
    pub fn children(&self, j: usize) -> impl Iterator<Item = usize> + '_ {
        self.parents
            .iter()
            .enumerate()
            .filter(move |(_, p)| **p == Some(j))
            .map(|(c, _)| c)
    }

    /// Appends a joint (identity orientation until oriented).
    pub(crate) fn push(&mut self, name: String, parent: Option<usize>, position: DVec3) {
        self.names.push(name);
        self.parents.push(parent);
        self.positions.push(position);
        self.orientations.push(DQuat::IDENTITY);
    }
}

/// Parameters of [`skeletonize`]. `Default` gives values that suit typical characters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SkeletonizeParams {
    /// Silhouette raster size in pixels along its longer side (default 256, clamped to 8..=4096).
    pub resolution: usize,
    /// Gaps up to `2 × close_radius` pixels wide are closed (default 1).
    pub close_radius: usize,
    /// Outline simplification tolerance in pixels (default 1.0).
    pub simplify_tolerance: f64,
    /// Outline loops smaller than this many square pixels are ignored (default 6.0).
    pub min_loop_area: f64,
    /// A terminal branch shorter than `prune_factor ×` the inscribed radius at its
    /// junction is pruned (default 1.6).
    pub prune_factor: f64,
    /// Junctions closer than `merge_factor ×` their radius are merged (default 1.5).
    pub merge_factor: f64,
    /// Smoothing passes over each branch, in plane and in depth (default 3).
    pub smooth_iterations: usize,
    /// An interior joint is placed where a branch turns by more than this many
    /// degrees (default 30).
    pub angle_limit_degrees: f64,
    /// Turn detection tolerance as a multiple of the local half-width (default 0.5).
    pub turn_tolerance: f64,
    /// When set, every branch gets exactly this many bones spaced by arc length,
    /// instead of joints at turns (default `None`).
    pub bones_per_branch: Option<usize>,
    /// Root at the skeleton point nearest this world position (default `None`:
    /// the highest-degree junction nearest the centroid; for a chain, its lowest end).
    pub root_hint: Option<DVec3>,
    /// View along this axis instead of the least-variance principal axis (default `None`).
    pub view_axis: Option<DVec3>,
    /// Skeletonize every silhouette part (one root each) instead of only the largest
    /// (default `false`).
    pub all_parts: bool,
}

impl Default for SkeletonizeParams {
    fn default() -> Self {
        SkeletonizeParams {
            resolution: 256,
            close_radius: 1,
            simplify_tolerance: 1.0,
            min_loop_area: 6.0,
            prune_factor: 1.6,
            merge_factor: 1.5,
            smooth_iterations: 3,
            angle_limit_degrees: 30.0,
            turn_tolerance: 0.5,
            bones_per_branch: None,
            root_hint: None,
            view_axis: None,
            all_parts: false,
        }
    }
}

/// Why a mesh could not be skeletonized or weighted.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum SkeletonizeError {
    /// The mesh has no vertices or no triangles.
    #[error("the mesh is empty ({vertices} vertices, {triangles} triangles); give a mesh with triangles")]
    EmptyMesh {
        /// Number of vertices.
        vertices: usize,
        /// Number of triangles.
        triangles: usize,
    },
    /// The mesh breaks the `Mesh` invariants.
    #[error("invalid mesh: {0}")]
    InvalidMesh(String),
    /// The mesh has no extent in at least two directions (a point or a line).
    #[error("the mesh is degenerate: it has no area when seen from any side (extent {extent:e}); a skeleton needs a mesh with width and length")]
    Degenerate {
        /// The largest extent of the mesh seen along its view axis.
        extent: f64,
    },
    /// The silhouette has no interior to draw an axis in.
    #[error(
        "the silhouette has no interior (it covers fewer than a few pixels); raise the resolution or check the mesh"
    )]
    NoInterior,
    /// The skeleton has no joints (weights need at least one).
    #[error("the skeleton has no joints")]
    EmptySkeleton,
    /// The sparse solver failed and no fallback applied.
    #[error("the weights solve failed: {0}")]
    Solver(String),
}

/// Everything [`skeletonize_detailed`] computed on the way, for inspection and drawing.
#[derive(Clone, Debug)]
pub struct SkeletonDetails {
    /// The skeleton.
    pub skeleton: Skeleton,
    /// The projection frame.
    pub frame: Frame,
    /// Silhouette parts in plane coordinates, largest first.
    pub parts: Vec<Part>,
    /// The chordal axis of the skeletonized parts, lifted to 3D.
    pub axis: Axis3,
}

/// Extracts a joint hierarchy from `mesh`.
///
/// Never panics; returns an error for empty, invalid or degenerate meshes, or when
/// the silhouette has no interior at the chosen resolution.
pub fn skeletonize(mesh: &Mesh, params: &SkeletonizeParams) -> Result<Skeleton, SkeletonizeError> {
    skeletonize_detailed(mesh, params).map(|d| d.skeleton)
}

/// Like [`skeletonize`], also returning the intermediate frame, outline and axis.
pub fn skeletonize_detailed(mesh: &Mesh, params: &SkeletonizeParams) -> Result<SkeletonDetails, SkeletonizeError> {
    if mesh.positions.is_empty() || mesh.triangles.is_empty() {
        return Err(SkeletonizeError::EmptyMesh {
            vertices: mesh.positions.len(),
            triangles: mesh.triangles.len(),
        });
    }
    mesh.validate().map_err(SkeletonizeError::InvalidMesh)?;
    let frame = Frame::principal(mesh, params.view_axis).ok_or(SkeletonizeError::Degenerate { extent: 0.0 })?;
    let (lo, hi) = mesh.positions.iter().fold(
        (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)),
        |(lo, hi), p| {
            let q = frame.to_plane(p.as_dvec3());
            (lo.min(q), hi.max(q))
        },
    );
    let ext = hi - lo;
    let has_area = ext.min_element() > 1e-9 * ext.max_element().max(1e-300);
    if !has_area || ext.max_element() <= 0.0 {
        return Err(SkeletonizeError::Degenerate {
            extent: ext.max_element().max(0.0),
        });
    }
    let raster = Raster::draw(mesh, &frame, params.resolution.max(8), params.close_radius).ok_or(
        SkeletonizeError::Degenerate {
            extent: ext.max_element(),
        },
    )?;
    let px = raster.pixel;
    let mut all = parts(
        &raster,
        params.simplify_tolerance.max(0.0) * px,
        params.min_loop_area.max(0.0) * px * px,
    );
    if all.is_empty() {
        return Err(SkeletonizeError::NoInterior);
    }
    if !params.all_parts {
        all.truncate(1);
    }
    let axis_params = AxisParams {
        prune_factor: params.prune_factor,
        merge_factor: params.merge_factor,
        smooth_iterations: params.smooth_iterations,
    };
    let mut axis = Axis3::default();
    for part in &all {
        let a2 = chordal_axis(part, &axis_params);
        axis.append(lift(&a2, &raster, &frame, params.smooth_iterations));
    }
    if axis.branches.is_empty() {
        return Err(SkeletonizeError::NoInterior);
    }
    let joint_params = JointParams {
        angle_limit: params.angle_limit_degrees.to_radians(),
        turn_tolerance: params.turn_tolerance,
        bones_per_branch: params.bones_per_branch,
        root_hint: params.root_hint,
    };
    let skeleton = build(&axis, &frame, &joint_params, params.all_parts);
    if skeleton.is_empty() {
        return Err(SkeletonizeError::NoInterior);
    }
    Ok(SkeletonDetails {
        skeleton,
        frame,
        parts: all,
        axis,
    })
}
