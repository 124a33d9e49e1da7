//! `curveInfo`, `pointOnCurveInfo` and `nearestPointOnCurve`: queries on a connected curve.

use glam::DVec3;
use sinew_core::{ComputeContext, ComputeError, Input, MultiOutput, NodeSpec, NodeType, Output, SpecError, Unit};

use super::cache::{curve_of, CurveIn};
use super::curve_eval::frenet;

/// `curveInfo`: the arc length, control points, knots and weights of `inputCurve`.
///
/// `arcLength` is computed by Gauss–Legendre quadrature of the speed (5 points on each of 8
/// pieces per span: a few 1e-12 relative). `controlPoints[i]`, `knots[i]` (Maya's knot
/// vector: `points + degree − 1` values, without the two outer knots of the full vector)
/// and `weights[i]` (always 1: sinew's curves are non-rational) are written for the
/// elements that are read; indices past the end get 0. A curve without points gives
/// length 0.
pub struct CurveInfo {
    spec: NodeSpec,
    input: CurveIn,
    arc_length: Output<f64>,
    control_points: MultiOutput<DVec3>,
    knots: MultiOutput<f64>,
    weights: MultiOutput<f64>,
}

impl CurveInfo {
    /// Creates the node type.
    pub fn new() -> Result<Self, SpecError> {
        let mut b = NodeSpec::builder("curveInfo");
        b.maya_names(&[
            ("inputCurve", "ic"),
            ("arcLength", "al"),
            ("controlPoints", "cp"),
            ("knots", "kn"),
            ("weights", "wt"),
            ("xValue", "xv"),
            ("yValue", "yv"),
            ("zValue", "zv"),
        ]);
        b.doc("arc length, control points, knots and weights of a curve");
        let input = CurveIn::declare(&mut b, "inputCurve", "the curve (connect worldSpace[0] or local)", true);
        let arc_length = b.output("arcLength", 0.0);
        let control_points = b.multi_output("controlPoints", DVec3::ZERO);
        let knots = b.multi_output("knots", 0.0);
        let weights = b.multi_output("weights", 1.0);
        // Maya's children of controlPoints[i]: xValue (xv), yValue (yv), zValue (zv).
        b.child_names(control_points, ["xValue", "yValue", "zValue"]);
        b.unit(arc_length, Unit::Distance)
            .attr_doc(arc_length, "length of the curve")
            .attr_doc(control_points, "control point i")
            .attr_doc(knots, "knot i of Maya's knot vector (points + degree - 1 values)")
            .attr_doc(weights, "weight of control point i (1: curves are non-rational)");
        b.affects(
            &[input.cache.id()],
            &[arc_length.id(), control_points.id(), knots.id(), weights.id()],
        );
        Ok(CurveInfo {
            spec: b.build()?,
            input,
            arc_length,
            control_points,
            knots,
            weights,
        })
    }
}

impl NodeType for CurveInfo {
    fn spec(&self) -> &NodeSpec {
        &self.spec
    }

    fn compute(&self, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
        if self.input.compute(ctx) {
            return Ok(());
        }
        let obj = self.input.get(ctx);
        let c = curve_of(&obj, "curveInfo.inputCurve")?;
        ctx.set(self.arc_length, c.map_or(0.0, |c| c.length()));
        let points = c.map_or(&[][..], |c| c.points());
        let knots = c.map_or(&[][..], |c| c.direction().maya_knots());
        for k in 0..ctx.multi_out_len(self.control_points) {
            let i = ctx.multi_out_index(self.control_points, k).unwrap_or(0) as usize;
            ctx.set_elem(self.control_points, k, points.get(i).copied().unwrap_or_default());
        }
        for k in 0..ctx.multi_out_len(self.knots) {
            let i = ctx.multi_out_index(self.knots, k).unwrap_or(0) as usize;
            ctx.set_elem(self.knots, k, knots.get(i).copied().unwrap_or_default());
        }
        for k in 0..ctx.multi_out_len(self.weights) {
            let i = ctx.multi_out_index(self.weights, k).unwrap_or(0) as usize;
            ctx.set_elem(self.weights, k, if i < points.len() { 1.0 } else { 0.0 });
        }
        Ok(())
    }
}

/// `pointOnCurveInfo`: position, tangent, normal and curvature of `inputCurve` at
/// `parameter` (or, with `turnOnPercentage`, at that fraction of the parameter domain,
/// `[0, 1]` mapped linearly: parametric, not arc length, as Maya).
///
/// `tangent` is `C'(t)`, `normal` the part of `C''(t)` orthogonal to it (the principal normal
/// scaled by `|C'|² κ`), each with a unit version; `curvatureRadius` is `|C'|³ / |C' × C''|`
/// and `curvatureCenter` the point plus the radius along the unit normal. Parameters out of
/// range clamp to the ends (open curves) or wrap (periodic); NaN counts as the start.
/// Degenerate cases ([`frenet`]): a zero `C'` takes its direction from `C''` (else +X); on a
/// straight stretch `normal` is 0, `normalizedNormal` a fixed unit vector orthogonal to the
/// tangent, `curvatureRadius` 0 (Maya's is infinite there) and `curvatureCenter` the point.
/// No curve connected: every output 0.
pub struct PointOnCurveInfo {
    spec: NodeSpec,
    input: CurveIn,
    parameter: Input<f64>,
    percentage: Input<bool>,
    position: Output<DVec3>,
    normal: Output<DVec3>,
    normalized_normal: Output<DVec3>,
    tangent: Output<DVec3>,
    normalized_tangent: Output<DVec3>,
    curvature_center: Output<DVec3>,
    curvature_radius: Output<f64>,
}

impl PointOnCurveInfo {
    /// Creates the node type.
    pub fn new() -> Result<Self, SpecError> {
        let mut b = NodeSpec::builder("pointOnCurveInfo");
        b.maya_names(&[
            ("inputCurve", "ic"),
            ("parameter", "pr"),
            ("turnOnPercentage", "top"),
            ("position", "p"),
            ("normalizedNormal", "nn"),
            ("tangent", "t"),
            ("normalizedTangent", "nt"),
            ("curvatureCenter", "cc"),
            ("curvatureRadius", "cr"),
        ]);
        b.doc("position, tangent, normal and curvature of a curve at a parameter");
        let input = CurveIn::declare(
            &mut b,
            "inputCurve",
            "the curve (connect worldSpace[0] or local)",
            false,
        );
        let parameter = b.input("parameter", 0.0);
        let percentage = b.input("turnOnPercentage", false);
        let position = b.output("position", DVec3::ZERO);
        let normal = b.output("normal", DVec3::ZERO);
        let normalized_normal = b.output("normalizedNormal", DVec3::ZERO);
        let tangent = b.output("tangent", DVec3::ZERO);
        let normalized_tangent = b.output("normalizedTangent", DVec3::ZERO);
        let curvature_center = b.output("curvatureCenter", DVec3::ZERO);
        let curvature_radius = b.output("curvatureRadius", 0.0);
        b.attr_doc(
            parameter,
            "curve parameter (or fraction of the domain with turnOnPercentage)",
        )
        .attr_doc(percentage, "read parameter as a fraction 0..1 of the parameter domain")
        .attr_doc(position, "C(t)")
        .attr_doc(normal, "part of C''(t) orthogonal to the tangent")
        .attr_doc(normalized_normal, "unit principal normal")
        .attr_doc(tangent, "C'(t)")
        .attr_doc(normalized_tangent, "unit tangent")
        .attr_doc(curvature_center, "centre of the osculating circle")
        .attr_doc(curvature_radius, "radius of curvature (0 where straight)");
        b.unit(position, Unit::Distance).unit(curvature_radius, Unit::Distance);
        b.affects(
            &[input.cache.id(), parameter.id(), percentage.id()],
            &[
                position.id(),
                normal.id(),
                normalized_normal.id(),
                tangent.id(),
                normalized_tangent.id(),
                curvature_center.id(),
                curvature_radius.id(),
            ],
        );
        Ok(PointOnCurveInfo {
            spec: b.build()?,
            input,
            parameter,
            percentage,
            position,
            normal,
            normalized_normal,
            tangent,
            normalized_tangent,
            curvature_center,
            curvature_radius,
        })
    }
}

impl NodeType for PointOnCurveInfo {
    fn spec(&self) -> &NodeSpec {
        &self.spec
    }

    fn compute(&self, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
        if self.input.compute(ctx) {
            return Ok(());
        }
        let obj = self.input.get(ctx);
        let Some(c) = curve_of(&obj, "pointOnCurveInfo.inputCurve")? else {
            for h in [
                self.position,
                self.normal,
                self.normalized_normal,
                self.tangent,
                self.normalized_tangent,
                self.curvature_center,
            ] {
                ctx.set(h, DVec3::ZERO);
            }
            ctx.set(self.curvature_radius, 0.0);
            return Ok(());
        };
        let p = ctx.get(self.parameter);
        let t = if ctx.get(self.percentage) {
            c.direction().from_fraction(p)
        } else {
            p
        };
        let e = c.eval(t);
        let f = frenet(&e);
        ctx.set(self.position, e.position);
        ctx.set(self.normal, f.normal);
        ctx.set(self.normalized_normal, f.normalized_normal);
        ctx.set(self.tangent, f.tangent);
        ctx.set(self.normalized_tangent, f.normalized_tangent);
        ctx.set(self.curvature_center, f.curvature_center);
        ctx.set(self.curvature_radius, f.curvature_radius);
        Ok(())
    }
}

/// `nearestPointOnCurve`: the point of `inputCurve` closest to `inPosition`, and its
/// parameter.
///
/// The search samples 16 points per span, then refines the best with Newton's method on
/// `C'(t) · (C(t) − q) = 0` inside the domain (ends included), so it finds the global
/// closest point unless two candidates lie within one sample spacing of each other. Of
/// equally close points the one with the smaller parameter wins. No curve (or a non-finite
/// `inPosition`): `position` = `inPosition` with non-finite components 0, `parameter` 0.
pub struct NearestPointOnCurve {
    spec: NodeSpec,
    input: CurveIn,
    in_position: Input<DVec3>,
    position: Output<DVec3>,
    parameter: Output<f64>,
}

impl NearestPointOnCurve {
    /// Creates the node type.
    pub fn new() -> Result<Self, SpecError> {
        let mut b = NodeSpec::builder("nearestPointOnCurve");
        b.maya_names(&[("inputCurve", "ic"), ("inPosition", "ip")]);
        b.doc("the point of a curve closest to a position, and its parameter");
        let input = CurveIn::declare(
            &mut b,
            "inputCurve",
            "the curve (connect worldSpace[0] or local)",
            false,
        );
        let in_position = b.input("inPosition", DVec3::ZERO);
        let position = b.output("position", DVec3::ZERO);
        let parameter = b.output("parameter", 0.0);
        b.unit(in_position, Unit::Distance)
            .unit(position, Unit::Distance)
            .attr_doc(in_position, "the query point (the curve's space)")
            .attr_doc(position, "closest point of the curve")
            .attr_doc(parameter, "its parameter");
        b.affects(&[input.cache.id(), in_position.id()], &[position.id(), parameter.id()]);
        Ok(NearestPointOnCurve {
            spec: b.build()?,
            input,
            in_position,
            position,
            parameter,
        })
    }
}

impl NodeType for NearestPointOnCurve {
    fn spec(&self) -> &NodeSpec {
        &self.spec
    }

    fn compute(&self, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
        if self.input.compute(ctx) {
            return Ok(());
        }
        let obj = self.input.get(ctx);
        let q = ctx.get(self.in_position);
        let (t, p) = match curve_of(&obj, "nearestPointOnCurve.inputCurve")? {
            Some(c) if q.is_finite() => c.closest(q),
            _ => (0.0, finite_or_zero(q)),
        };
        ctx.set(self.position, p);
        ctx.set(self.parameter, t);
        Ok(())
    }
}

/// `v` with every non-finite component replaced by 0.
pub(crate) fn finite_or_zero(v: DVec3) -> DVec3 {
    DVec3::from_array(v.to_array().map(|x| if x.is_finite() { x } else { 0.0 }))
}
