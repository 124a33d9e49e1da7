//! skeletonize: a skeleton from a mesh and automatic skin weights by bone-heat
//! diffusion. The default (volume) method voxelizes the mesh, takes the level sets of
//! the geodesic distance inside each part as the curve skeleton, roots it at the
//! torso's centre of mass, makes it symmetric when the mesh is, and puts joints where
//! limbs bend or thin; a silhouette method (the chordal axis of one view) serves flat
//! meshes. The algorithms are pure functions; the `skeletonize` node plugin wraps them.
//!
//! | module | what it is for |
//! | --- | --- |
//! | [`extract`] | public API: `skeletonize`, parameters, errors, details |
//! | [`voxel`] | the solid: grid, surface cells, outside flood fill, hole closing |
//! | [`distance`] | exact Euclidean distance transform (inscribed radii) |
//! | [`levels`] | parts, geodesic distance, level-set clusters and their graph |
//! | [`medial`] | medial detours for edges that cut through the surface (penalized paths) |
//! | [`volume`] | the volume method end to end, parts joined |
//! | [`curve`] | the curve graph and its clean-up (loops, spurs, junctions, tips) |
//! | [`tree`] | root at the torso's centre of mass, branches parent first |
//! | [`symmetry`] | mirror plane detection, exact symmetrization, `_L`/`_R` pairs |
//! | [`articulate`] | joints at bends and thickness minima, names, orientations |
//! | [`template`] | humanoid and quadruped templates fitted to the extracted skeleton |
//! | [`raster`] | silhouette method: projection frame and silhouette raster |
//! | [`outline`] | silhouette method: outline loops, simplification, parts with holes |
//! | [`chordal_axis`] | silhouette method: spade CDT, branch graph, pruning, smoothing |
//! | [`depth`] | silhouette method: mid-depth placement of the axis |
//! | [`silhouette`] | the silhouette method end to end |
//! | [`heat_weights`] | bone-heat weights with faer, inverse-distance fallback |
//! | [`shapes`] | procedural test shapes (capsule, plus, star, torus, humanoid) |
//! | [`bodies`] | procedural characters with known answers (humanoid, quadruped, hand, X, ring) |
//! | [`node`] | the `skeletonize` node plugin |

pub mod articulate;
pub mod bodies;
pub mod chordal_axis;
pub mod curve;
pub mod depth;
pub mod distance;
pub mod extract;
pub mod heat_weights;
pub mod levels;
pub mod medial;
pub mod node;
pub mod outline;
pub mod raster;
pub mod shapes;
pub mod silhouette;
pub mod symmetry;
pub mod template;
#[cfg(test)]
mod tests;
#[cfg(test)]
mod tests_bodies;
#[cfg(test)]
mod tests_node;
#[cfg(test)]
mod tests_parts;
pub mod tree;
pub mod volume;
pub mod voxel;

pub use extract::{
    skeletonize, skeletonize_detailed, Method, Skeleton, SkeletonDetails, SkeletonizeError, SkeletonizeParams,
};
pub use heat_weights::{bone_heat_weights, bone_heat_weights_with_report, Laplacian, WeightParams, WeightReport};
pub use template::Template;

pub use node::{SkeletonData, SkeletonizeNode};

/// Registers the `skeletonize` node type.
pub fn register(registry: &mut sinew_core::Registry) -> Result<(), sinew_core::SpecError> {
    registry.register(SkeletonizeNode::new()?)
}
