//! Constraints: world-space parent/point/orient/aim/scale/poleVector constraints.

use sinew_core::{Registry, SpecError};

/// Registers this family's node types.
pub fn register(registry: &mut Registry) -> Result<(), SpecError> {
    let _ = registry;
    Ok(())
}
