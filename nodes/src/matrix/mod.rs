//! Matrix arithmetic utilities: `addMatrix`, `wtAddMatrix`, `holdMatrix` and
//! `transposeMatrix` (Maya's names and attributes). The transform-aware
//! matrix nodes (`multMatrix`, `inverseMatrix`, `pickMatrix`, `blendMatrix`,
//! `aimMatrix`, compose/decompose) live in [`crate::transform`].
//!
//! Maya matrices are the transposes of sinew's glam matrices (see
//! [`crate::transform::math`]); sums, weighted sums and transposes commute
//! with that, so these nodes compute on glam matrices directly.
//!
//! Non-finite entries in a result (only from overflow: the graph refuses
//! non-finite values) saturate at `±f64::MAX`.

use glam::DMat4;
use sinew_core::{
    finite, ComputeContext, ComputeError, Input, MultiInput, NodeSpec, NodeType, Output, Registry, SpecError,
};

#[cfg(test)]
mod tests;

/// `m` with every entry made finite ([`finite`]).
pub fn finite_mat(m: DMat4) -> DMat4 {
    DMat4::from_cols_array(&m.to_cols_array().map(finite))
}

/// Maya's `addMatrix`: `matrixSum = Σ matrixIn[i]`, entry by entry, over the
/// existing elements; no element gives the identity (Maya's initial value).
pub struct AddMatrix {
    spec: NodeSpec,
    matrix_in: MultiInput<DMat4>,
    sum: Output<DMat4>,
}

impl AddMatrix {
    /// Creates the node type.
    pub fn new() -> Result<Self, SpecError> {
        let mut s = NodeSpec::builder("addMatrix");
        s.doc("matrixSum = the entry-wise sum of matrixIn[]; no element gives the identity");
        let matrix_in = s.multi_input("matrixIn", DMat4::IDENTITY);
        s.attr_doc(matrix_in, "the matrices to add");
        let sum = s.output("matrixSum", DMat4::IDENTITY);
        s.maya_names(&[("matrixIn", "i"), ("matrixSum", "o")]);
        Ok(AddMatrix {
            spec: s.build()?,
            matrix_in,
            sum,
        })
    }
}

impl NodeType for AddMatrix {
    fn spec(&self) -> &NodeSpec {
        &self.spec
    }

    fn compute(&self, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
        let n = ctx.multi_len(self.matrix_in);
        let mut acc = if n == 0 { DMat4::IDENTITY } else { DMat4::ZERO };
        for k in 0..n {
            if let Some((_, m)) = ctx.multi_at(self.matrix_in, k) {
                acc += m;
            }
        }
        ctx.set(self.sum, finite_mat(acc));
        Ok(())
    }
}

/// Maya's `wtAddMatrix`: `matrixSum = Σ weightIn[i] · matrixIn[i]` over the
/// elements `i` of `matrixIn[]`; a missing `weightIn[i]` is 0 (Maya's
/// default). No element gives the identity (Maya's initial value); weights
/// are not normalized (weights summing to 2 double the matrix, as in Maya).
///
/// Maya's compound `wtMatrix[i]` (children `matrixIn`, `weightIn`) is the
/// parallel multis `matrixIn[i]` and `weightIn[i]` here.
pub struct WtAddMatrix {
    spec: NodeSpec,
    matrix_in: MultiInput<DMat4>,
    weight_in: MultiInput<f64>,
    sum: Output<DMat4>,
}

impl WtAddMatrix {
    /// Creates the node type.
    pub fn new() -> Result<Self, SpecError> {
        let mut s = NodeSpec::builder("wtAddMatrix");
        s.doc("matrixSum = sum of weightIn[i] * matrixIn[i] (Maya's wtMatrix[i]); no element gives the identity");
        let matrix_in = s.multi_input("matrixIn", DMat4::IDENTITY);
        s.attr_doc(matrix_in, "wtMatrix[i].matrixIn: a matrix in the sum");
        let weight_in = s.multi_input("weightIn", 0.0);
        s.attr_doc(weight_in, "wtMatrix[i].weightIn: its weight (0 when absent)");
        let sum = s.output("matrixSum", DMat4::IDENTITY);
        s.maya_names(&[("matrixIn", "m"), ("weightIn", "w"), ("matrixSum", "o")]);
        Ok(WtAddMatrix {
            spec: s.build()?,
            matrix_in,
            weight_in,
            sum,
        })
    }
}

impl NodeType for WtAddMatrix {
    fn spec(&self) -> &NodeSpec {
        &self.spec
    }

    fn compute(&self, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
        let n = ctx.multi_len(self.matrix_in);
        let mut acc = if n == 0 { DMat4::IDENTITY } else { DMat4::ZERO };
        for k in 0..n {
            if let Some((i, m)) = ctx.multi_at(self.matrix_in, k) {
                let w = ctx.get_at(self.weight_in, i).unwrap_or(0.0);
                acc += m * w;
            }
        }
        ctx.set(self.sum, finite_mat(acc));
        Ok(())
    }
}

/// Maya's `holdMatrix`: `outMatrix = inMatrix`. Maya uses it to keep
/// (cache) a matrix; sinew's graph caches every plug, so it is a pass-through.
pub struct HoldMatrix {
    spec: NodeSpec,
    input: Input<DMat4>,
    out: Output<DMat4>,
}

impl HoldMatrix {
    /// Creates the node type.
    pub fn new() -> Result<Self, SpecError> {
        let mut s = NodeSpec::builder("holdMatrix");
        s.doc("outMatrix = inMatrix");
        let input = s.input("inMatrix", DMat4::IDENTITY);
        let out = s.output("outMatrix", DMat4::IDENTITY);
        Ok(HoldMatrix {
            spec: s.build()?,
            input,
            out,
        })
    }
}

impl NodeType for HoldMatrix {
    fn spec(&self) -> &NodeSpec {
        &self.spec
    }

    fn compute(&self, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
        let m = ctx.get(self.input);
        ctx.set(self.out, m);
        Ok(())
    }
}

/// Maya's `transposeMatrix`: `outputMatrix` is the transpose of `inputMatrix`
/// (rows and columns swapped, translation included: the result of a
/// rotation-only matrix is its inverse).
pub struct TransposeMatrix {
    spec: NodeSpec,
    input: Input<DMat4>,
    out: Output<DMat4>,
}

impl TransposeMatrix {
    /// Creates the node type.
    pub fn new() -> Result<Self, SpecError> {
        let mut s = NodeSpec::builder("transposeMatrix");
        s.doc("outputMatrix = the transpose of inputMatrix");
        let input = s.input("inputMatrix", DMat4::IDENTITY);
        let out = s.output("outputMatrix", DMat4::IDENTITY);
        Ok(TransposeMatrix {
            spec: s.build()?,
            input,
            out,
        })
    }
}

impl NodeType for TransposeMatrix {
    fn spec(&self) -> &NodeSpec {
        &self.spec
    }

    fn compute(&self, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
        let m = ctx.get(self.input);
        ctx.set(self.out, m.transpose());
        Ok(())
    }
}

/// Registers this family's node types.
pub fn register(registry: &mut Registry) -> Result<(), SpecError> {
    registry.register(AddMatrix::new()?)?;
    registry.register(WtAddMatrix::new()?)?;
    registry.register(HoldMatrix::new()?)?;
    registry.register(TransposeMatrix::new()?)?;
    Ok(())
}
