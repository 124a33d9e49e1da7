//! The machinery every deformer beyond skinCluster and blendShape shares: the
//! `geometryFilter` attributes (`inputGeometry`, `envelope`, `weightList`, membership,
//! `outputGeometry`), the generic node that runs a deformer kernel over the active vertices
//! only, normals recomputed when positions change, mesh connectivity for neighbourhood
//! deformers, and the fast `f32` trigonometry the kernels use.
//!
//! | module | what it is for |
//! | --- | --- |
//! | [`base`] | [`base::DeformerAttrs`], [`base::Membership`], [`base::Deformer`], [`base::DeformerNode`] |
//! | [`topology`] | vertex adjacency, border vertices, geodesic (edge) distances |
//! | [`fastmath`] | branch-free `sin`/`cos` for per-vertex kernels |
//! | `simd` | AVX2 transposes of eight points for the dense loops (x86-64) |
//!
//! A deformer family (`cluster/`, `nonlinear/`, `lattice/`, `wire/`, `mush/`, `wrap/`)
//! implements [`base::Deformer`] and registers `DeformerNode::<TheDeformer>::new(name, doc)`.
//! Chains are ordinary connections, `a.outputGeometry → b.inputGeometry`, in Maya's order.

pub mod base;
pub mod fastmath;
#[cfg(target_arch = "x86_64")]
pub mod simd;
pub mod topology;

#[cfg(test)]
pub(crate) mod testing;
#[cfg(test)]
mod tests_chain;

pub use base::{Deformer, DeformerAttrs, DeformerNode, Job, Membership};
