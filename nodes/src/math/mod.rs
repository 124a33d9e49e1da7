//! Utility math nodes (multiplyDivide, condition, plusMinusAverage, ...), Maya-compatible.
//!
//! Attribute and node names are Maya's. Every node is total: finite inputs
//! give finite outputs. The shared rules, stated once:
//! - division by zero gives 0 ([`arith::safe_div`]); a power without a real
//!   result gives 0 ([`arith::safe_pow`]);
//! - a result that overflows saturates at `±f64::MAX`, a NaN that reaches an
//!   output (only possible from non-finite values upstream) becomes 0.
//!
//! Files: `arith` (multiplyDivide, plusMinusAverage, reverse,
//! unitConversion), `select` (condition, blendColors, clamp, setRange),
//! `remap` (remapValue), `vector` (distanceBetween, vectorProduct), `blend`
//! (pairBlend).

use glam::DVec3;
use sinew_core::{Registry, SpecError};

pub mod arith;
pub mod blend;
pub mod remap;
pub mod select;
pub mod vector;

#[cfg(test)]
pub(crate) mod tests;
#[cfg(test)]
mod tests_more;
#[cfg(test)]
mod tests_select;

/// Implements [`sinew_core::NodeType`] for a struct with a `spec` field and a
/// `run(&self, ctx)` method.
/// With `unread`, the struct's `unread(&self, known)` method answers
/// [`NodeType::unread_inputs`](sinew_core::NodeType::unread_inputs).
macro_rules! node_type {
    ($t:ty) => {
        impl NodeType for $t {
            fn spec(&self) -> &NodeSpec {
                &self.spec
            }
            fn compute(&self, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
                self.run(ctx)
            }
        }
    };
    ($t:ty, unread) => {
        impl NodeType for $t {
            fn spec(&self) -> &NodeSpec {
                &self.spec
            }
            fn compute(&self, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
                self.run(ctx)
            }
            fn unread_inputs(&self, known: &sinew_core::KnownInputs<'_>) -> Vec<sinew_core::AttrId> {
                self.unread(known)
            }
        }
    };
}
pub(crate) use node_type;

/// `x` made finite: NaN becomes 0, infinities saturate at `±f64::MAX`.
#[inline]
pub fn finite(x: f64) -> f64 {
    sinew_core::finite(x)
}

/// [`finite`] per component.
#[inline]
pub fn finite3(v: DVec3) -> DVec3 {
    DVec3::new(finite(v.x), finite(v.y), finite(v.z))
}

/// Registers this family's node types.
pub fn register(registry: &mut Registry) -> Result<(), SpecError> {
    registry.register(arith::MultiplyDivide::new()?)?;
    registry.register(arith::PlusMinusAverage::new()?)?;
    registry.register(arith::Reverse::new()?)?;
    registry.register(arith::unit_conversion()?)?;
    registry.register(arith::add_double_linear()?)?;
    registry.register(arith::mult_double_linear()?)?;
    registry.register(select::Condition::new()?)?;
    registry.register(select::BlendColors::new()?)?;
    registry.register(select::Clamp::new()?)?;
    registry.register(select::SetRange::new()?)?;
    registry.register(remap::RemapValue::new()?)?;
    registry.register(vector::DistanceBetween::new()?)?;
    registry.register(vector::VectorProduct::new()?)?;
    registry.register(blend::PairBlend::new()?)?;
    Ok(())
}
