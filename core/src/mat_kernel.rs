//! Matrix kernels: an opt-in fast path for a compute group whose only output is one
//! matrix computed by a pure function of three whole matrix attributes (a transform's or a
//! joint's `worldMatrix` from `parentMatrix`, `offsetParentMatrix` and `matrix`). A compiled
//! [`Program`](crate::Program) runs the function straight over the instance's matrix
//! slots, without building a [`ComputeContext`](crate::ComputeContext) or calling
//! `compute`; the frame's dozens of world-matrix steps then cost the multiplication and
//! little else.
//!
//! The node's `compute` must call the same function for that group, so the lazy graph and
//! the compiled program stay bit-identical.

use glam::DMat4;

use crate::error::SpecError;
use crate::program::AttrBinding;
use crate::slots::Slots;
use crate::spec::{AttrId, NodeSpec, Output};
use crate::value::AttrType;

/// The function of a [`MatrixKernel`]: its three inputs, in order, to its output.
pub type MatrixFn = fn(&DMat4, &DMat4, &DMat4) -> DMat4;

/// A compute group's whole work as `output = f(a, b, c)` over single matrix attributes.
///
/// Return it from [`NodeType::matrix_kernel`](crate::NodeType::matrix_kernel). The inputs
/// may be inputs of the node or outputs of its other groups (read as precomputed data).
/// When an attribute is not bound to a whole matrix slot in a compiled program (an old
/// program, a value stored otherwise), the step calls `compute` as usual.
#[derive(Clone, Copy, Debug)]
pub struct MatrixKernel {
    inputs: [AttrId; 3],
    output: AttrId,
    group: u16,
    f: MatrixFn,
}

impl MatrixKernel {
    /// A kernel computing `output = f(inputs[0], inputs[1], inputs[2])` for the node type with
    /// `spec`. Fails when an attribute is not a single matrix of `spec`, or when the group
    /// computing `output` computes anything else or reads an attribute not among `inputs`.
    pub fn new(spec: &NodeSpec, inputs: [AttrId; 3], output: Output<DMat4>, f: MatrixFn) -> Result<Self, SpecError> {
        let fail = |message: String| SpecError {
            node_type: spec.name.clone(),
            message,
        };
        for id in inputs.iter().chain([&output.id()]) {
            match spec.attrs.get(id.index()) {
                Some(a) if a.ty == AttrType::Matrix && !a.multi => {}
                Some(a) => {
                    return Err(fail(format!(
                        "matrix kernel attribute `{}` is not a single matrix",
                        a.name
                    )))
                }
                None => {
                    return Err(fail(format!(
                        "matrix kernel attribute {} is not in the spec",
                        id.index()
                    )))
                }
            }
        }
        let groups = spec.groups();
        let Some(group) = groups.iter().position(|g| g.outputs.contains(&output.id())) else {
            return Err(fail("the matrix kernel's output is computed by no group".into()));
        };
        let g = &groups[group];
        if g.outputs.len() != 1 || g.time_dependent || g.inputs.iter().any(|i| !inputs.contains(i)) {
            return Err(fail(
                "a matrix kernel's group must compute only its output, from its inputs alone".into(),
            ));
        }
        Ok(MatrixKernel {
            inputs,
            output: output.id(),
            group: group as u16,
            f,
        })
    }
}

/// A [`MatrixKernel`] bound to the matrix slots of one compiled step.
#[derive(Clone, Copy, Debug)]
pub(crate) struct MatKernelStep {
    inputs: [u32; 3],
    output: u32,
    f: MatrixFn,
}

impl MatKernelStep {
    /// Binds `kernel` to a step of group `group` of a node with `spec` whose attribute
    /// bindings are `attrs`. `None` (the step calls `compute`) unless the step is the
    /// kernel's group and every attribute is bound to a whole slot.
    pub(crate) fn bind(kernel: &MatrixKernel, group: u16, attrs: &[AttrBinding]) -> Option<MatKernelStep> {
        if group != kernel.group {
            return None;
        }
        // `AttrBinding::slot` is the whole slot of a single attribute, `u32::MAX` otherwise.
        let slot = |id: AttrId| attrs.get(id.index()).map(|b| b.slot).filter(|&s| s != u32::MAX);
        Some(MatKernelStep {
            inputs: [
                slot(kernel.inputs[0])?,
                slot(kernel.inputs[1])?,
                slot(kernel.inputs[2])?,
            ],
            output: slot(kernel.output)?,
            f: kernel.f,
        })
    }

    /// Runs the kernel over `slots`; `false` (nothing written) when a slot is not a matrix
    /// slot there, so the caller falls back to `compute`.
    #[inline]
    pub(crate) fn run(&self, slots: &mut Slots) -> bool {
        let [a, b, c] = self.inputs;
        let (Some(a), Some(b), Some(c)) = (slots.mat(a), slots.mat(b), slots.mat(c)) else {
            return false;
        };
        let r = (self.f)(a, b, c);
        match slots.mat_mut(self.output) {
            Some(o) => {
                *o = r;
                true
            }
            None => false,
        }
    }
}

#[cfg(test)]
#[path = "mat_kernel_tests.rs"]
mod tests;
