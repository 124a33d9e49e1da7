//! skeletonize: a skeleton from a mesh's silhouette (chordal axis of a
//! constrained Delaunay triangulation, centred in depth) and automatic skin
//! weights by bone-heat diffusion. The algorithms are pure functions; the
//! `skeletonize` node plugin wraps them.
//!
//! | module | what it is for |
//! | --- | --- |
//! | [`raster`] | projection frame and silhouette raster (coverage, near/far depth) |
//! | [`outline`] | marching-squares outline loops, simplification, parts with holes |
//! | [`chordal_axis`] | spade CDT, branch graph, pruning, smoothing |
//! | [`depth`] | mid-depth placement of the axis |
//! | [`joints`] | root choice, joint placement, names, orientations |
//! | [`extract`] | public API: `skeletonize`, parameters, errors |
//! | [`heat_weights`] | bone-heat weights with faer, inverse-distance fallback |
//! | [`shapes`] | procedural test shapes (capsule, plus, star, humanoid) |
//! | [`node`] | the `skeletonize` node plugin |

pub mod chordal_axis;
pub mod depth;
pub mod extract;
pub mod heat_weights;
pub mod joints;
pub mod node;
pub mod outline;
pub mod raster;
pub mod shapes;
#[cfg(test)]
mod tests;
#[cfg(test)]
mod tests_node;

pub use extract::{skeletonize, skeletonize_detailed, Skeleton, SkeletonDetails, SkeletonizeError, SkeletonizeParams};
pub use heat_weights::{bone_heat_weights, bone_heat_weights_with_report, Laplacian, WeightParams, WeightReport};

pub use node::{SkeletonData, SkeletonizeNode};

/// Registers the `skeletonize` node type.
pub fn register(registry: &mut sinew_core::Registry) -> Result<(), sinew_core::SpecError> {
    registry.register(SkeletonizeNode::new()?)
}
