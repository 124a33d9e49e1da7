//! sinew-nodes: the standard node plugins of sinew, one module per family.
//!
//! Every node type here is written against the public plugin API of
//! `sinew-core`, exactly as a third-party plugin would be. [`register_all`]
//! adds them all to a registry; [`registry`] builds a shared one.

use std::sync::Arc;

use sinew_core::{Registry, SpecError};

pub mod anim;
pub mod animblend;
pub mod cluster;
pub mod constraint;
pub mod deform;
pub mod deformer;
pub mod expr;
pub mod ik;
pub mod lattice;
pub mod math;
pub mod mathnodes;
pub mod matrix;
pub mod mush;
pub mod nonlinear;
pub mod nurbs;
pub mod pin;
pub mod quat;
#[cfg(feature = "skeletonize")]
pub mod skeletonize;
pub mod transform;
pub mod wire;
pub mod wrap;

/// Registers every standard node type.
pub fn register_all(registry: &mut Registry) -> Result<(), SpecError> {
    transform::register(registry)?;
    math::register(registry)?;
    mathnodes::register(registry)?;
    matrix::register(registry)?;
    quat::register(registry)?;
    anim::register(registry)?;
    animblend::register(registry)?;
    constraint::register(registry)?;
    ik::register(registry)?;
    deform::register(registry)?;
    expr::register(registry)?;
    cluster::register(registry)?;
    nonlinear::register(registry)?;
    lattice::register(registry)?;
    mush::register(registry)?;
    wire::register(registry)?;
    wrap::register(registry)?;
    nurbs::register(registry)?;
    pin::register(registry)?;
    #[cfg(feature = "skeletonize")]
    skeletonize::register(registry)?;
    Ok(())
}

/// A registry holding every standard node type.
pub fn registry() -> Result<Arc<Registry>, SpecError> {
    let mut r = Registry::new();
    register_all(&mut r)?;
    Ok(Arc::new(r))
}

#[cfg(test)]
mod tests_validate;
