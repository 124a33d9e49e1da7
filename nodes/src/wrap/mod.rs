//! Driving a dense mesh by proxies: Maya's `wrap` and `proximityWrap`.
//!
//! | module | what it is for |
//! | --- | --- |
//! | [`bind`] | binding to the closest driver triangle, rebuilding from the deformed driver |
//! | [`nodes`] | `wrap`, `proximityWrap` |
//! | [`shrink_wrap`] | `shrinkWrap`: projection onto a target mesh |

pub mod bind;
pub mod nodes;
pub mod shrink_wrap;

#[cfg(test)]
mod tests;
#[cfg(test)]
mod tests_shrink_wrap;

use sinew_core::{Registry, SpecError};

use crate::deformer::DeformerNode;

/// Registers `wrap`, `proximityWrap` and `shrinkWrap`.
pub fn register(registry: &mut Registry) -> Result<(), SpecError> {
    registry.register(DeformerNode::<nodes::Wrap>::new(
        "wrap",
        "moves a dense mesh with the closest triangles of driver meshes",
    )?)?;
    registry.register(DeformerNode::<nodes::ProximityWrap>::new(
        "proximityWrap",
        "a wrap whose motion fades with distance from the drivers and is smoothed over the mesh",
    )?)?;
    registry.register(DeformerNode::<shrink_wrap::ShrinkWrap>::new(
        "shrinkWrap",
        "projects the mesh onto a target mesh: toward an inner mesh or a centre, along axes or normals, or to the closest point",
    )?)
}
