//! `pointOnSurfaceInfo` and `closestPointOnSurface`: queries on a connected NURBS surface.

use glam::DVec3;
use sinew_core::{ComputeContext, ComputeError, Input, NodeSpec, NodeType, Output, SpecError, Unit};

use super::cache::{surface_of, SurfaceIn};
use super::curve_nodes::finite_or_zero;

/// `pointOnSurfaceInfo`: position, tangents and normal of `inputSurface` at
/// (`parameterU`, `parameterV`), or with `turnOnPercentage` at those fractions of the
/// domains.
///
/// `tangentU` = `∂S/∂u`, `tangentV` = `∂S/∂v`, `normal` = `tangentU × tangentV` (Maya's
/// orientation), each with a unit version. Parameters out of range clamp (open) or wrap
/// (periodic); NaN counts as the start. Where the surface is degenerate (a collapsed edge)
/// `normal` is 0 and `normalizedNormal` is taken a millionth of the domain inwards (+Y if
/// the surface is degenerate there too); a zero tangent has a zero unit tangent. No
/// surface connected: every output 0.
pub struct PointOnSurfaceInfo {
    spec: NodeSpec,
    input: SurfaceIn,
    u: Input<f64>,
    v: Input<f64>,
    percentage: Input<bool>,
    position: Output<DVec3>,
    normal: Output<DVec3>,
    normalized_normal: Output<DVec3>,
    tangent_u: Output<DVec3>,
    normalized_tangent_u: Output<DVec3>,
    tangent_v: Output<DVec3>,
    normalized_tangent_v: Output<DVec3>,
}

impl PointOnSurfaceInfo {
    /// Creates the node type.
    pub fn new() -> Result<Self, SpecError> {
        let mut b = NodeSpec::builder("pointOnSurfaceInfo");
        // Short names as Maya writes them (connectAttr "groundShape.ws" "pointOnSurfaceInfo1.is" ...).
        b.maya_names(&[
            ("inputSurface", "is"),
            ("parameterU", "u"),
            ("parameterV", "v"),
            ("turnOnPercentage", "top"),
            ("position", "p"),
            ("normal", "n"),
            ("normalizedNormal", "nn"),
            ("tangentU", "tu"),
            ("normalizedTangentU", "ntu"),
            ("tangentV", "tv"),
            ("normalizedTangentV", "ntv"),
        ]);
        b.doc("position, tangents and normal of a surface at (u, v)");
        let input = SurfaceIn::declare(&mut b, "inputSurface", "the surface (connect worldSpace[0] or local)");
        let u = b.input("parameterU", 0.0);
        let v = b.input("parameterV", 0.0);
        let percentage = b.input("turnOnPercentage", false);
        let position = b.output("position", DVec3::ZERO);
        let normal = b.output("normal", DVec3::ZERO);
        let normalized_normal = b.output("normalizedNormal", DVec3::ZERO);
        let tangent_u = b.output("tangentU", DVec3::ZERO);
        let normalized_tangent_u = b.output("normalizedTangentU", DVec3::ZERO);
        let tangent_v = b.output("tangentV", DVec3::ZERO);
        let normalized_tangent_v = b.output("normalizedTangentV", DVec3::ZERO);
        // Maya's node reference names these children in lower case: tangentUx, tangentVz...
        b.child_names(tangent_u, ["tangentUx", "tangentUy", "tangentUz"]);
        b.child_names(tangent_v, ["tangentVx", "tangentVy", "tangentVz"]);
        b.unit(position, Unit::Distance)
            .attr_doc(u, "u parameter (or fraction of the u domain with turnOnPercentage)")
            .attr_doc(v, "v parameter (or fraction of the v domain with turnOnPercentage)")
            .attr_doc(percentage, "read the parameters as fractions 0..1 of the domains")
            .attr_doc(position, "S(u, v)")
            .attr_doc(normal, "tangentU × tangentV")
            .attr_doc(normalized_normal, "unit normal")
            .attr_doc(tangent_u, "∂S/∂u")
            .attr_doc(normalized_tangent_u, "unit ∂S/∂u")
            .attr_doc(tangent_v, "∂S/∂v")
            .attr_doc(normalized_tangent_v, "unit ∂S/∂v");
        b.affects(
            &[input.cache.id(), u.id(), v.id(), percentage.id()],
            &[
                position.id(),
                normal.id(),
                normalized_normal.id(),
                tangent_u.id(),
                normalized_tangent_u.id(),
                tangent_v.id(),
                normalized_tangent_v.id(),
            ],
        );
        Ok(PointOnSurfaceInfo {
            spec: b.build()?,
            input,
            u,
            v,
            percentage,
            position,
            normal,
            normalized_normal,
            tangent_u,
            normalized_tangent_u,
            tangent_v,
            normalized_tangent_v,
        })
    }
}

impl NodeType for PointOnSurfaceInfo {
    fn spec(&self) -> &NodeSpec {
        &self.spec
    }

    fn compute(&self, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
        if self.input.compute(ctx) {
            return Ok(());
        }
        let obj = self.input.get(ctx);
        let outs = [
            self.position,
            self.normal,
            self.normalized_normal,
            self.tangent_u,
            self.normalized_tangent_u,
            self.tangent_v,
            self.normalized_tangent_v,
        ];
        let Some(s) = surface_of(&obj, "pointOnSurfaceInfo.inputSurface")? else {
            outs.iter().for_each(|&h| ctx.set(h, DVec3::ZERO));
            return Ok(());
        };
        let (mut u, mut v) = (ctx.get(self.u), ctx.get(self.v));
        if ctx.get(self.percentage) {
            (u, v) = (s.dir_u().from_fraction(u), s.dir_v().from_fraction(v));
        }
        let sp = s.eval(u, v);
        let values = [
            sp.position,
            sp.du.cross(sp.dv),
            s.normal(&sp, DVec3::Y),
            sp.du,
            sp.du.normalize_or_zero(),
            sp.dv,
            sp.dv.normalize_or_zero(),
        ];
        for (h, x) in outs.into_iter().zip(values) {
            ctx.set(h, x);
        }
        Ok(())
    }
}

/// `closestPointOnSurface`: the point of `inputSurface` closest to `inPosition` and its
/// parameters.
///
/// The search samples 8 × 8 points per span pair, then refines the best with Gauss–Newton
/// steps on `S_u · r = S_v · r = 0` (`r = S − q`) inside the domain. No surface (or a
/// non-finite `inPosition`): `position` = `inPosition` with non-finite components 0,
/// parameters 0.
pub struct ClosestPointOnSurface {
    spec: NodeSpec,
    input: SurfaceIn,
    in_position: Input<DVec3>,
    position: Output<DVec3>,
    u: Output<f64>,
    v: Output<f64>,
}

impl ClosestPointOnSurface {
    /// Creates the node type.
    pub fn new() -> Result<Self, SpecError> {
        let mut b = NodeSpec::builder("closestPointOnSurface");
        // Short names as Maya writes them (connectAttr "closestPointOnSurface1.u" "pointOnSurfaceInfo1.u" ...).
        b.maya_names(&[
            ("inputSurface", "is"),
            ("inPosition", "ip"),
            ("position", "p"),
            ("parameterU", "u"),
            ("parameterV", "v"),
        ]);
        b.doc("the point of a surface closest to a position, and its (u, v)");
        let input = SurfaceIn::declare(&mut b, "inputSurface", "the surface (connect worldSpace[0] or local)");
        let in_position = b.input("inPosition", DVec3::ZERO);
        let position = b.output("position", DVec3::ZERO);
        let u = b.output("parameterU", 0.0);
        let v = b.output("parameterV", 0.0);
        b.unit(in_position, Unit::Distance)
            .unit(position, Unit::Distance)
            .attr_doc(in_position, "the query point (the surface's space)")
            .attr_doc(position, "closest point of the surface")
            .attr_doc(u, "its u parameter")
            .attr_doc(v, "its v parameter");
        b.affects(&[input.cache.id(), in_position.id()], &[position.id(), u.id(), v.id()]);
        Ok(ClosestPointOnSurface {
            spec: b.build()?,
            input,
            in_position,
            position,
            u,
            v,
        })
    }
}

impl NodeType for ClosestPointOnSurface {
    fn spec(&self) -> &NodeSpec {
        &self.spec
    }

    fn compute(&self, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
        if self.input.compute(ctx) {
            return Ok(());
        }
        let obj = self.input.get(ctx);
        let q = ctx.get(self.in_position);
        let (p, u, v) = match surface_of(&obj, "closestPointOnSurface.inputSurface")? {
            Some(s) if q.is_finite() => {
                let hit = s.closest(q);
                (hit.position, hit.u, hit.v)
            }
            _ => (finite_or_zero(q), 0.0, 0.0),
        };
        ctx.set(self.position, p);
        ctx.set(self.u, u);
        ctx.set(self.v, v);
        Ok(())
    }
}
