//! Maya 2020's matrix pins: `uvPin` (output matrices at UV coordinates of a mesh or NURBS
//! surface) and `proximityPin` (matrices that follow the closest point of a deforming mesh,
//! keeping their offset).
//!
//! Shared conventions (`common`): `normalAxis` and `tangentAxis` choose which local axis of
//! each output points along the surface normal and along the surface's `u` tangent (made
//! orthogonal to the normal); the third axis completes a right-handed frame; equal axes use
//! the axis after the normal axis. `relativeSpaceMode`: `world` (0, default) and `local`
//! (1) output the frame in the space the geometry arrives in (sinew's geometry carries no
//! transform: connect `worldMesh`/`worldSpace[0]` for world, `outMesh`/`local` for the
//! object's space), `custom` (2) outputs it relative to `relativeSpaceMatrix`
//! (`relativeSpaceMatrix⁻¹ · frame`, glam order; a singular matrix counts as identity).

mod common;
pub mod proximity_pin;
pub mod uv_pin;

#[cfg(test)]
mod tests;

pub use common::{RELATIVE_SPACE_MODES, SIGNED_AXES};

use sinew_core::{Registry, SpecError};

/// Registers this family's node types.
pub fn register(registry: &mut Registry) -> Result<(), SpecError> {
    registry.register(uv_pin::UvPin::new()?)?;
    registry.register(proximity_pin::ProximityPin::new()?)?;
    Ok(())
}
