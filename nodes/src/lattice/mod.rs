//! Maya's lattice deformer: a `lattice` shape, a base lattice (any transform) and the `ffd`
//! deformer, evaluated as Sederberg & Parry's trivariate Bernstein free-form deformation.
//!
//! | module | what it is for |
//! | --- | --- |
//! | [`ffd`] | the Bernstein evaluation (global and local windows), pure math |
//! | [`power`] | the same polynomial in centred power form, prepared per frame (the fast path) |
//! | [`nodes`] | `lattice` (shape) and `ffd` (deformer) |

pub mod ffd;
pub mod nodes;
pub mod power;

#[cfg(test)]
mod tests;

use sinew_core::{Registry, SpecError};

use crate::deformer::DeformerNode;

/// Registers `lattice` and `ffd`.
pub fn register(registry: &mut Registry) -> Result<(), SpecError> {
    registry.register(nodes::LatticeShape::new()?)?;
    registry.register(DeformerNode::<nodes::Ffd>::new(
        "ffd",
        "free-form deformation of a mesh by a lattice (trivariate Bernstein, Sederberg & Parry 1986)",
    )?)?;
    Ok(())
}
