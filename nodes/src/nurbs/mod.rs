//! NURBS curves and surfaces: the data's evaluation ([`basis`], [`curve_eval`],
//! [`surface_eval`]), the shape nodes `nurbsCurve` and `nurbsSurface`, and the query nodes
//! riggers build ribbons and tails from: `curveInfo`, `pointOnCurveInfo`,
//! `nearestPointOnCurve`, `motionPath`, `pointOnSurfaceInfo`, `closestPointOnSurface`.
//!
//! Curves and surfaces are non-rational B-splines (Maya's NURBS with every weight 1;
//! `curveInfo.weights` reports those 1s). Parameters follow Maya: a uniform open curve of
//! `n` spans has the domain `[0, n]`; out-of-range parameters clamp to the ends on open
//! curves and wrap on periodic ones; `turnOnPercentage` maps `[0, 1]` linearly onto the
//! domain (parametric, not arc length; `motionPath.fractionMode` is arc length). Nodes that
//! read geometry take it as connected: connect `worldSpace[0]` for world-space answers,
//! `local` for object space.
//!
//! Files: `basis` (knot vectors, Cox–de Boor basis and derivatives), `curve_eval`,
//! `surface_eval`, `shapes` (the two shape nodes), `curve_nodes` (curveInfo,
//! pointOnCurveInfo, nearestPointOnCurve), `motion_path`, `surface_nodes`
//! (pointOnSurfaceInfo, closestPointOnSurface).

pub mod basis;
pub(crate) mod cache;
pub mod curve_eval;
pub mod curve_nodes;
pub mod frame;
pub mod motion_path;
pub mod shapes;
pub mod surface_eval;
pub mod surface_nodes;

#[cfg(test)]
pub(crate) mod tests_eval;
#[cfg(test)]
mod tests_nan;
#[cfg(test)]
pub(crate) mod tests_nodes;

use sinew_core::{Registry, SpecError};

/// Registers this family's node types.
pub fn register(registry: &mut Registry) -> Result<(), SpecError> {
    registry.register(shapes::NurbsCurve::new()?)?;
    registry.register(shapes::NurbsSurface::new()?)?;
    registry.register(curve_nodes::CurveInfo::new()?)?;
    registry.register(curve_nodes::PointOnCurveInfo::new()?)?;
    registry.register(curve_nodes::NearestPointOnCurve::new()?)?;
    registry.register(motion_path::MotionPath::new()?)?;
    registry.register(surface_nodes::PointOnSurfaceInfo::new()?)?;
    registry.register(surface_nodes::ClosestPointOnSurface::new()?)?;
    Ok(())
}
