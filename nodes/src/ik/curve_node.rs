//! The `curveFromPoints` node: a B-spline curve whose control points come from points or controls' world matrices.

use std::sync::Arc;

use glam::{DMat4, DVec3};
use sinew_core::{
    ComputeContext, ComputeError, Curve, CurveForm, Input, MultiInput, NodeSpec, NodeType, Output, SpecError,
};

/// Choices of the `form` enum (Maya's nurbsCurve form), by index.
pub const FORM_CHOICES: [&str; 3] = ["open", "closed", "periodic"];

/// `curveFromPoints`: builds a non-rational B-spline (`Curve`) from control points, so
/// spline IK can be driven by controls.
///
/// Control point `k` is the translation of `pointMatrix[k]` when that element exists,
/// otherwise `point[k]`; the curve uses the union of both multis' indices in order, so
/// controls' `worldMatrix` can be connected to `pointMatrix[i]` and fixed points set on
/// `point[j]`. Knots are uniform clamped (Maya's parameterisation, domain `[0, spans]`).
///
/// `form`: `open`; `closed` (the first point is repeated at the end: the curve closes
/// with a corner, like Maya's closed form); `periodic` (smooth loop over the distinct
/// points). Fallbacks: `degree` below 1 counts as 1, and a degree above what the point
/// count allows is lowered to `points - 1`. Fewer than 2 control points is an error.
/// A non-finite control point (NaN arriving through a connection) gives an empty curve,
/// which `ikSpline` reports as invalid (rest pose, status 3).
pub struct CurveFromPoints {
    spec: NodeSpec,
    point: MultiInput<DVec3>,
    point_matrix: MultiInput<DMat4>,
    degree: Input<i64>,
    form: Input<i64>,
    out_curve: Output<Arc<Curve>>,
}

impl CurveFromPoints {
    /// Creates the node type.
    pub fn new() -> Result<Self, SpecError> {
        let mut b = NodeSpec::builder("curveFromPoints");
        b.doc("a B-spline curve from control points and/or controls' world matrices");
        let point = b.multi_input("point", DVec3::ZERO);
        b.attr_doc(
            point,
            "control points (world space), used where pointMatrix has no element",
        );
        let point_matrix = b.multi_input("pointMatrix", DMat4::IDENTITY);
        b.attr_doc(
            point_matrix,
            "control points as matrices (their translation); connect controls' worldMatrix",
        );
        let degree = b.input("degree", 3i64);
        b.attr_doc(
            degree,
            "polynomial degree (1 = polyline, 3 = cubic); lowered to points - 1 if needed",
        );
        let form = b.input_enum("form", &FORM_CHOICES, 0);
        b.attr_doc(form, "open, closed (repeat the first point) or periodic (smooth loop)");
        let out_curve = b.output("outCurve", Arc::new(Curve::default()));
        b.attr_doc(out_curve, "the curve (connect to ikSpline.curve)");
        Ok(CurveFromPoints {
            spec: b.build()?,
            point,
            point_matrix,
            degree,
            form,
            out_curve,
        })
    }
}

/// The control points: `pointMatrix[k]`'s translation where it exists, else `point[k]`,
/// over the union of both multis' logical indices in increasing order.
fn control_points(ctx: &ComputeContext<'_>, point: MultiInput<DVec3>, matrix: MultiInput<DMat4>) -> Vec<DVec3> {
    let mut items: Vec<(u32, DVec3, bool)> = Vec::new();
    for k in 0..ctx.multi_len(point) {
        if let Some((i, p)) = ctx.multi_at(point, k) {
            items.push((i, p, false));
        }
    }
    for k in 0..ctx.multi_len(matrix) {
        if let Some((i, m)) = ctx.multi_at(matrix, k) {
            items.push((i, m.w_axis.truncate(), true));
        }
    }
    // Sort by index, matrices first within an index, then keep the first of each index.
    items.sort_by_key(|&(i, _, is_matrix)| (i, !is_matrix));
    items.dedup_by_key(|it| it.0);
    items.into_iter().map(|(_, p, _)| p).collect()
}

impl NodeType for CurveFromPoints {
    fn spec(&self) -> &NodeSpec {
        &self.spec
    }

    fn compute(&self, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
        let mut points = control_points(ctx, self.point, self.point_matrix);
        if points.len() < 2 {
            return Err(ComputeError::new(format!(
                "curveFromPoints needs at least 2 control points but has {}; set point[0], point[1], ... \
                 or connect pointMatrix[i]",
                points.len()
            )));
        }
        let form = ctx.get(self.form);
        let curve = if points.iter().any(|p| !p.is_finite()) {
            Curve {
                points: Vec::new(),
                ..Curve::default()
            }
        } else {
            let form = match form {
                0 => CurveForm::Open,
                1 => {
                    points.push(points[0]);
                    CurveForm::Open
                }
                2 => CurveForm::Periodic,
                other => {
                    return Err(ComputeError::new(format!(
                        "form is {other}; use 0 (open), 1 (closed) or 2 (periodic)"
                    )))
                }
            };
            let max_degree = (points.len() - 1) as i64;
            let degree = ctx.get(self.degree).clamp(1, max_degree.max(1));
            Curve {
                degree: u32::try_from(degree).unwrap_or(1),
                points,
                knots: Vec::new(),
                form,
            }
        };
        ctx.set(self.out_curve, Arc::new(curve));
        Ok(())
    }
}
