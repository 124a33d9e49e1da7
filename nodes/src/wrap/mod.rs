//! Driving a dense mesh by proxies: Maya's `wrap` and `proximityWrap`.
//!
//! | module | what it is for |
//! | --- | --- |
//! | [`bind`] | binding to the closest driver triangle, rebuilding from the deformed driver |
//! | [`nodes`] | `wrap`, `proximityWrap` |

pub mod bind;
pub mod nodes;

#[cfg(test)]
mod tests;

use sinew_core::{Registry, SpecError};

use crate::deformer::DeformerNode;

/// Registers `wrap` and `proximityWrap`.
pub fn register(registry: &mut Registry) -> Result<(), SpecError> {
    registry.register(DeformerNode::<nodes::Wrap>::new(
        "wrap",
        "moves a dense mesh with the closest triangles of driver meshes",
    )?)?;
    registry.register(DeformerNode::<nodes::ProximityWrap>::new(
        "proximityWrap",
        "a wrap whose motion fades with distance from the drivers and is smoothed over the mesh",
    )?)
}
