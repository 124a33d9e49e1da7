//! The vector nodes of the Maya math set: `crossProduct`, `dotProduct`,
//! `normalize`, `length`, `rotateVector`, `multiplyPointByMatrix` and
//! `multiplyVectorByMatrix` (and their `...DL` twins), one generic node type
//! parameterized by the operation.
//!
//! Matrices follow the transform module's convention (Maya's row-vector
//! `p · M` is glam's `M * p`; see [`crate::transform::math`]).

use glam::{DMat4, DVec3};
use sinew_core::{
    finite, ComputeContext, ComputeError, Input, NodeSpec, NodeType, Output, Registry, SpecBuilder, SpecError, Unit,
};

use super::Flavor;
use crate::math::finite3;
use crate::math::vector::{length, unit};
use crate::transform::dag_nodes::{deg_to_rad, rotate_order, ROTATE_ORDERS};
use crate::transform::math::euler_to_quat;

/// The operation of a [`VectorNode`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum VectorOp {
    /// `output = input1 × input2`.
    Cross,
    /// `output = input1 · input2` (a float).
    Dot,
    /// `output = input / |input|`.
    Normalize,
    /// `output = |input|` (a float).
    Length,
    /// `output = input` rotated by the euler angles `rotate` in `rotateOrder`.
    Rotate,
    /// `output = input` as a point through `matrix`.
    PointMatrix,
    /// `output = input` as a direction through `matrix` (no translation).
    VectorMatrix,
}

impl VectorOp {
    /// Every operation with its Maya name and doc line.
    pub const ALL: [(VectorOp, &'static str, &'static str); 7] = [
        (VectorOp::Cross, "crossProduct", "output = input1 x input2"),
        (VectorOp::Dot, "dotProduct", "output = input1 . input2"),
        (
            VectorOp::Normalize,
            "normalize",
            "output = input / |input|; a zero (or non-finite) vector gives (0, 0, 0)",
        ),
        (
            VectorOp::Length,
            "length",
            "output = |input| (no overflow for huge finite components)",
        ),
        (
            VectorOp::Rotate,
            "rotateVector",
            "output = input rotated by the euler angles rotate (degrees) in rotateOrder",
        ),
        (
            VectorOp::PointMatrix,
            "multiplyPointByMatrix",
            "output = input as a point (w = 1) times matrix (the affine part: no perspective divide)",
        ),
        (
            VectorOp::VectorMatrix,
            "multiplyVectorByMatrix",
            "output = input as a direction (w = 0) times matrix",
        ),
    ];

    fn binary(self) -> bool {
        matches!(self, VectorOp::Cross | VectorOp::Dot)
    }
}

/// A vector node of the Maya math set (see [`VectorOp`]).
///
/// Operands are made finite first (NaN components count as 0); results
/// saturate at `±f64::MAX`. Matrices that are not finite count as the identity.
pub struct VectorNode {
    spec: NodeSpec,
    op: VectorOp,
    input: Input<DVec3>,
    input2: Option<Input<DVec3>>,
    matrix: Option<Input<DMat4>>,
    rotate: Option<Input<DVec3>>,
    order: Option<Input<i64>>,
    out_vec: Option<Output<DVec3>>,
    out_float: Option<Output<f64>>,
}

fn vec_input(s: &mut SpecBuilder, name: &str, unit: Unit, doc: &str) -> Input<DVec3> {
    let h = s.input(name, DVec3::ZERO);
    s.unit(h, unit).attr_doc(h, doc);
    h
}

impl VectorNode {
    /// The node type `op` (Maya name `base`) in `flavor`.
    pub fn new(op: VectorOp, base: &str, doc: &str, flavor: Flavor) -> Result<Self, SpecError> {
        let mut s = NodeSpec::builder(&flavor.type_name(base));
        s.doc(&flavor.doc(doc, base));
        let unit = flavor.unit(Unit::None);
        let (input, input2) = if op.binary() {
            let a = vec_input(&mut s, "input1", unit, "first vector");
            (a, Some(vec_input(&mut s, "input2", unit, "second vector")))
        } else {
            (vec_input(&mut s, "input", unit, "the vector"), None)
        };
        let (rotate, order) = if op == VectorOp::Rotate {
            let r = vec_input(&mut s, "rotate", Unit::Degrees, "the rotation, euler angles");
            let o = s.input_enum("rotateOrder", &ROTATE_ORDERS, 0);
            s.attr_doc(o, "the order the rotate angles apply in");
            (Some(r), Some(o))
        } else {
            (None, None)
        };
        let matrix = matches!(op, VectorOp::PointMatrix | VectorOp::VectorMatrix).then(|| {
            let m = s.input("matrix", DMat4::IDENTITY);
            s.attr_doc(m, "the matrix to multiply by");
            m
        });
        // Maya's short names (node reference): `i`/`ix..` (`x y z` under the matrix
        // products), `i1`/`i1x..`, `i2`/`i2x..`, `r`/`rx..`, `ro`, `m`, `o`/`ox..`.
        if op.binary() {
            s.maya_names(&[("input1", "i1"), ("input2", "i2")]);
        } else {
            s.maya_names(&[("input", "i")]);
        }
        if op == VectorOp::Rotate {
            s.maya_names(&[("rotate", "r"), ("rotateOrder", "ro")]);
        }
        if matrix.is_some() {
            s.maya_names(&[("matrix", "m"), ("inputX", "x"), ("inputY", "y"), ("inputZ", "z")]);
        }
        let (out_vec, out_float) = if matches!(op, VectorOp::Dot | VectorOp::Length) {
            let o = s.output("output", 0.0);
            s.unit(o, unit).attr_doc(o, "the result");
            (None, Some(o))
        } else {
            let o = s.output("output", DVec3::ZERO);
            s.unit(o, unit).attr_doc(o, "the result");
            (Some(o), None)
        };
        s.maya_names(&[("output", "o")]);
        Ok(VectorNode {
            spec: s.build()?,
            op,
            input,
            input2,
            matrix,
            rotate,
            order,
            out_vec,
            out_float,
        })
    }

    fn get_matrix(&self, ctx: &ComputeContext<'_>) -> DMat4 {
        let m = self.matrix.map_or(DMat4::IDENTITY, |h| ctx.get(h));
        if m.is_finite() {
            m
        } else {
            DMat4::IDENTITY
        }
    }
}

impl NodeType for VectorNode {
    fn spec(&self) -> &NodeSpec {
        &self.spec
    }

    fn compute(&self, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
        let a = finite3(ctx.get(self.input));
        let b = finite3(self.input2.map_or(DVec3::ZERO, |h| ctx.get(h)));
        let v = match self.op {
            VectorOp::Cross => a.cross(b),
            VectorOp::Normalize => unit(a),
            VectorOp::Rotate => {
                let r = self.rotate.map_or(DVec3::ZERO, |h| ctx.get(h));
                let order = rotate_order(self.order.map_or(0, |h| ctx.get(h)));
                euler_to_quat(deg_to_rad(r), order) * a
            }
            VectorOp::PointMatrix => self.get_matrix(ctx).transform_point3(a),
            VectorOp::VectorMatrix => self.get_matrix(ctx).transform_vector3(a),
            VectorOp::Dot => DVec3::splat(a.dot(b)),
            VectorOp::Length => DVec3::splat(length(a)),
        };
        if let Some(h) = self.out_vec {
            ctx.set(h, finite3(v));
        }
        if let Some(h) = self.out_float {
            ctx.set(h, finite(v.x));
        }
        Ok(())
    }
}

/// Registers every vector node in both flavors.
pub fn register(registry: &mut Registry) -> Result<(), SpecError> {
    for flavor in Flavor::BOTH {
        for (op, name, doc) in VectorOp::ALL {
            registry.register(VectorNode::new(op, name, doc, flavor)?)?;
        }
    }
    Ok(())
}
