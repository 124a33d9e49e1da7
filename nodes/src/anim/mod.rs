//! Animation curves: Maya-compatible key/tangent evaluation ([`curve`]) and
//! the animCurve node plugins built on it.

pub mod curve;
mod key;
mod segment;
mod tangents;

/// Registers this family's node types.
pub fn register(registry: &mut sinew_core::Registry) -> Result<(), sinew_core::SpecError> {
    let _ = registry;
    Ok(())
}
