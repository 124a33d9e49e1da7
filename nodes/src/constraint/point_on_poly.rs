//! `pointOnPolyConstraint`: the constrained node follows a point given by UV coordinates on
//! target meshes, with the surface's orientation.

use std::sync::Arc;

use glam::{DMat3, DMat4, DQuat, DVec3};
use sinew_core::{ComputeContext, ComputeError, Input, Mesh, MultiInput, NodeSpec, NodeType, Output, SpecError, Unit};

use super::common::{declare_parent_inverse, ids, offset_quat, Channel, ChildPivot, ChildRotation, INTERP_TYPES};
use super::rotation_path::local_rotation_mat3;
use crate::deform::surface::point_at_uv;
use crate::transform::math::quat_blend_weighted;

/// `pointOnPolyConstraint`: moves and rotates the constrained node to a UV point of its
/// target meshes.
///
/// Target `i` is `targetMesh[i]` (world space: connect a mesh's `worldMesh`) at
/// (`targetU[i]`, `targetV[i]`) (Maya keeps these as per-target dynamic attributes
/// `<target>U<i>`/`V<i>`; sinew flattens them), weighted by `targetWeight[i]`. Its frame is
/// the follicle's: X along `∂P/∂u`, Y along the interpolated normal, Z = X × Y; then
/// `offsetTranslate` and `offsetRotate` (degrees, xyz) are applied in that frame. Positions
/// blend by weighted average, orientations by the normalized weighted quaternion sum
/// (`interpType` average; the other choices act as average). Written back as
/// `parentConstraint` does: `constraintTranslate = PI · p − pivots`, `constraintRotate` the
/// Euler angles (compensating jointOrient, rotateAxis), of the equivalent triples the one
/// closest to `restRotate`. The UV is looked up on the mesh each evaluation (a scan of its
/// triangles: for large deforming meshes use a follicle or uvPin with an original mesh).
/// A UV outside every UV triangle, or a mesh without UVs, drops that target; with no target
/// left both outputs are the rest values.
pub struct PointOnPolyConstraint {
    spec: NodeSpec,
    mesh: MultiInput<Arc<Mesh>>,
    u: MultiInput<f64>,
    v: MultiInput<f64>,
    weight: MultiInput<f64>,
    parent_inverse: Input<DMat4>,
    rotation: ChildRotation,
    pivot: ChildPivot,
    offset_translate: Input<DVec3>,
    offset_rotate: Input<DVec3>,
    translate: Channel,
    rotate: Channel,
    out_translate: Output<DVec3>,
    out_rotate: Output<DVec3>,
}

impl PointOnPolyConstraint {
    /// Creates the node type.
    pub fn new() -> Result<Self, SpecError> {
        let mut b = NodeSpec::builder("pointOnPolyConstraint");
        b.maya_names(&[
            ("targetWeight", "tw"),
            ("constraintParentInverseMatrix", "cpim"),
            ("constraintRotateOrder", "cro"),
            ("constraintJointOrient", "cjo"),
            ("constraintRotatePivot", "crp"),
            ("constraintRotateTranslate", "crt"),
            ("restTranslate", "rst"),
            ("restRotate", "rsrr"),
            ("constraintTranslate", "ct"),
            ("constraintRotate", "cr"),
        ]);
        b.doc("translate + rotate the constrained node to a UV point of its target meshes");
        let mesh = b.multi_input("targetMesh", Arc::new(Mesh::default()));
        let u = b.multi_input("targetU", 0.0);
        let v = b.multi_input("targetV", 0.0);
        let weight = b.multi_input("targetWeight", 1.0);
        b.attr_doc(mesh, "target mesh i, world space (connect a mesh's worldMesh)")
            .attr_doc(u, "U of target i")
            .attr_doc(v, "V of target i")
            .attr_doc(weight, "weight of target i (default 1; negative counts as 0)");
        let parent_inverse = declare_parent_inverse(&mut b);
        let rotation = ChildRotation::declare(&mut b);
        let pivot = ChildPivot::declare(&mut b);
        let interp = b.input_enum("interpType", &INTERP_TYPES, 1);
        b.attr_doc(interp, "how orientations blend (every choice acts as average)");
        let offset_translate = b.input("offsetTranslate", DVec3::ZERO);
        let offset_rotate = b.input("offsetRotate", DVec3::ZERO);
        b.unit(offset_translate, Unit::Distance)
            .unit(offset_rotate, Unit::Degrees)
            .attr_doc(offset_translate, "offset in the surface frame")
            .attr_doc(offset_rotate, "rotation (degrees, xyz) in the surface frame");
        let translate = Channel::declare(&mut b, "Translate", DVec3::ZERO, Unit::Distance);
        let rotate = Channel::declare(&mut b, "Rotate", DVec3::ZERO, Unit::Degrees);
        let out_translate = b.output("constraintTranslate", DVec3::ZERO);
        let out_rotate = b.output("constraintRotate", DVec3::ZERO);
        b.unit(out_rotate, Unit::Degrees)
            .attr_doc(out_translate, "connect to the constrained node's translate")
            .attr_doc(out_rotate, "connect to the constrained node's rotate (degrees)");
        let target_ids = [
            mesh.id(),
            u.id(),
            v.id(),
            weight.id(),
            offset_translate.id(),
            offset_rotate.id(),
        ];
        b.affects(
            &ids(&[&target_ids, &[parent_inverse.id()], &pivot.ids(), &translate.ids()]),
            &[out_translate.id()],
        );
        b.affects(
            &ids(&[
                &target_ids,
                &[parent_inverse.id(), interp.id()],
                &rotation.ids(),
                &rotate.ids(),
            ]),
            &[out_rotate.id()],
        );
        Ok(PointOnPolyConstraint {
            spec: b.build()?,
            mesh,
            u,
            v,
            weight,
            parent_inverse,
            rotation,
            pivot,
            offset_translate,
            offset_rotate,
            translate,
            rotate,
            out_translate,
            out_rotate,
        })
    }

    /// Every target's world frame (with the offsets) and weight.
    fn frames(&self, ctx: &ComputeContext<'_>) -> Vec<(DMat4, f64)> {
        let off_t = ctx.get(self.offset_translate);
        let off_r = DMat3::from_quat(offset_quat(ctx.get(self.offset_rotate)));
        let mut out = Vec::new();
        for k in 0..ctx.multi_len(self.mesh) {
            let Some((i, mesh)) = ctx.multi_at(self.mesh, k) else {
                continue;
            };
            let w = ctx.get_at(self.weight, i).unwrap_or(1.0);
            if !(w.is_finite() && w > 0.0) {
                continue;
            }
            let (u, v) = (
                ctx.get_at(self.u, i).unwrap_or(0.0),
                ctx.get_at(self.v, i).unwrap_or(0.0),
            );
            let Some(sp) = point_at_uv(&mesh, u as f32, v as f32) else {
                continue;
            };
            let y = sp.normal.as_dvec3();
            let x = sp.tangent_u.as_dvec3();
            let rot = DMat3::from_cols(x, y, x.cross(y));
            let p = sp.position.as_dvec3() + rot * off_t;
            let mut m = DMat4::from_mat3(rot * off_r);
            m.w_axis = p.extend(1.0);
            out.push((m, w));
        }
        out
    }
}

impl NodeType for PointOnPolyConstraint {
    fn spec(&self) -> &NodeSpec {
        &self.spec
    }

    fn compute(&self, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
        let frames = self.frames(ctx);
        let total: f64 = frames.iter().map(|f| f.1).sum();
        let pim = ctx.get(self.parent_inverse);
        let have = !frames.is_empty() && total.is_finite() && total > 0.0;
        if ctx.wants(self.out_translate) {
            let p = have.then(|| {
                frames
                    .iter()
                    .fold(DVec3::ZERO, |acc, (m, w)| acc + m.w_axis.truncate() * (w / total))
            });
            let t = p.map(|p| pim.transform_point3(p) - self.pivot.sum(ctx));
            let t = self.translate.apply(ctx, t);
            ctx.set(self.out_translate, t);
        }
        if ctx.wants(self.out_rotate) {
            let rest = self.rotate.rest(ctx);
            let r = have.then(|| {
                let items: Vec<(DQuat, f64)> = frames
                    .iter()
                    .map(|(m, w)| (DQuat::from_mat3(&DMat3::from_mat4(*m)), *w))
                    .collect();
                let world = DMat3::from_quat(quat_blend_weighted(&items));
                self.rotation
                    .rotate_deg_mat3(ctx, &local_rotation_mat3(&pim, world, DVec3::ZERO), rest)
            });
            let r = self.rotate.apply(ctx, r);
            ctx.set(self.out_rotate, r);
        }
        Ok(())
    }
}
