//! Maya's `wire` deformer: curves that drag the mesh near them (Singh & Fiume 1998).
//!
//! | module | what it is for |
//! | --- | --- |
//! | [`sample`] | allocation-free B-spline sampling (de Boor) |
//! | [`node`] | the `wire` deformer |

pub mod node;
pub mod sample;

#[cfg(test)]
mod tests;

use sinew_core::{Registry, SpecError};

use crate::deformer::DeformerNode;

/// Registers `wire`.
pub fn register(registry: &mut Registry) -> Result<(), SpecError> {
    registry.register(DeformerNode::<node::Wire>::new(
        "wire",
        "drags the mesh near base curves along with their deformed copies (Singh & Fiume 1998)",
    )?)
}
