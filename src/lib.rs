//! sinew: a Maya-style rig evaluator.
//!
//! This facade crate ties the engine ([`sinew_core`]) and the standard node
//! plugins ([`sinew_nodes`]) together, and adds interchange ([`io`]) and the
//! `sinew` command-line tool. Embedders usually start from [`default_registry`]
//! and [`prelude`].

use std::sync::Arc;

pub use sinew_core as core;
/// Interchange file formats (glTF, BVH, OBJ) and their mapping to rigs: the `sinew-io` crate.
pub use sinew_io as io;
pub use sinew_nodes as nodes;

pub mod cli;
pub mod prelude;

/// A registry with every standard node type.
///
/// Fails only if a plugin declares an invalid spec (a bug in sinew, reported
/// rather than panicking).
pub fn default_registry() -> Result<Arc<sinew_core::Registry>, sinew_core::SpecError> {
    sinew_nodes::registry()
}
