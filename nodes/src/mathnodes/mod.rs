//! Maya 2024+ math nodes: `sum`, `subtract`, `multiply`, `divide`, `power`,
//! `log`, `modulo`, `absolute`, `negate`, `min`, `max`, `average`,
//! `clampRange`, `smoothStep`, `lerp`, `inverseLerp`, `floor`, `ceil`,
//! `round`, `truncate`, `sin`, `cos`, `tan`, `asin`, `acos`, `atan`,
//! `atan2`, the comparisons `equal`, `greaterThan`, `lessThan`, the logic
//! nodes `and`, `or`, `not`, and the vector nodes `crossProduct`,
//! `dotProduct`, `normalize`, `length`, `rotateVector`,
//! `multiplyPointByMatrix` and `multiplyVectorByMatrix`.
//!
//! Names, attributes and defaults follow Maya's node reference (Maya 2027
//! technical documentation, `Nodes/<name>.html`), where these nodes are
//! unitless. Each also exists as a deprecated `...DL` twin (`sumDL`,
//! `sinDL`, ...) whose plain numbers are distances; sinew registers the twins
//! too, with the same arithmetic and [`Unit::Distance`] on those attributes,
//! so scenes saved by Maya 2024/2025 (which wrote the distance versions)
//! import unchanged. `and`, `or` and `not` have no twin. Maya has no
//! `...Angle`/`...Int`/`...Vector` variants of these nodes (those names
//! belong to the third-party `maya-math-nodes` plug-in).
//!
//! One generic node type per shape, parameterized by its operation and
//! registered under each Maya name from a table: [`scalar`] (float in, float
//! out: a [`sinew_core::KernelNode`], so compiled programs run them without a
//! compute context), [`reduce`] (`input[]` lists, comparisons and logic),
//! [`vector`] (vec3 and matrix operands).
//!
//! Every node is total: finite inputs give finite outputs, a non-finite
//! result becomes 0 (NaN) or `±f64::MAX` (overflow), and each node documents
//! its degenerate cases (division by zero, logarithm of a non-positive
//! number, zero-length vectors...). Angles on plugs are degrees.

use sinew_core::{Registry, SpecError, Unit};

pub mod reduce;
pub mod scalar;
pub mod vector;

#[cfg(test)]
mod tests_reduce;
#[cfg(test)]
mod tests_scalar;
#[cfg(test)]
mod tests_vector;

/// Whether a node type is Maya's unitless node or its deprecated `...DL` twin.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Flavor {
    /// The unitless node (`sum`).
    Unitless,
    /// The distance twin (`sumDL`): plain numbers are distances.
    Distance,
}

impl Flavor {
    /// Both flavors, unitless first.
    pub const BOTH: [Flavor; 2] = [Flavor::Unitless, Flavor::Distance];

    /// The node type name for Maya's base name `base`.
    pub fn type_name(self, base: &str) -> String {
        match self {
            Flavor::Unitless => base.to_string(),
            Flavor::Distance => format!("{base}DL"),
        }
    }

    /// The unit of an attribute that is a plain number in the unitless node
    /// (`unit` is [`Unit::None`]); other units (degrees) are kept.
    pub fn unit(self, unit: Unit) -> Unit {
        match (self, unit) {
            (Flavor::Distance, Unit::None) => Unit::Distance,
            (_, u) => u,
        }
    }

    /// The node-type doc line for this flavor.
    pub fn doc(self, doc: &str, base: &str) -> String {
        match self {
            Flavor::Unitless => doc.to_string(),
            Flavor::Distance => format!("{doc} (deprecated distance twin of `{base}`)"),
        }
    }
}

/// Registers this family's node types.
pub fn register(registry: &mut Registry) -> Result<(), SpecError> {
    scalar::register(registry)?;
    reduce::register(registry)?;
    vector::register(registry)?;
    Ok(())
}
