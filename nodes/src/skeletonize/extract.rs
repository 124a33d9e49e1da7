//! Skeleton extraction from a mesh, end to end: the public entry point
//! [`skeletonize`], its parameters, its result type and its errors.
//!
//! Pipeline: a curve graph from one of two methods — the volume method (the solid's
//! level-set skeleton, [`super::volume`]; the default) or the silhouette method (the
//! chordal axis of one view, [`super::silhouette`]; for flat meshes, or on request) —
//! then its root at the torso's centre of mass ([`super::tree`]), mirror symmetry
//! ([`super::symmetry`]) and joints ([`super::articulate`]). Every stage works on any
//! input; what could not be used is reported in [`SkeletonDetails`], never dropped
//! silently.

use glam::{DQuat, DVec3};

use super::articulate::{articulate, Chain, JointParams};
use super::curve::CurveGraph;
use super::raster::Frame;
use super::silhouette::silhouette_graph;
use super::symmetry::{symmetrize, Mirror, SymmetryReport};
use super::template::{fit, Template};
use super::tree::{choose_roots, grow, Tree};
use super::volume::{curve_graph, PartFate, VolumeParams, VolumeReport};
use sinew_core::data::Mesh;

/// A joint hierarchy in parent-first order with world-space placement.
///
/// Orientation convention: each joint's +X aims at its main child (the one with the
/// longest subtree), +Z is the mesh's axis of least extent (its principal axis of
/// least variance) made perpendicular to +X, +Y = Z × X; leaves copy their parent's
/// orientation; right joints of mirror pairs are their left joints turned 180° about
/// the mirror normal (see [`super::articulate`]).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Skeleton {
    /// Unique joint names (see [`super::articulate`] for the scheme).
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

/// Which extraction method to use.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Method {
    /// The volume method, or the silhouette method for a flat mesh (thinner than
    /// 2.5 cells along its axis of least extent).
    #[default]
    Auto,
    /// The level-set skeleton of the voxelized solid ([`super::volume`]).
    Volume,
    /// The chordal axis of one silhouette, centred in depth ([`super::silhouette`]).
    Silhouette,
}

/// Parameters of [`skeletonize`]. `Default` gives values that suit typical characters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SkeletonizeParams {
    /// Extraction method (default [`Method::Auto`]).
    pub method: Method,
    /// Volume method: cells along the bounding box's longest side (default 96, at
    /// least 8; the cell size grows if the grid would exceed 2²⁴ cells).
    pub resolution: usize,
    /// Silhouette method: raster size in pixels along its longer side (default 256,
    /// clamped to 8..=4096).
    pub silhouette_resolution: usize,
    /// Volume method: width of a distance band in cells (default 1.8, the least).
    pub band: f64,
    /// Silhouette method: gaps up to `2 × close_radius` pixels wide are closed (default 1).
    pub close_radius: usize,
    /// Silhouette method: outline simplification tolerance in pixels (default 1.0).
    pub simplify_tolerance: f64,
    /// Silhouette method: outline loops smaller than this many square pixels are
    /// ignored (default 6.0).
    pub min_loop_area: f64,
    /// A terminal chain shorter than `prune_factor ×` the body radius at its junction
    /// is pruned (default 1.2).
    pub prune_factor: f64,
    /// Junctions closer than `merge_factor ×` their radius are merged (default 1.5).
    pub merge_factor: f64,
    /// Smoothing passes over the curve points (default 1; the silhouette method
    /// smooths its axis three times this).
    pub smooth_iterations: usize,
    /// A limb bend sharper than this many degrees is an articulation (default 20).
    pub angle_limit_degrees: f64,
    /// A radius at least this fraction below the largest on both sides is an
    /// articulation (default 0.15).
    pub thinning: f64,
    /// Bones per limb, from the limb's base to its tip (default 3).
    pub joints_per_limb: usize,
    /// When set, every branch gets exactly this many bones spaced by arc length, with
    /// no base joints or articulation search (default `None`).
    pub bones_per_branch: Option<usize>,
    /// Root at the skeleton point nearest this world position (default `None`: the
    /// torso's centre of mass).
    pub root_hint: Option<DVec3>,
    /// Silhouette method: view along this axis instead of the least-variance axis
    /// (default `None`).
    pub view_axis: Option<DVec3>,
    /// Join separate parts to the nearest part by a bridge bone (default `true`);
    /// when off, each part gets its own root.
    pub join_parts: bool,
    /// Parts smaller than this fraction of the largest one get no joints of their own
    /// (reported; default 0.01).
    pub min_part_fraction: f64,
    /// Detect a mirror plane and make the skeleton symmetric (default `true`).
    pub symmetry: bool,
    /// The mesh counts as symmetric when at most this fraction of its volume has no
    /// mirror image within one cell (default 0.03).
    pub symmetry_tolerance: f64,
    /// Fit a named skeleton to the extracted one (default `None`: the extracted joints
    /// with generic names).
    pub template: Option<Template>,
}

impl SkeletonizeParams {
    /// The volume method's tuning for a grid of `resolution` cells along the longest side
    /// (the symmetry tolerance only when `symmetry` is on).
    pub fn volume_params(&self, resolution: usize) -> VolumeParams {
        VolumeParams {
            resolution,
            band: self.band,
            prune_factor: self.prune_factor,
            merge_factor: self.merge_factor,
            smooth_iterations: self.smooth_iterations,
            min_part_fraction: self.min_part_fraction,
            symmetry_tolerance: self.symmetry.then_some(self.symmetry_tolerance),
        }
    }
}

impl Default for SkeletonizeParams {
    fn default() -> Self {
        SkeletonizeParams {
            method: Method::Auto,
            resolution: 96,
            silhouette_resolution: 256,
            band: 1.8,
            close_radius: 1,
            simplify_tolerance: 1.0,
            min_loop_area: 6.0,
            prune_factor: 1.2,
            merge_factor: 1.5,
            smooth_iterations: 1,
            angle_limit_degrees: 20.0,
            thinning: 0.15,
            joints_per_limb: 3,
            bones_per_branch: None,
            root_hint: None,
            view_axis: None,
            join_parts: true,
            min_part_fraction: 0.01,
            symmetry: true,
            symmetry_tolerance: 0.03,
            template: None,
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
        /// The largest extent of the mesh.
        extent: f64,
    },
    /// Nothing inside to draw an axis in.
    #[error(
        "the mesh has no interior to put a skeleton in (its solid or silhouette covers fewer than a few cells); raise the resolution or check the mesh"
    )]
    NoInterior,
    /// The skeleton has no joints (weights need at least one).
    #[error("the skeleton has no joints")]
    EmptySkeleton,
    /// The template does not fit the extracted skeleton.
    #[error("{0}")]
    Template(String),
    /// The sparse solver failed and no fallback applied.
    #[error("the weights solve failed: {0}")]
    Solver(String),
}

/// Everything [`skeletonize_detailed`] computed on the way, for reports and drawing.
#[derive(Clone, Debug)]
pub struct SkeletonDetails {
    /// The skeleton.
    pub skeleton: Skeleton,
    /// The method used (never [`Method::Auto`]).
    pub method: Method,
    /// The mesh's principal frame (`w`: the axis of least extent).
    pub frame: Frame,
    /// The cleaned curve graph the skeleton was built on.
    pub graph: CurveGraph,
    /// The rooted tree of branches (after symmetrization).
    pub tree: Tree,
    /// Per tree branch, its joints (in the extracted skeleton, before any template).
    pub chains: Vec<Chain>,
    /// The mirror plane the skeleton is symmetric across.
    pub mirror: Option<Mirror>,
    /// What the symmetrization did.
    pub symmetry: SymmetryReport,
    /// The volume method's report (grid, parts, holes, loops, mismatch).
    pub volume: Option<VolumeReport>,
    /// The silhouette method's outline parts, largest first, and what became of each.
    pub silhouette_parts: Vec<PartFate>,
}

/// Extracts a joint hierarchy from `mesh`.
///
/// Never panics; returns an error for empty, invalid or degenerate meshes, or when
/// nothing of the mesh has an interior at the chosen resolution.
pub fn skeletonize(mesh: &Mesh, params: &SkeletonizeParams) -> Result<Skeleton, SkeletonizeError> {
    skeletonize_detailed(mesh, params).map(|d| d.skeleton)
}

/// Like [`skeletonize`], also returning what was computed on the way.
pub fn skeletonize_detailed(mesh: &Mesh, params: &SkeletonizeParams) -> Result<SkeletonDetails, SkeletonizeError> {
    if mesh.positions.is_empty() || mesh.triangles.is_empty() {
        return Err(SkeletonizeError::EmptyMesh {
            vertices: mesh.positions.len(),
            triangles: mesh.triangles.len(),
        });
    }
    mesh.validate().map_err(SkeletonizeError::InvalidMesh)?;
    let frame = Frame::principal(mesh, None).ok_or(SkeletonizeError::Degenerate { extent: 0.0 })?;
    let (lo, hi) = frame_extent(mesh, &frame);
    let ext = hi - lo;
    let longest = ext.max_element();
    let mut sorted = [ext.x, ext.y, ext.z];
    sorted.sort_by(f64::total_cmp);
    let middle = sorted[1];
    if !(longest > 0.0 && longest.is_finite()) || middle <= 1e-9 * longest {
        return Err(SkeletonizeError::Degenerate {
            extent: longest.max(0.0),
        });
    }
    let resolution = params.resolution.max(8);
    let flat = sorted[0] < 2.5 * longest / resolution as f64;
    let method = match params.method {
        Method::Auto if flat => Method::Silhouette,
        Method::Auto => Method::Volume,
        m => m,
    };
    let (graph, volume, silhouette_parts, mirror_hint) = match method {
        Method::Silhouette => {
            let (g, fates) = silhouette_graph(mesh, params)?;
            (g, None, fates, None)
        }
        _ => {
            let vp = params.volume_params(resolution);
            let (g, report, _) =
                curve_graph(mesh, &vp, params.join_parts).ok_or(SkeletonizeError::Degenerate { extent: longest })?;
            let m = report.mirror;
            (g, Some(report), Vec::new(), m)
        }
    };
    if graph.live().next().is_none() {
        return Err(SkeletonizeError::NoInterior);
    }
    // The silhouette's axis keeps the loops of holes; joins never make one, but the
    // hierarchy needs a tree whatever the graph.
    let mut graph = graph;
    graph.break_loops();
    let cell = volume
        .as_ref()
        .map_or(longest / params.silhouette_resolution.max(8) as f64, |v| v.grid.h);
    let mirror = if params.symmetry && params.root_hint.is_none() {
        mirror_hint
    } else {
        None
    };
    let on_plane = |p: DVec3| mirror.is_none_or(|m| m.distance(p).abs() <= 1.5 * cell);
    let roots = choose_roots(&graph, params.root_hint, &on_plane);
    let mut tree = grow(&graph, &roots);
    let symmetry = match &mirror {
        Some(m) => symmetrize(&mut tree, m, 1.5 * cell),
        None => SymmetryReport::default(),
    };
    let joint_params = JointParams {
        joints_per_limb: params.joints_per_limb.max(1),
        bones_per_branch: params.bones_per_branch.filter(|&b| b > 0),
        angle_limit: params.angle_limit_degrees.to_radians(),
        thinning: params.thinning,
        reference: frame.w,
    };
    let art = articulate(&tree, &joint_params, mirror.as_ref());
    if art.skeleton.is_empty() {
        return Err(SkeletonizeError::NoInterior);
    }
    let skeleton = match params.template {
        Some(t) => fit(t, &art, &tree, mirror.as_ref(), frame.w)?,
        None => art.skeleton,
    };
    Ok(SkeletonDetails {
        skeleton,
        method,
        frame,
        graph,
        tree,
        chains: art.chains,
        mirror,
        symmetry,
        volume,
        silhouette_parts,
    })
}

/// Bounds of the vertices used by triangles, in the frame's (u, v, w) coordinates.
fn frame_extent(mesh: &Mesh, frame: &Frame) -> (DVec3, DVec3) {
    let mut lo = DVec3::INFINITY;
    let mut hi = DVec3::NEG_INFINITY;
    for t in &mesh.triangles {
        for &i in t {
            if let Some(p) = mesh.positions.get(i as usize) {
                let d = p.as_dvec3() - frame.origin;
                let q = DVec3::new(d.dot(frame.u), d.dot(frame.v), d.dot(frame.w));
                lo = lo.min(q);
                hi = hi.max(q);
            }
        }
    }
    (lo, hi)
}
