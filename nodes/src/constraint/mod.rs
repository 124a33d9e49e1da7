//! Constraints: world-space parent/point/orient/aim/scale/poleVector constraints, and the
//! geometry constraints (geometry, normal, tangent, pointOnPoly).
//!
//! Each constraint node reads its targets' world matrices and writes local
//! values for one constrained node ("the child") through the child's
//! `parentInverseMatrix`, as Maya's constraint nodes do. Node and attribute
//! names follow Maya where the model allows; where sinew differs (world
//! matrices instead of per-target translate/rotate/parentMatrix plugs) the
//! difference is stated here.
//!
//! # Common attributes
//!
//! * `targetWorldMatrix[i]` (matrix; connect from target.worldMatrix): the
//!   targets that exist are the existing elements of this multi.
//!   `targetWeight[i]` (float, default 1; negative counts as 0) and
//!   `targetOffset[i]` (matrix, identity = no offset) go with the same `i`.
//!   Target `i` stands for the world matrix `E_i = targetWorldMatrix[i] *
//!   targetOffset[i]` (glam column vectors; Maya row-vector order
//!   `targetOffset · targetWorldMatrix`). [`maintain_offset`] sets
//!   `targetOffset[i] = targetWorldMatrix[i]⁻¹ * childWorld` so that
//!   `E_i = childWorld` at creation.
//! * `constraintParentInverseMatrix` (connect from child.parentInverseMatrix).
//! * Rotation outputs: `constraintRotateOrder`, `constraintJointOrient`
//!   (degrees, 0 for transforms) and `constraintRotateAxis` (degrees):
//!   `constraintRotate` solves glam `JO * R * RA = local` for `R` in the
//!   rotate order ([`rotate_for_orientation`](crate::transform::math::rotate_for_orientation)),
//!   choosing among equivalent euler triples the one closest to `restRotate`.
//! * Translation outputs: `constraintRotatePivot` and
//!   `constraintRotateTranslate` (the child's rotatePivot and
//!   rotatePivotTranslate, 0 for joints) are subtracted so that the child's
//!   rotate pivot, not just its origin, lands on the target point.
//! * `skipTranslateX/Y/Z`, `skipRotateX/Y/Z`, `skipScaleX/Y/Z` (bool): a
//!   skipped axis outputs the matching component of `restTranslate` /
//!   `restRotate` / `restScale` (defaults 0 / 0 / 1; [`constrain`] sets them
//!   to the child's values at creation, so skipped axes stay put).
//!
//! # Zero weight and degenerate input
//!
//! When no target has positive weight (no targets, all weights 0 or
//! negative), every output is its rest value. Maya leaves the channels alone
//! unless `enableRestPosition` is on; a pure node cannot "leave alone", so
//! sinew always behaves as if `enableRestPosition` were on (the attribute
//! itself is not declared). Outputs are never NaN: non-finite intermediate
//! results also fall back to the rest values, and singular matrices take the
//! fallbacks documented on each node.
//!
//! # Orientation blending (`interpType`, parent and orient)
//!
//! Maya's choices, in Maya's enum order: `noFlip` (0), `average` (1, the
//! default), `shortest` (2), `longest` (3), `cache` (4).
//! * `average`: normalized weighted sum of the targets' quaternions, each
//!   flipped into the hemisphere of the first target
//!   ([`quat_blend_weighted`](crate::transform::math::quat_blend_weighted)).
//! * `shortest` / `longest`: successive slerps
//!   `q ← slerp(q, q_i, w_i / (w_0 + … + w_i))` along the shorter / longer
//!   arc. For two targets 50/50 `shortest` equals `average`.
//! * `noFlip` and `cache`: Maya's `noFlip` depends on the previous frame and
//!   `cache` on a baked curve; neither fits a pure node evaluated in any
//!   order, so both evaluate as `average` (which does not flip while the
//!   targets stay within 180° of target 0).
//!
//! # Files
//! `common` (shared inputs and blends), `rotation_path` (orient and parent
//! rotations on matrices), `parent` (parentConstraint,
//! pointConstraint), `orient` (orientConstraint, aimConstraint), `scale`
//! (scaleConstraint, poleVectorConstraint), `geometry` (geometryConstraint,
//! normalConstraint, tangentConstraint, over the target geometry of `geometry_targets`),
//! `point_on_poly` (pointOnPolyConstraint), `helpers` ([`constrain`],
//! [`maintain_offset`]).

mod common;
mod geometry;
mod geometry_targets;
mod helpers;
mod orient;
mod parent;
mod point_on_poly;
mod rotation_path;
mod scale;

#[cfg(test)]
mod tests;
#[cfg(test)]
mod tests_geometry;
#[cfg(test)]
mod tests_helpers;
#[cfg(test)]
mod tests_props;

pub use common::{INTERP_TYPES, ROTATE_ORDERS};
pub use geometry::{AimAtGeometry, GeometryConstraint};
pub use helpers::{constrain, maintain_offset, ConstraintKind};
pub(crate) use orient::world_up;
pub use orient::{AimConstraint, OrientConstraint, WORLD_UP_TYPES};
pub use parent::{ParentConstraint, PointConstraint};
pub use point_on_poly::PointOnPolyConstraint;
pub use scale::{PoleVectorConstraint, ScaleConstraint};

use sinew_core::{Registry, SpecError};

/// Registers this family's node types.
pub fn register(registry: &mut Registry) -> Result<(), SpecError> {
    registry.register(ParentConstraint::new()?)?;
    registry.register(PointConstraint::new()?)?;
    registry.register(OrientConstraint::new()?)?;
    registry.register(AimConstraint::new()?)?;
    registry.register(ScaleConstraint::new()?)?;
    registry.register(PoleVectorConstraint::new()?)?;
    registry.register(GeometryConstraint::new()?)?;
    registry.register(AimAtGeometry::normal()?)?;
    registry.register(AimAtGeometry::tangent()?)?;
    registry.register(PointOnPolyConstraint::new()?)?;
    Ok(())
}
