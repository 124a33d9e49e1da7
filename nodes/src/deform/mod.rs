//! Deformer kernels and mesh utilities: pure, allocation-free-per-frame functions that the
//! `mesh`, `skinCluster`, `blendShape`, `follicle`, `closestPointOnMesh` and `poseReader`
//! plugins wrap.
//!
//! Nothing here knows about the graph: every function takes plain slices and `glam` types
//! and writes into caller-provided buffers, so the compiled schedule can reuse its buffers
//! frame after frame.
//!
//! | module | what it is for |
//! | --- | --- |
//! | [`primitives`] | procedural meshes (plane, box, UV sphere, cylinder, capsule) with normals and UVs |
//! | [`weights`] | skin weight hygiene: normalize, prune, build from dense rows, validate |
//! | [`skin_weights`] | weights prepared once for the skinning kernels (padded, validated) |
//! | [`skinning`] | linear blend, dual quaternion and weight-blended skinning, serial and parallel |
//! | [`dual_quat`] | unit dual quaternions and the palette conversion used by DQ skinning |
//! | [`blend_shape`] | sparse blend shape targets with in-betweens, weight maps and envelope |
//! | [`bvh`] | a small bounding volume hierarchy over triangles (3D positions or 2D UVs) |
//! | [`closest_point`] | closest point on a mesh, with a reusable, refittable index |
//! | [`surface`] | point, normal and tangent at a UV coordinate (the follicle's query) |
//! | [`pose_reader`] | cone-falloff pose reader math |
//!
//! The node plugins built on them:
//!
//! | module | node types / helpers |
//! | --- | --- |
//! | [`mesh_nodes`] | `polyCube`, `polySphere`, `polyCylinder`, `polyPlane`, `polyCapsule`, `mesh` |
//! | [`skin_cluster`] | `skinCluster` (palette output for engines, precomputed weights) |
//! | [`blend_shape_node`] | `blendShape` (sparse targets, in-betweens, weight maps) |
//! | [`blend_shape_tangent`] | tangent-space blendShape targets (`postDeformersMode`) |
//! | [`blend_shape_transform`] | transform-space blendShape targets (`targetMatrix`) |
//! | [`pose_reader_node`] | `poseReader` (drives correctives) |
//! | [`follicle`] | `follicle`, `closestPointOnMesh` |
//! | [`bind`] | `bind_skin`, `smooth_bind`, `create_closest_follicle` |
//!
//! Deformer order: `mesh`/`polyX` → `blendShape` (pre-deformation) → `skinCluster` →
//! `follicle`, each connected `outputGeometry` → `inputGeometry` (the follicle's
//! `inputMesh`). Each deformer precomputes what does not change per frame (parsed targets,
//! pruned weights, spatial indices) in a separate compute group.

pub mod bind;
pub mod blend_shape;
pub mod blend_shape_node;
pub mod blend_shape_tangent;
pub mod blend_shape_transform;
pub mod bvh;
pub mod closest_point;
pub mod dual_quat;
pub mod follicle;
pub mod mesh_nodes;
pub mod pose_reader;
pub mod pose_reader_node;
pub mod primitives;
pub mod skin_cluster;
pub mod skin_weights;
pub mod skinning;
mod skinning_avx2;
mod skinning_avx2_normals;
mod skinning_lbs;
pub mod surface;
pub mod weights;

#[cfg(test)]
mod tests;
#[cfg(test)]
mod tests_blend_shape_options;
#[cfg(test)]
mod tests_chain;
#[cfg(test)]
mod tests_nodes;
#[cfg(test)]
mod tests_normals;

use sinew_core::{Registry, SpecError};

/// Registers the deformer node types: mesh sources, `skinCluster`, `blendShape`,
/// `poseReader`, `follicle` and `closestPointOnMesh`.
pub fn register(registry: &mut Registry) -> Result<(), SpecError> {
    mesh_nodes::register(registry)?;
    registry.register(skin_cluster::SkinCluster::new()?)?;
    registry.register(blend_shape_node::BlendShape::new()?)?;
    registry.register(pose_reader_node::PoseReader::new()?)?;
    registry.register(follicle::Follicle::new()?)?;
    registry.register(follicle::ClosestPointOnMesh::new()?)?;
    Ok(())
}
