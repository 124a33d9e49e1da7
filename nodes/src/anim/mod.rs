//! Animation curves: Maya-compatible key/tangent evaluation ([`curve`]) and
//! the animCurve node plugins built on it ([`nodes`]).

pub mod curve;
mod key;
pub mod nodes;
pub mod quat_curve;
mod segment;
pub mod set_keys;
mod tangents;
#[cfg(test)]
mod tests_nodes;

pub use nodes::{AnimCurveNode, CurveCache, CurveKind, TANGENT_NAMES};
pub use set_keys::set_keys;

/// Registers this family's node types (`animCurveTL/TA/TT/TU/UL/UA/UT/UU`, `quatCurve`, `vectorCurve`).
pub fn register(registry: &mut sinew_core::Registry) -> Result<(), sinew_core::SpecError> {
    nodes::register(registry)?;
    quat_curve::register(registry)
}
