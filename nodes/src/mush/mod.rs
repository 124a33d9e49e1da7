//! Neighbourhood deformers that clean up a deformation: `deltaMush` and `tension`.
//!
//! | module | what it is for |
//! | --- | --- |
//! | [`smooth`] | Laplacian smoothing over a fixed topology (bind-time adjacency) |
//! | [`delta_mush`] | `deltaMush` (Mancewicz et al. 2014) |
//! | [`frame`] | delta mush's per-vertex frames, eight vertices at a time |
//! | [`tension`] | `tension` (rest edge lengths restored by relaxation) |

pub mod delta_mush;
pub mod frame;
pub mod smooth;
#[cfg(target_arch = "x86_64")]
mod smooth_avx2;
pub mod tension;

#[cfg(test)]
mod tests;

use sinew_core::{Registry, SpecError};

use crate::deformer::DeformerNode;

/// Registers `deltaMush` and `tension`.
pub fn register(registry: &mut Registry) -> Result<(), SpecError> {
    registry.register(DeformerNode::<delta_mush::DeltaMush>::new(
        "deltaMush",
        "smooths a deformation while keeping the rest mesh's detail (Mancewicz et al. 2014)",
    )?)?;
    registry.register(DeformerNode::<tension::Tension>::new(
        "tension",
        "relaxes the deformed mesh towards its rest edge lengths",
    )?)?;
    Ok(())
}
