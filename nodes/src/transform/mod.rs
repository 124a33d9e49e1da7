//! Transform and joint nodes and the matrix utilities built on the same math.
//!
//! The math modules ([`math`], [`euler`], [`decompose`], [`orient`]) are pure
//! functions in radians; the node plugins convert the graph's degrees.

pub mod decompose;
pub mod euler;
pub mod math;
pub mod orient;

/// Registers this family's node types.
pub fn register(registry: &mut sinew_core::Registry) -> Result<(), sinew_core::SpecError> {
    let _ = registry;
    Ok(())
}
