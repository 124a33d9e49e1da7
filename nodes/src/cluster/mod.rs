//! Weighted rigid transforms of a mesh by a handle: Maya's `cluster` and `softMod`.
//!
//! | module | node types |
//! | --- | --- |
//! | [`handle`] | `cluster` (weighted handle transform, relative mode, bindPreMatrix) |
//! | [`soft_mod`] | `softMod` (the same transform faded by a falloff radius and curve, volume or surface distance) |
//! | [`falloff`] | the falloff ramp (Maya's `falloffCurve` keys) |

pub mod falloff;
pub mod handle;
pub mod soft_mod;

#[cfg(test)]
mod tests;

use sinew_core::{Registry, SpecError};

use crate::deformer::DeformerNode;

/// Registers `cluster` and `softMod`.
pub fn register(registry: &mut Registry) -> Result<(), SpecError> {
    registry.register(DeformerNode::<handle::Cluster>::new(
        "cluster",
        "moves vertices by the handle's transform since bind, scaled by weight and envelope",
    )?)?;
    registry.register(DeformerNode::<soft_mod::SoftMod>::new(
        "softMod",
        "a cluster whose weight fades with distance from falloffCenter along falloffCurve",
    )?)?;
    Ok(())
}
