//! Vector nodes: `distanceBetween` and `vectorProduct`.

use glam::{DMat4, DVec3};
use sinew_core::{ComputeContext, ComputeError, Input, NodeSpec, NodeType, Output, SpecError};

use super::{finite, finite3, node_type};

/// Maya's `distanceBetween`: `distance = |inMatrix2 · point2 − inMatrix1 · point1|`.
///
/// Each point is in the space of its matrix (connect a `worldMatrix` and
/// leave the point at the origin to measure between two transforms). The
/// length saturates at `f64::MAX` instead of overflowing.
pub struct DistanceBetween {
    spec: NodeSpec,
    point1: Input<DVec3>,
    point2: Input<DVec3>,
    in_matrix1: Input<DMat4>,
    in_matrix2: Input<DMat4>,
    distance: Output<f64>,
}

impl DistanceBetween {
    /// Creates the node type.
    pub fn new() -> Result<Self, SpecError> {
        let mut s = NodeSpec::builder("distanceBetween");
        // Maya's short names (see docs/rig-format.md, "Maya short names").
        s.maya_names(&[
            ("point1", "p1"),
            ("point2", "p2"),
            ("inMatrix1", "im1"),
            ("inMatrix2", "im2"),
            ("distance", "d"),
        ]);
        s.doc("distance = |inMatrix2 * point2 - inMatrix1 * point1|");
        let point1 = s.input("point1", DVec3::ZERO);
        let point2 = s.input("point2", DVec3::ZERO);
        let in_matrix1 = s.input("inMatrix1", DMat4::IDENTITY);
        let in_matrix2 = s.input("inMatrix2", DMat4::IDENTITY);
        let distance = s.output("distance", 0.0);
        s.attr_doc(point1, "first point, in the space of inMatrix1");
        s.attr_doc(point2, "second point, in the space of inMatrix2");
        Ok(DistanceBetween {
            spec: s.build()?,
            point1,
            point2,
            in_matrix1,
            in_matrix2,
            distance,
        })
    }

    fn run(&self, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
        let p1 = ctx.get(self.in_matrix1).transform_point3(ctx.get(self.point1));
        let p2 = ctx.get(self.in_matrix2).transform_point3(ctx.get(self.point2));
        let d = finite3(p2) - finite3(p1);
        ctx.set(self.distance, length(d));
        Ok(())
    }
}
node_type!(DistanceBetween);

/// Maya's `vectorProduct`.
///
/// `operation`: `noOperation` (output = input1), `dotProduct` (the dot
/// product in all three components), `crossProduct` (input1 × input2),
/// `vectorMatrixProduct` (input1 as a direction through `matrix`, no
/// translation), `pointMatrixProduct` (input1 as a point through `matrix`).
/// `normalizeOutput`: for `dotProduct` the two inputs are normalized first
/// (so the result is the cosine of their angle), otherwise the output vector
/// is normalized. A zero vector stays zero (never NaN).
pub struct VectorProduct {
    spec: NodeSpec,
    operation: Input<i64>,
    input1: Input<DVec3>,
    input2: Input<DVec3>,
    matrix: Input<DMat4>,
    normalize: Input<bool>,
    output: Output<DVec3>,
}

impl VectorProduct {
    /// Creates the node type.
    pub fn new() -> Result<Self, SpecError> {
        let mut s = NodeSpec::builder("vectorProduct");
        // Maya's short names (see docs/rig-format.md, "Maya short names").
        s.maya_names(&[("operation", "op"), ("input1", "i1"), ("input2", "i2"), ("output", "o")]);
        s.doc("dot, cross, vector-matrix or point-matrix product of input1 (and input2)");
        let operation = s.input_enum(
            "operation",
            &[
                "noOperation",
                "dotProduct",
                "crossProduct",
                "vectorMatrixProduct",
                "pointMatrixProduct",
            ],
            1,
        );
        let input1 = s.input("input1", DVec3::ZERO);
        let input2 = s.input("input2", DVec3::ZERO);
        let matrix = s.input("matrix", DMat4::IDENTITY);
        let normalize = s.input("normalizeOutput", false);
        let output = s.output("output", DVec3::ZERO);
        s.attr_doc(
            normalize,
            "normalize the inputs (dotProduct) or the output (other operations)",
        );
        Ok(VectorProduct {
            spec: s.build()?,
            operation,
            input1,
            input2,
            matrix,
            normalize,
            output,
        })
    }

    fn run(&self, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
        let (a, b) = (finite3(ctx.get(self.input1)), finite3(ctx.get(self.input2)));
        let norm = ctx.get(self.normalize);
        let op = ctx.get(self.operation);
        let v = match op {
            1 => {
                let (a, b) = if norm { (unit(a), unit(b)) } else { (a, b) };
                DVec3::splat(finite(a.dot(b)))
            }
            2 => a.cross(b),
            3 => ctx.get(self.matrix).transform_vector3(a),
            4 => ctx.get(self.matrix).transform_point3(a),
            _ => a,
        };
        let v = finite3(v);
        let v = if norm && op != 1 { unit(v) } else { v };
        ctx.set(self.output, v);
        Ok(())
    }
}
node_type!(VectorProduct);

/// `|v|`, scaled before squaring so huge but finite components do not
/// overflow; saturates at `f64::MAX`, and a non-finite vector gives 0.
pub fn length(v: DVec3) -> f64 {
    let m = v.abs().max_element();
    if m > 0.0 && m.is_finite() {
        finite(m * (v / m).length())
    } else {
        0.0
    }
}

/// `v` normalized; zero (or non-finite) vectors give zero.
pub fn unit(v: DVec3) -> DVec3 {
    let m = v.abs().max_element();
    if m > 0.0 && m.is_finite() {
        (v / m).normalize_or_zero()
    } else {
        DVec3::ZERO
    }
}
