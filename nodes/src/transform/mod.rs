//! Transform and joint nodes and the matrix utilities built on the same math.
//!
//! The math modules ([`math`], [`euler`], [`decompose`], [`orient`], [`trig`]) are pure
//! functions in radians; the node plugins convert the graph's degrees. The
//! plugins: [`dag_nodes`] (`transform`, `joint`), [`matrix_nodes`]
//! (`decomposeMatrix`, `composeMatrix`, `multMatrix`, `inverseMatrix`,
//! `pickMatrix`, `eulerToQuat`, `quatToEuler`), [`blend_nodes`]
//! (`blendMatrix`, `aimMatrix`) and [`time_node`] (`time`).

pub mod blend_nodes;
pub mod dag_nodes;
pub mod decompose;
pub mod euler;
pub mod math;
pub mod matrix_nodes;
pub mod orient;
pub mod orient_joints;
pub mod time_node;
pub mod trig;

/// Registers this family's node types.
pub fn register(registry: &mut sinew_core::Registry) -> Result<(), sinew_core::SpecError> {
    registry.register(dag_nodes::Transform::new()?)?;
    registry.register(dag_nodes::Joint::new()?)?;
    registry.register(time_node::TimeNode::new()?)?;
    registry.register(matrix_nodes::DecomposeMatrix::new()?)?;
    registry.register(matrix_nodes::ComposeMatrix::new()?)?;
    registry.register(matrix_nodes::MultMatrix::new()?)?;
    registry.register(matrix_nodes::InverseMatrix::new()?)?;
    registry.register(matrix_nodes::PickMatrix::new()?)?;
    registry.register(matrix_nodes::EulerToQuat::new()?)?;
    registry.register(matrix_nodes::QuatToEuler::new()?)?;
    registry.register(blend_nodes::BlendMatrix::new()?)?;
    registry.register(blend_nodes::AimMatrix::new()?)?;
    Ok(())
}

#[cfg(test)]
mod tests_matrix;
#[cfg(test)]
mod tests_nodes;
