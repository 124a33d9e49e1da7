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
//! | [`skinning`] | linear blend, dual quaternion and weight-blended skinning, serial and parallel |
//! | [`dual_quat`] | unit dual quaternions and the palette conversion used by DQ skinning |
//! | [`blend_shape`] | sparse blend shape targets with in-betweens, weight maps and envelope |
//! | [`bvh`] | a small bounding volume hierarchy over triangles (3D positions or 2D UVs) |
//! | [`closest_point`] | closest point on a mesh, with a reusable, refittable index |
//! | [`surface`] | point, normal and tangent at a UV coordinate (the follicle's query) |
//! | [`pose_reader`] | cone-falloff pose reader math |

pub mod blend_shape;
pub mod bvh;
pub mod closest_point;
pub mod dual_quat;
pub mod pose_reader;
pub mod primitives;
pub mod skinning;
pub mod surface;
pub mod weights;

#[cfg(test)]
mod tests;
